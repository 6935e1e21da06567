"""The general batched path (the engine of legs/engine.py, any architecture) against
the single-pose API, the P-P-R reduced path against the general path, and maps of every
shipped planar design (spatial designs: test_spatial_maps.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from helpers import (
    design_named,
    example_designs,
    has_reduced_form,
    is_planar,
    poses_around_workspace,
    wide_design,
)
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import length_balanced
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import (
    DesignError,
    InputDataError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.design import Design, default_design
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.workspace import load_npz, stiffness_map
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.statics.actuator import stiffness_from_force
from ppm_stiffness.statics.loading import loaded_state

ROOT = Path(__file__).parents[1]
EXAMPLES = example_designs(is_planar)
#: Measured: the general path equals the single-pose path to 6e-15 (length-balanced
#: K, relative to its largest entry) on these poses; 1e-10 leaves rounding room.
RTOL = 1e-10
PAPER_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])


def workspace_poses(design: Design, n: int, seed: int, phi_max: float = 0.3) -> np.ndarray:
    """Random poses over a box 20 % wider than the workspace at phi = 0."""
    return poses_around_workspace(design, n, seed, pad=0.1, phi_max=phi_max)


def single(design: Design, pose: np.ndarray, k_act: np.ndarray | None = None) -> np.ndarray | None:
    try:
        return stiffness_at_pose(design, pose, k_act)
    except (UnreachablePoseError, SingularConfigurationError):
        return None


def rel_balanced(a: np.ndarray, b: np.ndarray) -> float:
    ab, bb = length_balanced(a), length_balanced(b)
    return float(np.max(np.abs(ab - bb)) / np.max(np.abs(bb)))


@pytest.mark.parametrize("name", ["paper", *EXAMPLES])
def test_general_path_equals_single_pose_path(name: str) -> None:
    design = design_named(name)
    poses = workspace_poses(design, 80, 31)
    rng = np.random.default_rng(5)
    k_lock = np.array([leg.locked_stiffness() for leg in design.legs])
    k_act = k_lock * rng.uniform(0.05, 1.0, (len(poses), len(design.legs)))
    res = batch.evaluate_poses(design, poses, k_act, matrices=True, path="general", chunk_size=17)
    assert res.path == "general" and res.stiffness is not None
    checked = 0
    for i, pose in enumerate(poses):
        k_ref = single(design, pose, k_act[i])
        assert res.valid[i] == (k_ref is not None)
        if k_ref is None:
            assert res.k_phi.mask[i] and res.k_x.mask[i] and res.k_y.mask[i]
            continue
        checked += 1
        assert rel_balanced(res.stiffness[i], k_ref) <= RTOL
        dec = decouple(k_ref, "paper")
        np.testing.assert_allclose(
            [res.k_phi[i], res.k_x[i], res.k_y[i]],
            [dec.rotational_values[2], *dec.translational_values[:2]],
            rtol=RTOL,
        )
    assert checked >= 20  # the box is wider than the workspace: both outcomes occur
    assert checked < len(poses) or name == "redundant_4ppr"
    assert np.all(np.isfinite(res.k_x.compressed()))


@pytest.mark.parametrize("name", example_designs(has_reduced_form, paper=True))
def test_reduced_path_equals_general_path(name: str) -> None:
    design = design_named(name)
    assert batch.select_path(design) is not None  # every P-P-R leg offers it
    poses = workspace_poses(design, 300, 8)
    red = batch.evaluate_poses(design, poses, matrices=True, path="reduced")
    gen = batch.evaluate_poses(design, poses, matrices=True, path="general")
    assert red.path == "reduced" and gen.path == "general"
    np.testing.assert_array_equal(red.valid, gen.valid)
    np.testing.assert_array_equal(red.reachable, gen.reachable)
    assert 20 <= red.valid.sum()
    assert red.stiffness is not None and gen.stiffness is not None
    worst = max(rel_balanced(red.stiffness[i], gen.stiffness[i]) for i in np.flatnonzero(red.valid))
    assert worst <= 1e-9
    for field in ("k_phi", "k_x", "k_y"):
        np.testing.assert_allclose(
            getattr(red, field).compressed(), getattr(gen, field).compressed(), rtol=1e-9
        )


def test_reduced_and_general_masks_agree_near_a_singular_orientation() -> None:
    """At phi = 90 deg two force lines of the opened built-in design coincide; the
    transmission index crosses 1e-6 about 0.0047 rad away."""
    design = wide_design()
    offsets = np.array([0.0, 1e-6, 1e-3, 0.0046, 0.00472, 0.00474, 0.01, -0.0047, -0.0048, -0.05])
    poses = np.column_stack([np.zeros_like(offsets), np.zeros_like(offsets), np.pi / 2 + offsets])
    red = batch.evaluate_poses(design, poses, path="reduced")
    gen = batch.evaluate_poses(design, poses, path="general")
    expected = np.array([single(design, p) is not None for p in poses])
    assert expected.any() and not expected.all()
    np.testing.assert_array_equal(red.valid, expected)
    np.testing.assert_array_equal(gen.valid, expected)


def test_unsolvable_poses_are_masked_without_nan() -> None:
    """3-RRR: a platform 1 m away is out of every leg's reach (no IK solution)."""
    design = design_named("3rrr")
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.2], [0.01, 0.02, 0.1]])
    res = batch.evaluate_poses(design, poses, matrices=True)
    np.testing.assert_array_equal(res.valid, [True, False, False, True])
    np.testing.assert_array_equal(res.reachable, [True, False, False, True])
    assert res.stiffness is not None and np.all(np.isfinite(res.stiffness))
    assert np.all(res.stiffness[1:3] == 0.0)
    assert np.all(np.isfinite(res.k_phi.compressed())) and res.k_phi.count() == 2


