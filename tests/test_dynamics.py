"""The mass model and natural frequencies (issue 21): closed forms, frame invariance,
the kinetic energy along trajectories, the loaded tangent K, and units.

Residuals measured when the tolerances were set are given next to each assertion."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from helpers import example_designs, flexure_jointed, within_required
from ppm_stiffness.core import pose as P
from ppm_stiffness.core.conventions import stiffness_b_from_stiffness_a
from ppm_stiffness.design import Design, design_from_dict, design_to_dict
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.dynamics.condensation import leg_mass_matrix, leg_motion
from ppm_stiffness.dynamics.inertia import spatial_inertia
from ppm_stiffness.dynamics.mass import (
    leg_mass_matrices,
    mass_matrix,
    mass_matrix_at_pose,
    platform_mass_matrix,
)
from ppm_stiffness.dynamics.modes import mode_shapes, natural_frequencies
from ppm_stiffness.legs.chain import Link
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.poses import full_poses, home_pose, task_values
from ppm_stiffness.statics.loading import loaded_state
from spatial_legs import STEEL_ROD, STEEL_TUBE, hexapod_legs

TWO_PI = 2.0 * math.pi
#: The stiffnesses of parts scaled by STIFF to make a "rigid" structure.
_SPRING_KEYS = {
    "young_modulus",
    "shear_modulus",
    "roll",
    "pitch",
    "yaw",
    "lateral",
    "vertical",
    "tilt_lateral",
    "tilt_vertical",
    "radial_lateral",
    "radial_vertical",
    "tilt",
    "axial",
    "radial",
    "torsion",
}
STIFF = 1e8


def rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


# --- the platform alone: the congruence and the hat(c) terms ---------------------------


def test_platform_on_springs_diagonal_at_its_centre_of_mass_whatever_p() -> None:
    """K diagonal at the centre of mass in the principal axes of the inertia: the
    frequencies are sqrt(k_i / m) and sqrt(k_theta_i / I_i), wherever P is (the
    platform's spatial inertia and K both moved to P). Residual 3e-14."""
    rng = np.random.default_rng(7)
    m = 2.3
    moments = np.array([0.011, 0.017, 0.023])  # principal inertias [kg m^2]
    k_rot = np.array([3.1e3, 5.3e3, 7.7e3])  # [N m/rad]
    k_lin = np.array([2.0e6, 3.5e6, 9.0e6])  # [N/m]
    axes = rotation(rng)  # principal axes, columns, in F_b
    k_c = np.zeros((6, 6))
    k_c[:3, :3] = axes @ np.diag(k_rot) @ axes.T
    k_c[3:, 3:] = axes @ np.diag(k_lin) @ axes.T
    expected = np.sort(np.sqrt(np.r_[k_lin / m, k_rot / moments])) / TWO_PI
    for _ in range(5):
        c = rng.normal(scale=0.2, size=3)  # the centre of mass seen from P
        k_p = stiffness_b_from_stiffness_a(k_c, np.eye(3), c)  # the centre at c from P
        m_p = spatial_inertia(m, c, axes @ np.diag(moments) @ axes.T)
        assert np.max(np.abs(k_p - k_c)) > 1e-3 * np.max(np.abs(k_c))  # a real move
        f = natural_frequencies(k_p, m_p)
        assert np.allclose(f, expected, rtol=1e-12, atol=0)
        assert np.allclose(mode_shapes(k_p, m_p).frequencies, expected, rtol=1e-12, atol=0)


def test_platform_mass_matrix_turns_with_the_platform() -> None:
    """The design's [platform] at a rotated pose: centre R c_p, inertia R I R^T, and the
    kinetic energy of a twist is that of the body (m |v_c|^2 + w^T I w) / 2."""
    design = _with_masses(
        "hexapod_6ups",
        platform={
            "mass": 1.7,
            "centre_of_mass": [0.01, -0.02, 0.03],
            "inertia": [[0.02, 0.001, 0.0], [0.001, 0.03, -0.002], [0.0, -0.002, 0.04]],
        },
    )
    pose = home_pose(design) + np.array([0.003, -0.002, 0.004, 0.05, -0.04, 0.2])
    m_p = platform_mass_matrix(design, pose)
    r = P.rotation(pose)
    c = r @ np.array([0.01, -0.02, 0.03])
    inertia = r @ np.array(design.platform.inertia) @ r.T  # type: ignore[union-attr]
    rng = np.random.default_rng(3)
    for _ in range(5):
        t = rng.normal(size=6)
        v_c = t[3:] + np.cross(t[:3], c)
        energy = 1.7 * v_c @ v_c + t[:3] @ inertia @ t[:3]
        assert t @ m_p @ t == pytest.approx(energy, rel=1e-13)


# --- one U-P-S leg against its closed form ----------------------------------------------


def _stiff(section: dict[str, float]) -> dict[str, float]:
    return {
        **section,
        "young_modulus": section["young_modulus"] * STIFF,
        "shear_modulus": section["shear_modulus"] * STIFF,
    }


@pytest.mark.parametrize("pose_index", [0, 1, 2])
def test_ups_leg_against_its_closed_form(pose_index: int) -> None:
    """Cylinder (m_c, length L_c) and rod (m_r, from L_c to l), uniform, rigid joints and
    links 1e8 times stiffer than the steel's: B along n moves the rod only
    (energy m_r v^2 / 2); B normal to n turns the leg about A at v / l (energies
    m_c L_c^2 / 3 (v/l)^2 / 2 and m_r (L_c^2 + L_c l + l^2) / 3 (v/l)^2 / 2); a
    rotation of the platform about B leaves the leg still. Residuals 1e-10 (along n:
    the structure's share of the axial motion), 1e-15 (normal)."""
    m_c, m_r = 0.6, 0.25
    legs = hexapod_legs(
        cylinder={**_stiff(STEEL_TUBE), "mass": m_c},
        rod={**_stiff(STEEL_ROD), "mass": m_r},
        guide=None,
        base_joint=None,
        platform_joint=None,
    )
    poses = [
        np.array([0.0, 0.0, 0.25, 0.0, 0.0, 0.0]),
        np.array([0.01, -0.02, 0.25, 0.05, -0.03, 0.1]),
        np.array([-0.03, 0.01, 0.3, -0.08, 0.06, -0.2]),
    ]
    pose = poses[pose_index]
    for leg in legs:
        lp = leg.solve(pose)
        m = leg_mass_matrix(leg.chain(lp), 1e6)
        a, b = lp.points["A"], lp.points["B"]
        length = float(np.linalg.norm(b - a))
        n = (b - a) / length
        lc = leg.cylinder_length
        along = np.r_[0.0, 0.0, 0.0, n]
        assert along @ m @ along == pytest.approx(m_r, rel=1e-9)
        for helper in ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]):
            e = np.cross(n, helper)
            e /= np.linalg.norm(e)
            normal = np.r_[0.0, 0.0, 0.0, e]
            expected = (m_c * lc**2 + m_r * (lc**2 + lc * length + length**2)) / (3 * length**2)
            assert normal @ m @ normal == pytest.approx(expected, rel=1e-12)
        w = np.array([0.3, -0.2, 0.5])
        about_b = np.r_[w, -np.cross(w, b)]
        assert abs(about_b @ m @ about_b) <= 1e-12 * m_r * float(w @ w) * length**2


