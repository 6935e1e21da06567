"""Tolerance bands on the natural frequencies: masses in tolerance files
(``platform.mass``, ``leg*.<part>.mass``, ``leg*.actuator.carriage_mass``, ...),
``modes --tolerances`` (f1..f6), ``analyze --tolerances`` (f1) and ``map --quantities f1
--tolerances``.

The reference: a design whose only mass is its platform, a solid (its inertia
proportional to its mass), has M proportional to the platform mass m, so every
frequency scales exactly as ``f = f0 sqrt(m0 / m)``. Residuals measured when these
tests were written: first-order bands against the scaling's central difference (the
step FD_STEP of the propagation) 1.1e-13 relative, so 1e-11; QMC bands against the
scaling at the same Sobol points 2e-15, so 1e-12. Its links are massless, so that the
legs' own modes add nothing (with 8 per leg the frequencies equal the condensed ones
exactly, measured): these tests ask for the condensed model, which is cheaper.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from helpers import design_named
from ppm_stiffness.cli import main
from ppm_stiffness.design import Design, design_from_dict, design_to_dict
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.fit.band_outputs import modes_output
from ppm_stiffness.fit.tolerances import (
    parse_tolerances,
    sample_variables,
    tolerance_variables,
)
from ppm_stiffness.fit.uncertainty import FD_STEP, propagate
from ppm_stiffness.poses import home_pose

ROOT = Path(__file__).resolve().parent.parent
HEXAPOD = ROOT / "examples" / "hexapod_6ups.toml"
MASS_TOLERANCES = ROOT / "examples" / "identification" / "hexapod_mass_tolerances.toml"
X = 0.10  # the platform mass's half-width, relative


def _platform_only() -> Design:
    """The built-in 3-PPR with a solid cylinder platform as its only mass."""
    data = design_to_dict(design_named("paper"))
    data["platform"] = {"mass": 0.5, "shape": "cylinder", "radius": 0.06, "height": 0.01}
    for table in data["parts"].values():
        for key in ("mass", "mass_centre", "mass_centre_from", "inertia_transverse"):
            table.pop(key, None)
        table.pop("carriage_mass", None)
    design = design_from_dict(data)
    assert design.has_mass_model
    return design


def _bands(design: Design, text: str, method: str, link_modes: int | None = None) -> Any:
    variables = tolerance_variables(design, parse_tolerances(text))
    output = modes_output(home_pose(design), np.zeros(3), link_modes=link_modes)
    return variables, propagate(design, variables, output, method, 64, 0)


def _spread(h: float = FD_STEP) -> float:
    """2 sigma_f / f0 of the first-order band of ±X on the platform mass: the central
    difference of f(z) / f0 = (1 + X z)^(-1/2) with step h, times sqrt(var z) = 1/sqrt(3)
    (h -> 0: X / sqrt(3), the analytic derivative)."""
    slope = ((1 + X * h) ** -0.5 - (1 - X * h) ** -0.5) / (2 * h)
    return 2 * abs(slope) / np.sqrt(3)


def test_first_order_band_of_a_platform_mass_is_the_analytic_scaling() -> None:
    """±X uniform: the band is f0 (1 -+ spread) for every frequency, with the
    scaling's own central difference (measured 1.1e-13 relative; its limit X / sqrt(3),
    the analytic derivative, differs by 6e-7 of the spread: FD_STEP's truncation)."""
    design = _platform_only()
    _, bands = _bands(design, f'["platform.mass"]\npm = "{X:.0%}"\n', "first-order", 0)
    f0 = bands.nominal
    assert np.allclose(f0, modal_analysis(design, link_modes=0).frequencies, rtol=1e-14)
    assert np.allclose(bands.lower, f0 * (1 - _spread()), rtol=1e-11, atol=0)
    assert np.allclose(bands.upper, f0 * (1 + _spread()), rtol=1e-11, atol=0)
    assert _spread() == pytest.approx(X / np.sqrt(3), rel=1e-6)


def test_qmc_band_of_a_platform_mass_is_the_scaling_at_the_sobol_points() -> None:
    design = _platform_only()
    variables, bands = _bands(design, f'["platform.mass"]\npm = "{X:.0%}"\n', "qmc", 0)
    z, _ = sample_variables(variables, 64, 0)
    expected = bands.nominal[None, :] / np.sqrt(1.0 + X * z[:, :1])  # (64, 6)
    lower, upper = np.percentile(expected, (5.0, 95.0), axis=0)
    assert np.allclose(bands.lower, lower, rtol=1e-12, atol=0)
    assert np.allclose(bands.upper, upper, rtol=1e-12, atol=0)


