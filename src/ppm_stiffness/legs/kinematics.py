"""Inverse kinematics of any serial chain: product of exponentials and Newton's method.

A leg written as a list of joints (:mod:`ppm_stiffness.legs.types.chain_leg`) is, for
its kinematics, a serial chain of one-freedom screws given at the design's home pose:
a revolute freedom is a unit axis ``a`` through a point ``c`` (F_b, absolute) [m], a
prismatic one a unit direction ``a``. Joint coordinates are zero at home; the body
after freedom i moves by

    G_i(q) = exp(xi_1 q_1) ... exp(xi_i q_i)

(a rotation ``exp(hat(a) q)`` about c, or a translation ``a q``), and a point or axis
fixed to that body at home moves with G_i. A U joint is two revolutes (e1, then e2);
an S joint three, about the x, y and z axes of F_b through its centre at home (their
product parametrises its rotation away from +-90 deg of the middle one, far beyond
any ball joint's range).

The platform is the body after the last freedom: the chain closes at a pose when
``G_n(q)`` carries the platform's home pose onto it. A chain that ends in bars of fixed
length (a parallelogram's two bars, :class:`Bars`) closes when each bar's near end,
fixed to the last body, lies at the bar's length from its far end, fixed to the
platform: the closure is then the bars' length errors. Newton's method solves the
closure's six equations, in length-balanced units (rotations times
:data:`~ppm_stiffness.core.conventions.LENGTH_SCALE`), by least squares with the
minimum-norm step (a leg of fewer than six independent freedoms cannot close at
every pose: the remaining error is what its constraint reports; a chain with an
internal freedom, a rod's spin between two ball joints, keeps it at zero). A pose far
from home is reached by continuation along the straight line from the home pose in
pose coordinates (steps of at most :data:`CONTINUATION_STEP`), so that the solution
is the home pose's assembly mode and does not depend on which other poses are solved
with it.

Arrays have one leading batch axis (n poses). SI throughout.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import LENGTH_SCALE, BoolArray, FloatArray, cross, hat

_EYE = np.eye(3)
#: Largest closure error [m, or rad times LENGTH_SCALE] of a closed chain.
CLOSURE_TOLERANCE = 1e-12
#: Largest closure error [m, balanced] of a chain that closes: a Newton solution beyond
#: it is a least-squares one (the pose is out of the chain's reach).
CLOSED = 1e-9
#: Newton iterations per continuation step before a pose is declared not solved.
MAX_ITERATIONS = 40
#: Largest continuation step along the path from home [m, or rad times LENGTH_SCALE].
CONTINUATION_STEP = 0.05
#: Last Newton step [m or rad] at which a continuation step before the last is taken as
#: solved (only the last one needs the full precision).
PATH_TOLERANCE = 1e-6
#: Largest Newton step on the joint coordinates [m or rad].
MAX_STEP = 0.3
#: Singular-value ratio below which a direction of the chain's Jacobian counts as absent.
RANK_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class Freedoms:
    """A chain's freedoms at home (module doc), in order from the base.

    Attributes
    ----------
    axes : ndarray (n, 3)
        Unit axis (revolute) or direction (prismatic) of each freedom, F_b.
    points : ndarray (n, 3) [m]
        A point of each revolute's axis, F_b (ignored for a prismatic freedom).
    prismatic : ndarray of bool (n,)
    """

    axes: FloatArray
    points: FloatArray
    prismatic: FloatArray

    @property
    def count(self) -> int:
        return int(self.axes.shape[0])

    @cached_property
    def hats(self) -> FloatArray:
        """``hat(a)`` of every axis (n, 3, 3) (computed once per chain)."""
        return hat(self.axes)

    @cached_property
    def outers(self) -> FloatArray:
        """``a a^T`` of every axis (n, 3, 3)."""
        return np.asarray(self.axes[:, :, None] * self.axes[:, None, :])

    @cached_property
    def slides(self) -> BoolArray:
        """``prismatic`` as booleans (n,)."""
        return np.asarray(self.prismatic, dtype=bool)

    def __eq__(self, other: object) -> bool:
        """Equal arrays (a leg caches its freedoms: two equal legs compare equal)."""
        if not isinstance(other, Freedoms):
            return NotImplemented
        return all(
            np.array_equal(a, b)
            for a, b in (
                (self.axes, other.axes),
                (self.points, other.points),
                (self.prismatic, other.prismatic),
            )
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True)
class ChainState:
    """A chain at n poses.

    Attributes
    ----------
    q : ndarray (n, f)
        Joint coordinates [m or rad], zero at home.
    rotations : ndarray (n, f + 1, 3, 3)
        Rotation of the body after each freedom (index 0: the base, the identity).
    translations : ndarray (n, f + 1, 3) [m]
        Its translation: a point x fixed to that body at home is at ``R x + t``.
    error : ndarray (n, 6) or (n, m)
        Remaining closure error, length-balanced (module doc), at the platform's
        reference point: (rotation vector * LENGTH_SCALE, translation) [m]; for a
        chain closed by m bars, their length errors [m].
    converged : ndarray of bool (n,)
        Newton's last step was within tolerance (the least-squares solution found).
    """

    q: FloatArray
    rotations: FloatArray
    translations: FloatArray
    error: FloatArray
    converged: BoolArray

    def carry(self, body: int, point: ArrayLike) -> FloatArray:
        """Where a point fixed to ``body`` (0: base, i: after freedom i) at home (3,)
        is, (n, 3) [m], F_b."""
        x = np.asarray(point, dtype=float)
        return np.asarray(self.rotations[:, body] @ x + self.translations[:, body])

    def turn(self, body: int, axis: ArrayLike) -> FloatArray:
        """A direction fixed to ``body`` at home (3,), now; (n, 3)."""
        return np.asarray(self.rotations[:, body] @ np.asarray(axis, dtype=float))


def forward(freedoms: Freedoms, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Rotations (n, f + 1, 3, 3) and translations (n, f + 1, 3) of every body."""
    n, f = q.shape
    rot = np.empty((n, f + 1, 3, 3))
    trans = np.empty((n, f + 1, 3))
    rot[:, 0] = _EYE
    trans[:, 0] = 0.0
    if f == 0:
        return rot, trans
    # Rodrigues for every freedom at once: R_i = cos I + sin hat(a) + (1 - cos) a a^T
    cos, sin = np.cos(q)[:, :, None, None], np.sin(q)[:, :, None, None]
    turns = cos * _EYE + sin * freedoms.hats + (1.0 - cos) * freedoms.outers
    for i in range(f):
        if freedoms.prismatic[i]:
            rot[:, i + 1] = rot[:, i]
            trans[:, i + 1] = trans[:, i] + q[:, i, None] * (rot[:, i] @ freedoms.axes[i])
            continue
        c = freedoms.points[i]
        rot[:, i + 1] = rot[:, i] @ turns[:, i]
        # about c: x -> R_prev (R_i (x - c) + c) + t_prev
        trans[:, i + 1] = trans[:, i] + rot[:, i] @ c - rot[:, i + 1] @ c
    return rot, trans


