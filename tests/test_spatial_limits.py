"""Tests that would catch a wrong spatial model (issue 20): the rigid-structure limit of
every spatial example, the two-force legs of the shipped hexapod, and the screw springs
of the symmetric spatial examples at their home pose."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from helpers import design_named, example_designs, is_spatial
from ppm_stiffness.core.conventions import GAMMA, length_balanced_compliance
from ppm_stiffness.core.eigenscrews import eigenscrews, stiffness_from_screw_springs
from ppm_stiffness.design import Design, design_from_dict
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.poses import full_poses, home_pose, task_indices

SPATIAL = example_designs(is_spatial)
#: The leg types whose rigid-structure compliance :func:`rigid_compliance` writes in
#: closed form (a chain leg's closed forms: tests/test_chain_leg.py).
CLOSED_FORM_TYPES = {"UPS", "PRS", "RPS"}
CLOSED_FORM = example_designs(
    lambda d: is_spatial(d) and all(leg.type in CLOSED_FORM_TYPES for leg in d.legs)
)
#: Design keys of springs and sections: the structure (the actuator's law excluded).
SPRING_PARTS = {"guide", "base_joint", "platform_joint", "carriage_revolute", "base_revolute"}
SECTION_PARTS = {"cylinder", "rod", "link"}


def structure_scaled(design: Design, eps: float) -> Design:
    """Every structural compliance (links, joint springs) times ``eps``; actuators kept."""
    data: dict[str, Any] = design.model_dump()
    for leg in data["legs"]:
        for key, part in leg.items():
            if not isinstance(part, dict):
                continue
            if key in SPRING_PARTS:
                for name, value in part.items():
                    if name != "max_angle" and value is not None:
                        part[name] = value / eps
            elif key in SECTION_PARTS:
                part["young_modulus"] /= eps
                part["shear_modulus"] /= eps
    return design_from_dict(data)


def sample_poses(design: Design, n: int, seed: int) -> np.ndarray:
    """The home pose and seeded poses over the required region, completed."""
    rng = np.random.default_rng(seed)
    region = design.workspace.required
    assert region is not None
    ranges = np.array(list(region.ranges().values()))
    values = rng.uniform(ranges[:, 0], ranges[:, 1], size=(n - 1, len(ranges)))
    home = home_pose(design)
    poses, ok = full_poses(design, np.vstack([home[list(task_indices(design))], values]))
    assert ok.all()
    return poses


def rigid_compliance(design: Design, pose: np.ndarray) -> np.ndarray:
    """C0 = W^-T diag(c_a, 0) W^-1 of the issue: W's columns the unit wrenches the rigid
    legs transmit through B_i (actuation along the link, constraint along the revolute
    axis); c_a = 1/k_a, or (s . u)^2 / k_a for a rail actuator."""
    columns, compliances = [], []
    for leg in design.legs:
        lp = leg.solve(pose)
        b = lp.points["B"]
        k_a = leg.actuator.locked_stiffness
        if leg.type == "PRS":
            s = (b - lp.points["C"]) / np.linalg.norm(b - lp.points["C"])
            u = np.asarray(leg.rail_direction)
            c_a = float(s @ u) ** 2 / k_a
        else:
            s = (b - lp.points["A"]) / np.linalg.norm(b - lp.points["A"])
            c_a = 1.0 / k_a
        columns.append(np.concatenate([np.cross(b, s), s]))
        compliances.append(c_a)
        if leg.type in ("PRS", "RPS"):
            e = np.asarray(leg.revolute_axis)
            columns.append(np.concatenate([np.cross(b, e), e]))
            compliances.append(0.0)
    w = np.array(columns).T
    w_inv = np.linalg.inv(w)
    return np.asarray(w_inv.T @ np.diag(compliances) @ w_inv)


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_rigid_structure_limit_is_reached_at_first_order(name: str) -> None:
    """Length-balanced compliance -> C0 as the structure stiffens: the error falls 10x
    per decade of eps (a slope, not an absolute tolerance)."""
    design = design_named(name)
    for pose in sample_poses(design, 3, seed=8):
        c0 = length_balanced_compliance(rigid_compliance(design, pose))
        errors = []
        for eps in (1e-4, 1e-5, 1e-6):
            k = stiffness_at_pose(structure_scaled(design, eps), pose)
            c = length_balanced_compliance(np.linalg.inv(k))
            errors.append(float(np.max(np.abs(c - c0)) / np.max(np.abs(c0))))
        for coarse, fine in zip(errors[:-1], errors[1:], strict=True):
            assert 9.0 < coarse / fine < 11.0, errors


def test_shipped_hexapod_is_a_sum_of_two_force_legs() -> None:
    """K = sum k_i w_i w_i^T with w_i = ((B_i - P) x n_i; n_i) and 1/k_i the axial
    compliances in series (actuator, cylinder, rod, U and S joints), to 2e-15 of the
    largest balanced entry (measured 3.7e-16)."""
    design = design_named("hexapod_6ups")
    worst = 0.0
    for pose in sample_poses(design, 6, seed=4):
        expected = np.zeros((6, 6))
        for leg in design.legs:
            lp = leg.solve(pose)
            a, b = lp.points["A"], lp.points["B"]
            length = float(np.linalg.norm(b - a))
            n = (b - a) / length
            w = np.concatenate([np.cross(b, n), n])
            cyl, rod = leg.cylinder, leg.rod
            c = (
                1 / leg.actuator.locked_stiffness
                + leg.cylinder_length / (cyl.young_modulus * cyl.area)
                + (length - leg.cylinder_length) / (rod.young_modulus * rod.area)
                + 1 / leg.base_joint.axial
                + 1 / leg.platform_joint.axial
            )
            expected += np.outer(w, w) / c
        k = stiffness_at_pose(design, pose)
        s = np.array([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])
        scale = np.max(np.abs(expected * s[:, None] * s[None, :]))
        worst = max(worst, float(np.max(np.abs((k - expected) * s[:, None] * s[None, :]))) / scale)
    assert worst < 2e-15  # measured 3.7e-16


@pytest.mark.parametrize("name", SPATIAL)
def test_screw_springs_rebuild_K_at_the_symmetric_home_pose(name: str) -> None:
    """At the 3-fold symmetric home pose eigenvalues repeat: the springs must still
    rebuild K and be reciprocal (zeta_i^T Gamma zeta_j = 0, i != j)."""
    design = design_named(name)
    k = stiffness_at_pose(design)
    springs = eigenscrews(k)
    assert springs.repeated  # the symmetric home pose has repeated eigenvalues
    s = np.array([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])
    rebuilt = stiffness_from_screw_springs(springs)
    err = np.linalg.norm((rebuilt - k) * s[:, None] * s[None, :]) / np.linalg.norm(
        k * s[:, None] * s[None, :]
    )
    assert err < 1e-13
    z = springs.eigenvectors
    g = z.T @ GAMMA @ z
    d = np.sqrt(np.abs(np.diag(g)))
    off = np.abs(g) / np.outer(d, d) - np.eye(6)
    assert np.max(np.abs(off)) < 1e-13
