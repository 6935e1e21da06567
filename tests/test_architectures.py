"""Every architecture through the same chain builder: tests that catch a wrong model.

- the rigid-link limit (Gosselin 1990): K -> J^T K_a J when everything but the
  actuators is rigid, to O(eps);
- symmetry, positive definiteness and frame (rotation) equivariance at seeded random
  reachable poses of every shipped design;
- equivalence of the chain-built 3-PPR with the hand-written P-P-R springs;
- a rail-rod angle other than 90 deg against an independent geometry computation;
- the tool point: power invariance and rigid-body transport.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import legacy_ppr
from helpers import flexure_jointed, within_required
from ppm_stiffness.analysis import analyze_design
from ppm_stiffness.core.conventions import length_balanced, rotation_z, twist_b_from_twist_a
from ppm_stiffness.core.pose import pose_from_rotation, rotation
from ppm_stiffness.core.solver import cartesian_stiffness
from ppm_stiffness.design import Design, default_design, design_from_dict, load_design
from ppm_stiffness.legs.types.chain_leg import turned_leg
from ppm_stiffness.model import (
    leg_springs_at_pose,
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
)
from ppm_stiffness.poses import full_poses, home_pose, task_indices

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SHIPPED = {
    "paper_3ppr": default_design(),
    **{p.stem: load_design(p) for p in sorted(EXAMPLES.glob("*.toml"))},
}


def random_reachable_poses(design: Design, n: int, seed: int) -> np.ndarray:
    """Seeded reachable, nonsingular full poses (n, 6) around the home pose: task
    coordinates within 20 mm and 0.2 rad (0.05 rad for a design with six; a twentieth for
    a flexure-jointed design), completed."""
    rng = np.random.default_rng(seed)
    home = home_pose(design)
    task = list(task_indices(design))
    angle = 0.05 if len(task) == 6 else 0.2
    spans = np.array([0.02, 0.02, 0.02, angle, angle, angle])[task]
    if flexure_jointed(design):  # its flexures' range: a twentieth, within its region
        spans = within_required(design, spans * 0.05)
    out: list[np.ndarray] = []
    for _ in range(200 * n):
        full, ok = full_poses(design, home[task] + rng.uniform(-1, 1, len(task)) * spans)
        if ok and all(bool(leg.reachable(leg.solve(full))) for leg in design.legs):
            out.append(full)
            if len(out) == n:
                break
    assert len(out) == n, "too few reachable poses near the centre"
    return np.array(out)


def rel_diff_balanced(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| on the length-balanced matrices."""
    return float(np.max(np.abs(length_balanced(a - b))) / np.max(np.abs(length_balanced(b))))


# ------------------------------------------------------------------ rigid-link limit
K_LEG = 2.0e6  # actuator stiffness along each leg [N/m]
R_BASE, R_PLATFORM, PHI_HOME = 0.25, 0.06, math.radians(25.0)


def symmetric_3rpr(eps: float) -> Design:
    """A 3-fold symmetric 3-RPR (legs 120 deg apart, platform joints aligned with the
    base joints at phi = 0) whose every compliance but the actuators' is scaled by eps."""
    soft = 1.0 / eps
    section = {
        "young_modulus": 70e9 * soft,
        "shear_modulus": 26e9 * soft,
        "area": 1e-4,
        "torsion_constant": 1e-8,
        "inertia_y": 5e-9,
        "inertia_z": 5e-9,
    }
    revolute = {"tilt": 4e3 * soft, "axial": 1e7 * soft, "radial": 2e7 * soft}
    legs = []
    for i in range(3):
        th = math.radians(90 + 120 * i)
        legs.append(
            {
                "type": "RPR",
                "base_point": [R_BASE * math.cos(th), R_BASE * math.sin(th)],
                "psi": math.remainder(th + math.pi, 2 * math.pi),
                "platform_radius": R_PLATFORM,
                "housing_length": 0.05,
                "stroke": [0.06, 0.4],
                "base_revolute": revolute,
                "platform_revolute": revolute,
            }
        )
    return design_from_dict(
        {
            "schema": 2,
            "name": f"rigid-limit 3-RPR, eps = {eps:g}",
            "parts": {
                "actuator": {
                    "locked_stiffness": K_LEG,
                    "k_a": K_LEG,
                    "q": 1.0,
                    "threshold_displacement": 0.0,
                },
                "guide": {
                    k: v * soft
                    for k, v in {
                        "roll": 4700.0,
                        "pitch": 1700.0,
                        "yaw": 1700.0,
                        "lateral": 2.5e6,
                        "vertical": 5.1e6,
                    }.items()
                },
                "proximal": section,
                "distal": section,
            },
            "legs": legs,
        }
    )