def test_path_requests() -> None:
    with pytest.raises(DesignError, match="no exact reduced form"):
        batch.evaluate_poses(design_named("3rrr"), np.zeros(3), path="reduced")
    with pytest.raises(InputDataError, match="path must be 'auto', .* got 'fast'"):
        batch.evaluate_poses(default_design(), np.zeros(3), path="fast")  # type: ignore[arg-type]
    with pytest.raises(InputDataError, match="poses must be finite"):
        batch.evaluate_poses(default_design(), [np.nan, 0.0, 0.0])


# ---------------------------------------------------------------------------- maps
@pytest.mark.parametrize(
    "name", example_designs(lambda d: is_planar(d) and not has_reduced_form(d))
)
def test_general_map_equals_single_pose_with_each_legs_law(name: str) -> None:
    design = design_named(name)
    for acts in ("max", "min"):
        smap = stiffness_map(design, phi=0.1, actuators=acts, grid=(7, 6))
        assert 0 < smap.reachable.sum() < smap.reachable.size
        if acts == "max":
            k_act = np.array([leg.locked_stiffness() for leg in design.legs])
        else:
            k_act = np.array(
                [float(stiffness_from_force(leg.actuator, 10.0)) for leg in design.legs]
            )
        np.testing.assert_array_equal(smap.actuator_stiffness, [k_act, k_act])
        for j, y in enumerate(smap.y):
            for i, x in enumerate(smap.x):
                k = single(design, np.array([x, y, 0.1]), k_act)
                assert smap.reachable[j, i] == (k is not None)
                if k is None:
                    continue
                dec = decouple(k, "paper")
                np.testing.assert_allclose(
                    [smap.k_phi[j, i], smap.k_x[j, i], smap.k_y[j, i]],
                    [dec.rotational_values[2], *dec.translational_values[:2]],
                    rtol=RTOL,
                )


@pytest.mark.parametrize("name", ["redundant_4ppr", "3rrr"])
def test_wrench_map_is_loaded_state_per_pose(name: str) -> None:
    """Redundant or general designs: each pose's actuator stiffness from loaded_state."""
    design = design_named(name)
    smap = stiffness_map(design, actuators="wrench", wrench=PAPER_WRENCH, grid=4)
    assert smap.reachable.any()
    lo, hi = np.full(len(design.legs), np.inf), np.full(len(design.legs), -np.inf)
    for j, y in enumerate(smap.y):
        for i, x in enumerate(smap.x):
            if not smap.reachable[j, i]:
                continue
            state = loaded_state(design, PAPER_WRENCH, np.array([x, y, 0.0]))
            k_act = state.actuator_stiffness
            lo, hi = np.minimum(lo, k_act), np.maximum(hi, k_act)
            dec = decouple(state.stiffness_matrix, "paper")
            np.testing.assert_allclose(
                [smap.k_phi[j, i], smap.k_x[j, i], smap.k_y[j, i]],
                [dec.rotational_values[2], *dec.translational_values[:2]],
                rtol=RTOL,
            )
    np.testing.assert_allclose(smap.actuator_stiffness, [lo, hi], rtol=1e-12)


@pytest.mark.parametrize("name", EXAMPLES)
@pytest.mark.parametrize("acts", ["max", "min", "5,5,20,0,0,0.1"])
def test_cli_map_runs_on_every_example(
    name: str, acts: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    data = tmp_path / "m.npz"
    rc = main(
        [
            "map",
            "--design",
            str(ROOT / "examples" / f"{name}.toml"),
            "--grid",
            "6",
            f"--actuators={acts}",
            "--data",
            str(data),
            "--quiet",
        ]
    )
    assert rc == 0
    assert "k_phi" in capsys.readouterr().out
    smap = load_npz(data)
    assert smap.reachable.any()
    for values in smap.fields().values():
        assert np.all(np.isfinite(values.compressed())) and np.all(values.compressed() > 0)
        assert np.all(np.isnan(values.data[~smap.reachable]))


def test_cli_map_figure_of_a_3rrr(tmp_path: Path) -> None:
    fig = tmp_path / "m.png"
    assert (
        main(
            [
                "map",
                "--design",
                str(ROOT / "examples" / "3rrr.toml"),
                "--grid",
                "10",
                "--out",
                str(fig),
                "--quiet",
            ]
        )
        == 0
    )
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