def rotation_log(r: FloatArray) -> FloatArray:
    """Rotation vectors (n, 3) of rotations (n, 3, 3) of angle below pi."""
    cos = np.clip((np.trace(r, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cos)
    axial = np.stack(
        [r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0], r[..., 1, 0] - r[..., 0, 1]],
        axis=-1,
    )
    small = angle < 1e-6
    factor = np.where(
        small, 0.5 + angle**2 / 12.0, angle / (2.0 * np.sin(np.where(small, 1, angle)))
    )
    return np.asarray(factor[..., None] * axial)


def jacobian(
    freedoms: Freedoms, rot: FloatArray, trans: FloatArray, reference: FloatArray
) -> FloatArray:
    """Unit twists (n, 6, f) of the freedoms now, at ``reference`` (n, 3) [m] (F_b)."""
    n = rot.shape[0]
    f = freedoms.count
    out = np.zeros((n, 6, f))
    if f == 0:
        return out
    body = rot[:, :f]  # the body carrying each freedom's axis
    a = (body @ freedoms.axes[:, :, None])[..., 0]  # (n, f, 3)
    c = (body @ freedoms.points[:, :, None])[..., 0] + trans[:, :f]
    moment = cross(c - reference[:, None, :], a)
    prismatic = freedoms.slides[:, None]
    out[:, :3] = np.swapaxes(np.where(prismatic, 0.0, a), 1, 2)
    out[:, 3:] = np.swapaxes(np.where(prismatic, a, moment), 1, 2)
    return out


_BALANCE_TWIST = np.array([LENGTH_SCALE] * 3 + [1.0] * 3)
#: Pose coordinates (x, y, z, rx, ry, rz) to path length [m].
_PATH_WEIGHTS = np.array([1.0] * 3 + [LENGTH_SCALE] * 3)


def closure_error(
    rot_end: FloatArray,
    trans_end: FloatArray,
    home: FloatArray,
    target: FloatArray,
) -> FloatArray:
    """Balanced error twist (n, 6) from the chain's end to the target poses (n, 6):
    the rotation vector of ``R_target R_now^T`` and the position error of P."""
    return _end_error(rot_end, trans_end, _Goal.of(home, target, None))


@dataclass(frozen=True)
class _Goal:
    """What a closure compares the chain's end with, computed once per solve: the
    platform's home position (3,) and rotation (3, 3), the target positions (n, 3) and
    rotations (n, 3, 3), and for a chain closed by bars their far ends (n, m, 3)."""

    p_home: FloatArray
    r_home: FloatArray
    p_target: FloatArray
    r_target: FloatArray
    far: FloatArray | None

    @classmethod
    def of(cls, home: FloatArray, target: FloatArray, bars: Bars | None) -> _Goal:
        far = None if bars is None else bars.far_points(home, target)
        return cls(
            pose6.position(home),
            pose6.rotation(home),
            pose6.position(target),
            pose6.rotation(target),
            far,
        )

    def take(self, rows: np.ndarray) -> _Goal:
        """The goal of the rows ``rows`` of the batch."""
        far = None if self.far is None else self.far[rows]
        return _Goal(self.p_home, self.r_home, self.p_target[rows], self.r_target[rows], far)


def _end_error(rot_end: FloatArray, trans_end: FloatArray, goal: _Goal) -> FloatArray:
    """:func:`closure_error` against a precomputed goal."""
    p_now = (rot_end @ goal.p_home) + trans_end
    r_now = rot_end @ goal.r_home
    dr = rotation_log(goal.r_target @ np.swapaxes(r_now, -1, -2))
    return np.concatenate([dr, goal.p_target - p_now], axis=-1) * _BALANCE_TWIST


@dataclass(frozen=True, eq=False)
class Bars:
    """Bars of fixed length closing a chain (module doc): bar k runs from ``near[k]``
    (fixed to the chain's last body; F_b at home) to ``far[k]`` (fixed to the
    platform; F_b at home) [m] and keeps its home length."""

    near: FloatArray
    far: FloatArray

    @property
    def lengths(self) -> FloatArray:
        return np.asarray(np.linalg.norm(self.far - self.near, axis=-1))

    def far_points(self, home: FloatArray, poses: FloatArray) -> FloatArray:
        """The far ends (n, m, 3) [m] with the platform at ``poses`` (n, 6)."""
        local = (self.far - pose6.position(home)) @ pose6.rotation(home)  # platform frame
        r = pose6.rotation(poses)
        return np.asarray(np.einsum("nij,mj->nmi", r, local) + pose6.position(poses)[:, None])

    def near_points(self, rot_end: FloatArray, trans_end: FloatArray) -> FloatArray:
        """The near ends (n, m, 3) [m] carried by the chain's last body, at rotations
        (n, 3, 3) and translations (n, 3)."""
        return np.asarray(np.einsum("nij,mj->nmi", rot_end, self.near) + trans_end[:, None])

    def directions(self, near_now: FloatArray, far_now: FloatArray) -> FloatArray:
        """Unit directions (n, m, 3) of the bars, near to far."""
        d = far_now - near_now
        return np.asarray(d / np.linalg.norm(d, axis=-1, keepdims=True))


def closure(
    freedoms: Freedoms,
    home: FloatArray,
    target: FloatArray,
    q: FloatArray,
    bars: Bars | None,
) -> tuple[FloatArray, FloatArray]:
    """The closure error (n, m), the target less the chain's end now, and the end's
    Jacobian (n, m, f) in the joint coordinates, both length-balanced: the end body's
    error twist (m = 6), or the bars' lengths less their distances now (m = the number
    of bars)."""
    return _closure(freedoms, _Goal.of(home, target, bars), q, bars)


def _closure(
    freedoms: Freedoms, goal: _Goal, q: FloatArray, bars: Bars | None
) -> tuple[FloatArray, FloatArray]:
    """:func:`closure` against a precomputed goal."""
    rot, trans = forward(freedoms, q)
    if bars is None or goal.far is None:
        error = _end_error(rot[:, -1], trans[:, -1], goal)
        reference = (rot[:, -1] @ goal.p_home) + trans[:, -1]
        return error, jacobian(freedoms, rot, trans, reference) * _BALANCE_TWIST[:, None]
    near = bars.near_points(rot[:, -1], trans[:, -1])
    far = goal.far
    error = bars.lengths - np.linalg.norm(far - near, axis=-1)  # target less now
    n = bars.directions(near, far)
    jac = jacobian(freedoms, rot, trans, np.zeros_like(trans[:, -1]))
    # velocity of a near end x: v + w x x; d(length)/dq = -n . (v + w x x)
    rows = []
    for k in range(bars.near.shape[0]):
        v = jac[:, 3:] + cross(np.swapaxes(jac[:, :3], 1, 2), near[:, k, None, :]).swapaxes(1, 2)
        rows.append(-np.einsum("ni,nif->nf", n[:, k], v))
    return np.asarray(error), np.stack(rows, axis=1)


def _newton(
    freedoms: Freedoms,
    home: FloatArray,
    target: FloatArray,
    q: FloatArray,
    tolerance: FloatArray,
    bars: Bars | None = None,
) -> tuple[FloatArray, BoolArray]:
    """Least-squares Newton from ``q`` (n, f) toward ``target`` (n, 6) until the last
    step is within ``tolerance`` (n,) [m or rad]; (q, converged). Each iteration works
    on the poses not yet converged only."""
    q = q.copy()
    converged = np.zeros(q.shape[0], dtype=bool)
    active = np.arange(q.shape[0])
    whole = _Goal.of(home, target, bars)
    for _ in range(MAX_ITERATIONS):
        qa = q[active]
        goal = whole if active.size == q.shape[0] else whole.take(active)
        error, jac = _closure(freedoms, goal, qa, bars)
        step = _least_squares(jac, error)
        size = np.max(np.abs(step), axis=-1, initial=0.0)
        with np.errstate(invalid="ignore"):
            scale = np.minimum(1.0, MAX_STEP / np.maximum(size, 1e-300))
        q[active] = qa + step * scale[:, None]
        done = size <= tolerance[active]
        converged[active[done]] = True
        active = active[~done & np.isfinite(size)]
        if active.size == 0:
            break
    return q, converged


def _least_squares(jac: FloatArray, error: FloatArray) -> FloatArray:
    """Minimum-norm least-squares steps (n, f) of ``jac @ step = error`` (jac (n, m, f)
    of full rank: the normal equations of the smaller side); NaN where singular."""
    m, f = jac.shape[-2:]
    if f == 0:
        return np.zeros(error.shape[:-1] + (0,))
    jt = np.swapaxes(jac, -1, -2)
    with np.errstate(all="ignore"):
        if f <= m:  # (J^T J) step = J^T e
            normal, rhs = jt @ jac, np.einsum("nji,nj->ni", jac, error)
            return _solve_or_nan(normal, rhs)
        y = _solve_or_nan(jac @ jt, error)  # step = J^T (J J^T)^-1 e
        return np.asarray(np.einsum("nij,nj->ni", jt, y))


def _solve_or_nan(a: FloatArray, b: FloatArray) -> FloatArray:
    """``solve(a, b)`` per pose (a (n, m, m), b (n, m)); NaN rows where a is singular."""
    try:
        return np.asarray(np.linalg.solve(a, b[..., None])[..., 0])
    except np.linalg.LinAlgError:
        out = np.full(b.shape, np.nan)
        for i in range(a.shape[0]):
            try:
                out[i] = np.linalg.solve(a[i], b[i])
            except np.linalg.LinAlgError:
                continue
        return out


def solve(
    freedoms: Freedoms,
    home: ArrayLike,
    poses: ArrayLike,
    bars: Bars | None = None,
    start: tuple[FloatArray, FloatArray] | None = None,
) -> ChainState:
    """Joint coordinates closing the chain at ``poses`` (n, 6) (module doc).

    Parameters
    ----------
    freedoms : Freedoms
        The chain at home.
    home : array_like (6,)
        The design's home pose [m, rad], where every joint coordinate is zero.
    poses : array_like (n, 6)
    bars : Bars or None
        Bars of fixed length that close the chain (module doc); None: the platform is
        the chain's last body.
    start : (ndarray (n, 6), ndarray (n, f)) or None
        Poses already solved on the home pose's branch and their joint coordinates:
        each pose continues from its start instead of from home (a Newton iteration's
        previous iterate, a neighbouring pose); a row whose coordinates are not finite
        continues from home.

    Returns
    -------
    ChainState
        ``error`` is zero (within :data:`CLOSURE_TOLERANCE`) where the chain closes:
        (n, 6), or (n, m) for m bars.
    """
    home = np.asarray(home, dtype=float)
    target = np.asarray(poses, dtype=float).reshape(-1, 6)
    n = target.shape[0]
    origin = np.broadcast_to(home, target.shape).copy()
    q = np.zeros((n, freedoms.count))
    if start is not None:
        warm = np.all(np.isfinite(start[1]), axis=-1) & np.all(np.isfinite(start[0]), axis=-1)
        origin[warm], q[warm] = start[0][warm], start[1][warm]
    span = np.max(np.abs((target - origin) * _PATH_WEIGHTS), axis=-1, initial=0.0)
    span[~np.isfinite(span)] = 0.0  # a pose not given (NaN): one step, which fails
    steps = np.maximum(1, np.ceil(span / CONTINUATION_STEP)).astype(int)
    failed: BoolArray = np.zeros(n, dtype=bool)
    for k in range(1, int(steps.max(initial=1)) + 1):
        index = np.flatnonzero((k <= steps) & ~failed)
        if index.size == 0:
            break
        last = steps[index] == k
        along = origin[index] + (target[index] - origin[index]) * (k / steps[index])[:, None]
        tolerance = np.where(last, CLOSURE_TOLERANCE, PATH_TOLERANCE)
        q_k, ok = _newton(freedoms, home, along, q[index], tolerance, bars)
        q[index] = q_k
        failed[index] = ~ok
    converged = ~failed
    rot, trans = forward(freedoms, q)
    error, _ = closure(freedoms, home, target, q, bars)
    return ChainState(q, rot, trans, error, converged)


def constraint_basis(jac_balanced: FloatArray, count: int) -> FloatArray:
    """The ``count`` balanced unit wrenches (n, 6, count) reciprocal to a chain's
    freedoms (the left singular vectors of its balanced Jacobian (n, 6, f) beyond its
    rank); NaN where the Jacobian is not finite (a chain that did not close: the SVD
    would not converge)."""
    jac = np.asarray(jac_balanced, dtype=float)
    finite = np.all(np.isfinite(jac), axis=(-2, -1))
    out = np.full(jac.shape[:-1] + (count,), np.nan)
    if np.any(finite):
        u, _, _ = np.linalg.svd(jac[finite], full_matrices=True)
        out[finite] = u[..., 6 - count :]
    return out


def rank(jac: FloatArray) -> int:
    """Rank of one balanced Jacobian (6, f)."""
    if jac.shape[-1] == 0:
        return 0
    s = np.linalg.svd(jac, compute_uv=False)
    return int(np.sum(s > RANK_TOLERANCE * s[0]))


__all__ = [
    "CLOSURE_TOLERANCE",
    "Bars",
    "ChainState",
    "Freedoms",
    "closure",
    "closure_error",
    "constraint_basis",
    "forward",
    "jacobian",
    "rank",
    "solve",
]
