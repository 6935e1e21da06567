"""Values that are physically implausible are warned about, not passed on silently:
force-displacement data in mm under a metre header (``fit-actuator``), and a
first-order tolerance band that reaches a negative stiffness."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.design import load_design
from ppm_stiffness.fit.band_outputs import POSE_FAILED_VALUE, pose_output
from ppm_stiffness.fit.tolerances import parse_tolerances, tolerance_variables
from ppm_stiffness.fit.uncertainty import LinearisationWarning, propagate
from ppm_stiffness.statics.actuator_fit import ImplausibleDataWarning, read_force_displacement

ROOT = Path(__file__).parents[1]
ACTUATOR_DATA = ROOT / "src/ppm_stiffness/data/actuator_synthetic.csv"
RPR = load_design(ROOT / "examples/3rpr.toml")


def _metre_header(tmp_path: Path) -> Path:
    """The synthetic actuator data (0.01 to 1 mm) under a displacement_m header."""
    text = ACTUATOR_DATA.read_text(encoding="utf-8")
    path = tmp_path / "metres.csv"
    path.write_text(text.replace("displacement_mm,", "displacement_m,"), encoding="utf-8")
    return path


def test_mm_values_under_a_metre_header_are_warned_about(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Fitted as metres they give k_a = 9.52 N/m^q instead of the 44.75 the data were
    made with (a factor 1000^q): the fit runs, with a warning naming the likely
    mistake."""
    path = _metre_header(tmp_path)
    with pytest.warns(ImplausibleDataWarning, match=r"displacements up to 1 m under a"):
        data = read_force_displacement(path)
    assert data.displacement_unit == "m"
    assert main(["fit-actuator", str(path)]) == 0
    out, err = capsys.readouterr()
    assert "k_a = 9.5235" in out
    assert err.count("\n") == 1 and err.startswith("ppm-stiffness: warning: ")
    assert "if the values are in mm, name the column displacement_mm" in err
    # the same values under their right header: no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleDataWarning)
        assert np.max(read_force_displacement(ACTUATOR_DATA).displacement_m) == 1e-3


def test_a_first_order_band_below_zero_stiffness_is_warned_about() -> None:
    """3-RPR half a degree from the orientation where its leg lines meet at P, psi
    within +-1 deg: the first-order k_phi band reaches -14.0 N·m/rad (docs/
    identification.md). Where the band stays positive (home pose, psi +-1 %) there is
    no warning."""
    near = tolerance_variables(RPR, parse_tolerances('["leg*.psi"]\npm = 0.01745\n'))
    out = pose_output(np.array([0.0, 0.0, math.radians(-60.5)]), np.zeros(3))
    with pytest.warns(LinearisationWarning, match=r"use the QMC method") as caught:
        bands = propagate(RPR, near, out, "first-order", lower_limit=POSE_FAILED_VALUE[:39])
    assert bands.lower[0] == pytest.approx(-14.0, abs=0.05)  # the docs' printed value
    assert f"down to {bands.lower[0]:.4g} for a nominal" in str(caught[0].message)
    small = tolerance_variables(RPR, parse_tolerances('["leg*.psi"]\npm = "1%"\n'))
    with warnings.catch_warnings():
        warnings.simplefilter("error", LinearisationWarning)
        home = propagate(
            RPR,
            small,
            pose_output(np.zeros(3), np.zeros(3)),
            "first-order",
            lower_limit=POSE_FAILED_VALUE[:39],
        )
    assert np.all(home.lower[:3] > 0)


def test_analyze_warns_of_a_negative_first_order_bound(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Guide yaw springs (1700 N·m/rad) with sigma = 8500 N·m/rad (500 %, given in
    absolute units: a relative tolerance of 100 % or more is refused): the printed
    first-order bounds of k_phi, k_x, k_y and f1 are negative; a one-line warning says
    the band is meaningless."""
    tol = tmp_path / "tol.toml"
    tol.write_text('["leg*.guide.yaw"]\nsigma = 8500.0\n', encoding="utf-8")
    assert main(["analyze", "--tolerances", str(tol)]) == 0
    out, err = capsys.readouterr()
    assert err.count("\n") == 1
    # k_phi, k_x, k_y and f1 (the built-in design has a mass model: f1 is appended)
    assert "warning: the first-order band of 4 of 40 outputs reaches below its " in err
    assert "the band means nothing there; use the QMC method (--tolerance-method qmc)" in err
