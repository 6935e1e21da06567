"""Exact reduced form of a P-P-R leg, for fast batched evaluation.

Seen from its platform point D, everything in a P-P-R leg is rigidly attached to the
rod: the bearing C sits at ``-L w`` from D (L the rod free length), the guide block and
the proximal link a constant offset further away, and u, w, z never change. At D (axes
of F_b) the leg's spring compliance is a cubic polynomial in L plus the actuator term,
and the passive joints (hence the wrenches the leg transmits) do not depend on the pose.
For a planar design the transmitted wrenches split into one in-plane wrench and two
out-of-plane ones. :func:`reduce_leg` extracts these from the general model
(:func:`ppm_stiffness.legs.chain.leg_springs` on the P-P-R chain,
:func:`ppm_stiffness.core.beam.cantilever_compliance`)
once per design; :mod:`ppm_stiffness.maps.batch` evaluates them for many poses.

This is P-P-R knowledge, so it lives beside the leg type (a private module: the leg
registry skips it); the maps reach it only through
:meth:`ppm_stiffness.legs.base.LegModel.reduced_form`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import BeamSection, cantilever_compliance
from ppm_stiffness.core.conventions import BoolArray, FloatArray, hat
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.legs.base import LegPose
from ppm_stiffness.legs.chain import Element, leg_springs

#: Twist / wrench components of the in-plane motion (phi_z, x, y) and out-of-plane
#: motion (phi_x, phi_y, z), in the order of :mod:`ppm_stiffness.core.conventions`.
IN_PLANE = (2, 3, 4)
OUT_OF_PLANE = (0, 1, 5)
#: Columns of the distal rod cantilever in the P-P-R chain's springs.
_ROD = slice(16, 22)


class _Section(Protocol):
    def section(self) -> BeamSection: ...


class PPRGeometry(Protocol):
    """What :func:`reduce_ppr_leg` reads of a P-P-R leg
    (:class:`ppm_stiffness.legs.types.ppr.PPRLeg`), so that this module need not
    import the leg type, which imports it (no import cycle)."""

    @property
    def base_point(self) -> tuple[float, float]: ...
    @property
    def psi(self) -> float: ...
    @property
    def platform_radius(self) -> float: ...
    @property
    def bearing_offset(self) -> float: ...
    @property
    def stroke(self) -> tuple[float, float]: ...
    @property
    def rod_length_range(self) -> tuple[float, float]: ...
    @property
    def distal(self) -> _Section: ...

    def directions(self) -> tuple[FloatArray, FloatArray]: ...
    def solve(self, poses: ArrayLike) -> LegPose: ...
    def chain(self, leg_pose: LegPose) -> Sequence[Element]: ...


@dataclass(frozen=True)
class ReducedLeg:
    """Exact reduced form of one P-P-R leg (SI, axes of F_b).

    Attributes
    ----------
    base_point, u, w : ndarray (2,)
        Rail origin A [m], rail and rod directions (unit).
    psi, radius, bearing_offset : float
        Platform point angle [rad], platform radius and bearing offset [m].
    stroke, rod_length_range : tuple of float
        Actuator coordinate and rod free length limits [m].
    in_basis : ndarray (3,)
        The in-plane wrench the leg transmits, at D, components (m_z, f_x, f_y).
    in_poly : ndarray (4,)
        ``s_in(L) = sum_k in_poly[k] L^k``: its compliance without the actuator [m/N].
    in_actuator : float
        Projection ``a`` of the actuator twist; ``s_in += a**2 / k_act``.
    out_basis : ndarray (3, 2)
        Out-of-plane wrenches the leg transmits, at D, components (m_x, m_y, f_z).
    out_poly : ndarray (4, 3)
        Cubic coefficients of the 2x2 compliance block entries (00, 01, 11).
    """

    base_point: FloatArray
    u: FloatArray
    w: FloatArray
    psi: float
    radius: float
    bearing_offset: float
    stroke: tuple[float, float]
    rod_length_range: tuple[float, float]
    in_basis: FloatArray
    in_poly: FloatArray
    in_actuator: float
    out_basis: FloatArray
    out_poly: FloatArray

    def kinematics(
        self, x: ArrayLike, y: ArrayLike, phi: ArrayLike
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Platform point ``d = D - P`` (x, y parts) [m], actuator coordinate rho [m] and
        rod free length [m] at poses given as broadcastable arrays (x, y [m], phi [rad]).

        Same expressions as :meth:`ppm_stiffness.legs.types.ppr.PPRLeg.solve` (the 2x2
        solve ``D - A = rho u + (bearing_offset + rod) w``).
        """
        ang = self.psi + np.asarray(phi, dtype=float)
        dx = -self.radius * np.cos(ang)
        dy = -self.radius * np.sin(ang)
        px = (np.asarray(x, dtype=float) + dx) - self.base_point[0]
        py = (np.asarray(y, dtype=float) + dy) - self.base_point[1]
        det = self.u[0] * self.w[1] - self.u[1] * self.w[0]
        rho = (px * self.w[1] - py * self.w[0]) / det
        rod = (self.u[0] * py - self.u[1] * px) / det - self.bearing_offset
        return np.asarray(dx), np.asarray(dy), np.asarray(rho), np.asarray(rod)

    def within_limits(self, rho: ArrayLike, rod: ArrayLike) -> BoolArray:
        """Mask of the joint values inside the stroke and the rod length range."""
        r, length = np.asarray(rho), np.asarray(rod)
        return np.asarray(
            (r >= self.stroke[0])
            & (r <= self.stroke[1])
            & (length >= self.rod_length_range[0])
            & (length <= self.rod_length_range[1])
        )