def test_qmc_band_lies_within_the_extreme_designs_by_brute_force() -> None:
    """The hexapod with its legs' masses (no exact scaling): the QMC band of f1 from
    ±X on the platform mass lies between f1 of the two extreme designs, evaluated on
    their own, and reaches most of the way to them (the 5th-95th percentile of a uniform
    draw: 90 % of the width). Condensed (with link modes the hexapod's f1 is a strut
    mode that the platform's mass hardly moves)."""
    design = design_named("hexapod_6ups")
    _, bands = _bands(design, f'["platform.mass"]\npm = "{X:.0%}"\n', "qmc", link_modes=0)
    m0 = design.parameter("platform.mass")
    heavy, light = (
        modal_analysis(
            design.with_parameters({"platform.mass": m0 * (1 + s)}), link_modes=0
        ).to_dict()["frequencies"][0]
        for s in (X, -X)
    )
    f0 = bands.nominal[0]
    assert heavy < bands.lower[0] < f0 < bands.upper[0] < light
    assert bands.upper[0] - bands.lower[0] > 0.8 * (light - heavy)


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict[str, Any]:
    assert main(argv) == 0
    return dict(json.loads(capsys.readouterr().out))


def test_modes_and_analyze_give_the_same_f1_band(capsys: pytest.CaptureFixture[str]) -> None:
    """The shipped mass tolerance file on the hexapod: ``modes`` bands f1..f6 and
    ``analyze`` f1 (the same propagation: equal), every mass variable ranked."""
    common = ["--design", str(HEXAPOD), "--tolerances", str(MASS_TOLERANCES), "--json"]
    modes = _json(capsys, ["modes", *common])["uncertainty"]
    analyze = _json(capsys, ["analyze", *common])["uncertainty"]
    assert list(modes["quantities"]) == [f"f{j}" for j in range(1, 7)]
    for key in ("nominal", "lower", "upper", "std"):
        assert analyze["quantities"]["f1"][key] == pytest.approx(
            modes["quantities"]["f1"][key], rel=1e-12
        )
    ranked = {r["parameter"] for r in modes["sensitivity"]["f1"]}
    assert ranked == {
        "platform.mass",
        "leg*.rod.mass",
        "leg*.cylinder.mass",
        "leg*.actuator.locked_stiffness",
    }
    f = modes["quantities"]["f3"]
    assert f["lower"] < f["nominal"] < f["upper"] and f["unit"] == "Hz"


def test_the_modes_band_is_of_the_frequencies_the_table_shows(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``modes --link-modes N --tolerances``: the bands' nominal values are the
    frequencies ``modes`` prints with N modes per leg, bit for bit (the same
    modal_analysis call; the bands were of the default 8 modes whatever N)."""
    common = ["--design", str(HEXAPOD), "--tolerances", str(MASS_TOLERANCES), "--json"]
    for modes in (0, 2):
        doc = _json(capsys, ["modes", *common, "--link-modes", str(modes)])
        nominal = [doc["uncertainty"]["quantities"][f"f{j}"]["nominal"] for j in range(1, 7)]
        assert nominal == doc["frequencies"]


def test_f1_band_map(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``map --quantities f1 --tolerances`` on the platform-only design: a band of f1
    over the grid whose relative spread is the scaling's (:func:`_spread`) at every
    point."""
    from ppm_stiffness.design import dump_design

    tol = tmp_path / "tol.toml"
    tol.write_text(f'["platform.mass"]\npm = "{X:.0%}"\n', encoding="utf-8")
    design = tmp_path / "design.toml"
    design.write_text(dump_design(_platform_only()), encoding="utf-8")
    argv = ["map", "--design", str(design), "--grid", "4", "--quantities", "f1"]
    argv += ["--link-modes", "0"]  # massless legs: no own modes either way
    doc = _json(capsys, [*argv, "--tolerances", str(tol), "--json"])
    summary = doc["uncertainty"]["summary"]["f1"]
    assert summary["unit"] == "Hz"
    for key in ("median_relative_spread", "max_relative_spread"):
        assert summary[key] == pytest.approx(2 * _spread(), rel=1e-10)


def test_a_mass_key_on_a_design_without_one_is_named(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    tol = tmp_path / "tol.toml"
    tol.write_text('["leg*.distal.carriage_mass"]\npm = "10%"\n', encoding="utf-8")
    assert main(["modes", "--tolerances", str(tol)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "unknown design parameter 'leg*.distal.carriage_mass'" in err
