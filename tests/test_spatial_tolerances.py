"""Uncertainty bands (``--tolerances``) on spatial designs: the spatial principal
stiffnesses at the tool point, K, the loaded twist and deflection curves."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import design_named
from ppm_stiffness.cli import main
from ppm_stiffness.core.principal import principal_compliance
from ppm_stiffness.fit.band_outputs import (
    SPATIAL_PRINCIPAL,
    deflection_output,
    pose_failed_value,
    pose_labels,
    pose_output,
)
from ppm_stiffness.fit.tolerances import parse_tolerances, tolerance_variables
from ppm_stiffness.fit.uncertainty import propagate
from ppm_stiffness.model import stiffness_at_pose, stiffness_at_tool_point
from ppm_stiffness.poses import full_pose
from ppm_stiffness.statics.deflection import deflection_curve

ROOT = Path(__file__).parents[1]
TOOL = np.array([0.01, -0.02, 0.05])
HEXAPOD = design_named("hexapod_6ups")
HEX_POSE = full_pose(HEXAPOD, [0.01, -0.005, 0.21, 0.05, -0.03, 0.08])


def _variables(design: object, text: str) -> list[object]:
    return tolerance_variables(design, parse_tolerances(text))  # type: ignore[arg-type]


def test_the_spatial_principal_stiffnesses_lead_the_output() -> None:
    """A spatial design's pose output: the rotational and translational principal
    stiffnesses of C = K^-1 at the tool point in ascending order, then K at the tool
    point (42 values; 48 with the loaded twist); the same values as
    core.principal.principal_compliance of that K (to 1e-15 relative)."""
    out = pose_output(HEX_POSE, TOOL)(HEXAPOD)
    k_tool = stiffness_at_tool_point(stiffness_at_pose(HEXAPOD, HEX_POSE), HEX_POSE, TOOL)
    pc = principal_compliance(k_tool)
    np.testing.assert_allclose(out[:3], np.sort(pc.rotational_values), rtol=1e-15)
    np.testing.assert_allclose(out[3:6], np.sort(pc.translational_values), rtol=1e-15)
    np.testing.assert_array_equal(out[6:], k_tool.ravel())
    names, units = pose_labels(HEXAPOD, loaded=True)
    assert (
        names[:6]
        == [n for n, _ in SPATIAL_PRINCIPAL]
        == ["k_rot_1", "k_rot_2", "k_rot_3", "k_trans_1", "k_trans_2", "k_trans_3"]
    )
    assert len(names) == len(units) == 48 and units[0] == "N·m/rad" and units[3] == "N/m"
    assert pose_failed_value(HEXAPOD).shape == (42,)
    assert pose_labels(design_named("paper"))[0][:3] == ["k_phi", "k_x", "k_y"]


def test_the_bands_of_two_force_legs_ignore_their_bending() -> None:
    """The hexapod's legs (passive U and S joints) transmit only an axial force: a
    tolerance of 10 % on the links' bending and torsion and the rod bushing's lateral
    and tilt springs leaves every principal stiffness where it is (band width measured
    0), while 1 % on the actuators' stiffness moves them (relative sigma 1e-3)."""
    text = "".join(
        f'["leg*.{name}"]\npm = "10%"\n'
        for name in ("rod.inertia_y", "cylinder.torsion_constant", "guide.lateral", "guide.pitch")
    )
    out = pose_output(HEX_POSE, TOOL)
    bending = propagate(HEXAPOD, _variables(HEXAPOD, text), out, "first-order")
    assert np.max(bending.std[:6] / bending.nominal[:6]) < 1e-12
    actuators = _variables(HEXAPOD, '["leg*.actuator.locked_stiffness"]\npm = "1%"\n')
    moved = propagate(HEXAPOD, actuators, out, "first-order")
    assert np.min(moved.std[:6] / moved.nominal[:6]) > 1e-4