# --- the chain's motion adds up to the platform's --------------------------------------


@pytest.mark.parametrize("name", example_designs(paper=True))
def test_the_last_bodys_twist_is_the_platforms(name: str) -> None:
    """The twists of a leg's coordinates add up to the platform twist (the static
    condensation's bordered system solved exactly). Residual 1.7e-13 (1.1e-12 for the
    flexure 6-RUS, whose 4.7 N·m/rad flexures meet springs of 1e7 in one LU; 1.8e-11
    with 1/k in the compliance)."""
    design = _named(name)
    pose = home_pose(design)
    tol = 4e-12 if flexure_jointed(design) else 1e-12
    for leg in design.legs:
        motion = leg_motion(leg.chain(leg.solve(pose)), leg.locked_stiffness())
        assert np.max(np.abs(motion.after[-1] - np.eye(6))) <= tol


# --- frame consistency --------------------------------------------------------------------


def test_moving_the_reference_point_is_a_congruence_and_keeps_the_frequencies() -> None:
    """The same hexapod with its platform frame's origin moved by d (platform points and
    centre of mass minus d, P at p + R d): M and K change by the congruence of the
    twists' change of point, the frequencies not at all. Residuals 7e-15 (M, relative
    to its largest entry), 5e-17 (K, likewise), 7e-15 (f)."""
    base = _with_masses(
        "hexapod_6ups",
        platform={"mass": 1.2, "shape": "box", "size": [0.22, 0.2, 0.03]},
        masses={"cylinder": {"mass": 0.5, "mass_centre": 0.05}, "rod": {"mass": 0.2}},
        actuator={"carriage_mass": 0.1},
    )
    d = np.array([0.02, -0.03, 0.05])
    data = design_to_dict(base)
    for leg in data["legs"]:
        leg["platform_point"] = (np.array(leg["platform_point"]) - d).tolist()
    data["platform"]["centre_of_mass"] = (-d).tolist()
    moved = design_from_dict(data)
    pose = home_pose(base) + np.array([0.004, 0.003, -0.005, 0.03, -0.02, 0.05])
    r = P.rotation(pose)
    pose_moved = pose.copy()
    pose_moved[:3] += r @ d
    m, m2 = mass_matrix_at_pose(base, pose), mass_matrix_at_pose(moved, pose_moved)
    k, k2 = stiffness_at_pose(base, pose), stiffness_at_pose(moved, pose_moved)
    # A: the frame at P; B: at P' = P + R d; A's origin seen from B: -R d
    mb = stiffness_b_from_stiffness_a(m, np.eye(3), -r @ d)
    assert np.max(np.abs(mb - m2)) <= 3e-14 * np.max(np.abs(m2))
    kb = stiffness_b_from_stiffness_a(k, np.eye(3), -r @ d)
    assert np.max(np.abs(kb - k2)) <= 1e-15 * np.max(np.abs(k2))
    assert np.max(np.abs(m2 - m)) > 1e-3 * np.max(np.abs(m))  # a real move
    f, f2 = natural_frequencies(k, m), natural_frequencies(k2, m2)
    assert np.allclose(f, f2, rtol=3e-14, atol=0)