def gosselin_planar() -> np.ndarray:
    """J^T K_a J (phi_z, x, y) of the rigid 3-RPR at (0, 0, PHI_HOME): each leg a unit
    force along its line A_i -> D_i with signed moment arm m_i = (D_i x e_i)_z."""
    k = np.zeros((3, 3))
    for i in range(3):
        th = math.radians(90 + 120 * i)
        a = R_BASE * np.array([math.cos(th), math.sin(th)])
        d = R_PLATFORM * np.array([math.cos(th + PHI_HOME), math.sin(th + PHI_HOME)])
        e = (d - a) / np.linalg.norm(d - a)
        row = np.array([d[0] * e[1] - d[1] * e[0], e[0], e[1]])
        k += K_LEG * np.outer(row, row)
    return k


def test_gosselin_reference_is_the_textbook_symmetric_case() -> None:
    """The reference itself: K_xx = K_yy = 3k/2, K_xy = K_x phi = K_y phi = 0,
    K_phi phi = 3 k m^2 (m: distance from P to a leg line)."""
    k = gosselin_planar()
    th = math.radians(90)
    a = R_BASE * np.array([math.cos(th), math.sin(th)])
    d = R_PLATFORM * np.array([math.cos(th + PHI_HOME), math.sin(th + PHI_HOME)])
    e = (d - a) / np.linalg.norm(d - a)
    m = abs(d[0] * e[1] - d[1] * e[0])
    assert m > 0.01  # a rotated home pose: the legs do not pass through P
    np.testing.assert_allclose(
        k, np.diag([3 * K_LEG * m**2, 1.5 * K_LEG, 1.5 * K_LEG]), atol=1e-9 * K_LEG
    )


def test_rigid_link_limit_is_reached_at_order_eps() -> None:
    """Scaling every compliance but the actuators' by eps, the planar block of K tends
    to Gosselin's J^T K_a J with an error proportional to eps (ratio 10 per decade)."""
    ref = gosselin_planar()
    scale = np.array([1 / 0.1, 1.0, 1.0])  # length-balanced (phi_z at 0.1 m)
    errors = []
    for eps in (1e-3, 1e-4, 1e-5):
        k = stiffness_at_pose(symmetric_3rpr(eps), [0.0, 0.0, PHI_HOME])
        planar = k[np.ix_([2, 3, 4], [2, 3, 4])]
        diff = (planar - ref) * scale[:, None] * scale[None, :]
        errors.append(float(np.max(np.abs(diff)) / np.max(np.abs(ref * scale[:, None] * scale))))
    # measured: 2.56e-4, 2.56e-5, 2.56e-6 (the structure is ~0.26x as compliant as
    # the actuators at eps = 1): first order in eps
    assert errors[-1] < 5e-6
    for coarse, fine in zip(errors[:-1], errors[1:], strict=True):
        assert 9.0 < coarse / fine < 11.0


# ------------------------------------------------- properties on every shipped design
@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_symmetric_positive_definite_at_random_poses(name: str) -> None:
    design = SHIPPED[name]
    for pose in random_reachable_poses(design, 8, seed=11):
        k = stiffness_at_pose(design, pose)
        kb = length_balanced(k)
        assert np.max(np.abs(kb - kb.T)) <= 1e-12 * np.max(np.abs(kb))
        assert np.linalg.eigvalsh(kb)[0] > 0


#: Leg fields that are points or directions fixed in F_b (they turn with the base).
BASE_VECTORS = ("base_point", "rail_direction", "revolute_axis", "base_joint_axis")


