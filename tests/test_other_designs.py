"""Designs other than the paper's, through the same solver: symmetry and equilibrium."""

from __future__ import annotations

import math

import numpy as np

from ppm_stiffness.core.conventions import rotation_z, stiffness_b_from_stiffness_a
from ppm_stiffness.core.eigenscrews import eigenscrews
from ppm_stiffness.design import Design, default_design, design_from_dict
from ppm_stiffness.model import leg_stiffnesses_at_pose, stiffness_at_pose
from ppm_stiffness.statics.loading import leg_wrenches


def symmetric_design(n_legs: int) -> Design:
    """n identical P-P-R legs of the paper's leg 3, rotated by 360/n degrees."""
    data = default_design().model_dump()
    template = data["legs"][2]
    legs = []
    for k in range(n_legs):
        a = 2 * np.pi * k / n_legs
        c, s = np.cos(a), np.sin(a)
        x, y = template["base_point"]
        leg = dict(template)
        leg["base_point"] = (c * x - s * y, s * x + c * y)
        leg["alpha"] = math.remainder(template["alpha"] + a, 2 * math.pi)
        leg["psi"] = math.remainder(template["psi"] + a, 2 * math.pi)
        leg["stroke"] = (-1.0, 1.0)
        leg["rod_length_range"] = (1e-4, 1.0)
        legs.append(leg)
    data["legs"] = legs
    data["name"] = f"symmetric {n_legs}-PPR"
    return design_from_dict(data)


def test_three_fold_symmetric_design_has_symmetric_stiffness() -> None:
    design = symmetric_design(3)
    k = stiffness_at_pose(design, [0.0, 0.0, 0.0])
    # rotating the frame by 120 deg maps the machine onto itself: K is invariant
    rotated = stiffness_b_from_stiffness_a(k, rotation_z(2 * np.pi / 3), np.zeros(3))
    np.testing.assert_allclose(rotated, k, atol=1e-9 * np.abs(k).max())
    # hence K_tt is isotropic in the plane and K_rt has no in-plane bias
    assert abs(k[3, 3] - k[4, 4]) < 1e-9 * k[3, 3]
    assert abs(k[3, 4]) < 1e-9 * k[3, 3]
    assert np.all(eigenscrews(k).spring_constants > 0)


def test_redundant_four_leg_design_shares_load_in_equilibrium() -> None:
    design = symmetric_design(4)
    pose = np.array([0.002, -0.001, 0.05])
    legs = leg_stiffnesses_at_pose(design, pose)
    k = stiffness_at_pose(design, pose)
    wrench = np.array([0.1, -0.2, 0.3, 5.0, -3.0, 10.0])
    shares = leg_wrenches(legs, wrench)
    np.testing.assert_allclose(shares.sum(axis=0), wrench, rtol=1e-10, atol=1e-12)
    # a redundant machine is stiffer than any 3-leg subset of it
    k3 = sum(legs[:3])
    assert np.all(np.linalg.eigvalsh(k - k3) > -1e-9 * np.abs(k).max())
    assert np.linalg.eigvalsh(k - k3)[-1] > 0