# --- the kinetic energy along a trajectory ------------------------------------------------


def _link_energy(
    design: Design, before: np.ndarray, after: np.ndarray, h: float, at: np.ndarray
) -> float:
    """Kinetic energy [J] of the legs' links, carriages and rotors from finite
    differences of their positions (inverse kinematics) at two poses 2h apart (the
    rate of the path parameter 1), uniform-rod defaults and spin neglected."""
    energy = 0.0
    for leg in design.legs:
        lo, hi, mid = leg.solve(before), leg.solve(after), leg.solve(at)
        chains = [leg.chain(x) for x in (lo, hi, mid)]
        for e_lo, e_hi, e_mid in zip(*chains, strict=True):
            if isinstance(e_mid, Link):
                if e_mid.mass is None:
                    continue
                body = e_mid.mass
                length = float(np.linalg.norm(e_mid.end - e_mid.start))
                # the material point at the centre of mass at the middle pose: a link
                # whose length changes slides through its start and is fixed at its end
                if body.centre is None:
                    from_end = 0.5 * length
                else:
                    from_end = body.centre if body.from_end else length - body.centre

                def centre(e: Link, from_end: float = from_end) -> np.ndarray:
                    n = (e.end - e.start) / np.linalg.norm(e.end - e.start)
                    return np.asarray(e.end - from_end * n)

                n = (e_mid.end - e_mid.start) / length
                dn = (
                    (e_hi.end - e_hi.start) / np.linalg.norm(e_hi.end - e_hi.start)
                    - (e_lo.end - e_lo.start) / np.linalg.norm(e_lo.end - e_lo.start)
                ) / (2 * h)
                omega = np.cross(n, dn)
                # positions are relative to P: add P's own motion
                v_c = (centre(e_hi) + after[:3] - centre(e_lo) - before[:3]) / (2 * h)
                i_t = body.mass * length**2 / 12 if body.transverse is None else body.transverse
                energy += 0.5 * body.mass * v_c @ v_c + 0.5 * i_t * omega @ omega
            elif e_mid.mass is not None:
                v = (e_hi.point + after[:3] - e_lo.point - before[:3]) / (2 * h)
                energy += 0.5 * e_mid.mass.mass * v @ v
                if e_mid.actuated and e_mid.mass.rotor > 0:
                    name = leg.ACTUATED_COORDINATE
                    rate = (hi.coordinates[name] - lo.coordinates[name]) / (2 * h)
                    energy += 0.5 * e_mid.mass.rotor * float(rate) ** 2
    return energy


