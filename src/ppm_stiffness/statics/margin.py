"""The load margin: how far a load is from the one at which the machine becomes unstable.

Along the load path ``lambda w`` (lambda >= 0, w the user's wrench at the load point,
:mod:`ppm_stiffness.statics.moving`) the equilibrium with moving geometry is followed
from the unloaded state. The **load margin** is the smallest factor lambda at which the
loaded tangent K_F becomes singular: a bifurcation (an eigenvalue of K_F crosses 0 on a
path that goes on, e.g. the buckling of a straight column) or a limit point (the path
turns back: no equilibrium beyond). The test is the stability index of
:func:`~ppm_stiffness.statics.moving_core.stability_index`, the smallest real part of
the eigenvalues of the length-balanced K_F: where K_F is symmetric (a pure force at the
load point) its smallest eigenvalue, and it reaches 0 where det K_F does.

Search. Continuation in lambda, the first step :data:`FIRST_STEP` (of the load), doubled
after each stable step and shortened to reach the zero of the index predicted from the
last two steps, and to the step that moves the platform
:data:`~ppm_stiffness.statics.moving_core.MOTION_AIM` of
:data:`~ppm_stiffness.statics.moving_core.MAX_STEP_MOTION` (the last step's motion
scaled linearly); a step whose Newton's method fails is quartered, one that converges
but moves the platform by more than that is shortened to that aim. A step
that reaches an unstable state brackets a bifurcation, refined by regula falsi
(Illinois) on the index to a relative width :data:`RELATIVE_TOLERANCE`; a step that
fails while already shorter than :data:`RELATIVE_TOLERANCE` of lambda is a limit point.
The search stops at ``max_factor`` (:data:`MAX_FACTOR` by default: "no instability up to
lambda = max_factor") or where an actuator reaches its whole stroke (beyond which the
model does not hold).

The **buckling mode** is the eigenvector of K_F for that eigenvalue at the last stable
state, as a twist at the displaced load point (length-balanced, unit norm, signed so that
its largest component is positive), named by its dominant direction ("x translation",
"rotation about z"); with the legs' coordinate modes (each chain's response to that twist).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, DIRECTION_NAMES, LENGTH_SCALE, FloatArray
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.design import Design
from ppm_stiffness.model import tool_offset, validate_pose
from ppm_stiffness.poses import full_poses
from ppm_stiffness.statics.moving_core import (
    MAX_STEP_MOTION,
    MOTION_AIM,
    ChainState,
    PlatformChains,
    linearize,
    motion,
    newton,
    stability_index,
    step_per_motion,
    zero_state,
)
from ppm_stiffness.statics.moving_path import load_point, platform_chains

#: The load factors searched by default: [0, MAX_FACTOR].
MAX_FACTOR = 1000.0
#: The first continuation step, as a factor of the load.
FIRST_STEP = 0.25
#: Relative width of the bracket of a bifurcation, and the shortest step (relative to
#: lambda) whose failure marks a limit point.
RELATIVE_TOLERANCE = 1e-9
#: A stability index within this fraction of its unloaded value is 0: the state is the
#: singular point itself.
ZERO_INDEX = 1e-13
#: The step past the margin that tells a bifurcation from a limit point.
BEYOND = 1e-6
#: Continuation and refinement steps at most.
MAX_STEPS = 400


class MarginKind(IntEnum):
    """How the search ended."""

    #: no instability up to the largest factor searched
    NONE = 0
    #: an eigenvalue of K_F crosses 0 on the path (det K_F changes sign)
    BIFURCATION = 1
    #: the path turns back: no equilibrium beyond
    LIMIT_POINT = 2
    #: an actuator reaches its whole stroke first (the model's limit)
    STROKE = 3
    #: the unloaded pose is refused (unreachable or singular)
    REFUSED = 4


@dataclass(frozen=True)
class MarginBatch:
    """The load margin at k problems.

    Attributes
    ----------
    factor : ndarray (k,)
        The load margin lambda (NaN where none was found: kind NONE, STROKE or
        REFUSED).
    kind : ndarray of int (k,)
        :class:`MarginKind`.
    searched_up_to : ndarray (k,)
        The largest factor at which a stable equilibrium was found.
    mode : ndarray (k, 6)
        The buckling mode, a twist at the displaced load point (rotation [rad],
        displacement [m]) of unit length-balanced norm; NaN where no factor.
    stability : ndarray (k,)
        The stability index at the last stable state [N/m].
    coordinate_modes : tuple of ndarray (k, n_i)
        Each leg's chain coordinates' response to the mode twist.
    steps : ndarray of int (k,)
        Newton solves used.
    """

    factor: FloatArray
    kind: np.ndarray
    searched_up_to: FloatArray
    mode: FloatArray
    stability: FloatArray
    coordinate_modes: tuple[FloatArray, ...]
    steps: np.ndarray

    def mode_name(self, i: int) -> str | None:
        """The dominant direction of problem i's mode ("rotation about z"), or None."""
        return mode_name(self.mode[i])


