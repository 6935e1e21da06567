"""A link body whose centre of mass lies outside its link (issue 27, item 1): it moves
rigidly with the section at the nearer end (docs/dynamics.md, "The mass matrix").

The reference is the body's kinetic energy built by hand from that end's twist (rigid
body kinematics, no shape function): ``v_c = v + omega x c`` with (omega, v) the end's
twist at P and c the centre from P, ``T = (m |v_c|^2 + omega^T I omega) / 2``."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.design import load_design
from ppm_stiffness.dynamics.condensation import leg_mass_matrix, leg_motion
from ppm_stiffness.dynamics.links import link_mass_matrix
from ppm_stiffness.legs.chain import Link, LinkMass
from ppm_stiffness.poses import home_pose

ROOT = Path(__file__).parents[1]

SECTION = BeamSection(
    young_modulus=2.1e11,
    shear_modulus=8.1e10,
    area=1e-4,
    torsion_constant=2e-9,
    inertia_y=1e-9,
    inertia_z=1e-9,
)


def _rigid_energy(twist: np.ndarray, centre: np.ndarray, axis: np.ndarray, body: LinkMass) -> float:
    """Kinetic energy [J] of a rigid body with the twist (omega, v at P) (6,), its centre
    ``centre`` (3,) from P, inertia axisymmetric about ``axis`` (unit, 3,)."""
    omega, v = twist[:3], twist[3:]
    v_c = v + np.cross(omega, centre)
    assert body.transverse is not None
    inertia = body.transverse * np.eye(3) + (body.axial - body.transverse) * np.outer(axis, axis)
    return float(0.5 * body.mass * v_c @ v_c + 0.5 * omega @ inertia @ omega)


@pytest.mark.parametrize(
    ("centre", "from_end"),
    [
        (0.25, True),  # 0.05 m behind the start (a rod's centre inside its cylinder)
        (0.45, True),  # 0.25 m behind the start
        (0.31, False),  # 0.11 m past the end
    ],
)
def test_a_body_outside_its_link_moves_rigidly_with_that_end(centre: float, from_end: bool) -> None:
    """Random link geometry (0.2 m long) and random (elastic) maps from the platform
    twist to its start's and end's twists: 0.5 t^T M t equals the rigid body's energy
    built from the twist of the end it lies beyond, for random t. Before the rigid
    continuation the body rode on the cantilever cubic extrapolated past the end
    (4.17 J against 2.59 J in the first draw); largest residual 4.7e-15 relative."""
    rng = np.random.default_rng(27)
    length = 0.2
    body = LinkMass(mass=0.3, centre=centre, from_end=from_end, transverse=2e-3, axial=4e-4)
    s = length - centre if from_end else centre  # from the start [m]
    for _ in range(5):
        start = rng.normal(scale=0.1, size=3)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        link = Link(start, start + length * direction, SECTION, name="rod", mass=body)
        start_twist, end_twist = rng.normal(size=(2, 6, 6))
        m = link_mass_matrix(link, start_twist, end_twist)
        near = start_twist if s < 0 else end_twist
        for _ in range(4):
            t = rng.normal(size=6)
            expected = _rigid_energy(near @ t, start + s * direction, direction, body)
            assert 0.5 * t @ m @ t == pytest.approx(expected, rel=1e-13)


def test_a_struts_rod_inside_its_cylinder_moves_with_the_guide_section() -> None:
    """The shipped hexapod's rod (0.2442 kg, centre 0.1228 m from its S joint, 0.0796 m
    free at home: xi = -0.54), alone in its leg's chain: the leg's condensed mass
    matrix equals the rod's energy built from the twist of the body before it (the
    cylinder with the guide's springs: the rod's clamp section at C), at 5 random
    platform twists. The leg's springs make the twists of C and B differ (the
    cubic extrapolated behind C gave 0.0495 J against 0.0496 J at the first twist).
    Largest residual 8.9e-16 relative."""
    design = load_design(ROOT / "examples" / "hexapod_6ups.toml")
    leg = design.legs[0]
    chain = list(leg.chain(leg.solve(home_pose(design))))
    rod = next(i for i, e in enumerate(chain) if isinstance(e, Link) and e.name == "rod")
    chain = [replace(e, mass=None) if i != rod else e for i, e in enumerate(chain)]
    body = chain[rod].mass
    assert body is not None and body.from_end and body.centre is not None
    k_act = leg.actuator.locked_stiffness
    m = leg_mass_matrix(chain, k_act)
    motion = leg_motion(chain, k_act, [rod])
    start, end = chain[rod].start, chain[rod].end
    n = (end - start) / np.linalg.norm(end - start)
    centre = end - body.centre * n
    assert (centre - start) @ n < 0  # behind the guide, inside the cylinder
    assert body.transverse is not None  # the shipped rod gives its inertia
    rng = np.random.default_rng(5)
    assert np.max(np.abs(motion.before[rod] - motion.after[rod])) > 1e-3  # elastic
    for _ in range(5):
        t = rng.normal(size=6)
        expected = _rigid_energy(motion.before[rod] @ t, centre, n, body)
        assert 0.5 * t @ m @ t == pytest.approx(expected, rel=1e-12)
