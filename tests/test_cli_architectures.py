"""The commands this module's developer owns, on every shipped design: `analyze --json`
gives a symmetric positive definite K in the library's conventions, `deflect` runs the
three loading modes, and the redundant design's loaded state is the exact equilibrium."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from helpers import flexure_jointed
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import (
    length_balanced,
    twist_b_from_twist_a,
    wrench_b_from_wrench_a,
)
from ppm_stiffness.design import default_design, load_design
from ppm_stiffness.model import (
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
    workspace_centre,
)
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.deflection import mode_wrench
from ppm_stiffness.statics.equilibrium import equilibrium

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DESIGNS = [None, *sorted(str(p) for p in EXAMPLES.glob("*.toml"))]


def _json(capsys: pytest.CaptureFixture[str], *args: str) -> dict[str, object]:
    assert main(list(args)) == 0
    return json.loads(capsys.readouterr().out)  # type: ignore[no-any-return]


@pytest.mark.parametrize("path", DESIGNS, ids=lambda p: Path(p).stem if p else "built-in")
def test_analyze_json_on_every_design(capsys: pytest.CaptureFixture[str], path: str | None) -> None:
    args = ["analyze", "--json"] + (["--design", path] if path else [])
    out = _json(capsys, *args)
    k = np.array(out["stiffness_matrix"])
    design = load_design(path) if path else default_design()
    home = home_pose(design)  # K at the design's tool point (P unless it sets one)
    k_tool = stiffness_at_tool_point(stiffness_at_pose(design), home, design.tool_point)
    np.testing.assert_allclose(k, k_tool, rtol=1e-12, atol=0)
    kb = length_balanced(k)
    assert np.max(np.abs(kb - kb.T)) <= 1e-12 * np.max(np.abs(kb))
    assert np.linalg.eigvalsh(kb)[0] > 0
    assert out["architecture"] == design.architecture
    assert len(out["actuator_units"]) == len(design.legs)  # type: ignore[arg-type]


@pytest.mark.parametrize("path", DESIGNS, ids=lambda p: Path(p).stem if p else "built-in")
@pytest.mark.parametrize("mode", ["planar-force", "moment", "vertical-force"])
def test_deflect_on_every_design(
    capsys: pytest.CaptureFixture[str], path: str | None, mode: str
) -> None:
    """The printed path starts unloaded and ends at the equilibrium of the top load,
    solved independently (Newton on the nonlinear actuator law, no path integration).
    Measured: twists to at most 2.9e-14 of the largest component (3-PRR, planar force),
    actuator forces to 1.8e-15 of the largest; 1e-13 allowed for both (a vertical force
    loads no actuator of these planar designs: forces 0, compared to 1e-13 N)."""
    top = {"planar-force": "5", "moment": "0.2", "vertical-force": "5"}[mode]
    args = ["deflect", "--mode", mode, "--max", top, "--step", top, "--json"]
    out = _json(capsys, *args, *(["--design", path] if path else []))
    design = load_design(path) if path else default_design()
    pose = workspace_centre(design)
    offset = tool_offset(pose, design.tool_point)
    w_tool = float(top) * mode_wrench(mode)  # alpha 45 deg, the command's default
    eq = equilibrium(design, wrench_b_from_wrench_a(np.eye(3), offset) @ w_tool, pose)
    expected = twist_b_from_twist_a(np.eye(3), -offset) @ eq.twist
    twists = np.array(out["twists"])
    assert twists.shape == (2, 6)
    assert not np.any(twists[0])  # the path starts unloaded
    scale = np.max(np.abs(expected))
    assert scale > 0
    # the flexure 6-RUS: 3.5e-12 measured (its 4.7 N·m/rad flexures beside 1e7 N/m
    # springs in one solve, as in tests/test_moving_geometry.py)
    tol = 1e-11 if flexure_jointed(design) else 1e-13
    np.testing.assert_allclose(twists[1], expected, rtol=0, atol=tol * scale)
    forces = np.array(out["actuator_forces"])[1]
    # forces compared at the scale of the load (a tripod's actuators carry none of a
    # planar force: their forces are round-off of the 5 N load, measured 1.1e-13 N)
    force_scale = max(float(np.max(np.abs(eq.actuator_forces))), float(top))
    np.testing.assert_allclose(forces, eq.actuator_forces, rtol=0, atol=1e-13 * force_scale)


def test_analyze_redundant_wrench_is_the_equilibrium(capsys: pytest.CaptureFixture[str]) -> None:
    """The CLI's loaded state of the 4-PPR is the exact equilibrium (pinned against
    independent solutions in tests/test_statics_redundant.py)."""
    path = str(EXAMPLES / "redundant_4ppr.toml")
    out = _json(
        capsys,
        "analyze",
        "--json",
        "--design",
        path,
        "--x",
        "15",
        "--y",
        "-15",
        "--phi",
        "-12",
        "--wrench",
        "15,-8,10,0.05,-0.03,0.4",
    )
    eq = equilibrium(
        load_design(path),
        [0.05, -0.03, 0.4, 15.0, -8.0, 10.0],
        [0.015, -0.015, math.radians(-12.0)],
    )
    np.testing.assert_allclose(out["actuator_forces"], eq.actuator_forces, rtol=1e-12)
    np.testing.assert_allclose(out["twist"], eq.twist, rtol=1e-12)
    np.testing.assert_allclose(out["stiffness_matrix"], eq.stiffness_matrix, rtol=1e-12)
