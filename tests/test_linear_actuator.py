"""A linear actuator law (q = 1) has one stiffness: ``locked_stiffness`` and ``k_a``
are the same parameter (issue 27, item 3). Before, they could differ: the unloaded K
used one and any load, even 1 mN, the other."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import ActuatorModel, load_design
from ppm_stiffness.fit.calibration import calibrate
from ppm_stiffness.fit.identify import MeasurementRows, identify
from ppm_stiffness.fit.tolerances import (
    design_at,
    parse_tolerances,
    read_tolerances,
    tolerance_variables,
)
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.optimize.variables import check_distinct, parse_variable
from ppm_stiffness.statics.actuator import stiffness_from_force
from ppm_stiffness.statics.deflection import deflection_path

ROOT = Path(__file__).parents[1]
RPS = ROOT / "examples/3rps.toml"
HEXAPOD = ROOT / "examples/hexapod_6ups.toml"
PAPER = ROOT / "examples/symmetric_3ppr.toml"
IDENT = ROOT / "examples/identification"


def _edited(tmp_path: Path, source: Path, old: str, new: str) -> Path:
    text = source.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / source.name
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


# ------------------------------------------------------------------ the design file
def test_a_disagreement_is_refused_naming_both(tmp_path: Path) -> None:
    path = _edited(tmp_path, RPS, "k_a = 60000000.0", "k_a = 50000000.0")
    with pytest.raises(
        DesignError,
        match=r"key 'parts.actuator.k_a': k_a = 5e\+07 and locked_stiffness = 6e\+07 differ",
    ):
        load_design(path)


def test_a_leg_that_overrides_one_is_named(tmp_path: Path) -> None:
    """[parts.actuator] gives both, leg 1 overrides k_a alone: the error names leg 1."""
    text = RPS.read_text(encoding="utf-8")
    end = text.index("\n\n", text.index("[[legs]]"))
    path = tmp_path / "override.toml"
    path.write_text(text[:end] + "\nactuator.k_a = 30000000.0" + text[end:], encoding="utf-8")
    with pytest.raises(DesignError, match=r"key 'leg1.actuator.k_a': k_a = 3e\+07 and locked_"):
        load_design(path)


def test_a_disagreement_exits_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _edited(tmp_path, RPS, "k_a = 60000000.0", "k_a = 50000000.0")
    assert main(["analyze", "--design", str(path)]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert out == "" and len(lines) == 1 and "q = 1" in lines[0] and "k_a = 5e+07" in lines[0]


@pytest.mark.parametrize("dropped", ["k_a = 60000000.0\n", "locked_stiffness = 60000000.0\n"])
def test_either_stiffness_alone_gives_both(tmp_path: Path, dropped: str) -> None:
    design = load_design(_edited(tmp_path, RPS, dropped, ""))
    for leg in design.legs:
        assert leg.actuator.locked_stiffness == leg.actuator.k_a == 6e7


def test_a_power_law_still_needs_both(tmp_path: Path) -> None:
    """q != 1: the locked stiffness (eq. 21, below the threshold) is its own value."""
    path = _edited(tmp_path, PAPER, "locked_stiffness = 111080.0\n", "")
    with pytest.raises(DesignError, match="locked_stiffness': Field required"):
        load_design(path)


def test_a_power_law_keeps_two_stiffnesses() -> None:
    """The paper's law: 1.1108e5 N/m locked, the tangent above the threshold (eq. 21)."""
    law = ActuatorModel(locked_stiffness=111080.0, k_a=44.75, q=0.225, threshold_displacement=6e-6)
    g_th = 44.75 * 6e-6**0.225
    assert stiffness_from_force(law, 0.5 * g_th) == 111080.0
    delta = (2 * g_th / 44.75) ** (1 / 0.225)
    assert stiffness_from_force(law, 2 * g_th) == pytest.approx(0.225 * 44.75 * delta**-0.775)


# ------------------------------------------------------------------ set by name
@pytest.mark.parametrize("key", ["locked_stiffness", "k_a"])
def test_setting_either_sets_both(key: str) -> None:
    design = load_design(RPS).with_parameters({f"leg1.actuator.{key}": 3e7})
    assert design.legs[0].actuator.locked_stiffness == design.legs[0].actuator.k_a == 3e7
    assert design.legs[1].actuator.locked_stiffness == design.legs[1].actuator.k_a == 6e7


def test_the_unloaded_and_loaded_stiffness_agree() -> None:
    """k_a of leg 1 halved by name: the unloaded K and a 1 mN load use the same 3e7 N/m
    (before: 6e7 unloaded, 3e7 under load), and the 1 mN twist is C w exactly."""
    design = load_design(RPS).with_parameters({"leg1.actuator.k_a": 3e7})
    w = np.array([0.0, 0.0, 0.0, 0.3, -0.2, 1.0])
    curve = deflection_path(design, w, [0.0, 1e-3], method="closed-form")
    np.testing.assert_array_equal(curve.actuator_stiffness[:, 0], [3e7, 3e7])
    c = np.linalg.inv(stiffness_at_pose(design))
    np.testing.assert_allclose(curve.twists[1], 1e-3 * c @ w, rtol=1e-9, atol=1e-20)


def test_a_power_law_sets_only_the_named_one() -> None:
    design = load_design(PAPER).with_parameters({"leg*.actuator.k_a": 50.0})
    assert design.legs[0].actuator.k_a == 50.0
    assert design.legs[0].actuator.locked_stiffness == 111080.0


def test_the_law_made_linear_in_the_same_call_ties_them() -> None:
    """q set to 1 with k_a: the new law is linear, so its locked value follows."""
    design = load_design(PAPER).with_parameters({"actuator.q": 1.0, "actuator.k_a": 2e4})
    assert all(leg.actuator.locked_stiffness == 2e4 for leg in design.legs)


