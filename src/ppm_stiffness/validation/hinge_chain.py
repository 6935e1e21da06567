"""A notch hinge in the FE frame: a chain of short prismatic beam members along its profile.

The virtual-joint model lumps a notch hinge (:mod:`ppm_stiffness.legs.flexure_hinge`)
into an elastic R at its centre with springs 1 / C_ii (its compliance at the centre,
diagonal for a symmetric notch). The FE frame instead builds the notch itself: ``n``
Euler-Bernoulli members, graded along it (:func:`stations`), from its base-side end
(centre - L/2 e2) to its platform-side end (centre + L/2 e2), e2 the notch's direction
(the joint's ``axis2``), each member's section the *harmonic mean* of the profile's over its length
(:func:`segment_sections`), its local y the hinge's y (e3) and local z the rotation axis
(e1). A drive in parallel with the hinge (the actuated hinge of a piezo-lever stage) is a
rotational spring about e1 between the notch's two end nodes (:func:`add_hinge`).

Why harmonic means. A prismatic member of length D and section property P has the
compliances D / (E P) (rotation), D / (E A) (axial), D / (G J) (torsion): with P the
harmonic mean of P(x) over the segment, 1 / P = (1 / D) int dx / P(x), these equal the
segment's exact integrals for any n, so C_phiz_phiz, C_phiy_phiy, C_xx and C_phix_phix
of the chain are the hinge's own. Only the transverse entries int s^k w ds (k = 1, 2;
w = 1 / (E I)) are approximated: the member puts the segment's flexibility uniformly
along it, missing the first moment int (s - s_mid) w ds = w' D^3 / 12 of each segment,
an error -(1/6) int s w' D^2 ds: second order in D = L / n, with a smooth expansion, so
that Richardson extrapolation over n and 2n removes it. Sections taken at the segment's
midpoint get no entry exactly (1 / I(x) = 12 / (b h^3) varies over a few t around a thin
notch's waist); on the 3-RRR flexure stage their error is smaller at n = 8 to 64 but
follows no clean power of n, and Richardson extrapolation does not improve it
(figures in ``docs/flexures.md``, "FE frame").

Grading. Summed over the members, the leading error of int u^2 w du (u from the notch's
centre, the only entry left inexact by a mirror-symmetric mesh of a symmetric notch)
is (1/6) int u w'(u) D(u)^2 du, one sign throughout: with n fixed it is least when D is
proportional to |u w'|^(-1/3) (:func:`stations`).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from scipy.optimize import brentq

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.chain import Joint
from ppm_stiffness.legs.flexure_hinge import FlexureHinge, torsion_constant
from ppm_stiffness.validation.frame import FrameBuilder
from ppm_stiffness.validation.joints import Placement

#: Gauss-Legendre nodes per piece (a segment's part in one profile segment).
_POINTS = 24


def _inverse(shape: object, x: float, u0: float, u1: float) -> float:
    """The profile parameter u in [u0, u1] where the segment's x(u) = x."""

    def gap(u: float) -> float:
        return float(shape(np.array([u]))[0][0]) - x  # type: ignore[operator]

    return float(brentq(gap, u0, u1, xtol=1e-15, rtol=1e-15))


#: Samples per profile segment of the table that places the stations.
_TABLE = 4001


def stations(hinge: FlexureHinge, n: int) -> FloatArray:
    """The ``n + 1`` stations x [m] of the members, from 0 to L, graded to equidistribute
    the chain's leading error (module doc): equal increments of int rho dx with
    rho = |u d(1/h^3)/dx|^(1/3) + a floor of a tenth of its mean (u = x - L/2; the floor
    keeps members finite where the section is constant: a plain leaf is meshed
    uniformly). Members are shortest on the waist's flanks, where the flexibility
    1/h^3 falls fastest at some distance from the centre, and longest at the notch's ends
    and at the waist itself (u = 0: its error has no lever arm). On the 3-RRR flexure
    stage this grading gives 0.65 times the error of members of equal depth
    int dx / h (the previous rule) or equal length (docs/flexures.md, "FE frame")."""
    xs, hs = [], []
    for u0, u1, shape in hinge.profile.segments():
        x, h, _ = shape(np.linspace(u0, u1, _TABLE))
        xs.append(np.asarray(x, float))
        hs.append(np.asarray(h, float))
    x, h = np.concatenate(xs), np.concatenate(hs)
    keep = np.concatenate([[True], np.diff(x) > 0])
    x, h = x[keep], h[keep]
    rho = np.cbrt(np.abs((x - 0.5 * hinge.length) * np.gradient(h**-3.0, x)))
    mean = float(np.mean(rho))
    rho = rho + (0.1 * mean if mean > 0.0 else 1.0)
    depth = np.concatenate([[0.0], np.cumsum(np.diff(x) * 0.5 * (rho[1:] + rho[:-1]))])
    out = np.interp(np.linspace(0.0, depth[-1], n + 1), depth, x)
    out[0], out[-1] = 0.0, hinge.length
    return np.asarray(out)


def _section_means(hinge: FlexureHinge, edges: FloatArray) -> FloatArray:
    """Means over each segment between ``edges`` [m] of 1/h, 1/h^3 and 1/J(b, h),
    shape (3, len(edges) - 1)."""
    n = len(edges) - 1
    g, gw = np.polynomial.legendre.leggauss(_POINTS)
    sums = np.zeros((3, n))
    b = hinge.width
    for u0, u1, shape in hinge.profile.segments():
        x0, x1 = (float(v) for v in shape(np.array([u0, u1]))[0])
        for k in range(n):
            lo, hi = max(edges[k], x0), min(edges[k + 1], x1)
            if hi <= lo:
                continue
            ua = u0 if lo == x0 else _inverse(shape, lo, u0, u1)
            ub = u1 if hi == x1 else _inverse(shape, hi, u0, u1)
            mid, half = 0.5 * (ua + ub), 0.5 * (ub - ua)
            _, h, dxdu = shape(mid + half * g)
            w = half * gw * dxdu
            sums[:, k] += [np.sum(w / h), np.sum(w / h**3), np.sum(w / torsion_constant(b, h))]
    return sums / np.diff(edges)


