"""A leg's joint chain as a product of exponentials of unit screws (moving geometry).

The virtual-joint model (:mod:`ppm_stiffness.legs.chain`) gives a leg's springs and
passive joints at one configuration. When the geometry moves under load every
coordinate of the chain -- each virtual spring's deflection and each passive joint's
displacement -- moves the bodies after it, and the leg's last body (the platform) is
displaced, from the reference configuration, by

    g(x) = exp(s_1^ x_1) exp(s_2^ x_2) ... exp(s_n^ x_n)

with ``s_k`` the unit twists of the coordinates at the reference configuration, in chain
order from the base (the "spatial" product of exponentials; twists about a point c0
fixed in F_b, axes of F_b, rotation first as in :mod:`ppm_stiffness.core.conventions`).
``g = (R, p)`` maps a point X (relative to c0) to ``R X + p``: p is the displacement of
the body point that was at c0.

Coordinates, in chain order (:func:`screw_chain`):

- a **link**: its six tip springs (rotation about its local x, y, z and translation along
  x, y, z at its end), with the cantilever compliance of eq. (3c);
- an **actuated joint**: the actuator along its freedom, then the joint's hardware springs
  (they ride on the moving part: a carriage's guide block);
- a **passive joint**: its hardware springs, then its freedoms (the bearing's
  compliance tilts the axis the joint turns about);
- an **elastic joint** (a flexure): its hardware springs, then its freedoms, with
  their stiffnesses (``ScrewChain.elastic``: the equilibrium holds them in stiffness
  form, never as ``1/k``), at rest at the reference configuration: the preload of a
  flexure bent away from home is not carried (as in the frozen K);
- an **actuated elastic joint** (a drive in parallel with a flexure: a piezo stack on
  a notch hinge's lever): one actuator column whose generalised force is the drive's
  plus the flexure's, ``tau = G + k_h x`` with ``x = delta(G)`` the drive's law
  (``ScrewChain.parallel``: k_h, the flexure resting at the reference configuration,
  like the elastic joints').

At x = 0 the columns are exactly those of :func:`ppm_stiffness.legs.chain.leg_springs`
(reordered): the order changes nothing to first order, only the second derivatives.

Derivatives (:func:`forward`): the twist of coordinate k at x is
``J_k = Ad(g_1 ... g_{k-1}) s_k`` (the spatial Jacobian, about c0), and
``dJ_k / dx_l = [J_l, J_k]`` for l < k (0 for l >= k), with the Lie bracket of twists
``[a, b] = (w_a x w_b, w_a x v_b - w_b x v_a)`` (:func:`bracket`). So the Hessian of
``w . (position)`` along the chain is made of brackets (:func:`bracket_form`); the tests
check both against finite differences of :func:`forward`.

Every array has one leading batch axis (k,): k configurations of one leg.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.pose import rotation_exp
from ppm_stiffness.legs.chain import (
    Element,
    Joint,
    Link,
    check_chain,
    constrained_screws,
    elastic_stiffnesses,
    freedom_count,
    freedom_screws,
    link_screws,
)
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.legs.parts import ActuatorModel


@dataclass(frozen=True)
class BarPair:
    """Two bars with ball joints at both ends (a parallelogram's) between a chain's
    last body and the platform, at k reference configurations: two-force members whose
    axial forces N (tension positive) are two more coordinates of the leg
    (:func:`ppm_stiffness.statics.moving_core.linearize_bar_leg`).

    Attributes
    ----------
    near, far : ndarray (k, 2, 3) [m]
        The bars' ends on the chain's last body and on the platform at the reference
        configuration, relative to the reference point c0, axes of F_b.
    rest : ndarray (k, 2) [m]
        The bars' unloaded lengths (their lengths at the reference configuration).
    compliance : float [m/N]
        One bar's axial compliance (0: rigid).
    """

    near: FloatArray
    far: FloatArray
    rest: FloatArray
    compliance: float

    def take(self, index: np.ndarray) -> BarPair:
        """The configurations ``index``."""
        return replace(self, near=self.near[index], far=self.far[index], rest=self.rest[index])


@dataclass(frozen=True)
class ScrewChain:
    """One leg's coordinates at k reference configurations (module doc).

    Attributes
    ----------
    screws : ndarray (k, 6, n)
        Unit twists of the coordinates at the reference configuration, about the
        reference point c0, axes of F_b, chain order.
    compliance : ndarray (k, n, n)
        Compliance of the linear springs in their coordinates (block diagonal:
        ``1/k`` of a joint spring, 0 for a rigid one, eq. 3c for a link's six); zero
        rows and columns for the passive joints and for the actuator.
    passive : ndarray of bool (n,)
        The coordinates that are passive joints' freedoms (they carry no load).
    actuator : int or None
        Column of the actuator, whose deflection follows ``law``; None: no actuator
        (a chain of linear springs only).
    law : ActuatorModel or None
        The actuator law (:mod:`ppm_stiffness.statics.actuator`).
    elastic : ndarray (n,) or None
        The stiffness of each elastic coordinate (a flexure's freedom) [N·m/rad or N/m],
        0 for the others; their compliance rows are zero: they enter the equilibrium
        in stiffness form, ``tau_e = k x_e``. None: none.
    parallel : float
        The elastic stiffness k_h in parallel with the actuator (its joint's elastic
        stiffness) [N·m/rad or N/m], 0 without: the actuator column carries
        ``G + k_h x`` (module doc).
    bars : BarPair or None
        Two bars from the chain's last body to the platform (a parallelogram's): the
        leg's closure is their lengths, not the last body's pose, and their axial
        forces are the last two coordinates (``n`` counts them; ``screws``,
        ``compliance`` and ``passive`` are the chain's without them). None: the last
        body is the platform.
    rotational : ndarray of bool (n,)
        The coordinates that are rotations (unit rotation part), the others are
        translations: a generalised force is in N·m or N accordingly.
    """

    screws: FloatArray
    compliance: FloatArray
    passive: BoolArray
    actuator: int | None = None
    law: ActuatorModel | None = None
    elastic: FloatArray | None = None
    parallel: float = 0.0
    bars: BarPair | None = None

    @property
    def size(self) -> int:
        """The number of configurations k."""
        return int(self.screws.shape[0])

    @property
    def n(self) -> int:
        """The number of coordinates (with two bars' axial forces)."""
        return int(self.screws.shape[-1]) + (0 if self.bars is None else 2)

    @property
    def rotational(self) -> BoolArray:
        return np.asarray(np.linalg.norm(self.screws[0, :3, :], axis=0) > 0.5)

    def shifted(self, offset: ArrayLike) -> ScrewChain:
        """The same chain with its twists about ``c0 + offset`` (offset (k, 3) or (3,)
        [m], axes of F_b): ``v' = v + w x offset``; its bars' ends, if any, relative to
        the new point."""
        d = np.broadcast_to(np.asarray(offset, dtype=float), (self.size, 3))
        s = self.screws.copy()
        s[:, 3:, :] += cross(np.swapaxes(s[:, :3, :], 1, 2), d[:, None, :]).swapaxes(1, 2)
        if self.bars is None:
            return replace(self, screws=s)
        near, far = self.bars.near - d[:, None, :], self.bars.far - d[:, None, :]
        return replace(self, screws=s, bars=replace(self.bars, near=near, far=far))


def screw_chain(
    chain: Sequence[Element], law: ActuatorModel | None, size: int, reference: ArrayLike = 0.0
) -> ScrewChain:
    """A leg's coordinates (module doc) from its joint chain at k configurations.

    Parameters
    ----------
    chain : sequence of Joint and Link
        Base to platform (:meth:`ppm_stiffness.legs.base.LegModel.chain`); points
        relative to P, axes of F_b, each (k, 3) or (3,).
    law : ActuatorModel or None
        The actuated joint's law.
    size : int
        k.
    reference : array_like (k, 3) or (3,)
        The reference point c0 relative to P [m]: the twists are taken about it.

    Returns
    -------
    ScrewChain
    """
    check_chain(chain)
    k = size
    columns: list[FloatArray] = []
    blocks: list[FloatArray | None] = []  # None: a passive or actuator column
    passive: list[bool] = []
    stiffness: list[float] = []  # per column: an elastic coordinate's stiffness, else 0
    actuator = None
    parallel = 0.0
    for element in chain:
        if isinstance(element, Link):
            screws, length = link_screws(element)
            columns.append(np.broadcast_to(screws, (k, 6, 6)))
            blocks.append(
                np.broadcast_to(cantilever_compliance(element.section, length), (k, 6, 6))
            )
            passive += [False] * 6
            continue
        free = np.broadcast_to(freedom_screws(element), (k, 6, freedom_count(element)))
        springs = _joint_springs(element, k)
        elastic = elastic_stiffnesses(element)
        if element.actuated:
            parallel = 0.0 if elastic is None else float(elastic[0])
            actuator = sum(c.shape[-1] for c in columns)
            columns.append(free[..., :1])
            blocks.append(None)
            passive.append(False)
        if springs is not None:
            columns.append(springs[0])
            blocks.append(springs[1])
            passive += [False] * springs[0].shape[-1]
        if elastic is not None and not element.actuated:  # a flexure: k, resting here
            columns.append(free)
            blocks += [None] * free.shape[-1]
            passive += [False] * free.shape[-1]
            stiffness += [0.0] * (len(passive) - len(stiffness) - free.shape[-1])
            stiffness += elastic.tolist()
        elif not element.actuated:
            columns.append(free)
            blocks += [None] * free.shape[-1]
            passive += [True] * free.shape[-1]
    screws = np.concatenate(columns, axis=-1)
    n = screws.shape[-1]
    compliance = np.zeros((k, n, n))
    i = 0
    for block in blocks:
        if block is None:
            i += 1
            continue
        m = block.shape[-1]
        compliance[:, i : i + m, i : i + m] = block
        i += m
    stiffness += [0.0] * (n - len(stiffness))
    elastic_k = np.array(stiffness) if any(stiffness) else None
    chain_out = ScrewChain(
        np.array(screws), compliance, np.array(passive), actuator, law, elastic_k, parallel
    )
    return chain_out.shifted(reference)


def _joint_springs(joint: Joint, k: int) -> tuple[FloatArray, FloatArray] | None:
    """A joint's hardware springs: unit twists (k, 6, c) and compliance (k, c, c)
    (``1/k``; 0 for an ``inf`` spring), or None for a joint without springs."""
    if joint.springs is None:
        return None
    c = joint_kind(joint.kind).constrained_count
    stiff = np.broadcast_to(np.asarray(joint.springs, dtype=float), (k, c))
    screws = np.broadcast_to(constrained_screws(joint), (k, 6, c))
    return screws, np.eye(c) / stiff[:, None, :]


def cross(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """``a x b`` along the last axis (broadcast), without numpy.cross's overhead."""
    x = np.asarray(a, dtype=float)
    y = np.asarray(b, dtype=float)
    x0, x1, x2 = x[..., 0], x[..., 1], x[..., 2]
    y0, y1, y2 = y[..., 0], y[..., 1], y[..., 2]
    return np.stack([x1 * y2 - x2 * y1, x2 * y0 - x0 * y2, x0 * y1 - x1 * y0], axis=-1)


def se3_exp(twists: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """``exp`` of twists (..., 6) = (w, v) (v: the velocity of the point at the origin):
    rotation (..., 3, 3) and translation (..., 3), ``X -> R X + p``.

    ``p = V(w) v`` with ``V = I + (1 - cos a)/a^2 w^ + (a - sin a)/a^3 w^2``, a = |w|
    (series near a = 0).
    """
    t = np.asarray(twists, dtype=float)
    w, v = t[..., :3], t[..., 3:]
    a = np.linalg.norm(w, axis=-1)
    small = a < 1e-5
    safe = np.where(small, 1.0, a)
    c1 = np.where(small, 0.5 - a**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    c2 = np.where(small, 1.0 / 6.0 - a**2 / 120.0, (safe - np.sin(safe)) / safe**3)
    wv = cross(w, v)
    p = v + c1[..., None] * wv + c2[..., None] * cross(w, wv)
    return rotation_exp(w), np.asarray(p)


def rotation_log(rotation: ArrayLike) -> FloatArray:
    """The rotation vector (..., 3) [rad] of rotations (..., 3, 3): ``exp(hat(r)) = R``,
    ``|r| <= pi``. Closed form from the skew part, ``theta = atan2(|v|, (tr R - 1)/2)``
    and ``r = v theta / |v|`` (``v`` the axial vector of ``(R - R^T)/2``); within 0.1 rad
    of a half turn, where that loses digits, scipy's."""
    r = np.asarray(rotation, dtype=float)
    v = 0.5 * np.stack(
        [r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0], r[..., 1, 0] - r[..., 0, 1]],
        axis=-1,
    )
    s = np.sqrt(np.einsum("...i,...i->...", v, v))
    c = 0.5 * (r[..., 0, 0] + r[..., 1, 1] + r[..., 2, 2] - 1.0)
    theta = np.arctan2(s, c)
    small = s < 1e-8
    ratio = np.where(small, 1.0 + s**2 / 6.0, theta / np.where(small, 1.0, s))
    out = np.asarray(v * ratio[..., None])
    near_pi = theta > np.pi - 0.1
    if np.any(near_pi):
        from scipy.spatial.transform import Rotation

        out[near_pi] = Rotation.from_matrix(r[near_pi].reshape(-1, 3, 3)).as_rotvec()
    return out


def adjoint(rotation: FloatArray, translation: FloatArray, twists: FloatArray) -> FloatArray:
    """``Ad(g) s`` of twists (k, 6, m) for displacements g = (R (k, 3, 3), p (k, 3)):
    ``w' = R w``, ``v' = R v + p x R w``."""
    w = rotation @ twists[:, :3, :]
    v = rotation @ twists[:, 3:, :]
    v = v + cross(translation[:, None, :], np.swapaxes(w, 1, 2)).swapaxes(1, 2)
    return np.concatenate([w, v], axis=1)


def bracket(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """The Lie bracket ``[a, b] = (w_a x w_b, w_a x v_b - w_b x v_a)`` of twists (..., 6)."""
    x = np.asarray(a, dtype=float)
    y = np.asarray(b, dtype=float)
    return np.concatenate(
        [
            cross(x[..., :3], y[..., :3]),
            cross(x[..., :3], y[..., 3:]) - cross(y[..., :3], x[..., 3:]),
        ],
        axis=-1,
    )


@dataclass(frozen=True)
class ChainKinematics:
    """:func:`forward` at k configurations.

    Attributes
    ----------
    rotation : ndarray (k, 3, 3)
    translation : ndarray (k, 3) [m]
        The displacement g = (R, p) of the chain's last body (module doc).
    jacobian : ndarray (k, 6, n)
        ``J_k = Ad(g_1 ... g_{k-1}) s_k``, about c0.
    """

    rotation: FloatArray
    translation: FloatArray
    jacobian: FloatArray


def forward(screws: FloatArray, coordinates: FloatArray) -> ChainKinematics:
    """The displacement of the chain's last body and the spatial Jacobian (module doc).

    Parameters
    ----------
    screws : ndarray (k, 6, n)
    coordinates : ndarray (k, n) [m or rad]
    """
    k, _, n = screws.shape
    twists = np.swapaxes(screws, 1, 2) * coordinates[:, :, None]  # (k, n, 6)
    steps = np.zeros((k, n, 4, 4))
    turning = np.any(screws[:, :3, :] != 0, axis=(0, 1))  # (n,)
    if turning.all():
        steps[:, :, :3, :3], steps[:, :, :3, 3] = se3_exp(twists)
    else:  # a translation's exp is (I, v) exactly: se3_exp of the others only
        t = np.flatnonzero(turning)
        steps[:, :, :3, :3] = np.eye(3)
        steps[:, :, :3, 3] = twists[:, :, 3:]
        r_t, p_t = se3_exp(twists[:, t])
        steps[:, t, :3, :3] = r_t
        steps[:, t, :3, 3:] = p_t[..., None]
    steps[:, :, 3, 3] = 1.0
    prefix = np.empty((k, n + 1, 4, 4))  # g_1 ... g_{i-1}, before coordinate i
    prefix[:, 0] = np.eye(4)
    for i in range(n):
        np.matmul(prefix[:, i], steps[:, i], out=prefix[:, i + 1])
    rots = prefix[:, :n, :3, :3]
    poss = prefix[:, :n, :3, 3]
    rot = prefix[:, n, :3, :3]
    pos = prefix[:, n, :3, 3]
    s = np.swapaxes(screws, 1, 2)  # (k, n, 6)
    w = np.einsum("knij,knj->kni", rots, s[..., :3])
    v = np.einsum("knij,knj->kni", rots, s[..., 3:]) + cross(poss, w)
    jac = np.swapaxes(np.concatenate([w, v], axis=2), 1, 2)
    return ChainKinematics(rot.copy(), pos.copy(), np.ascontiguousarray(jac))


def bracket_form(jacobian: FloatArray, wrench: FloatArray) -> FloatArray:
    """``Q[l, m] = w . [J_l, J_m]`` (k, n, n) for a wrench (k, 6) = (moment, force) about
    the point the twists are taken about.

    ``w . [a, b] = m . (w_a x w_b) + f . (w_a x v_b - w_b x v_a)``.
    """
    om = np.swapaxes(jacobian[:, :3, :], 1, 2)  # (k, n, 3)
    vel = np.swapaxes(jacobian[:, 3:, :], 1, 2)
    m = wrench[:, None, :3]
    f = wrench[:, None, 3:]
    # m . (w_l x w_m) = w_l . (w_m x m);  f . (w_l x v_m) = w_l . (v_m x f)
    vf = cross(vel, f)
    # (batched matmul: some 15x faster than einsum's loop at n = 30)
    a = om @ np.swapaxes(cross(om, m) + vf, 1, 2)
    # f . (w_m x v_l) = w_m . (v_l x f)
    b = vf @ np.swapaxes(om, 1, 2)
    return np.asarray(a - b)


def moving_point_jacobian(jacobian: FloatArray, point: FloatArray) -> FloatArray:
    """Twists (k, 6, n) about c0 re-expressed about the point ``point`` (k, 3) (relative
    to c0): ``v' = v + w x point``."""
    w = jacobian[:, :3, :]
    v = jacobian[:, 3:, :] + cross(np.swapaxes(w, 1, 2), point[:, None, :]).swapaxes(1, 2)
    return np.concatenate([w, v], axis=1)


__all__ = [
    "BarPair",
    "ChainKinematics",
    "ScrewChain",
    "adjoint",
    "bracket",
    "bracket_form",
    "cross",
    "forward",
    "moving_point_jacobian",
    "rotation_log",
    "screw_chain",
    "se3_exp",
]
