"""Calibration recovers known parameters and reports what it cannot determine."""

from __future__ import annotations

import numpy as np
import pytest

from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import default_design
from ppm_stiffness.fit.calibration import calibrate, default_sigma
from ppm_stiffness.model import stiffness_at_pose

DESIGN = default_design()
LEG3 = ["leg3.bearing_offset", "leg3.guide_offset_u", "leg3.guide_offset_w"]


def test_recovers_known_parameters_from_noisy_model_matrix() -> None:
    truth = {
        "leg3.bearing_offset": 0.080,
        "leg3.guide_offset_u": -0.090,
        "leg3.guide_offset_w": 0.050,
    }
    true_design = DESIGN.with_parameters(truth)
    k_true = stiffness_at_pose(true_design)
    sigma = 0.002 * default_sigma(k_true) / 0.01  # 0.2 % of each entry's natural scale
    rng = np.random.default_rng(7)
    noise = rng.normal(size=(6, 6)) * sigma
    noise = np.triu(noise) + np.triu(noise, 1).T
    target = k_true + noise
    start = DESIGN.with_parameters(
        {"leg3.bearing_offset": 0.060, "leg3.guide_offset_u": -0.110, "leg3.guide_offset_w": 0.03}
    )
    bounds = {
        "leg3.bearing_offset": (0.0, 0.15),
        "leg3.guide_offset_u": (-0.15, 0.0),
        "leg3.guide_offset_w": (-0.1, 0.1),
    }
    result = calibrate(start, target, LEG3, bounds=bounds, sigma=sigma)
    assert not result.flat_directions()
    for name, value, std in zip(
        result.names, result.values, result.standard_deviations, strict=True
    ):
        assert np.isfinite(std) and std > 0
        assert abs(value - truth[name]) < 4 * std, (name, value, truth[name], std)
    # the fit is as good as the noise: weighted RMS of order 1
    assert 0.2 < result.weighted_rms < 2.0


def test_exact_target_is_recovered_exactly() -> None:
    truth = DESIGN.with_parameters({"leg2.bearing_offset": 0.135})
    target = stiffness_at_pose(truth)
    result = calibrate(
        DESIGN, target, ["leg2.bearing_offset"], bounds={"leg2.bearing_offset": (0.10, 0.15)}
    )
    assert result.values[0] == pytest.approx(0.135, abs=1e-9)


def test_reports_flat_direction_for_springs_in_series() -> None:
    # The guide's vertical spring and the bearing's vertical radial spring are pure
    # translations along z in series in every leg: only 1/k_g + 1/k_b is visible.
    target = stiffness_at_pose(DESIGN)
    names = ["leg*.guide.vertical", "leg*.bearing.radial_vertical"]
    result = calibrate(DESIGN, target, names)
    flat = result.flat_directions()
    assert len(flat) == 1
    assert abs(flat[0]["leg*.guide.vertical"]) > 0.1
    assert abs(flat[0]["leg*.bearing.radial_vertical"]) > 0.1
    assert np.all(np.isinf(result.standard_deviations))
    assert result.singular_values[1] < 1e-6 * result.singular_values[0]


def test_bad_calibration_input() -> None:
    k = stiffness_at_pose(DESIGN)
    with pytest.raises(InputDataError, match=r"target must be 6x6, got shape \(5, 5\)"):
        calibrate(DESIGN, k[:5, :5], ["leg1.bearing_offset"])
    with pytest.raises(InputDataError, match="no free parameters given"):
        calibrate(DESIGN, k, [])
    with pytest.raises(InputDataError, match=r"each bound must be \(low, high\) with low < high"):
        calibrate(DESIGN, k, ["leg1.bearing_offset"], bounds={"leg1.bearing_offset": (1, 0)})
    from ppm_stiffness.core.errors import DesignError

    with pytest.raises(DesignError, match="unknown design parameter"):
        calibrate(DESIGN, k, ["leg9.bearing_offset"])