def rotated(design: Design, angle: float) -> Design:
    """The whole design turned by ``angle`` about the z axis of F_b through its origin:
    base points and base directions rotate; every angle measured from the x axis of F_b
    (rails and a rotary actuator's stroke) grows by ``angle``; platform attachments
    (psi, platform points and axes) are in the platform frame and turn with the pose;
    a chain leg's elements, given in F_b at the home pose, turn with it (their strokes
    are from home)."""
    r = rotation_z(angle)
    data = design.model_dump()
    for leg_data, leg in zip(data["legs"], design.legs, strict=True):
        if leg.type == "chain":  # every point and axis of its elements is in F_b at home
            leg_data.update(turned_leg(leg_data, r))
            continue
        for key in BASE_VECTORS:
            if key in leg_data:
                v = np.zeros(3)
                v[: len(leg_data[key])] = leg_data[key]
                leg_data[key] = tuple((r @ v)[: len(leg_data[key])])
        if "alpha" in leg_data:
            leg_data["alpha"] = math.remainder(leg_data["alpha"] + angle, 2 * math.pi)
        if leg.coordinate(leg.ACTUATED_COORDINATE).unit == "rad":
            lo, hi = leg_data["stroke"]
            leg_data["stroke"] = (lo + angle, hi + angle)
    ws = data["workspace"]
    ws["centre_x"], ws["centre_y"], _ = r @ [ws["centre_x"], ws["centre_y"], 0.0]
    ws["phi"] += angle
    ws["required"] = None  # a region over rx, ry does not turn with the machine
    return design_from_dict(data)


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_frame_equivariance(name: str) -> None:
    """Turning the whole machine and its pose by gamma turns K: K' = T K T^T with
    T = blockdiag(R, R) (rotations and translations both rotate)."""
    design = SHIPPED[name]
    gamma = 0.7
    turned = rotated(design, gamma)
    r = rotation_z(gamma)
    t = np.zeros((6, 6))
    t[:3, :3] = t[3:, 3:] = r
    for pose in random_reachable_poses(design, 4, seed=5):
        moved = pose_from_rotation(r @ pose[:3], r @ rotation(pose))
        k = stiffness_at_pose(design, pose)
        k_turned = stiffness_at_pose(turned, moved)
        assert rel_diff_balanced(k_turned, t @ k @ t.T) < 1e-10


# ------------------------------------------------------------- the P-P-R equivalence
@pytest.mark.parametrize(
    "name", [n for n, d in SHIPPED.items() if all(leg.type == "PPR" for leg in d.legs)]
)
def test_chain_built_ppr_equals_the_hand_written_springs(name: str) -> None:
    design = SHIPPED[name]
    for pose in random_reachable_poses(design, 10, seed=3):
        chain = cartesian_stiffness(leg_springs_at_pose(design, pose))
        planar = pose[[0, 1, 5]]
        hand = cartesian_stiffness([legacy_ppr.leg_springs(leg, planar) for leg in design.legs])
        assert rel_diff_balanced(chain, hand) <= 1e-9


# ------------------------------------------------------------ rail-rod angle != 90 deg
@pytest.mark.parametrize("beta_deg", [-80.0, -60.0, -110.0])
def test_oblique_rod_geometry_against_line_intersection(beta_deg: float) -> None:
    """With beta != +-90 deg, C must lie on the rod line through D (the old orthogonal
    projection put the bearing 27.7 mm off it at beta = -80 deg): an independent
    computation intersects the rail-offset line A + bearing_offset w + rho u with the
    rod line D - s w by least squares."""
    data = SHIPPED["symmetric_3ppr"].model_dump()
    for leg in data["legs"]:
        leg["beta"] = math.radians(beta_deg)
        leg["stroke"] = (-1.0, 1.0)
        leg["rod_length_range"] = (1e-4, 1.0)
    design = design_from_dict(data)
    pose = np.array([0.004, -0.003, 0.05])
    for leg in design.legs:
        lp = leg.solve(pose)
        u, w = leg.directions()
        a = np.array([*leg.base_point, 0.0]) - np.array([pose[0], pose[1], 0.0])
        d = lp.points["D"]
        # a + bo w + rho u = d - s w  ->  [u, w] [rho, s + bo] = d - a (least squares)
        sol, *_ = np.linalg.lstsq(np.stack([u[:2], w[:2]], axis=1), (d - a)[:2], rcond=None)
        rho, along = sol
        assert float(lp.coordinates["rho"]) == pytest.approx(rho, abs=1e-12)
        assert float(lp.coordinates["rod"]) == pytest.approx(along - leg.bearing_offset, abs=1e-12)
        c = lp.points["C"]
        off_line = np.linalg.norm(np.cross(w, d - c))
        assert off_line < 1e-12
    # and the stiffness at the pose is still symmetric positive definite
    k = stiffness_at_pose(design, pose)
    assert np.linalg.eigvalsh(length_balanced(k))[0] > 0