def mode_name(mode: ArrayLike) -> str | None:
    """The name of a twist's dominant length-balanced component, or None if not finite."""
    m = np.asarray(mode, dtype=float)
    if not np.all(np.isfinite(m)):
        return None
    return DIRECTION_NAMES[int(np.argmax(np.abs(m / BALANCE)))]


def chains_margin(
    system: PlatformChains, wrench: FloatArray, max_factor: float = MAX_FACTOR
) -> MarginBatch:
    """The load margin (module doc) of k problems under wrenches (k, 6) at the load point."""
    k = system.size
    lo = np.zeros(k)
    hi = np.full(k, np.inf)
    state = zero_state(system)
    lin0 = linearize(system, state, np.zeros((k, 6)))
    stiffness = lin0.stiffness.copy()
    mu_lo = stability_index(stiffness)
    mu_start = mu_lo.copy()
    mu_hi = np.full(k, np.nan)
    prev = np.full((k, 2), np.nan)  # the previous stable (lambda, index)
    h = np.full(k, min(FIRST_STEP, max_factor))
    kind = np.full(k, -1)
    side = np.zeros(k, dtype=int)  # refinement: the bracket end moved last (+1 hi, -1 lo)
    steps = np.zeros(k, dtype=int)
    for _ in range(MAX_STEPS):
        idx = np.flatnonzero(kind < 0)
        if idx.size == 0:
            break
        bracketed = np.isfinite(hi[idx])
        trial = _next_factor(lo[idx], hi[idx], mu_lo[idx], mu_hi[idx])
        trial = np.where(bracketed, trial, np.minimum(lo[idx] + h[idx], max_factor))
        before = state.take(idx)
        res = newton(system.take(idx), before, trial[:, None] * wrench[idx])
        steps[idx] += 1
        mu = stability_index(res.stiffness)
        moved = motion(before, res.state)
        # the step's length against the motion it gave: the next step's motion cap
        per_motion = step_per_motion(trial - lo[idx], moved)
        converged = res.converged & (moved <= MAX_STEP_MOTION)
        stable = converged & (mu > 0)
        beyond = _beyond_stroke(system.take(idx), res.state) & stable
        for j in np.flatnonzero(beyond):
            i = idx[j]
            kind[i] = MarginKind.STROKE
        stable &= ~beyond
        for j in np.flatnonzero(stable):
            i = idx[j]
            prev[i] = (lo[i], mu_lo[i])
            lo[i], mu_lo[i] = trial[j], mu[j]
            stiffness[i] = res.stiffness[j]
            if bracketed[j]:  # Illinois: the upper end kept twice, its index halved
                if side[i] < 0:
                    mu_hi[i] *= 0.5
                side[i] = -1
            else:
                h[i] = min(
                    _grow(h[i], lo[i], prev[i], mu_lo[i], max_factor),
                    MOTION_AIM * MAX_STEP_MOTION * per_motion[j],
                )
                if lo[i] >= max_factor:
                    kind[i] = MarginKind.NONE
        state.put(idx[stable], res.state.take(np.flatnonzero(stable)))
        at_zero = converged & (np.abs(mu) <= ZERO_INDEX * np.abs(mu_start[idx]))
        for j in np.flatnonzero(at_zero & ~stable):  # exactly at the singular point
            i = idx[j]
            lo[i] = hi[i] = trial[j]
            mu_lo[i] = mu_hi[i] = 0.0
            stiffness[i] = res.stiffness[j]
            state.put(np.array([i]), res.state.take(np.array([j])))
            kind[i] = MarginKind.BIFURCATION
        unstable = np.flatnonzero(converged & ~(mu > 0) & ~at_zero)
        for j in unstable:
            i = idx[j]
            if bracketed[j] and side[i] > 0:
                mu_lo[i] *= 0.5
            hi[i], mu_hi[i] = trial[j], mu[j]
            side[i] = 1
        for j in np.flatnonzero(~converged):
            i = idx[j]
            if bracketed[j]:
                hi[i], mu_hi[i] = trial[j], np.nan
                side[i] = 1
            else:
                # Newton failed: a quarter; converged but moved too much: the step that
                # moves MOTION_AIM of the most (motion linear in the step)
                aimed = MOTION_AIM * MAX_STEP_MOTION * per_motion[j]
                h[i] = aimed if res.converged[j] else h[i] / 4
                if h[i] <= RELATIVE_TOLERANCE * max(lo[i], FIRST_STEP):
                    kind[i] = MarginKind.LIMIT_POINT
        for i in idx[kind[idx] < 0]:
            if np.isfinite(hi[i]) and hi[i] - lo[i] <= RELATIVE_TOLERANCE * hi[i]:
                kind[i] = (
                    MarginKind.BIFURCATION if np.isfinite(mu_hi[i]) else MarginKind.LIMIT_POINT
                )
    kind[kind < 0] = MarginKind.NONE  # pragma: no cover - MAX_STEPS is far
    _classify(system, state, wrench, lo, kind)
    return _result(system, state, stiffness, lo, hi, mu_lo, mu_hi, kind, steps)