def _platform_twist(before: np.ndarray, after: np.ndarray, h: float) -> np.ndarray:
    """The platform's twist (rate of the path parameter 1) from two poses 2h apart."""
    from scipy.spatial.transform import Rotation

    relative = P.rotation(after) @ P.rotation(before).T
    omega = Rotation.from_matrix(relative).as_rotvec() / (2 * h)
    return np.r_[omega, (after[:3] - before[:3]) / (2 * h)]


@pytest.mark.parametrize(
    ("name", "masses", "actuator"),
    [
        ("paper", {"proximal": {"mass": 0.12}, "distal": {"mass": 0.06}}, {"carriage_mass": 0.2}),
        (
            "paper",
            {"distal": {"mass": 0.06, "mass_centre": 0.08, "mass_centre_from": "end"}},
            {"carriage_mass": 0.2},
        ),
        (
            "3rrr",
            {"proximal": {"mass": 0.2, "mass_centre": 0.03}, "distal": {"mass": 0.1}},
            {"rotor_inertia": 2e-5, "gear_ratio": 50.0},
        ),
        ("3prr", {"distal": {"mass": 0.15, "inertia_transverse": 1e-3}}, {"carriage_mass": 0.3}),
        (
            "hexapod_6ups",
            {
                "cylinder": {"mass": 0.6, "mass_centre": 0.04},
                "rod": {"mass": 0.2, "mass_centre": 0.09, "mass_centre_from": "end"},
            },
            {},
        ),
        (
            "3prs",
            {"link": {"mass": 3.0}},
            {"carriage_mass": 6.0, "rotor_inertia": 1e-4, "gear_ratio": 2 * math.pi / 0.01},
        ),
        (
            "3rps",
            {"cylinder": {"mass": 1.4, "mass_centre": 0.06}, "rod": {"mass": 0.7}},
            {},
        ),
    ],
)
def test_leg_masses_against_the_kinetic_energy_along_a_trajectory(
    name: str, masses: dict[str, Any], actuator: dict[str, Any]
) -> None:
    """Rigid legs (every part 1e8 times stiffer, the actuator 1000 times softer, so the legs
    follow their inverse kinematics): the legs' t^T M t / 2 against the kinetic energy
    of their bodies from central differences of their positions at two poses of a path
    through the pose (dependent coordinates completed), h = 1e-5; a link's body moves
    rigidly with its start's body, so its centre is a material point (fixed to the
    link's end, through whose start a sliding rod passes). Residual <= 1.3e-8 (the
    finite differences' h^2 and the structure's share)."""
    design = _rigid(_with_masses(name, masses=masses, actuator=actuator))
    rng = np.random.default_rng(11)
    centre = task_values(design, home_pose(design))
    h = 1e-5
    for _ in range(3):
        direction = rng.normal(size=centre.size)
        direction /= np.linalg.norm(direction)
        at = centre + 0.2 * _task_scale(design) * rng.uniform(-1, 1, size=centre.size)
        path = np.stack([at - h * direction, at + h * direction, at])
        poses, ok = full_poses(design, path)
        assert ok.all()
        t = _platform_twist(poses[0], poses[1], h)
        legs = np.sum(leg_mass_matrices(design, poses[2]), axis=0)
        expected = _link_energy(design, poses[0], poses[1], h, poses[2])
        assert expected > 0
        assert 0.5 * t @ legs @ t == pytest.approx(expected, rel=5e-8)


# --- the loaded state -----------------------------------------------------------------------


def test_loaded_modes_use_the_tangent_k_and_the_tangent_actuators() -> None:
    """Under a wrench the modal analysis takes the loaded tangent K (symmetric) and
    builds M with the tangent actuator stiffnesses; the paper's actuator law softens, so
    the first frequency drops. Residual 0 (the same matrices)."""
    design = _with_masses(
        "paper",
        platform={"mass": 0.23, "shape": "cylinder", "radius": 0.045, "height": 0.01},
        masses={"proximal": {"mass": 0.1}, "distal": {"mass": 0.06}},
        actuator={"carriage_mass": 0.2},
    )
    wrench = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])
    locked = modal_analysis(design, link_modes=0).to_dict()
    loaded = modal_analysis(design, wrench=wrench, link_modes=0).to_dict()
    state = loaded_state(design, wrench, home_pose(design))
    k = np.array(loaded["stiffness_matrix"])
    assert np.array_equal(k, state.stiffness_matrix) and np.array_equal(k, k.T)
    m = mass_matrix_at_pose(design, None, state.actuator_stiffness)
    assert np.array_equal(np.array(loaded["mass_matrix"]), m)
    assert np.allclose(loaded["frequencies"], natural_frequencies(k, m), rtol=1e-12)
    assert loaded["frequencies"][0] < 0.9 * locked["frequencies"][0]
    assert loaded["state"] == "loaded" and locked["state"] == "locked"


