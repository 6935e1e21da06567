"""The shipped example designs and the README's Python snippet, pinned."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pytest

from helpers import design_named, example_designs, has_reduced_form, rotational_symmetry
from ppm_stiffness.core.conventions import rotation_z, stiffness_b_from_stiffness_a
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import PPMStiffnessError
from ppm_stiffness.design import load_design
from ppm_stiffness.maps.batch import evaluate_poses
from ppm_stiffness.model import stiffness_at_pose

if TYPE_CHECKING:
    from helpers import DocRun

ROOT = Path(__file__).parents[1]
#: The examples of P-P-R legs (the reduced form) and their rotational symmetry.
EXAMPLES = {
    f"{n}.toml": rotational_symmetry(design_named(n)) for n in example_designs(has_reduced_form)
}


@pytest.mark.parametrize(("name", "n"), [(m, n) for m, n in EXAMPLES.items() if n >= 3])
def test_example_is_n_fold_symmetric(name: str, n: int) -> None:
    design = load_design(ROOT / "examples" / name)
    assert len(design.legs) == n
    k = stiffness_at_pose(design, [0.0, 0.0, 0.0])
    # the machine maps onto itself under a rotation by 360/n deg: so does K
    rotated = stiffness_b_from_stiffness_a(k, rotation_z(2 * np.pi / n), np.zeros(3))
    np.testing.assert_allclose(rotated, k, atol=1e-9 * np.abs(k).max())
    assert k[3, 3] == pytest.approx(k[4, 4], rel=1e-12)  # isotropic in the plane


@pytest.mark.parametrize("name", EXAMPLES)
def test_fast_batched_path_serves_other_designs(name: str) -> None:
    # the reduced form of batch.py is derived per design: it must equal the general
    # single-pose path on designs whose rails are not along x and y
    design = load_design(ROOT / "examples" / name)
    rng = np.random.default_rng(11)
    poses = np.column_stack(
        [rng.uniform(-0.02, 0.02, 30), rng.uniform(-0.02, 0.02, 30), rng.uniform(-0.3, 0.3, 30)]
    )
    result = evaluate_poses(design, poses)
    checked = 0
    for i, pose in enumerate(poses):
        try:
            dec = decouple(stiffness_at_pose(design, pose))
        except PPMStiffnessError:
            assert not result.valid[i]
            continue
        assert result.valid[i]
        expected = [dec.rotational_values[2], *dec.translational_values[:2]]
        got = [result.k_phi[i], result.k_x[i], result.k_y[i]]
        np.testing.assert_allclose(got, expected, rtol=1e-10)
        checked += 1
    assert checked >= 20


def _python_blocks(path: Path) -> list[str]:
    """The ``python`` code blocks of a page (tests/test_mass_model_input.py runs
    docs/dynamics.md's)."""
    blocks = re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), re.S)
    assert blocks, f"{path.name} has python blocks"
    return blocks


def test_readme_python_snippet_runs(doc_runs: dict[str, DocRun]) -> None:
    """The README's example runs as written from the top folder, and prints K_phiphi
    and (k_x, k_y, k_z) of the 3-RRR at its pose."""
    run = doc_runs["README.md"]
    assert run.blocks >= 1 and run.error is None, run.error
    lines = run.out.splitlines()
    design = load_design(ROOT / "examples" / "3rrr.toml")
    k = stiffness_at_pose(design, [0.01, 0.0, 0.1])
    assert lines[0] == f"{k[2, 2]} N·m/rad"
    assert len(json.loads(lines[1])) == 3


def test_api_page_runs(doc_runs: dict[str, DocRun]) -> None:
    run = doc_runs["docs/api.md"]
    assert run.blocks >= 1 and run.error is None, run.error
    out = run.out
    assert "3-RRR" in out and "refused:" in out