def _classify(
    system: PlatformChains, state: ChainState, wrench: FloatArray, lo: FloatArray, kind: np.ndarray
) -> None:
    """Tell a bifurcation from a limit point (in place): the path goes on past a
    bifurcation (Newton from the last stable state converges at ``(1 + BEYOND) lambda``
    to a state within 1 % of it, length-balanced), not past a limit point."""
    idx = np.flatnonzero((kind == MarginKind.BIFURCATION) | (kind == MarginKind.LIMIT_POINT))
    if idx.size == 0:
        return
    start = state.take(idx)
    res = newton(system.take(idx), start, ((1 + BEYOND) * lo[idx])[:, None] * wrench[idx])
    moved = np.max(np.abs((res.state.twist() - start.twist()) / BALANCE), axis=1)
    size = np.max(np.abs(start.twist() / BALANCE), axis=1)
    on = res.converged & (moved <= 0.01 * size + 1e-12 * LENGTH_SCALE)
    kind[idx] = np.where(on, MarginKind.BIFURCATION, MarginKind.LIMIT_POINT)


def _next_factor(
    lo: FloatArray, hi: FloatArray, mu_lo: FloatArray, mu_hi: FloatArray
) -> FloatArray:
    """Inside a bracket: regula falsi on the index (Illinois: the caller halves the
    index of an end kept twice), bisection where the upper index is unknown, kept off
    the ends by 1 % of the width."""
    with np.errstate(all="ignore"):
        t = lo + (hi - lo) * mu_lo / (mu_lo - mu_hi)
    with np.errstate(all="ignore"):
        mid = 0.5 * (lo + hi)
        t = np.where(np.isfinite(t), t, mid)
        width = hi - lo
        return np.asarray(np.clip(t, lo + 0.01 * width, hi - 0.01 * width))