# --- every example: symmetric positive definite, batched = single ------------------------


@pytest.mark.parametrize("name", example_designs(paper=True))
def test_mass_matrix_is_symmetric_positive_definite_and_batched_equals_single(
    name: str,
) -> None:
    design = _with_masses(name, masses=_uniform_links(name))
    home = home_pose(design)
    rng = np.random.default_rng(5)
    tasks = task_values(design, home) + 0.1 * _task_scale(design) * rng.uniform(
        -1, 1, size=(4, len(design.task_coordinates))
    )
    poses, ok = full_poses(design, tasks)
    assert ok.all()
    batch = mass_matrix(design, poses)
    for i in range(4):
        single = mass_matrix_at_pose(design, poses[i])
        assert np.allclose(batch[i], single, rtol=0, atol=1e-15 * np.max(np.abs(single)))
        assert np.array_equal(single, single.T)
        assert np.linalg.eigvalsh(single)[0] > 0
    k = np.array([stiffness_at_pose(design, p) for p in poses])
    f = natural_frequencies(k, batch)
    for i in range(4):
        assert np.allclose(f[i], mode_shapes(k[i], batch[i]).frequencies, rtol=1e-10)


# --- helpers ---------------------------------------------------------------------------------


def _named(name: str) -> Design:
    from helpers import design_named

    return design_named(name)


def _task_scale(design: Design) -> np.ndarray:
    """A size per task coordinate: 10 mm or 0.05 rad (within a flexure stage's required
    region: :func:`helpers.within_required`)."""
    scale = np.array([0.05 if n in ("rx", "ry", "rz") else 0.01 for n in design.task_coordinates])
    return within_required(design, scale)


def _uniform_links(name: str) -> dict[str, Any]:
    design = _named(name)
    names = {
        e.name
        for leg in design.legs
        for e in leg.chain(leg.solve(home_pose(design)))
        if isinstance(e, Link)
    }
    return {n: {"mass": 0.1} for n in names}


_MASS_KEYS = (
    "mass",
    "mass_centre",
    "mass_centre_from",
    "inertia_transverse",
    "inertia_axial",
    "carriage_mass",
    "rotor_inertia",
    "gear_ratio",
)


def _with_masses(
    name: str,
    platform: dict[str, Any] | None = None,
    masses: dict[str, Any] | None = None,
    actuator: dict[str, Any] | None = None,
) -> Design:
    """An example with its own mass model replaced by the given tables (every leg's
    part alike)."""
    data = design_to_dict(_named(name))
    data["platform"] = platform or {
        "mass": 1.0,
        "shape": "cylinder",
        "radius": 0.1,
        "height": 0.02,
    }
    tables = [*data.get("parts", {}).values()]
    for leg in data["legs"]:
        tables += [v for v in leg.values() if isinstance(v, dict)]
    for table in tables:
        for key in _MASS_KEYS:
            table.pop(key, None)
    given = {**(masses or {}), **({"actuator": actuator} if actuator else {})}
    for part, fields in given.items():
        holders = [data.get("parts", {})] + data["legs"]
        for holder in holders:
            if isinstance(holder.get(part), dict):
                holder[part] = {**holder[part], **fields}
    return design_from_dict(data)


def _rigid(design: Design) -> Design:
    """Every part's stiffness times :data:`STIFF`, the actuator's divided by 1000 (so
    that the actuator takes the motion its joint allows)."""
    data = design_to_dict(design)
    actuator = data["parts"]["actuator"]
    for key in ("locked_stiffness", "k_a"):
        actuator[key] = actuator[key] / 1000.0

    def scale(part: dict[str, Any]) -> dict[str, Any]:
        return {k: v * STIFF if k in _SPRING_KEYS else v for k, v in part.items()}

    for key, part in data.get("parts", {}).items():
        if key != "actuator":
            data["parts"][key] = scale(part)
    for leg in data["legs"]:
        for key, part in leg.items():
            if isinstance(part, dict) and key != "actuator":
                leg[key] = scale(part)
    return design_from_dict(data)