def test_a_law_made_linear_with_two_stiffnesses_is_refused() -> None:
    """q set to 1 alone on the paper's law (locked 1.1108e5, k_a 44.75): the two differ,
    and which one is meant is not ours to guess (taking k_a made the unloaded k_x 770
    times lower than at q = 0.9999): refused naming both; with k_a named too, one
    stiffness."""
    design = load_design(PAPER)
    with pytest.raises(DesignError, match=r"k_a = 44\.75 and locked_stiffness = 111080 differ"):
        design.with_parameters({"actuator.q": 1.0})
    with pytest.raises(DesignError, match=r"^actuator\.q = 1: .*differ, but with q = 1"):
        design.check_value("actuator.q", 1.0)
    linear = design.with_parameters({"actuator.q": 1.0, "actuator.k_a": 2e4})
    assert all(leg.actuator.locked_stiffness == leg.actuator.k_a == 2e4 for leg in linear.legs)


def test_deflect_q_1_alone_is_refused_naming_both(capsys: pytest.CaptureFixture[str]) -> None:
    """``deflect --q 1`` on the paper's law: one line naming both stiffnesses and --k-a
    as the way to give the one; with --k-a it runs."""
    assert main(["deflect", "--mode", "moment", "--max", "0.1", "--step", "0.1", "--q", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("ppm-stiffness: error: --q: ")
    assert "k_a = 44.75 and locked_stiffness = 111080 differ" in err
    argv = ["deflect", "--mode", "moment", "--max", "0.1", "--step", "0.1", "--q", "1"]
    assert main([*argv, "--k-a", "1e5"]) == 0


def test_both_set_differently_are_refused() -> None:
    with pytest.raises(DesignError, match="differ, but with q = 1"):
        load_design(RPS).with_parameters(
            {"leg1.actuator.k_a": 3e7, "leg1.actuator.locked_stiffness": 4e7}
        )


def test_addressed_names_the_twin_only_under_q_1() -> None:
    assert load_design(RPS).addressed("leg2.actuator.locked_stiffness") == [
        "leg2.actuator.locked_stiffness",
        "leg2.actuator.k_a",
    ]
    assert load_design(PAPER).addressed("leg2.actuator.k_a") == ["leg2.actuator.k_a"]


# ------------------------------------------------------------------ every command
def test_vary_either_changes_both_and_both_are_refused() -> None:
    design = load_design(HEXAPOD)
    v = parse_variable("leg*.actuator.k_a=2e7:5e7", design, False)
    assert "leg3.actuator.locked_stiffness" in v.matches
    w = parse_variable("leg*.actuator.locked_stiffness=2e7:5e7", design, False)
    with pytest.raises(InputDataError, match="both set parameter .*one stiffness"):
        check_distinct([v, w])


def test_free_both_is_refused_by_identify_and_calibrate() -> None:
    design = load_design(RPS)
    free = ["leg1.actuator.k_a", "leg*.actuator.locked_stiffness"]
    rows = MeasurementRows(
        np.zeros((2, 6)), np.ones((2, 6)), np.zeros((2, 6)), np.ones((2, 6)) * 1e-6
    )
    with pytest.raises(InputDataError, match="both address 'leg1.actuator.locked_stiffness'"):
        identify(design, rows, free)
    with pytest.raises(InputDataError, match="both set 'leg1.actuator.locked_stiffness'"):
        calibrate(design, stiffness_at_pose(design), free)


def test_a_tolerance_file_naming_both_is_refused() -> None:
    entries = parse_tolerances(
        '["leg*.actuator.locked_stiffness"]\npm = "1%"\n["leg2.actuator.k_a"]\npm = "1%"\n'
    )
    with pytest.raises(InputDataError, match="both address 'leg2.actuator.k_a'"):
        tolerance_variables(load_design(HEXAPOD), entries)


def test_the_shipped_mass_tolerances_vary_both() -> None:
    """examples/identification/hexapod_mass_tolerances.toml varies locked_stiffness
    alone (3 %, tied): a drawn design has k_a equal to it."""
    design = load_design(HEXAPOD)
    variables = tolerance_variables(design, read_tolerances(IDENT / "hexapod_mass_tolerances.toml"))
    z = np.array([1.0 if "actuator" in v.label else 0.0 for v in variables])
    drawn = design_at(design, variables, z)
    for leg in drawn.legs:
        assert leg.actuator.locked_stiffness == leg.actuator.k_a == pytest.approx(3.4e7 * 1.03)


def test_the_shipped_3rps_identification_writes_one_stiffness(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The documented run (docs/identification.md) frees k_a alone: the identified
    design's locked stiffness is the same estimate, and the estimates are the doc's."""
    out = tmp_path / "identified.toml"
    free = "leg1.actuator.k_a,leg2.actuator.k_a,leg3.actuator.k_a,leg*.base_revolute.tilt"
    argv = ["identify", "--design", str(RPS), "--measurements"]
    argv += [str(IDENT / "3rps_measurements.csv"), "--free", f"{free},leg*.guide.lateral"]
    assert main([*argv, "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    estimates = {p["name"]: p["estimate"] for p in doc["parameters"]}
    written = load_design(out)
    for i, printed in enumerate((50.82e6, 66.52e6, 56.74e6)):  # the doc's 4 digits
        k_a = estimates[f"leg{i + 1}.actuator.k_a"]
        assert k_a == pytest.approx(printed, abs=0.005e6)
        assert written.legs[i].actuator.locked_stiffness == written.legs[i].actuator.k_a == k_a