def _grow(h: float, lo: float, prev: FloatArray, mu: float, max_factor: float) -> float:
    """The next continuation step: doubled, but aimed 10 % past the zero of the index
    predicted by the last two stable states when that is nearer."""
    step = 2.0 * h
    lam0, mu0 = prev
    if np.isfinite(mu0) and mu0 > mu and lo > lam0:
        zero = lo + mu * (lo - lam0) / (mu0 - mu)
        step = min(step, max(1.1 * (zero - lo), 0.05 * h))
    return float(min(step, max_factor - lo)) if lo < max_factor else step


def _beyond_stroke(system: PlatformChains, state: ChainState) -> np.ndarray:
    """Problems (k,) where an actuator has moved beyond its whole stroke."""
    k = system.size
    if system.strokes is None:
        return np.zeros(k, dtype=bool)
    out = np.zeros(k, dtype=bool)
    for i, chain in enumerate(system.chains):
        if chain.actuator is not None:
            out |= np.abs(state.coordinates[i][:, chain.actuator]) > system.strokes[i]
    return out


def _result(
    system: PlatformChains,
    state: ChainState,
    stiffness: FloatArray,
    lo: FloatArray,
    hi: FloatArray,
    mu_lo: FloatArray,
    mu_hi: FloatArray,
    kind: np.ndarray,
    steps: np.ndarray,
) -> MarginBatch:
    k = system.size
    found = (kind == MarginKind.BIFURCATION) | (kind == MarginKind.LIMIT_POINT)
    with np.errstate(all="ignore"):
        interp = lo + (hi - lo) * mu_lo / (mu_lo - mu_hi)
    factor = np.where(kind == MarginKind.BIFURCATION, np.where(np.isfinite(interp), interp, lo), lo)
    factor = np.where(found, factor, np.nan)
    mode = np.full((k, 6), np.nan)
    kb = stiffness * BALANCE[None, :, None] * BALANCE[None, None, :]
    for i in np.flatnonzero(found):
        values, vectors = np.linalg.eig(kb[i])
        j = int(np.argmin(values.real))
        v = vectors[:, j].real
        v = v / np.linalg.norm(v)
        v = v if v[np.argmax(np.abs(v))] > 0 else -v
        mode[i] = v * BALANCE  # balanced twist (phi L, u) -> (phi, u)
    coords = tuple(np.full((k, c.n), np.nan) for c in system.chains)
    if np.any(found):
        rows = np.flatnonzero(found)
        lin = linearize(system.take(rows), state.take(rows), np.zeros((rows.size, 6)))
        for mine, leg in zip(coords, lin.legs, strict=True):
            mine[rows] = np.einsum("knj,kj->kn", leg.dx_t, mode[rows])
    return MarginBatch(factor, kind, lo, mode, mu_lo, coords, steps)


@dataclass(frozen=True)
class LoadMargin:
    """The load margin at one pose (:class:`MarginBatch`'s fields at one problem).

    Attributes
    ----------
    factor : float or None
        lambda at the first instability; None when none was found.
    kind : MarginKind
    searched_up_to : float
        The largest factor with a stable equilibrium found.
    max_factor : float
        The end of the range searched.
    mode : ndarray (6,) or None
        The buckling mode (a twist at the displaced load point).
    mode_name : str or None
        Its dominant direction.
    coordinate_modes : tuple of ndarray (n_i,)
    """

    factor: float | None
    kind: MarginKind
    searched_up_to: float
    max_factor: float
    mode: FloatArray | None
    mode_name: str | None
    coordinate_modes: tuple[FloatArray, ...]

    def describe(self) -> str:
        """One line: "1.234 (bifurcation; mode: rotation about z)" or "no instability up
        to 1000 times the load"."""
        if self.factor is not None:
            what = "bifurcation" if self.kind == MarginKind.BIFURCATION else "limit point"
            return f"{self.factor:.6g} times the load ({what}; mode: {self.mode_name})"
        if self.kind == MarginKind.STROKE:
            return (
                f"no instability up to {self.searched_up_to:.4g} times the load, where an "
                "actuator reaches its whole stroke"
            )
        return f"no instability up to {self.max_factor:.4g} times the load"


