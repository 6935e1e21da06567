"""Fitting the actuator law G = k_a delta^q (eq. 20) to force-displacement data."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.statics.actuator_fit import (
    fit_power_law,
    power_law_force,
    read_force_displacement,
)

#: The paper's law (eq. 20 text): the values the shipped synthetic file was made from.
K_A, Q = 44.75, 0.225
#: Force noise of the shipped synthetic file [N] (stated in its header).
SIGMA = 0.1


def shipped() -> Path:
    return Path(str(resources.files("ppm_stiffness").joinpath("data/actuator_synthetic.csv")))


def test_shipped_file_is_labelled_synthetic_and_states_its_generator() -> None:
    data = read_force_displacement(shipped())
    text = " ".join(data.comments)
    assert "SYNTHETIC" in text
    assert "k_a = 44.75" in text and "q = 0.225" in text and "seed=3" in text
    assert data.displacement_unit == "mm"
    assert data.displacement_m.size == 30
    assert data.displacement_m.min() == pytest.approx(1e-5)
    assert data.displacement_m.max() == pytest.approx(1e-3)


def test_fit_recovers_generating_values_on_shipped_data() -> None:
    """The fit of the shipped file is consistent with k_a = 44.75, q = 0.225: each
    within 2 standard errors, and jointly (the estimates are ~0.99 correlated) inside
    the 95% confidence ellipse. R^2 on the force and the residual std match the
    stated noise (chi-square with 28 dof, 99% range)."""
    data = read_force_displacement(shipped())
    fit = fit_power_law(data.displacement_m, data.force_n)
    z_k = (fit.k_a - K_A) / fit.k_a_std
    z_q = (fit.q - Q) / fit.q_std
    assert abs(z_k) < 2 and abs(z_q) < 2
    r = fit.correlation
    mahalanobis2 = (z_k**2 - 2 * r * z_k * z_q + z_q**2) / (1 - r**2)
    assert mahalanobis2 < stats.chi2.ppf(0.95, 2)
    assert fit.r_squared > 0.99
    lo, hi = np.sqrt(stats.chi2.ppf([0.005, 0.995], fit.n - 2) / (fit.n - 2))
    assert lo * SIGMA < fit.residual_std < hi * SIGMA
    assert fit.n == 30


def test_noise_free_data_give_the_law_exactly() -> None:
    d = np.geomspace(1e-5, 1e-3, 12)
    fit = fit_power_law(d, power_law_force(d, K_A, Q))
    assert fit.k_a == pytest.approx(K_A, rel=1e-9)
    assert fit.q == pytest.approx(Q, rel=1e-9)
    assert fit.r_squared == pytest.approx(1.0, abs=1e-12)


def test_odd_law_with_pulls_and_pushes() -> None:
    d = np.concatenate([-np.geomspace(1e-5, 1e-3, 8), [0.0], np.geomspace(2e-5, 8e-4, 7)])
    fit = fit_power_law(d, power_law_force(d, 30.0, 0.5))
    assert (fit.k_a, fit.q) == (pytest.approx(30.0, rel=1e-9), pytest.approx(0.5, rel=1e-9))


def test_standard_errors_have_their_nominal_coverage() -> None:
    """Over 300 seeded synthetic data sets (additive Gaussian force noise) the
    interval estimate +- 1 standard error covers the true q about 68% of the time
    (binomial 3-sigma band for 300 draws: +-0.08). A log-log straight-line fit
    would be biased; this checks the nonlinear least squares and its covariance."""
    rng = np.random.default_rng(2024)
    d = np.geomspace(1e-5, 1e-3, 30)
    g0 = power_law_force(d, K_A, Q)
    hits_q = hits_k = 0
    n = 300
    for _ in range(n):
        fit = fit_power_law(d, g0 + rng.normal(0.0, SIGMA, d.size))
        hits_q += abs(fit.q - Q) < fit.q_std
        hits_k += abs(fit.k_a - K_A) < fit.k_a_std
    assert 0.60 < hits_q / n < 0.76
    assert 0.60 < hits_k / n < 0.76


def test_read_metres_equals_millimetres(tmp_path: Path) -> None:
    mm = tmp_path / "mm.csv"
    m = tmp_path / "m.csv"
    mm.write_text("# test\nforce_N,displacement_mm\n3.0,0.01\n5.0,0.1\n9.0,1.0\n")
    m.write_text("displacement_m,force_N\n1e-5,3.0\n1e-4,5.0\n1e-3,9.0\n")
    a, b = read_force_displacement(mm), read_force_displacement(m)
    np.testing.assert_allclose(a.displacement_m, b.displacement_m, rtol=1e-12)
    np.testing.assert_array_equal(a.force_n, b.force_n)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "no header row and no data"),  # empty
        ("# only a comment\n", "no header row and no data"),
        # no units in the header
        ("displacement,force\n0.1,5\n", "the header row must name one displacement column"),
        ("displacement_mm,force_N\n0.1,abc\n", r"line 2: not numeric: \['0.1', 'abc'\]"),
        ("displacement_mm,force_N\n0.1\n", "line 2: 1 fields, the header has 2"),  # short row
        (  # two displacements
            "displacement_mm,displacement_m,force_N\n0.1,1e-4,5\n",
            "the header row must name one displacement column",
        ),
        ("displacement_mm,force_N\nnan,5\n", "displacements and forces must be finite"),
    ],
)
def test_malformed_csv_raises(tmp_path: Path, text: str, message: str) -> None:
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(InputDataError, match=message):
        read_force_displacement(p)


def test_missing_file_raises(tmp_path: Path) -> None:
    with pytest.raises(InputDataError, match="not found"):
        read_force_displacement(tmp_path / "nope.csv")


@pytest.mark.parametrize(
    ("d", "g", "message"),
    [
        ([1e-5, 1e-4], [3.0, 5.0], "needs at least 3 points"),  # too few points
        ([1e-5, 1e-5, 1e-5], [3.0, 3.1, 2.9], "at least 2 distinct nonzero displacements"),
        ([1e-5, 1e-4, 1e-3], [3.0, 5.0], r"equal length, got \(3,\) and \(2,\)"),
        ([1e-5, np.inf, 1e-3], [3.0, 5.0, 9.0], "displacements and forces must be finite"),
    ],
)
def test_bad_arrays_raise(d: list[float], g: list[float], message: str) -> None:
    with pytest.raises(InputDataError, match=message):
        fit_power_law(d, g)
