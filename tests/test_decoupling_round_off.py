"""A K that is decoupled already (K_rt round-off) is reported so (issue 19, item 3).

The residual coupling ``||K_rt + D K_tt|| / ||K_rt||`` divides round-off by round-off
on the symmetric designs at their home pose (K_rt ~ 1e-12 N against K_rr ~ 1e3 N·m/rad,
K_tt ~ 1e5 N/m). Below ``DECOUPLED_TOLERANCE`` (one named constant) the library says
``already_decoupled``, shifts nothing and reports a residual of 0; the CLI prints
"n/a (already decoupled ...)", JSON carries the flag, the report says so and the
deflection picture draws round-off as 0.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from helpers import ROOT, design_named, example_designs, is_planar, rotational_symmetry
from ppm_stiffness.analysis import analyze_design
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import stiffness_b_from_stiffness_a
from ppm_stiffness.core.decoupling import (
    DECOUPLED_TOLERANCE,
    Method,
    coupling_ratio,
    decouple,
)
from ppm_stiffness.model import stiffness_at_pose, workspace_centre

#: Planar examples with a 3-fold or higher symmetry: decoupled at their centre.
SYMMETRIC = example_designs(lambda d: is_planar(d) and rotational_symmetry(d) >= 3)


def home_stiffness(name: str) -> np.ndarray:
    design = design_named(name)
    return stiffness_at_pose(design, workspace_centre(design))


def coupled(ratio: float) -> np.ndarray:
    """A positive definite K with ``coupling_ratio(K) == ratio`` exactly: a diagonal K
    turned by a rotation (K_rt = 0) plus a coupling block of the chosen size."""
    rng = np.random.default_rng(4)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))
    k = stiffness_b_from_stiffness_a(np.diag([800.0, 900.0, 150.0, 5e4, 6e4, 2e5]), q, np.zeros(3))
    k = 0.5 * (k + k.T)
    k[:3, 3:] = k[3:, :3] = 0.0
    c = rng.normal(size=(3, 3))
    scale = math.sqrt(np.linalg.norm(k[:3, :3]) * np.linalg.norm(k[3:, 3:]))
    k[:3, 3:] = ratio * scale * c / np.linalg.norm(c)
    k[3:, :3] = k[:3, 3:].T
    return k


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_both_sides_of_the_tolerance(factor: float) -> None:
    k = coupled(factor * DECOUPLED_TOLERANCE)
    assert coupling_ratio(k) == pytest.approx(factor * DECOUPLED_TOLERANCE, rel=1e-12)
    methods: tuple[Method, ...] = ("paper", "least-squares")
    for method in methods:
        dec = decouple(k, method)
        assert dec.already_decoupled == (factor < 1)
        if factor < 1:
            assert dec.residual_coupling == 0.0
            np.testing.assert_array_equal(dec.d, np.zeros(3))
            np.testing.assert_array_equal(dec.K_rr, k[:3, :3])
        else:  # a real (if small) coupling: the shift is computed and reported
            assert dec.residual_coupling > 0.0
            assert np.linalg.norm(dec.d) > 0.0


@pytest.mark.parametrize("name", SYMMETRIC)
def test_symmetric_examples_are_already_decoupled(name: str) -> None:
    k = home_stiffness(name)
    assert coupling_ratio(k) <= DECOUPLED_TOLERANCE
    dec = decouple(k, "paper")
    assert dec.already_decoupled and dec.residual_coupling == 0.0
    # nothing was shifted: K'_rr is K_rr
    np.testing.assert_array_equal(dec.K_rr, k[:3, :3])


def test_the_paper_design_is_coupled() -> None:
    # the built-in 3-PPR: ratio 0.33, far above the tolerance; residuals as docs/model.md
    k = home_stiffness("paper")
    assert coupling_ratio(k) > 1e6 * DECOUPLED_TOLERANCE
    dec = decouple(k, "paper")
    assert not dec.already_decoupled and dec.residual_coupling > 1.0


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def test_cli_says_n_a_and_json_carries_the_flag(capsys: pytest.CaptureFixture[str]) -> None:
    design = str(ROOT / "examples" / "redundant_4ppr.toml")
    text = _run(capsys, "analyze", "--design", design)
    assert text.count("residual coupling: n/a (already decoupled") == 2
    data = json.loads(_run(capsys, "analyze", "--design", design, "--json"))
    for key in ("decoupling", "decoupling_least_squares"):
        assert data[key]["already_decoupled"] is True
        assert data[key]["residual_coupling"] == 0.0
    data = json.loads(_run(capsys, "analyze", "--json"))  # the paper's: coupled
    assert data["decoupling"]["already_decoupled"] is False
    assert data["decoupling"]["residual_coupling"] > 1.0
    assert "n/a" not in _run(capsys, "analyze")


def test_report_says_n_a() -> None:
    from ppm_stiffness.visuals.report import _decoupling_section

    design = design_named("symmetric_3ppr")
    html = _decoupling_section(analyze_design(design).to_dict(), "unloaded")
    assert html.count("n/a (already decoupled") == 2
    assert "residual_coupling" not in html  # no traced number for it
    html = _decoupling_section(analyze_design(design_named("paper")).to_dict(), "unloaded")
    assert "already decoupled" not in html and "unloaded/decoupling/residual_coupling" in html


def test_round_off_components_are_drawn_as_zero() -> None:
    from ppm_stiffness.visuals.deflection import round_off_as_zero

    twist = np.array([[0.0, 0.0, 1e-3, 1e-4, 2e-4, 0.0]])  # rad, m
    # a rotation (length-balanced: times 0.1 m) just below and just above the tolerance
    # of the largest component, 2e-4 m
    for factor, kept in ((0.5, False), (2.0, True)):
        t = twist.copy()
        t[0, 2] = factor * DECOUPLED_TOLERANCE * 2e-4 / 0.1
        out = round_off_as_zero(t)
        assert (out[0, 2] != 0.0) == kept
        np.testing.assert_array_equal(out[0, 3:], t[0, 3:])


def test_deflection_picture_of_a_symmetric_design_shows_zero_rotation() -> None:
    pytest.importorskip("matplotlib")
    from ppm_stiffness.statics.deflection import deflection_curve
    from ppm_stiffness.visuals.deflection import plot_deflection_curves

    design = design_named("redundant_4ppr")
    curve = deflection_curve(design, "planar-force", np.linspace(0.0, 10.0, 6))
    assert np.max(np.abs(curve.twists[:, 2])) < 1e-15  # round-off rotation [rad]
    fig = plot_deflection_curves(curve)
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("φz")]
    np.testing.assert_array_equal(line.get_ydata(), np.zeros(6))
    fig = plot_deflection_curves(deflection_curve(design_named("paper"), "planar-force", [0, 5]))
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("φz")]
    assert np.abs(line.get_ydata()[-1]) > 1e-3  # deg: the paper's coupled design turns