def margin_batch(
    design: Design,
    poses: ArrayLike,
    wrench: ArrayLike,
    tool_point: ArrayLike | None = None,
    max_factor: float = MAX_FACTOR,
) -> MarginBatch:
    """The load margin of ``wrench`` (6,) at the load point at k poses (task coordinates or
    full poses); kind REFUSED where the unloaded pose is unreachable or singular (its
    frozen refusal code, :func:`ppm_stiffness.statics.equilibrium.loaded_states`)."""
    from ppm_stiffness.statics.equilibrium import loaded_states

    w = validate_wrench(wrench)
    b = load_point(design, tool_point)
    p, completed = full_poses(design, np.asarray(poses, dtype=float))
    p = p.reshape(-1, 6)
    k = p.shape[0]
    unloaded = loaded_states(design, p, np.zeros(6))
    ok = (unloaded.refusal == 0) & completed.reshape(-1)
    offsets = tool_offset(p, b).reshape(k, 3)
    sizes = None
    idx = np.flatnonzero(ok)
    if idx.size:
        system = platform_chains(design, p[idx], offsets[idx])
        sub = chains_margin(system, np.broadcast_to(w, (idx.size, 6)).copy(), max_factor)
        sizes = [c.n for c in system.chains]
    out = MarginBatch(
        np.full(k, np.nan),
        np.full(k, int(MarginKind.REFUSED)),
        np.zeros(k),
        np.full((k, 6), np.nan),
        np.full(k, np.nan),
        tuple(np.full((k, n), np.nan) for n in (sizes or [])),
        np.zeros(k, dtype=int),
    )
    if idx.size:
        for name in ("factor", "kind", "searched_up_to", "mode", "stability", "steps"):
            getattr(out, name)[idx] = getattr(sub, name)
        for mine, theirs in zip(out.coordinate_modes, sub.coordinate_modes, strict=True):
            mine[idx] = theirs
    return out


def load_margin(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike | None = None,
    tool_point: ArrayLike | None = None,
    max_factor: float = MAX_FACTOR,
) -> LoadMargin:
    """The load margin of ``wrench`` at one pose (module doc).

    Parameters
    ----------
    design : Design
    wrench : array_like (6,) [N·m, N]
        At the load point, axes of F_b.
    pose : array_like, optional
        The unloaded pose; the home pose if None.
    tool_point : array_like (3,), optional
        The load point in the platform frame [m]; P if None.
    max_factor : float
        The end of the range searched.

    Raises
    ------
    UnreachablePoseError, SingularConfigurationError
        At the unloaded pose.
    """
    from ppm_stiffness.model import stiffness_at_pose

    p = validate_pose(design, pose)
    stiffness_at_pose(design, p)  # refuses an unreachable or singular pose
    batch = margin_batch(design, p.reshape(1, 6), wrench, tool_point, max_factor)
    return margin_of(batch, 0, max_factor)


def margin_of(batch: MarginBatch, i: int, max_factor: float = MAX_FACTOR) -> LoadMargin:
    """Problem ``i`` of a batch as a :class:`LoadMargin`."""
    kind = MarginKind(int(batch.kind[i]))
    found = np.isfinite(batch.factor[i])
    if kind == MarginKind.REFUSED:
        raise ValueError(f"problem {i} is refused: no margin")  # pragma: no cover
    return LoadMargin(
        factor=float(batch.factor[i]) if found else None,
        kind=kind,
        searched_up_to=float(batch.searched_up_to[i]),
        max_factor=max_factor,
        mode=batch.mode[i].copy() if found else None,
        mode_name=batch.mode_name(i) if found else None,
        coordinate_modes=tuple(x[i].copy() for x in batch.coordinate_modes),
    )


__all__ = [
    "DIRECTION_NAMES",
    "MAX_FACTOR",
    "MOTION_AIM",
    "LoadMargin",
    "MarginBatch",
    "MarginKind",
    "Refusal",
    "chains_margin",
    "load_margin",
    "margin_batch",
    "margin_of",
    "mode_name",
]
