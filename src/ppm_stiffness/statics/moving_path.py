"""Following the load path of the moving-geometry equilibrium (statics/moving.py).

A design's legs as screw chains about the load point (:func:`platform_chains`), the start
of Newton's method from the frozen model's solution (:func:`frozen_prediction`), and the
path from the unloaded state to the full load (:func:`follow_load`): Newton's method from
that start at the full load, else load stepping, each step moving the platform by at most
:data:`~ppm_stiffness.statics.moving_core.MAX_STEP_MOTION`; a state whose K_F is not
stable ends the path (``Refusal.UNSTABLE``), as does a step that cannot be shortened
further (``Refusal.NO_EQUILIBRIUM``). Arrays have a leading problem axis (k,).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.pose import rotation_exp
from ppm_stiffness.core.refusals import Refusal, RefusalArray
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import LegModel, LegPose
from ppm_stiffness.legs.screw_chain import BarPair, ScrewChain, cross, screw_chain
from ppm_stiffness.model import validate_pose
from ppm_stiffness.statics.equilibrium import EquilibriumBatch
from ppm_stiffness.statics.moving_core import (
    MAX_STEP_MOTION,
    ChainState,
    NewtonResult,
    PlatformChains,
    motion,
    newton,
    spring_law,
    stability_index,
    zero_state,
)

#: Load stepping: the first step is this fraction of the load; a failed step is halved,
#: down to :data:`SMALLEST_STEP` of the load (then no equilibrium is found).
FIRST_STEP = 0.5
SMALLEST_STEP = 1.0 / 1024


def load_point(design: Design, tool_point: ArrayLike | None) -> FloatArray:
    """The load point b (3,) in the platform frame [m]: ``tool_point``, or P (0, 0, 0)
    when None; refused unless 3 finite numbers."""
    b = np.zeros(3) if tool_point is None else np.asarray(tool_point, dtype=float)
    if b.shape != (3,) or not np.all(np.isfinite(b)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    return b


def platform_chains(design: Design, poses: FloatArray, offsets: FloatArray) -> PlatformChains:
    """Every leg's screw chain (:mod:`ppm_stiffness.legs.screw_chain`) at reachable full
    poses (k, 6), its twists about the load points ``offsets`` (k, 3) (relative to P,
    axes of F_b). A leg whose moving geometry is not modelled is refused.

    Raises
    ------
    InputDataError
        A leg's :meth:`~ppm_stiffness.legs.base.LegModel.moving_geometry_gap`.
    """
    k = poses.shape[0]
    chains = []
    for i, leg in enumerate(design.legs):
        gap = leg.moving_geometry_gap()
        if gap is not None:
            raise InputDataError(
                f"leg {i + 1}: {gap}; the frozen geometry (--geometry frozen) gives the "
                "stiffness under load to first order"
            )
        chains.append(_leg_chain(leg, leg.solve(poses), k, offsets))
    strokes = np.array(
        [
            float(np.subtract(*leg.limits().get(leg.ACTUATED_COORDINATE, (-np.inf, np.inf))[::-1]))
            for leg in design.legs
        ]
    )
    return PlatformChains(tuple(chains), strokes)


def _leg_chain(leg: LegModel, leg_pose: LegPose, k: int, offsets: FloatArray) -> ScrewChain:
    """One leg's screw chain about the load points (k, 3); a leg ending in two bars
    (:meth:`~ppm_stiffness.legs.base.LegModel.bar_pair`): its arm's, with the bars."""
    pair = leg.bar_pair(leg_pose)
    if pair is None:
        return screw_chain(leg.chain(leg_pose), leg.actuator, k, offsets)
    arm = screw_chain(pair.chain, leg.actuator, k, offsets)
    near = np.reshape(pair.near, (k, 2, 3)) - offsets[:, None, :]
    far = np.reshape(pair.far, (k, 2, 3)) - offsets[:, None, :]
    rest = np.linalg.norm(far - near, axis=-1)
    return replace(arm, bars=BarPair(near, far, rest, pair.compliance))


def bar_forces(chain: ScrewChain, wrenches: FloatArray) -> FloatArray:
    """The bars' axial forces (k, 2) [N] that carry a leg's wrench about c0 at the
    reference configuration (least squares, length-balanced)."""
    assert chain.bars is not None
    near, far = chain.bars.near, chain.bars.far
    u = (far - near) / chain.bars.rest[..., None]
    lines = np.concatenate([cross(near, u), u], axis=-1) / BALANCE  # (k, 2, 6)
    rhs = wrenches / BALANCE
    return np.einsum("kbi,ki->kb", np.linalg.pinv(np.swapaxes(lines, 1, 2)), rhs)