def segment_sections(
    hinge: FlexureHinge, edges: FloatArray, rule: Literal["harmonic", "midpoint"] = "harmonic"
) -> list[BeamSection]:
    """The sections of ``n`` equal members along the notch (module doc).

    Parameters
    ----------
    hinge : FlexureHinge
    edges : ndarray, shape (n + 1,)
        The members' ends x [m], from 0 to L (:func:`stations`).
    rule : {"harmonic", "midpoint"}
        Harmonic means over each segment (the default), or the profile at its midpoint
        (for comparison only).

    Returns
    -------
    list of BeamSection
        Local y = hinge y (across the thickness), local z = hinge z (the rotation axis):
        ``inertia_z`` = b h^3 / 12 (in-plane bending), ``inertia_y`` = h b^3 / 12.
    """
    mat = hinge.material
    e, g, b = mat.young_modulus, mat.shear, hinge.width
    if rule == "harmonic":
        inv_h, inv_h3, inv_j = _section_means(hinge, edges)
        area, i_z, i_y, j = b / inv_h, b / 12.0 / inv_h3, b**3 / 12.0 / inv_h, 1.0 / inv_j
    else:
        h = _thickness_at(hinge, 0.5 * (edges[1:] + edges[:-1]))
        area, i_z, i_y = b * h, b * h**3 / 12.0, h * b**3 / 12.0
        j = torsion_constant(b, h)
    return [
        BeamSection(e, g, float(area[k]), float(j[k]), float(i_y[k]), float(i_z[k]))
        for k in range(len(edges) - 1)
    ]


def _thickness_at(hinge: FlexureHinge, x: FloatArray) -> FloatArray:
    """h at stations x [m] (in [0, L])."""
    out = np.empty(len(x))
    for u0, u1, shape in hinge.profile.segments():
        x0, x1 = (float(v) for v in shape(np.array([u0, u1]))[0])
        for k, xk in enumerate(x):
            if x0 <= xk <= x1:
                out[k] = float(shape(np.array([_inverse(shape, float(xk), u0, u1)]))[1][0])
    return out


def notch_ends(joint: Joint, hinge: FlexureHinge) -> tuple[FloatArray, FloatArray]:
    """The notch's base-side and platform-side ends [m]: centre -+ L/2 along e2."""
    _, e2, _ = joint.frame()
    c = np.asarray(joint.point, dtype=float)
    half = 0.5 * hinge.length * np.asarray(e2, dtype=float)
    return c - half, c + half


def notch_points(joint: Joint, hinge: FlexureHinge, n: int) -> FloatArray:
    """The ``n + 1`` node positions of the notch's chain [m], shape (n + 1, 3)."""
    start, end = notch_ends(joint, hinge)
    s = stations(hinge, n)[:, None] / hinge.length
    return np.asarray(start + s * (end - start))


def add_hinge(
    fb: FrameBuilder,
    plan: Placement,
    before: str,
    joint: Joint,
    hinge: FlexureHinge,
    n: int,
    k_act: float,
    label: str,
    after: str | None = None,
) -> str:
    """Add the notch as ``n`` members from node ``before`` (at its base-side end) to a
    new node at its platform-side end (``after`` if given: a node there), plus the drive
    in parallel with it for an actuated joint (``k_act`` [N·m/rad] about e1). Returns
    the end node."""
    e1, _, e3 = (np.asarray(v, dtype=float) for v in joint.frame())
    points = notch_points(joint, hinge, n)
    nodes = [before] + [fb.node(q, "F") for q in points[1:-1]]
    nodes.append(fb.node(points[-1], "F") if after is None else after)
    for k, section in enumerate(segment_sections(hinge, stations(hinge, n))):
        mat = fb.material(section, "notch")  # not a design link (the modal FE's masses)
        fb.orient(fb.member(nodes[k], nodes[k + 1], mat, mat), e3)
    if joint.actuated and k_act > 0.0:
        _add_drive(fb, plan, (nodes[0], nodes[-1]), np.asarray(joint.point, float), e1, e3, k_act)
    return nodes[-1]


def _add_drive(
    fb: FrameBuilder,
    plan: Placement,
    ends: tuple[str, str],
    centre: FloatArray,
    e1: FloatArray,
    e3: FloatArray,
    k: float,
) -> None:
    """A rotational spring k [N·m/rad] about e1 between the notch's end nodes: two
    moment-only members (:meth:`FrameBuilder.moment_member`) of 2k about e1 in series
    through an auxiliary node X beside the notch (across it, along e3), X's
    translations held; the first member free about its other axes, the second holding
    X about them (no energy: X carries nothing else)."""
    pos, _ = plan.find(centre, [e3, -e3], 1, False, "hinge drive")
    plan.add_point(pos)
    x_node = fb.node(pos, "X")
    fb.support(x_node, "DX DY DZ")
    for node, free in ((ends[0], (True, True, False)), (ends[1], (False, False, False))):
        start = fb.position(node)
        plan.add_segment(start, pos)
        axis = (pos - start) / np.linalg.norm(pos - start)
        y_axis = np.cross(e1, axis)
        fb.moment_member(node, x_node, (axis, y_axis), np.full(3, 2.0 * k), free)