# --------------------------------------------------------------------- tool point
@pytest.mark.parametrize("name", list(SHIPPED))
def test_tool_point_power_invariance_and_transport(name: str) -> None:
    """K at a tool point T is the same spring seen from T: for any small platform
    motion the stored energy t_T . K_T t_T equals t_P . K_P t_P (t_T = X t_P, the
    twist of the same motion at T); and the deflection of T under a wrench applied at
    T is what a rigid platform carries from P."""
    design = SHIPPED[name]
    pose = random_reachable_poses(design, 1, seed=2)[0]
    tool = np.array([0.02, -0.01, 0.05])  # platform frame [m]
    k_p = stiffness_at_pose(design, pose)
    k_t = stiffness_at_tool_point(k_p, pose, tool)
    offset = tool_offset(pose, tool)
    x = twist_b_from_twist_a(np.eye(3), -offset)  # twist at P -> twist at T
    rng = np.random.default_rng(0)
    for _ in range(3):
        t_p = np.concatenate([rng.normal(size=3) * 1e-3, rng.normal(size=3) * 1e-4])
        t_t = x @ t_p
        assert t_t @ k_t @ t_t == pytest.approx(t_p @ k_p @ t_p, rel=1e-10)
    # (m, f) at T, small enough that every actuator stays on its linear (locked) branch
    wrench_t = np.array([0.0, 0.0, 0.01, 1.0, -0.5, 0.5])
    res = analyze_design(design, pose, wrench_t, tool_point=tool).to_dict()
    np.testing.assert_allclose(res["stiffness_matrix"], k_t, rtol=1e-12, atol=0)
    twist_t = np.linalg.solve(k_t, wrench_t)
    # every actuator stays locked, so the deflection is exactly K_T^-1 w_T (round-off)
    np.testing.assert_allclose(
        res["twist"], twist_t, rtol=1e-10, atol=1e-12 * np.max(np.abs(twist_t))
    )


@pytest.mark.parametrize("name", ["paper_3ppr", "3rpr"])
def test_map_at_a_tool_point_equals_the_single_pose_analysis(name: str) -> None:
    """map's principal stiffnesses at a tool point are those of analyze at that point."""
    from ppm_stiffness.maps.workspace import stiffness_map

    design = SHIPPED[name]
    tool = np.array([0.015, 0.01, 0.03])
    phi = float(design.workspace.phi) + 0.1
    smap = stiffness_map(design, phi=phi, grid=6, tool_point=tool)
    iy, ix = np.argwhere(smap.reachable)[len(np.argwhere(smap.reachable)) // 2]
    pose = np.array([smap.x[ix], smap.y[iy], phi])
    res = analyze_design(design, pose, tool_point=tool).to_dict()
    assert float(smap.k_phi[iy, ix]) == pytest.approx(
        res["principal"]["rotational"]["values"][2], rel=1e-9
    )
    assert float(smap.k_x[iy, ix]) == pytest.approx(
        res["principal"]["translational"]["values"][0], rel=1e-9
    )
    at_p = stiffness_map(design, phi=phi, grid=6)
    assert not np.allclose(at_p.k_phi.compressed(), smap.k_phi.compressed(), rtol=1e-3)


# ------------------------------------------------------------------- working modes
@pytest.mark.parametrize("name", ["3prr", "3rrr"])
def test_both_working_modes_solve_the_loop_closure(name: str) -> None:
    """Each branch gives a configuration that closes the leg's loop (link lengths met),
    and the two branches differ: P-R-R puts D ahead of / behind the carriage along the
    rail, R-R-R puts the elbow left / right of the line A -> D."""
    from ppm_stiffness.legs.chain import Link

    design = SHIPPED[name]
    pose = np.array([0.01, -0.005, 0.05])
    for leg in design.legs:
        sides = []
        for branch in (1, -1):
            other = leg.model_copy(update={"branch": branch})
            lp = other.solve(pose)
            assert bool(lp.solvable)
            links = [e for e in other.chain(lp) if isinstance(e, Link)]
            lengths = [
                float(np.linalg.norm(np.asarray(e.end) - np.asarray(e.start))) for e in links
            ]
            expected = (
                [leg.link_length] if name == "3prr" else [leg.proximal_length, leg.distal_length]
            )
            np.testing.assert_allclose(lengths, expected, rtol=0, atol=1e-12)
            d, c = lp.points["D"], lp.points["C"]
            if name == "3prr":
                sides.append(float((d - c) @ other.rail_direction()))
            else:
                a = lp.points["A"]
                sides.append(float(np.cross(d - a, c - a)[2]))
        assert sides[0] > 0 > sides[1]


def test_out_of_reach_pose_is_refused() -> None:
    from ppm_stiffness.core.errors import UnreachablePoseError

    with pytest.raises(UnreachablePoseError, match="out of the leg's reach"):
        stiffness_at_pose(SHIPPED["3rrr"], [0.4, 0.0, 0.0])
    with pytest.raises(UnreachablePoseError, match="outside"):
        stiffness_at_pose(SHIPPED["3rpr"], [0.0, 0.2, 0.0])
