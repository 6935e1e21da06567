"""Completing a pose: the dependent coordinates from the legs' constraints.

A design's task coordinates (``("x", "y", "rz")``, all six, ``("z", "rx", "ry")``) are
the pose coordinates a user gives; the others, the dependent coordinates, follow from
the legs' constraints (:meth:`ppm_stiffness.legs.base.LegModel.constraint`): their
closure residuals must vanish. For a 3-PRS or 3-RPS tripod the dependent coordinates
x, y and rz are the parasitic motion; for a planar design z, rx and ry are zero.

The residuals are solved by Newton's method in the dependent coordinates, from a start
(the design's home pose, by default): with the stacked residuals r (c) and their
wrenches W (6 x c), ``dr = W^T dt`` and ``dt = E dq``
(:func:`ppm_stiffness.core.pose.twist_from_coordinate_rates`), so the Jacobian is
``J = W^T E[:, dependent]`` (c x n_dep) and the step solves ``J^T J dq = -J^T r`` (the
stacked residuals may repeat a constraint: every planar leg states the plane). The
iteration stops when every residual is within :data:`RESIDUAL_TOLERANCE` [m or rad]
and the last step within :data:`STEP_TOLERANCE`; it fails after
:data:`MAX_ITERATIONS`. Every array has leading batch axes: a map completes all its
poses at once. A joint-list leg's inverse kinematics (a continuation from home,
:func:`ppm_stiffness.legs.kinematics.solve`) continues at each iterate from its
solution at the previous iterate of the same pose, not from home again: the same
branch, each pose independent of the others in its batch.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.pose import twist_from_coordinate_rates

#: Largest residual [m or rad] of a completed pose.
RESIDUAL_TOLERANCE = 1e-12
#: Largest last Newton step [m or rad] of a completed pose.
STEP_TOLERANCE = 1e-12
#: Newton iterations before a pose is declared not completed.
MAX_ITERATIONS = 30
#: Largest step [m or rad] of one Newton iteration (keeps a far start from jumping).
MAX_STEP = 0.2


Start = tuple[FloatArray, FloatArray]


class Constrained(Protocol):
    """What the completion needs of a leg."""

    def constraint(self, poses: ArrayLike) -> tuple[FloatArray, FloatArray]: ...

    def constraint_continued(
        self, poses: ArrayLike, start: Start | None
    ) -> tuple[FloatArray, FloatArray, Start | None]: ...


def residuals(legs: Sequence[Constrained], poses: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Every leg's closure residuals (..., c) and wrenches (..., 6, c), stacked."""
    q = np.asarray(poses, dtype=float)
    parts = [leg.constraint(q) for leg in legs]
    r = np.concatenate([p[0] for p in parts], axis=-1)
    w = np.concatenate([p[1] for p in parts], axis=-1)
    return r, w


def _continued_residuals(
    legs: Sequence[Constrained],
    poses: FloatArray,
    rows: NDArray[np.intp],
    memo: list[Start | None],
    total: int,
) -> tuple[FloatArray, FloatArray]:
    """:func:`residuals` at ``poses`` (k, 6), rows ``rows`` of the batch, each leg's
    inverse kinematics continued from its solution at the previous iterate of the same
    rows (``memo``: per leg, (poses (total, 6), joint coordinates (total, f)) of the
    whole batch, updated in place)."""
    parts = []
    for i, leg in enumerate(legs):
        kept = memo[i]
        start = None if kept is None else (kept[0][rows], kept[1][rows])
        r, w, now = leg.constraint_continued(poses, start)
        if now is not None:
            if kept is None:
                kept = (np.full((total, 6), np.nan), np.full((total, now[1].shape[-1]), np.nan))
                memo[i] = kept
            kept[0][rows], kept[1][rows] = now
        parts.append((r, w))
    return (
        np.concatenate([p[0] for p in parts], axis=-1),
        np.concatenate([p[1] for p in parts], axis=-1),
    )


def complete_poses(
    legs: Sequence[Constrained],
    dependent: Sequence[int],
    poses: ArrayLike,
    max_iterations: int = MAX_ITERATIONS,
) -> tuple[FloatArray, BoolArray]:
    """Solve the dependent coordinates of poses so that every leg's residual vanishes.

    Parameters
    ----------
    legs : sequence of LegModel
    dependent : sequence of int
        Indices (into x, y, z, rx, ry, rz) of the dependent coordinates.
    poses : array_like (..., 6)
        Task coordinates set; the dependent coordinates hold the start.
    max_iterations : int

    Returns
    -------
    poses : ndarray (..., 6)
        Completed (the dependent coordinates solved); where not converged, the last
        iterate.
    converged : ndarray of bool (...)
        Residuals within :data:`RESIDUAL_TOLERANCE` and last step within
        :data:`STEP_TOLERANCE`.
    """
    q = np.array(poses, dtype=float)
    batch = q.shape[:-1]
    flat = q.reshape(-1, 6)
    dep = list(dependent)
    n = flat.shape[0]
    converged = np.zeros(n, dtype=bool)
    active = np.arange(n)
    last_step = np.zeros(n)  # a start that satisfies the residuals is complete
    if not dep:
        r, _ = residuals(legs, flat)
        ok = np.all(np.abs(r) <= RESIDUAL_TOLERANCE, axis=-1) if r.shape[-1] else np.ones(n, bool)
        return q, ok.reshape(batch)
    memo: list[Start | None] = [None] * len(legs)
    for _ in range(max_iterations + 1):
        if active.size == 0:
            break
        sub = flat[active]
        r, w = _continued_residuals(legs, sub, active, memo, n)
        small = np.all(np.abs(r) <= RESIDUAL_TOLERANCE, axis=-1) & (
            last_step[active] <= STEP_TOLERANCE
        )
        converged[active[small]] = True
        keep = ~small
        active, sub, r, w = active[keep], sub[keep], r[keep], w[keep]
        if active.size == 0:
            break
        e = twist_from_coordinate_rates(sub)[..., dep]
        jac = np.swapaxes(w, -1, -2) @ e  # (k, c, n_dep)
        jt = np.swapaxes(jac, -1, -2)
        normal = jt @ jac
        rhs = -(jt @ r[..., None])[..., 0]
        try:
            step = np.linalg.solve(normal, rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            step = np.stack(
                [np.linalg.lstsq(a, b, rcond=None)[0] for a, b in zip(normal, rhs, strict=True)]
            )
        size = np.max(np.abs(step), axis=-1)
        scale = np.minimum(1.0, MAX_STEP / np.maximum(size, 1e-300))
        step = step * scale[:, None]
        sub[:, dep] += step
        flat[active] = sub
        last_step[active] = np.max(np.abs(step), axis=-1)
    return flat.reshape(q.shape), converged.reshape(batch)
