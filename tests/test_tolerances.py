"""Tolerance files, QMC samples, first-order and QMC bands, sensitivity, and
``--tolerances`` on the commands."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import default_design, load_design
from ppm_stiffness.fit.band_outputs import POSE_FAILED_VALUE, pose_output
from ppm_stiffness.fit.tolerances import (
    design_at,
    parse_tolerances,
    sample_variables,
    tolerance_variables,
)
from ppm_stiffness.fit.uncertainty import propagate

ROOT = Path(__file__).parents[1]
PPR = default_design()
RPR = load_design(ROOT / "examples/3rpr.toml")


# ------------------------------------------------------------------ the file
def test_entries_globs_ties_and_nesting() -> None:
    text = """
["leg*.guide.yaw"]
sigma = "5%"
["leg*.actuator.locked_stiffness"]
pm = "10%"
tied = true
[leg3.distal]
young_modulus = { pm = 1e10 }
"""
    variables = tolerance_variables(PPR, parse_tolerances(text))
    labels = [v.label for v in variables]
    assert labels == [
        "leg1.guide.yaw",
        "leg2.guide.yaw",
        "leg3.guide.yaw",
        "leg*.actuator.locked_stiffness",
        "leg3.distal.young_modulus",
    ]
    yaw, act, e = variables[0], variables[3], variables[4]
    assert yaw.distribution == "normal" and yaw.width[0] == pytest.approx(0.05 * 1700)
    assert act.distribution == "uniform" and len(act.names) == 3
    np.testing.assert_allclose(act.width, 0.1 * 1.1108e5)
    assert e.width[0] == 1e10
    # a tied draw moves every match by the same relative amount
    moved = design_at(PPR, variables, np.array([0, 0, 0, -0.5, 0]))
    for i in (1, 2, 3):
        assert moved.parameter(f"leg{i}.actuator.locked_stiffness") == pytest.approx(
            0.95 * 1.1108e5
        )


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('["leg*.guide.yaw"]\npm = -0.1\n', r"leg\*.guide.yaw.pm = -0.1 must be finite and >= 0"),
        ('["leg*.guide.yaw"]\nsigma = "-5%"\n', r"sigma = '-5%' must be finite and >= 0"),
        ('["leg*.guide.yaw"]\npm = "ten%"\n', "is not a percentage"),
        (
            '["leg1.guide.yaw"]\npm = "150%"\n',
            r"leg1\.guide\.yaw\.pm = '150%': a relative tolerance of 100 % or more reaches "
            r"zero .*below 100 % \(did you mean \"1\.5%\"\?\)$",
        ),
        ('["leg1.guide.yaw"]\nsigma = "100%"\n', r"sigma = '100%': a relative tolerance"),
        ('["leg*.guide.yaw"]\npm = "10"\n', "not a number or a percentage"),
        ('["leg*.guide.yaw"]\npm = 0.1\nsigma = 0.1\n', "exactly one of pm and sigma"),
        ('["leg*.guide.yaw"]\npm = 0.1\nspread = 1\n', "guide.yaw.spread: unknown key"),
        ('["leg*.guide.yaw"]\npm = 0.1\ntied = "yes"\n', "must be true or false"),
        ("guide = 3\n", "expected a table"),
        ("pm = [\n", "not valid TOML"),
        ("", "no tolerance given"),
    ],
)
def test_bad_tolerance_files_name_the_key(text: str, match: str) -> None:
    with pytest.raises(InputDataError, match=match):
        parse_tolerances(text)


def test_unknown_and_overlapping_parameters() -> None:
    with pytest.raises(DesignError, match="unknown design parameter 'leg1.guide.yawn'"):
        tolerance_variables(PPR, parse_tolerances('["leg1.guide.yawn"]\npm = 1.0\n'))
    text = '["leg*.guide.yaw"]\npm = 1.0\n["leg2.guide.yaw"]\npm = 2.0\n'
    with pytest.raises(InputDataError, match="both address 'leg2.guide.yaw'"):
        tolerance_variables(PPR, parse_tolerances(text))


# ------------------------------------------------------------------ samples
@pytest.mark.parametrize(
    ("spec", "below"),
    [
        ('sigma = "60%"', 0.0478),  # P(N(1, 0.6) <= 0) = Phi(-1/0.6)
        ("pm = 2550.0", 1.0 / 6.0),  # 150 % of 1700 N·m/rad: P(U(-0.5, 2.5) <= 0)
    ],
)
def test_values_that_would_make_a_stiffness_negative_are_redrawn_and_counted(
    spec: str, below: float
) -> None:
    """1024 Sobol points: the count of redrawn values is the probability mass below
    zero to within 1 % of the samples (Sobol's stratification; measured within 0.3 %),
    and every drawn stiffness is > 0 with the distribution's shape above zero kept."""
    variables = tolerance_variables(PPR, parse_tolerances(f'["leg1.guide.yaw"]\n{spec}\n'))
    z, redrawn = sample_variables(variables, 1024, seed=3)
    assert abs(redrawn / 1024 - below) < 0.01
    values = variables[0].nominal[0] + variables[0].width[0] * z[:, 0]
    assert np.all(values > 0)


# ------------------------------------------------------------------ bands
def test_first_order_and_qmc_agree_for_small_tolerances() -> None:
    """3-RPR at its home pose, each leg's platform joint angle psi within +-1 %
    (uniform, independent): k_phi, k_x, k_y are nearly linear in them, so the QMC
    standard deviation (64 Sobol samples) equals the first-order sigma to 5 %
    (measured 1 %), and the 5th-95th percentile band lies inside the first-order
    +-2 sigma band and beyond +-1.2 sigma (a sum of uniforms: about +-1.6 sigma)."""
    variables = tolerance_variables(RPR, parse_tolerances('["leg*.psi"]\npm = "1%"\n'))
    out = pose_output(np.zeros(3), np.zeros(3))
    fo = propagate(RPR, variables, out, "first-order")
    qmc = propagate(RPR, variables, out, "qmc", samples=64)
    assert qmc.failed == 0 and qmc.redrawn == 0
    for i in range(3):
        assert abs(qmc.std[i] / fo.std[i] - 1) < 0.05
        for bound in (qmc.lower[i], qmc.upper[i]):
            assert 1.2 * fo.std[i] < abs(bound - fo.nominal[i]) < 2 * fo.std[i]


def test_first_order_and_qmc_differ_near_a_singularity() -> None:
    """3-RPR turned to phi = -60.5 deg, half a degree from the orientation where the
    three leg lines meet at P (k_phi -> 0, every moment arm m_i -> 0: k_phi ~ sum k
    m_i^2). Within psi +-1 deg the moment arms change sign: k_phi is quadratic, not
    linear. First order gives an impossible negative lower bound and misses the upper
    tail; QMC is several times wider above and counts the samples that became
    singular (measured: fo [-14.0, 30.8], QMC [12.9, 91.3] over the successful samples,
    7 of 64 singular). A singular sample has k_phi = 0: ranked there, more than 5 % of
    the samples sit at 0, so the 5th percentile is 0 (review finding: leaving them out
    reported 12.9)."""
    variables = tolerance_variables(RPR, parse_tolerances('["leg*.psi"]\npm = 0.01745\n'))
    out = pose_output(np.array([0.0, 0.0, math.radians(-60.5)]), np.zeros(3))
    fo = propagate(RPR, variables, out, "first-order")
    left_out = propagate(RPR, variables, out, "qmc", samples=64)
    qmc = propagate(RPR, variables, out, "qmc", samples=64, failed_value=POSE_FAILED_VALUE[:39])
    assert fo.lower[0] < 0 < left_out.lower[0]
    assert "successful samples only" in left_out.label
    assert qmc.failed == left_out.failed and qmc.failed / 64 > 0.05
    assert qmc.lower[0] == 0.0
    assert qmc.upper[0] > 2 * fo.upper[0]


def test_sensitivity_shares() -> None:
    """Shares sum to 1; a tolerance the output does not depend on has share 0 (the
    3-PPR's in-plane k_x does not see leg 1's guide lateral stiffness: its lateral
    spring is along the passive rod); the largest share of k_x is leg 3's (the leg
    along x)."""
    text = '["leg1.guide.lateral"]\npm = "10%"\n["leg*.actuator.locked_stiffness"]\npm = "10%"\n'
    variables = tolerance_variables(PPR, parse_tolerances(text))
    fo = propagate(PPR, variables, pose_output(np.zeros(3), np.zeros(3)), "first-order")
    share = fo.sensitivity()
    np.testing.assert_allclose(share[:, :3].sum(axis=0), 1.0, rtol=1e-12)
    ranking = dict(fo.ranking(1))
    assert ranking["leg1.guide.lateral"] < 1e-9
    assert fo.ranking(1)[0][0] == "leg3.actuator.locked_stiffness"


# ------------------------------------------------------------------ commands
TOL = """
["leg*.guide.yaw"]
sigma = "5%"
["leg*.actuator.locked_stiffness"]
pm = "10%"
tied = true
"""


def test_commands_with_tolerances(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    tol = tmp_path / "tol.toml"
    tol.write_text(TOL)
    assert main(["analyze", "--json", "--tolerances", str(tol)]) == 0
    unc = json.loads(capsys.readouterr().out)["uncertainty"]
    k_x = unc["quantities"]["k_x"]
    assert k_x["lower"] < k_x["nominal"] < k_x["upper"] and unc["band"] == "±2σ, first order"
    assert [r["parameter"] for r in unc["sensitivity"]["k_x"]][
        0
    ] == "leg*.actuator.locked_stiffness"
    plot = tmp_path / "d.png"
    args = ["deflect", "--json", "--tolerances", str(tol), "--tolerance-method", "qmc", "--method"]
    args.append("closed-form")
    assert main([*args, "--samples", "8", "--plot", str(plot), "--max", "4", "--step", "2"]) == 0
    unc = json.loads(capsys.readouterr().out)["uncertainty"]
    assert unc["band"].startswith("5th-95th percentile, QMC (8 samples)")
    assert len(unc["twists_lower"]) == 3 and plot.stat().st_size > 0
    fig = tmp_path / "m.png"
    assert main(["map", "--grid", "6", "--tolerances", str(tol), "--out", str(fig)]) == 0
    out = capsys.readouterr().out
    assert "median spread" in out and "sensitivity" in out and fig.stat().st_size > 0


@pytest.mark.parametrize(
    "text",
    [
        '["leg*.guide.yaw"]\npm = -1\n',
        '["leg*.guide.yaw"]\npm = "x"\n',
        '["leg*.guide.yaw"]\npm = "150%"\n',
    ],
)
def test_bad_tolerance_file_exit_2_nothing_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str
) -> None:
    tol = tmp_path / "tol.toml"
    tol.write_text(text)
    for argv in (
        ["deflect", "--csv", str(tmp_path / "d.csv")],
        ["map", "--grid", "4", "--out", str(tmp_path / "m.png")],
        ["report", "--grid", "4", "--out", str(tmp_path / "rep")],
        ["analyze"],
    ):
        assert main([*argv, "--tolerances", str(tol)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "guide.yaw.pm" in err[0]
    assert list(tmp_path.iterdir()) == [tol]
