"""Legs written as joint lists (``type = "chain"``, :mod:`ppm_stiffness.legs.types.chain_leg`)
against independent computations: today's U-P-S leg type, closed forms of two-force legs
and of a spherical wrist, a closed-form inverse kinematics.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from tests.helpers import design_named, example_designs

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.errors import DesignError, UnreachablePoseError
from ppm_stiffness.design.io import design_from_dict
from ppm_stiffness.dynamics.mass import mass_matrix_at_pose
from ppm_stiffness.model import full_pose, stiffness_at_pose
from ppm_stiffness.poses import home_pose, task_indices

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: The built-in design's file (``design_named("paper")``).
PAPER = Path(__file__).resolve().parents[1] / "src" / "ppm_stiffness" / "data" / "paper_3ppr.toml"


def _data(name: str) -> dict[str, Any]:
    with open(PAPER if name == "paper.toml" else EXAMPLES / name, "rb") as f:
        return tomllib.load(f)


def _relative(k1: np.ndarray, k2: np.ndarray) -> float:
    """max |dK_ij| / sqrt(K_ii K_jj)."""
    d = np.sqrt(np.outer(np.abs(np.diag(k1)), np.abs(np.diag(k1))))
    return float(np.max(np.abs(k1 - k2) / d))


def as_joint_lists(name: str) -> dict[str, Any]:
    """An example design with each leg written as the joint list its preset writes
    (:meth:`LegModel.joint_list`), every other key of the file kept (parts are in
    the legs' lists)."""
    data = _data(f"{name}.toml")
    design = design_named(name)
    home = home_pose(design)
    out = {k: copy.deepcopy(v) for k, v in data.items() if k not in ("parts", "legs")}
    out["legs"] = [leg.joint_list(home) for leg in design.legs]
    out["task_coordinates"] = list(design.task_coordinates)  # a chain design's: all six
    return out


def writes_joint_lists(design: Any) -> bool:
    """Every leg of the design is a preset that writes its joint list."""
    home = home_pose(design)
    return all(leg.type != "chain" and leg.joint_list(home) is not None for leg in design.legs)


def _random_poses(home: np.ndarray, half: np.ndarray, count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return home + rng.uniform(-1.0, 1.0, (count, 6)) * half


@pytest.mark.parametrize("name", example_designs(writes_joint_lists, paper=True))
def test_presets_written_as_joint_lists_equal_the_preset(name: str) -> None:
    """K, M, the completed pose, the joint angles and the actuated travel of a design
    whose legs are the joint lists their presets write equal the preset's at random
    poses (the pose to the completion's 1e-12; K and M to 1e-13 of their largest
    entries, measured 9.1e-15 and 1.2e-14 on the 3-RPS, 5.9e-16 and 6.1e-15 on the
    hexapod, 1.8e-15 and 6.2e-16 on the 3-RRR, 2.4e-14 and 1.0e-14 on the 3-RPR,
    1.6e-14 and 1.6e-14 on the 3-PRS, 9.5e-15 and 2.3e-15 on the 3-PRR, 8.7e-16 and
    2.4e-16 on the paper's 3-PPR, 1.5e-15 and 6.6e-16 on the symmetric 3-PPR, 1.1e-15
    and 4.4e-16 on the redundant 4-PPR): the generic chain, its Newton inverse
    kinematics and the product-of-exponentials joint axes reproduce the closed-form legs
    (issue 28, item 4; all seven presets write one). A pose beyond a preset's limits
    (the paper's 3-PPR: a rod shorter than its range, one of the six draws) is refused
    by the joint list's limits too (its bearing's ``travel``). The P-R-S, P-R-R and
    P-P-R guides' springs act at the moving carriage (``carried_by = "after"``; at the
    fixed bushing K misses by 2.7e-2, 2.3e-1 and 1.1e-1), the P-R-S guide's lateral
    axis along its revolute (``axis2``; without it 1.3e-3)."""
    preset = design_named(name)
    chain = design_from_dict(as_joint_lists(name))
    home = home_pose(preset)
    idx = list(task_indices(preset))
    half = np.array([0.01, 0.01, 0.01, 0.05, 0.05, 0.05])[idx]
    rng = np.random.default_rng(3)
    compared = 0
    for task in home[idx] + rng.uniform(-1.0, 1.0, (6, len(idx))) * half:
        pose = full_pose(preset, task)
        np.testing.assert_allclose(full_pose(chain, task), pose, rtol=0, atol=1e-12)
        try:
            k_preset = stiffness_at_pose(preset, pose)
        except UnreachablePoseError:  # beyond a limit: the joint list's limits refuse it too
            with pytest.raises(UnreachablePoseError, match="travel|outside"):
                stiffness_at_pose(chain, pose)
            continue
        compared += 1
        assert _relative(k_preset, stiffness_at_pose(chain, pose)) < 1e-13
        m1, m2 = mass_matrix_at_pose(preset, pose), mass_matrix_at_pose(chain, pose)
        assert np.max(np.abs(m1 - m2)) < 1e-13 * np.max(np.abs(m1))
        for leg_preset, leg_chain in zip(preset.legs, chain.legs, strict=True):
            a, b = leg_preset.solve(pose), leg_chain.solve(pose)
            for angle in ("base_joint_angle", "platform_joint_angle"):
                if angle in a.coordinates:
                    assert abs(float(a.coordinates[angle] - b.coordinates[angle])) < 1e-12
            # the chain's actuated coordinate is the preset's change from home
            name_a = leg_preset.ACTUATED_COORDINATE
            travel = float(a.coordinates[name_a] - leg_preset.solve(home).coordinates[name_a])
            assert abs(travel - float(b.coordinates["actuated"])) < 1e-12
    assert compared >= 4


def _crank_angle(c: np.ndarray, a: np.ndarray, u0: np.ndarray, b: np.ndarray, rod: float) -> float:
    """The crank angle (branch of 0) putting the crank tip at ``rod`` from b: scalar
    Newton on |B - U(q)|^2 = rod^2, U(q) = c + Rot(a, q) (u0 - c)."""
    q = 0.0
    for _ in range(60):
        r = pose6.rotation_exp(q * a) @ (u0 - c)
        u = c + r
        f = float(np.sum((b - u) ** 2) - rod**2)
        df = float(-2.0 * (b - u) @ np.cross(a, r))
        step = f / df
        q -= step
        if abs(step) < 1e-15:
            break
    return q


def _rus_geometry(design: Any, pose: np.ndarray) -> list[dict[str, np.ndarray]]:
    """Each R-U-S leg's crank pivot c, axis a, crank tip U and platform joint B at
    ``pose`` by the closed-form crank angle (independent of the chain's Newton)."""
    home = np.array(design.workspace.start())
    out = []
    for leg in design.legs:
        r_joint, _, u_joint, _, s_joint = leg.elements
        c, a = np.array(r_joint.point), np.array(r_joint.axis)
        a /= np.linalg.norm(a)  # (a file's unit vector, to its printed digits)
        u0, b0 = np.array(u_joint.point), np.array(s_joint.point)
        b_platform = pose6.rotation(home).T @ (b0 - home[:3])
        b = pose[:3] + pose6.rotation(pose) @ b_platform
        q = _crank_angle(c, a, u0, b, float(np.linalg.norm(b0 - u0)))
        u = c + pose6.rotation_exp(q * a) @ (u0 - c)
        out.append({"c": c, "a": a, "u": u, "b": b, "q": np.array(q)})
    return out


RUS_HALF = np.array([0.01, 0.01, 0.01, 0.05, 0.05, 0.05])


def test_rus_crank_angle_equals_the_closed_form() -> None:
    """The chain's actuated coordinate of each 6-RUS leg equals the crank angle solved
    from |B - U(q)| = rod length (1e-12 rad)."""
    design = design_from_dict(_data("6rus.toml"))
    for pose in _random_poses(np.array(design.workspace.start()), RUS_HALF, 5, seed=5):
        for leg, geometry in zip(design.legs, _rus_geometry(design, pose), strict=True):
            q = float(leg.solve(pose).coordinates["actuated"])
            assert abs(q - float(geometry["q"])) < 1e-12


def _frame(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e1, unit(z x e1), e1 x e2): the joint and link frame convention."""
    e2 = np.cross([0.0, 0.0, 1.0], axis)
    e2 /= np.linalg.norm(e2)
    return axis, e2, np.cross(axis, e2)


def _rus_leg_compliance(leg: Any, g: dict[str, np.ndarray], n: np.ndarray) -> float:
    """1/k of one two-force R-U-S leg: the compliances a unit force along n at U meets
    (the issue's closed form), each written from the parts."""
    law = leg.actuator.locked_stiffness
    r_joint, crank, u_joint, rod, s_joint = leg.elements
    arm = g["u"] - g["c"]
    moment = np.cross(arm, n)
    e1, e2, e3 = _frame(g["a"])
    springs = r_joint.springs
    compliance = float(moment @ e1) ** 2 / law  # the actuator: d^2 / k_a
    compliance += (float(moment @ e2) ** 2 + float(moment @ e3) ** 2) / springs.tilt
    compliance += float(n @ e1) ** 2 / springs.axial
    compliance += (float(n @ e2) ** 2 + float(n @ e3) ** 2) / springs.radial
    # the crank: a cantilever loaded at its tip (x along it, y = unit(z x x))
    length = float(np.linalg.norm(arm))
    x, y, z = _frame(arm / length)
    s = crank.link
    compliance += float(n @ x) ** 2 * length / (s.young_modulus * s.area)
    compliance += float(n @ y) ** 2 * length**3 / (3 * s.young_modulus * s.inertia_z)
    compliance += float(n @ z) ** 2 * length**3 / (3 * s.young_modulus * s.inertia_y)
    rod_length = float(np.linalg.norm(g["b"] - g["u"]))
    compliance += rod_length / (rod.link.young_modulus * rod.link.area)
    compliance += 1.0 / u_joint.springs.radial + 1.0 / s_joint.springs.axial
    return compliance


@pytest.mark.parametrize("rigid", [False, True])
def test_rus_hexapod_is_a_sum_of_two_force_legs(rigid: bool) -> None:
    """K of the 6-RUS = sum k_i s_i s_i^T, s_i = ((B_i - P) x n_i ; n_i), 1/k_i the
    series compliance of the actuator, crank bearing, crank, rod and rod-end joints
    along n_i (isotropic U and S springs); with rigid links and joints, 1/k_i =
    d_i^2 / k_a, d_i = n_i . (a_i x (U_i - c_i)). At random poses to 2e-14 (measured
    2.6e-15 and 2.9e-15)."""
    data = _data("6rus.toml")
    if rigid:
        leg = data["legs"][0]
        for element in leg["elements"]:
            element.pop("springs", None)
            if "link" in element:
                element["link"] = "rigid"
    design = design_from_dict(data)
    for pose in _random_poses(np.array(design.workspace.start()), RUS_HALF, 5, seed=7):
        expected = np.zeros((6, 6))
        for leg, g in zip(design.legs, _rus_geometry(design, pose), strict=True):
            n = (g["b"] - g["u"]) / np.linalg.norm(g["b"] - g["u"])
            s = np.concatenate([np.cross(g["b"] - pose[:3], n), n])
            if rigid:
                d = float(n @ np.cross(g["a"], g["u"] - g["c"]))
                k = leg.actuator.locked_stiffness / d**2
            else:
                k = 1.0 / _rus_leg_compliance(leg, g, n)
            expected += k * np.outer(s, s)
        assert _relative(expected, stiffness_at_pose(design, pose)) < 2e-14


def test_a_chain_legs_parts_are_design_parameters() -> None:
    """``leg*.rod.area`` (an element's part, by its name) is a design parameter: every
    leg's rod takes the new area and K is the two-force closed form with it (2e-14)."""
    design = design_from_dict(_data("6rus.toml")).with_parameters({"leg*.rod.area": 4e-5})
    assert design.parameter("leg*.rod.area") == 4e-5
    assert design.parameter_unit("leg1.rod.area") == "m^2"
    assert design.parameter_unit("leg2.crank_drive.springs.tilt") == "N·m/rad"
    pose = np.array(design.workspace.start()) + np.array([0.004, -0.003, 0.002, 0.02, 0.0, -0.03])
    expected = np.zeros((6, 6))
    for leg, g in zip(design.legs, _rus_geometry(design, pose), strict=True):
        assert leg.elements[3].link.area == 4e-5
        n = (g["b"] - g["u"]) / np.linalg.norm(g["b"] - g["u"])
        s = np.concatenate([np.cross(g["b"] - pose[:3], n), n])
        expected += np.outer(s, s) / _rus_leg_compliance(leg, g, n)
    assert _relative(expected, stiffness_at_pose(design, pose)) < 2e-14


def test_spherical_wrist_at_home_is_isotropic() -> None:
    """Spherical 3-RRR at home (axes e_i, e_(i+1), e_(i+2) through O = P) with rigid
    links, near-rigid tilt and translational joint springs k_t: K_rr = k_a I, K_rt = 0,
    K_tt = k_t I (three legs of three joints in series), to 1e-11 (measured 4.0e-13,
    1.3e-12, 2.6e-13: the 1e16 N·m/rad tilt springs' own compliance, 2 k_a / 1e16)."""
    data = _data("spherical_3rrr.toml")
    k_t, k_a = 3e6, 2e3
    for leg in data["legs"]:
        leg["actuator"] = {"locked_stiffness": k_a, "q": 1.0, "threshold_displacement": 0.0}
        for element in leg["elements"]:
            if "link" in element:
                element["link"] = "rigid"
            else:
                element["springs"] = {"tilt": 1e16, "axial": k_t, "radial": k_t}
    design = design_from_dict(data)
    k = stiffness_at_pose(design, np.zeros(6))
    assert np.max(np.abs(k[:3, :3] - k_a * np.eye(3))) < 1e-11 * k_a
    assert np.max(np.abs(k[3:, 3:] - k_t * np.eye(3))) < 1e-11 * k_t
    assert np.max(np.abs(k[:3, 3:])) < 1e-11 * math.sqrt(k_a * k_t)


def test_spherical_wrist_completion_keeps_the_centre() -> None:
    """The wrist's legs constrain x, y, z: the completed pose keeps P at O (1e-12 m) at
    random orientations."""
    from ppm_stiffness.poses import full_pose

    design = design_from_dict(_data("spherical_3rrr.toml"))
    rng = np.random.default_rng(11)
    for angles in rng.uniform(-0.3, 0.3, (4, 3)):
        pose = full_pose(design, angles)
        assert np.max(np.abs(pose[:3])) < 1e-12
        assert np.allclose(pose[3:], angles, atol=1e-15)


def _one_leg(**changes: Any) -> dict[str, Any]:
    data = _data("6rus.toml")
    leg = data["legs"][0]
    for index, change in changes.items():
        i = int(index[1:])
        if change is None:
            del leg["elements"][i]
        else:
            leg["elements"][i] = {**leg["elements"][i], **change}
    return data


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (
            {"e0": {"actuated": False, "stroke": None}},
            r"leg1\.actuator': this leg has no actuated joint \(a passive constraining leg\)",
        ),
        ({"e2": {"actuated": True, "stroke": [-0.1, 0.1]}}, "an actuated joint has one freedom"),
        ({"e2": {"axis2": None}}, "a universal joint needs axis2"),
        ({"e0": {"stroke": [0.1, 0.5]}}, "lo <= 0 <= hi"),
        ({"e2": {"axis2": [0.0, 0.0, 1.0]}}, "must be normal to axis"),
        ({"e2": None}, "two links in a row"),
        ({"e4": {"axis": [1.0, 0.0, 0.0]}}, "a spherical joint has no axis"),
        ({"e0": {"stroke": [-90.0, 90.0]}}, "angles in design files are in radians"),
        ({"e3": None}, "platform_joint: max_angle needs a link at the joint"),
        ({"e0": {"axis2": [0.0, 0.0, 1.0], "carried_by": "after"}}, "a revolute joint's point"),
        ({"e0": {"axis2": [0.9396926208, -0.3420201433, 0.0]}}, "must be normal to axis"),
        ({"e0": {"travel": [-0.01, 0.01]}}, "an actuated joint has its stroke"),
        ({"e2": {"travel": [-0.01, 0.01]}}, "a universal joint does not slide"),
    ],
)
def test_malformed_chain_legs_are_refused(changes: dict[str, Any], message: str) -> None:
    data = _one_leg(**changes)
    for element in data["legs"][0]["elements"]:
        for key in [k for k, v in element.items() if v is None]:
            del element[key]
    with pytest.raises(DesignError, match=message):
        design_from_dict(data)


def test_a_pattern_error_names_the_written_leg() -> None:
    data = _data("6rus.toml")
    data["legs"][0]["pattern"] = {"copies": 0}
    with pytest.raises(DesignError, match=r"leg1\.pattern'.*copies = 0"):
        design_from_dict(data)