def test_first_order_and_qmc_agree_for_small_tolerances_on_a_tripod() -> None:
    """3-RPS at a tilted pose under a wrench at the tool point, the actuators and the
    base revolutes' tilt within +-1 %: every output is nearly linear in them, so the QMC
    standard deviation (64 Sobol samples) equals the first-order sigma to 3 % for the
    principal stiffnesses and the twist (measured within 0.4 %), and no sample fails."""
    design = design_named("3rps")
    pose = full_pose(design, [0.36, 0.08, -0.05])
    text = '["leg*.actuator.locked_stiffness"]\npm = "1%"\n["leg*.base_revolute.tilt"]\npm = "1%"\n'
    variables = _variables(design, text)
    out = pose_output(pose, TOOL, np.array([1.0, 0, 0, 100.0, 0, 50.0]))
    fo = propagate(design, variables, out, "first-order")
    qmc = propagate(design, variables, out, "qmc", samples=64)
    assert fo.nominal.shape == (48,) and qmc.failed == 0
    for i in [*range(6), *range(42, 48)]:
        assert abs(qmc.std[i] / fo.std[i] - 1) < 0.03


def test_deflection_bands_of_a_tripod() -> None:
    """The band output of a 3-PRS curve at a tilted pose (its full pose given) is the
    curve's twists at the nominal design, and moves with the actuators' stiffness."""
    design = design_named("3prs")
    pose = full_pose(design, [0.38, 0.08, -0.05])
    curve = deflection_curve(
        design,
        "direction",
        [0.0, 50.0, 100.0],
        pose,
        tool_point=TOOL,
        direction=[0, 0, 1.0, 1.0, 0, 0.5],
    )
    out = deflection_output(curve.unit_wrench, curve.loads, curve.pose, curve.tool_point)
    np.testing.assert_allclose(out(design), curve.twists, rtol=1e-12, atol=1e-22)
    variables = _variables(design, '["leg*.actuator.k_a"]\npm = "5%"\n')
    bands = propagate(design, variables, out, "first-order")
    assert np.all(bands.std[-1, 3:] > 0)


# ------------------------------------------------------------------ the commands
@pytest.fixture()
def tolerances(tmp_path: Path) -> Path:
    path = tmp_path / "tol.toml"
    path.write_text(
        # the examples' actuators are linear (q = 1): this varies k_a with it
        '["leg*.actuator.locked_stiffness"]\npm = "10%"\n',
        encoding="utf-8",
    )
    return path


def test_analyze_bands_of_a_spatial_design(
    tolerances: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """analyze --tolerances on the 3-PRS (it failed: 'poses must have shape (..., 3)'):
    the bands of the six spatial principal stiffnesses, nominal = analyze's values."""
    design = str(ROOT / "examples/3prs.toml")
    assert main(["analyze", "--json", "--design", design, "--tolerances", str(tolerances)]) == 0
    doc = json.loads(capsys.readouterr().out)
    q = doc["uncertainty"]["quantities"]
    assert list(q) == [n for n, _ in SPATIAL_PRINCIPAL] + ["f1"]  # f1: it has a mass model
    assert q["f1"]["nominal"] == pytest.approx(doc["first_frequency"], rel=1e-12)
    pc = doc["principal_compliance"]
    np.testing.assert_allclose(
        [q[f"k_rot_{j}"]["nominal"] for j in (1, 2, 3)],
        np.sort(pc["rotational"]["values"]),
        rtol=1e-12,
    )
    np.testing.assert_allclose(
        [q[f"k_trans_{j}"]["nominal"] for j in (1, 2, 3)],
        np.sort(pc["translational"]["values"]),
        rtol=1e-12,
    )
    for name, _ in SPATIAL_PRINCIPAL:
        assert q[name]["lower"] < q[name]["nominal"] < q[name]["upper"]
    assert main(["analyze", "--design", design, "--tolerances", str(tolerances)]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "k_trans_1" in out
    # the bands' numbering (ascending) is not the principal table's (by direction)
    assert "k_rot_1..3 and k_trans_1..3: the principal stiffnesses in ascending order" in out


def test_deflect_bands_of_the_hexapod(tolerances: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Six components with bands print as two tables of three."""
    argv = ["deflect", "--design", str(ROOT / "examples/hexapod_6ups.toml"), "--direction"]
    argv += ["100,-50,200,5,-3,2", "--max", "200", "--step", "100", "--tolerances", str(tolerances)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert out.count("lo..hi") == 6 and "phi_x lo..hi" in out and "z lo..hi" in out