def frozen_prediction(
    system: PlatformChains, frozen: EquilibriumBatch, offsets: FloatArray
) -> ChainState:
    """A start for Newton's method from the frozen model's solution (k poses): its twist
    moved to the load point, the legs' wrenches about it, every spring's deflection under
    its frozen load and the passive joints' displacements closing each chain to first
    order (least squares, length-balanced)."""
    twist = frozen.twist
    translation = twist[:, 3:] + cross(twist[:, :3], offsets)
    wrenches = frozen.leg_wrenches.copy()
    wrenches[..., :3] -= cross(offsets[:, None, :], wrenches[..., 3:])
    coords = []
    for i, chain in enumerate(system.chains):
        tau = np.einsum("kin,ki->kn", chain.screws, wrenches[:, i])
        defl, _ = spring_law(chain, tau)
        x = np.where(chain.passive, 0.0, defl)
        q = chain.passive
        if np.any(q) and chain.bars is None:
            moved = np.concatenate([twist[:, :3], translation], axis=1)
            rest = moved - np.einsum("kin,kn->ki", chain.screws, x)
            jq = chain.screws[:, :, q] / BALANCE[None, :, None]
            x[:, q] = np.einsum("kpi,ki->kp", np.linalg.pinv(jq), rest / BALANCE)
        if chain.bars is not None:  # the arm's springs as above, the bars' forces
            x = np.concatenate([x, bar_forces(chain, wrenches[:, i])], axis=1)
        coords.append(x)
    return ChainState(rotation_exp(twist[:, :3]), translation, tuple(coords), wrenches)


@dataclass(frozen=True)
class PathResult:
    """:func:`follow_load` at k problems: the state reached, K_F there, the legs'
    generalised forces, the load factor reached (1: the full load), accepted load
    steps, Newton iterations and a refusal code (0, ``NO_EQUILIBRIUM`` or
    ``UNSTABLE``)."""

    state: ChainState
    stiffness: FloatArray
    forces: tuple[FloatArray, ...]
    factor: FloatArray
    steps: np.ndarray
    iterations: np.ndarray
    refusal: RefusalArray
    unstable_between: FloatArray


def follow_load(
    system: PlatformChains,
    wrench: FloatArray,
    start: ChainState | None = None,
    use_start: np.ndarray | None = None,
) -> PathResult:
    """The equilibrium under ``wrench`` (k, 6) at the load point (module doc): Newton
    from ``start`` at the full load (the problems ``use_start``, all by default), and
    load stepping from the unloaded state where that gives no stable state."""
    k = system.size
    state = zero_state(system)
    stiffness = np.full((k, 6, 6), np.nan)
    forces = tuple(np.zeros((k, c.n)) for c in system.chains)
    factor = np.zeros(k)
    steps = np.zeros(k, dtype=int)
    iterations = np.zeros(k, dtype=int)
    refusal = np.zeros(k, dtype=np.int8)
    between = np.full((k, 2), np.nan)
    done = np.zeros(k, dtype=bool)

    def record(rows: np.ndarray, sel: np.ndarray, res: NewtonResult) -> None:
        state.put(rows, res.state.take(sel))
        stiffness[rows] = res.stiffness[sel]
        for mine, theirs in zip(forces, res.forces, strict=True):
            mine[rows] = theirs[sel]

    if start is not None:
        first = np.arange(k) if use_start is None else np.flatnonzero(use_start)
        if first.size:
            res = newton(system.take(first), start.take(first), wrench[first])
            iterations[first] += np.maximum(res.iterations, 0)
            near = motion(zero_state(system.take(first)), res.state) <= MAX_STEP_MOTION
            good = np.flatnonzero(res.converged & near & (stability_index(res.stiffness) > 0))
            rows = first[good]
            record(rows, good, res)
            factor[rows], steps[rows], done[rows] = 1.0, 1, True
    lam = np.zeros(k)
    h = np.full(k, FIRST_STEP)
    current = zero_state(system)
    while not np.all(done):
        idx = np.flatnonzero(~done)
        trial = np.minimum(lam[idx] + h[idx], 1.0)
        before = current.take(idx)
        res = newton(system.take(idx), before, trial[:, None] * wrench[idx])
        iterations[idx] += np.maximum(res.iterations, 0)
        mu = stability_index(res.stiffness)
        converged = res.converged & (motion(before, res.state) <= MAX_STEP_MOTION)
        stable = converged & (mu > 0)
        unstable = converged & ~(mu > 0)
        ok = np.flatnonzero(stable)
        if ok.size:
            rows = idx[ok]
            current.put(rows, res.state.take(ok))
            lam[rows] = trial[ok]
            steps[rows] += 1
            h[rows] = np.minimum(2 * h[rows], 1.0)
            full = ok[trial[ok] >= 1.0]
            record(idx[full], full, res)
            factor[idx[full]] = 1.0
            done[idx[full]] = True
        bad = np.flatnonzero(unstable)
        if bad.size:
            rows = idx[bad]
            record(rows, bad, res)
            refusal[rows] = Refusal.UNSTABLE
            between[rows, 0], between[rows, 1] = lam[rows], trial[bad]
            factor[rows] = trial[bad]
            done[rows] = True
        fail = np.flatnonzero(~converged)
        if fail.size:
            rows = idx[fail]
            h[rows] /= 2
            give_up = rows[h[rows] < SMALLEST_STEP]
            refusal[give_up] = Refusal.NO_EQUILIBRIUM
            factor[give_up] = lam[give_up]
            state.put(give_up, current.take(give_up))
            done[give_up] = True
    return PathResult(state, stiffness, forces, factor, steps, iterations, refusal, between)


def chain_sizes(design: Design) -> list[int]:
    """The number of chain coordinates of each leg (:func:`screw_chain`)."""
    home = validate_pose(design, None).reshape(1, 6)
    return [c.n for c in platform_chains(design, home, np.zeros((1, 3))).chains]
