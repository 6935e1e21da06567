"""Identification of element stiffnesses from platform deflections (fit/identify.py).

Synthetic data from designs whose element stiffnesses differ from the catalogue by
known factors, on the paper's 3-PPR and on the 3-RPR example: exact recovery from
noise-free data, 1-sigma coverage over seeded noisy repetitions, 1/sqrt(n) shrinking,
identifiability, and the prediction against ``deflect``'s."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.fit.identify import (
    IdentifiabilityWarning,
    MeasurementRows,
    identify,
    measurement_rows,
    predict_twists,
)
from ppm_stiffness.model import workspace_centre
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.deflection import deflection_path
from ppm_stiffness.statics.measurements import read_measurements

ROOT = Path(__file__).parents[1]
PPR = default_design()
RPR = load_design(ROOT / "examples/3rpr.toml")

#: In-plane wrenches (m_x, m_y, m_z, f_x, f_y, f_z) per unit; scaled per design so that
#: the 3-PPR's actuators stay locked (leg forces below their 2.99 N threshold).
IN_PLANE = np.array(
    [[0, 0, 0, 1.0, 0, 0], [0, 0, 0, 0, 1.0, 0], [0, 0, 0.03, 0, 0, 0], [0, 0, 0.02, 1, -1, 0]]
)
#: Out-of-plane wrenches (vertical force, tilting moments).
OUT_OF_PLANE = np.array([[0, 0, 0, 0, 0, 5.0], [0.2, 0, 0, 0, 0, 0], [0, 0.2, 0, 0, 0, 0]])


def _rows(
    design: Design,
    truth: Design,
    wrenches: np.ndarray,
    offsets: list[tuple[float, float, float]],
    sigma: list[float],
) -> MeasurementRows:
    """Noise-free rows of ``truth`` at the design's centre + offsets [m, m, rad]; the
    components with a NaN sigma are not measured."""
    c = workspace_centre(design)
    poses = np.array([c + off for off in offsets for _ in wrenches])
    w = np.tile(wrenches, (len(offsets), 1))
    sig = np.tile(np.array(sigma, dtype=float), (len(poses), 1))
    t = np.where(np.isfinite(sig), predict_twists(truth, poses, w), np.nan)
    return MeasurementRows(poses, w, t, sig)


def _perturbed(design: Design, factors: dict[str, float]) -> tuple[Design, dict[str, float]]:
    truth = {n: design.parameter(n) * f for n, f in factors.items()}
    return design.with_parameters(truth), truth


# ------------------------------------------------------------------ the prediction
@pytest.mark.parametrize("load", [2.0, 9.0])  # below and above the actuator threshold
def test_prediction_is_what_deflect_computes(load: float) -> None:
    """One row, the same pose and wrench: identify's prediction and deflect's
    integrated load path (an independent solution: the tangent model integrated
    with DOP853 at rtol 1e-10) agree to 1e-8 relative (measured: 4e-16 with the
    actuators locked, 1.5e-11 with them powered)."""
    pose = workspace_centre(PPR) + [0.004, -0.003, 0.02]
    w_hat = np.array([0.0, 0.0, 0.01, 0.6, 0.8, 0.5])
    curve = deflection_path(PPR, w_hat, [0.0, load], pose, "integrate", tool_point=np.zeros(3))
    mine = predict_twists(PPR, pose[None, :], load * w_hat[None, :])[0]
    scale = np.max(np.abs(curve.twists[-1]))
    assert np.max(np.abs(mine - curve.twists[-1])) <= 1e-8 * scale


# ------------------------------------------------------------------ recovery
def test_noise_free_recovery_on_the_3ppr() -> None:
    """Five element stiffnesses of the paper's 3-PPR (a tied glob among them) changed
    by 10-20 %; in- and out-of-plane loads large enough to power the actuators:
    recovered to 1e-11 relative (measured: below 1e-13; the issue asks 1e-6)."""
    factors = {
        "leg1.guide.yaw": 1.2,
        "leg2.guide.yaw": 0.85,
        "leg3.distal.young_modulus": 1.1,
        "leg1.proximal.young_modulus": 0.9,
        "leg*.actuator.locked_stiffness": 1.15,
    }
    truth_design, truth = _perturbed(PPR, factors)
    wrenches = np.vstack([5 * IN_PLANE, OUT_OF_PLANE])
    rows = _rows(
        PPR, truth_design, wrenches, [(0, 0, 0), (-0.005, -0.005, 0.05)], [1e-5] * 3 + [1e-6] * 3
    )
    result = identify(PPR, rows, list(factors))
    expected = np.array([truth[n] for n in result.names])
    np.testing.assert_allclose(result.values, expected, rtol=1e-11)
    assert result.weighted_rms < 1e-6
    assert result.design.parameter("leg3.actuator.locked_stiffness") == pytest.approx(
        truth["leg*.actuator.locked_stiffness"], rel=1e-11
    )


def test_noise_free_recovery_on_the_3rpr() -> None:
    """3-RPR example: the three ball-screw stiffnesses (k_a, linear law) and the tied
    base-bearing tilt and rod modulus, recovered to 1e-11 relative (measured: below
    1e-13; the issue asks 1e-6)."""
    factors = {
        "leg1.actuator.k_a": 1.2,
        "leg2.actuator.k_a": 0.8,
        "leg3.actuator.k_a": 1.1,
        "leg*.base_revolute.tilt": 0.9,
        "leg*.distal.young_modulus": 1.1,
    }
    truth_design, truth = _perturbed(RPR, factors)
    wrenches = np.vstack([100 * IN_PLANE, 10 * OUT_OF_PLANE])
    rows = _rows(
        RPR, truth_design, wrenches, [(0, 0, 0), (0.01, 0.0, 0.0)], [1e-7] * 3 + [1e-8] * 3
    )
    result = identify(RPR, rows, list(factors))
    expected = np.array([truth[n] for n in result.names])
    np.testing.assert_allclose(result.values, expected, rtol=1e-11)


# ------------------------------------------------------------------ uncertainty
CASES = {
    # design, free (the three actuators), in-plane load scale, sigma (phi_z, x, y)
    "3-PPR": (PPR, "leg{}.actuator.locked_stiffness", 1.0, (2e-5, 3e-7, 3e-7)),
    "3-RPR": (RPR, "leg{}.actuator.k_a", 100.0, (1e-7, 2e-8, 2e-8)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_one_sigma_intervals_cover_the_truth_about_68_percent(case: str) -> None:
    """100 seeded repetitions of Gaussian noise on in-plane data (4 rows at one pose,
    actuators locked: the twist is exactly linear in the compliances, so the first
    stage gives the least-squares solution and each fit is fast: 0.09 s). The 1-sigma
    intervals of the three actuator stiffnesses (300 intervals) cover the truth in
    60-76 % of the cases (68.3 % expected; the binomial 1-sigma of 300 draws is 2.7 %).
    Measured: 67.7 % (3-PPR), 71.3 % (3-RPR); RMS of error / sigma 0.95 and 0.94."""
    design, pattern, scale, sig = CASES[case]
    free = [pattern.format(i) for i in (1, 2, 3)]
    truth_design, truth = _perturbed(design, dict(zip(free, (1.2, 0.8, 1.1), strict=True)))
    sigma = [math.nan, math.nan, *sig, math.nan]
    base = _rows(design, truth_design, scale * IN_PLANE, [(0, 0, 0)], sigma)
    expected = np.array([truth[n] for n in free])
    rng = np.random.default_rng(2024)
    covered = 0
    errors = []
    for _ in range(100):
        noise = rng.normal(size=base.twists.shape) * np.nan_to_num(base.sigmas)
        result = identify(design, base.with_twists(base.twists + noise), free)
        covered += int(np.sum(np.abs(result.values - expected) <= result.standard_errors))
        errors.append((result.values - expected) / result.standard_errors)
    assert 0.60 <= covered / 300 <= 0.76
    # the standard errors are the spread of the estimates: RMS of error / sigma near 1
    assert 0.85 < float(np.sqrt(np.mean(np.square(errors)))) < 1.15


@pytest.mark.parametrize("case", sorted(CASES))
def test_standard_errors_shrink_as_one_over_root_n(case: str) -> None:
    """The same rows measured n = 4 times over: every standard error halves (1/sqrt(4))
    to 1e-13 (noise-free data, the Jacobian at the same point; measured 4e-16)."""
    design, pattern, scale, sig = CASES[case]
    free = [pattern.format(i) for i in (1, 2, 3)]
    truth_design, _ = _perturbed(design, dict(zip(free, (1.2, 0.8, 1.1), strict=True)))
    rows = _rows(
        design, truth_design, scale * IN_PLANE, [(0, 0, 0)], [math.nan] * 2 + [*sig, math.nan]
    )
    one = identify(design, rows, free)
    four = identify(design, rows.repeated(4), free)
    np.testing.assert_allclose(four.standard_errors / one.standard_errors, 0.5, rtol=1e-13)


# ------------------------------------------------------------------ ill-posed input
def _in_plane_rows() -> MeasurementRows:
    return _rows(PPR, PPR, IN_PLANE, [(0, 0, 0)], [math.nan] * 2 + [2e-5, 3e-7, 3e-7, math.nan])


def test_unidentifiable_combinations_are_named_and_refused() -> None:
    """In-plane data at one pose cannot tell a leg's actuator from its guide's yaw
    spring in series with it; nor see the out-of-plane guide roll at all."""
    free = ["leg1.actuator.locked_stiffness", "leg1.guide.yaw", "leg2.guide.roll"]
    with pytest.raises(InputDataError, match="cannot separate") as info:
        identify(PPR, _in_plane_rows(), free)
    assert "leg2.guide.roll +1.00" in str(info.value)
    assert "leg1.guide.yaw" in str(info.value)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = identify(PPR, _in_plane_rows(), free, fix_unidentifiable=True)
    assert any(issubclass(w.category, IdentifiabilityWarning) for w in caught)
    assert "leg2.guide.roll" in result.fixed and len(result.names) == 1
    assert result.design.parameter("leg2.guide.roll") == PPR.parameter("leg2.guide.roll")


def test_too_few_measurements_and_bad_names() -> None:
    rows = _in_plane_rows()
    one = MeasurementRows(rows.poses[:1], rows.wrenches[:1], rows.twists[:1], rows.sigmas[:1])
    free = [f"leg{i}.actuator.locked_stiffness" for i in (1, 2, 3)]
    with pytest.raises(InputDataError, match="too few measurements: 3 measured values for 3"):
        identify(PPR, one, free)
    with pytest.raises(DesignError, match="unknown design parameter 'leg1.guide.yawn'"):
        identify(PPR, rows, ["leg1.guide.yawn"])
    with pytest.raises(InputDataError, match="both address"):
        identify(PPR, rows, ["leg*.guide.yaw", "leg2.guide.yaw"])


def test_rows_from_files(tmp_path: Path) -> None:
    """Sigma from columns or options (not both, not missing); a deflect file gives its
    wrenches through its mode; a zero wrench is refused."""
    p = tmp_path / "m.csv"
    p.write_text("fx_N,x_mm,y_mm,sigma_x_mm\n2,0.05,0.01,0.001\n")
    meas = read_measurements(p)
    with pytest.raises(InputDataError, match="no noise given for y_mm"):
        measurement_rows(PPR, meas)
    rows = measurement_rows(PPR, meas, {4: 2e-6})
    np.testing.assert_allclose(rows.sigmas[0, 3:5], [1e-6, 2e-6])
    with pytest.raises(InputDataError, match="given twice"):
        measurement_rows(PPR, meas, {3: 2e-6, 4: 2e-6})
    np.testing.assert_allclose(rows.poses[0], home_pose(PPR))
    p.write_text("fx_N,fy_N,x_mm\n0,0,0.01\n")
    with pytest.raises(InputDataError, match="zero wrench"):
        measurement_rows(PPR, read_measurements(p), {3: 1e-6})
    p.write_text("# mode: moment\nload,phi_z_deg\n0.2,0.3\n")
    rows = measurement_rows(PPR, read_measurements(p), {2: 1e-4})
    np.testing.assert_allclose(rows.wrenches[0], [0, 0, 0.2, 0, 0, 0])
    p.write_text("load,phi_z_deg\n0.2,0.3\n")
    with pytest.raises(InputDataError, match="mode"):
        measurement_rows(PPR, read_measurements(p), {2: 1e-4})