def _shift_twists_to(points: FloatArray, twists: FloatArray) -> FloatArray:
    """Twists (6, m) given at P expressed at the point ``points`` (3,) relative to P."""
    t = np.eye(6)
    t[3:, :3] = -hat(points)
    return np.asarray(t @ twists)


def _null_basis(rows: FloatArray, dim: int) -> FloatArray:
    """Orthonormal basis (3, dim) of the vectors orthogonal to the columns of ``rows``."""
    if rows.shape[1] == 0:
        return np.eye(3)[:, :dim]
    u, s, _ = np.linalg.svd(rows, full_matrices=True)
    rank = int(np.sum(s > 1e-12 * max(float(s[0]), 1e-300)))
    if 3 - rank != dim:
        raise DesignError("a leg's passive joints do not have the P-P-R structure")
    return np.asarray(u[:, rank:])


def reduce_ppr_leg(leg: PPRGeometry) -> ReducedLeg:
    """Reduced form of one P-P-R leg, from the general model.

    Raises
    ------
    DesignError
        If the leg does not have the structure assumed (a compliant platform revolute,
        or a compliance that couples in-plane and out-of-plane motions).
    """
    u3, w3 = leg.directions()
    delta = 0.1  # [m] rod length step between the two evaluations (exactly linear)
    poses = np.array([[0.0, 0.0, 0.0], [delta * w3[0], delta * w3[1], 0.0]])
    geo = [leg.solve(p) for p in poses]
    springs = [leg_springs(leg.chain(g), 1.0) for g in geo]
    if springs[0].screws.shape[-1] != _ROD.stop:
        raise DesignError("the reduced P-P-R form needs a rigid platform revolute")
    lengths = [float(g.coordinates["rod"]) for g in geo]
    d_points = [g.points["D"] for g in geo]
    jd = [_shift_twists_to(d, s.screws) for d, s in zip(d_points, springs, strict=True)]
    j1 = (jd[1] - jd[0]) / (lengths[1] - lengths[0])
    j0 = jd[0] - lengths[0] * j1
    act = springs[0].actuator_index
    assert act is not None  # a P-P-R leg's first P is actuated
    c_fix = springs[0].compliance.copy()
    c_fix[act, act] = 0.0
    c_fix[_ROD, :] = 0.0
    c_fix[:, _ROD] = 0.0
    c_other = springs[1].compliance.copy()
    c_other[act, act] = 0.0
    c_other[_ROD, :] = 0.0
    c_other[:, _ROD] = 0.0
    if not np.allclose(c_other, c_fix, rtol=1e-12, atol=0.0):  # the layout assumed here
        raise DesignError("P-P-R chain: springs other than the rod depend on the pose")
    e = j0[:, act]
    j_rod = j0[:, _ROD]
    # exact cubic of the cantilever compliance: interpolate at L = 0, 1, 2, 3 m
    nodes = np.arange(4.0)
    samples = cantilever_compliance(leg.distal.section(), nodes).reshape(4, 36)
    vander = np.vander(nodes, 4, increasing=True)
    rod_poly = np.linalg.solve(vander, samples).reshape(4, 6, 6)
    poly = np.empty((4, 6, 6))
    poly[0] = j0 @ c_fix @ j0.T
    poly[1] = j1 @ c_fix @ j0.T + j0 @ c_fix @ j1.T
    poly[2] = j1 @ c_fix @ j1.T
    poly[3] = 0.0
    poly += np.einsum("ia,kab,jb->kij", j_rod, rod_poly, j_rod)

    passive = _shift_twists_to(d_points[0], springs[0].passive)
    inp, outp = list(IN_PLANE), list(OUT_OF_PLANE)
    q_in = passive[inp]
    q_out = passive[outp]
    norms = np.linalg.norm(passive, axis=0)
    is_in = np.linalg.norm(q_out, axis=0) <= 1e-12 * norms
    is_out = np.linalg.norm(q_in, axis=0) <= 1e-12 * norms
    if not np.all(is_in | is_out):
        raise DesignError("batched evaluation needs a planar design (in/out-of-plane joints)")
    w_in = _null_basis(q_in[:, is_in], 1)[:, 0]
    w_out = _null_basis(q_out[:, is_out], 2)
    scale = float(np.max(np.abs(poly)))
    mixed = np.einsum("a,kab,bj->kj", w_in, poly[:, inp][:, :, outp], w_out)
    if np.max(np.abs(mixed)) > 1e-12 * scale or np.max(np.abs(e[outp])) > 1e-12:
        raise DesignError("batched evaluation needs a planar design (coupled compliance)")
    s_in = np.einsum("a,kab,b->k", w_in, poly[:, inp][:, :, inp], w_in)
    s_out = np.einsum("ai,kab,bj->kij", w_out, poly[:, outp][:, :, outp], w_out)
    return ReducedLeg(
        base_point=np.array(leg.base_point, dtype=float),
        u=u3[:2].copy(),
        w=w3[:2].copy(),
        psi=float(leg.psi),
        radius=float(leg.platform_radius),
        bearing_offset=float(leg.bearing_offset),
        stroke=(float(leg.stroke[0]), float(leg.stroke[1])),
        rod_length_range=(float(leg.rod_length_range[0]), float(leg.rod_length_range[1])),
        in_basis=w_in,
        in_poly=s_in,
        in_actuator=float(w_in @ e[inp]),
        out_basis=w_out,
        out_poly=np.stack([s_out[:, 0, 0], s_out[:, 0, 1], s_out[:, 1, 1]], axis=1),
    )
