"""The loaded equilibrium with moving geometry: displaced pose, loaded tangent K_F.

The paper's statics (:mod:`ppm_stiffness.statics.equilibrium`, the **frozen** model) keep
the geometry at the unloaded pose: only the actuator law changes with the load. Here
(the **moving** model) the platform and every leg move under the load: each leg's chain
closes at the displaced platform, its passive joints carry no load, every virtual spring
follows its law (the actuator's nonlinear law of eq. 20-21 included) and the legs'
wrenches sum to the applied one (:mod:`ppm_stiffness.statics.moving_core`, where the
equations are written out). The load is the user's wrench at the load point -- the tool
point, P by default: a force of fixed direction applied at that platform point and a
couple of fixed direction, axes of F_b.

Solution. Newton's method with the analytic tangent, started from the frozen model's
solution at the full load (its twist and the legs' deflections, passive joints by least
squares); where it does not converge to a stable state near the unloaded pose, load
stepping from the unloaded pose (steps of half the load at first, halved on failure down
to 1/1024, doubled after a success). A solution that moves the platform by more than
:data:`~ppm_stiffness.statics.moving_core.MAX_STEP_MOTION` (0.05 rad, or 0.05 L) from
the previous one counts as a failure: the path is followed in steps short enough that
Newton's method cannot jump to a distant equilibrium, past a limit point or onto another
branch, unnoticed. A pose is refused (:class:`~ppm_stiffness.core.refusals.Refusal`)
where it is unreachable or singular unloaded (as the frozen model), where no equilibrium
is found (``NO_EQUILIBRIUM``), where an actuator would move beyond its whole stroke
(``BEYOND_STROKE``), and where the load path passes the first instability (``UNSTABLE``:
a state reached whose K_F has an eigenvalue with a real part at or below 0, a limit or
bifurcation point before the full load; :mod:`ppm_stiffness.statics.margin` gives its
load factor).

K_F is the loaded tangent stiffness ``dw = K_F dt`` **at the displaced load point** (P'
when the load acts at P), axes of F_b, for the twist update of
:func:`ppm_stiffness.core.pose.displaced_pose` (``R -> exp(hat(dphi)) R``, the load point
moved by dv). It tends to today's K as the load tends to 0, is symmetric when the wrench
at the load point is a pure force, and has the antisymmetric part ``-m^/2`` in its
rotation block under a couple m.

One implementation for one pose and many (:func:`moving_states`, every array with a
leading pose axis); :func:`moving_loaded_state` is the batch of one that raises.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import (
    FloatArray,
    stiffness_b_from_stiffness_a,
    wrench_b_from_wrench_a,
)
from ppm_stiffness.core.errors import EquilibriumError, InputDataError
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.core.pose import pose_from_rotation, rotation
from ppm_stiffness.core.refusals import Refusal, RefusalArray
from ppm_stiffness.design import Design
from ppm_stiffness.model import pose_label, tool_offset, validate_pose
from ppm_stiffness.poses import full_poses
from ppm_stiffness.statics import actuator as act
from ppm_stiffness.statics.equilibrium import (
    EquilibriumBatch,
    check_actuator_travel,
    loaded_states,
    raise_refusal,
)
from ppm_stiffness.statics.moving_core import (
    PlatformChains,
    linearize,
    relative_difference,
    relative_size,
    stability_index,
)
from ppm_stiffness.statics.moving_path import (
    PathResult,
    chain_sizes,
    follow_load,
    frozen_prediction,
    load_point,
    platform_chains,
)

__all__ = [
    "MovingBatch",
    "MovingEquilibrium",
    "MovingLoadedState",
    "PathResult",
    "follow_load",
    "load_point",
    "moving_equilibrium",
    "moving_load_states",
    "moving_loaded_state",
    "moving_states",
    "platform_chains",
    "raise_moving_refusal",
    "relative_difference",
    "relative_size",
    "state_of",
]


@dataclass(frozen=True)
class MovingBatch:
    """The equilibrium with moving geometry at k poses (SI; axes of F_b).

    Attributes
    ----------
    poses : ndarray (k, 6)
        The reference (unloaded) full poses.
    wrench : ndarray (6,) or (k, 6)
        (m_x, m_y, m_z, f_x, f_y, f_z) at the load point: one for every pose
        (:func:`moving_states`) or one per pose (:func:`moving_load_states`).
    tool_point : ndarray (3,)
        The load point in the platform frame [m] ((0, 0, 0): P).
    refusal : ndarray of int8 (k,)
        :class:`~ppm_stiffness.core.refusals.Refusal` codes (module doc); 0 exactly
        where :func:`moving_loaded_state` returns.
    displaced_poses : ndarray (k, 6)
        The loaded pose of P (the reference pose where refused).
    twist : ndarray (k, 6)
        The load point's finite displacement: the platform's rotation vector [rad]
        and the load point's displacement [m].
    stiffness : ndarray (k, 6, 6)
        K_F at the displaced load point.
    elastic_stiffness : ndarray (k, 6, 6)
        Its elastic part: the springs' tangent at the displaced geometry without the
        second-derivative (geometric) terms; ``stiffness - elastic_stiffness`` is the
        geometric term.
    frozen_stiffness : ndarray (k, 6, 6)
        The frozen model's loaded tangent K at the (unloaded) load point.
    leg_wrenches : ndarray (k, n_legs, 6)
        Each leg's wrench about the displaced load point (they sum to ``wrench``).
    coordinates : tuple of ndarray (k, n_i)
        Each leg's chain coordinates (:mod:`ppm_stiffness.legs.screw_chain`) [m or rad];
        a leg ending in a parallelogram: its arm's, then its two bars' axial forces
        [N] (tension positive; :mod:`ppm_stiffness.statics.moving_bars`).
    actuator_forces, actuator_displacements, actuator_stiffness : ndarray (k, n_legs)
        G [N or N·m], delta(G) [m or rad] and the tangent K_act(G) (eq. 21).
    factor : ndarray (k,)
        The load factor reached: 1 where solved; where refused, the last stable one.
    unstable_between : ndarray (k, 2)
        Where refused as ``UNSTABLE``: a stable factor and the unstable one after it.
    steps, iterations : ndarray of int (k,)
        Load steps (1: Newton from the frozen solution converged at the full load) and
        Newton iterations in all.
    stability : ndarray (k,)
        The smallest real part of the eigenvalues of the length-balanced K_F [N/m].
    frozen : EquilibriumBatch
        The frozen model's solution at the same poses (the start).
    """

    poses: FloatArray
    wrench: FloatArray
    tool_point: FloatArray
    refusal: RefusalArray
    displaced_poses: FloatArray
    twist: FloatArray
    stiffness: FloatArray
    elastic_stiffness: FloatArray
    frozen_stiffness: FloatArray
    leg_wrenches: FloatArray
    coordinates: tuple[FloatArray, ...]
    actuator_forces: FloatArray
    actuator_displacements: FloatArray
    actuator_stiffness: FloatArray
    factor: FloatArray
    unstable_between: FloatArray
    steps: np.ndarray
    iterations: np.ndarray
    stability: FloatArray
    frozen: EquilibriumBatch


def moving_states(
    design: Design, poses: ArrayLike, wrench: ArrayLike, tool_point: ArrayLike | None = None
) -> MovingBatch:
    """The equilibrium with moving geometry under ``wrench`` at k poses (module doc).

    Parameters
    ----------
    design : Design
    poses : array_like (k, n_task) or (k, 6) [m, rad]
        Task coordinates or full poses (:mod:`ppm_stiffness.poses`), unloaded.
    wrench : array_like (6,) [N·m, N]
        At the load point, axes of F_b.
    tool_point : array_like (3,), optional
        The load point in the platform frame [m]; P if None.
    """
    w = validate_wrench(wrench)
    b = load_point(design, tool_point)
    p, completed = full_poses(design, np.asarray(poses, dtype=float))
    p = p.reshape(-1, 6)
    rows = np.broadcast_to(w, (p.shape[0], 6)).copy()
    return _solve(design, p, completed.reshape(-1), rows, w, b)


def moving_load_states(
    design: Design,
    wrenches: ArrayLike,
    pose: ArrayLike | None = None,
    tool_point: ArrayLike | None = None,
) -> MovingBatch:
    """The equilibrium with moving geometry at one pose under k wrenches (a load path,
    e.g. ``deflect --geometry moving``), each solved as :func:`moving_loaded_state` solves
    it: row i of the batch is ``moving_loaded_state(design, wrenches[i], pose, tool_point)``.

    Parameters
    ----------
    design : Design
    wrenches : array_like (k, 6) [N·m, N]
        At the load point, axes of F_b.
    pose : array_like (n_task,) or (6,), optional
        The unloaded pose; the home pose if None.
    tool_point : array_like (3,), optional
        The load point in the platform frame [m]; P if None.

    Returns
    -------
    MovingBatch
        ``wrench`` is (k, 6).
    """
    rows = np.asarray(wrenches, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != 6 or rows.shape[0] == 0:
        raise InputDataError(f"wrenches must be a (k, 6) array, got shape {rows.shape}")
    for w in rows:
        validate_wrench(w)
    p = validate_pose(design, pose)
    b = load_point(design, tool_point)
    k = rows.shape[0]
    return _solve(design, np.tile(p, (k, 1)), np.ones(k, dtype=bool), rows, rows, b)


def _solve(
    design: Design,
    p: FloatArray,
    completed: np.ndarray,
    rows: FloatArray,
    wrench: FloatArray,
    b: FloatArray,
) -> MovingBatch:
    """:func:`moving_states` at full poses (k, 6) under the wrenches ``rows`` (k, 6);
    ``wrench`` is stored in the batch as given."""
    k = p.shape[0]
    offsets = tool_offset(p, b).reshape(k, 3)
    to_p = np.stack([wrench_b_from_wrench_a(np.eye(3), o) for o in offsets])
    w_p = np.einsum("kij,kj->ki", to_p, rows)  # the same load about P, for the frozen model
    frozen = _frozen_states(design, p, w_p, completed)
    refusal = frozen.refusal.copy()
    refusal[refusal > Refusal.SINGULAR] = 0
    idx = np.flatnonzero(refusal == 0)
    if idx.size == 0:
        return _empty(design, p, wrench, b, refusal, frozen, offsets, chain_sizes(design))
    system = platform_chains(design, p[idx], offsets[idx])
    out = _empty(design, p, wrench, b, refusal, frozen, offsets, [c.n for c in system.chains])
    sub_frozen = _take_frozen(frozen, idx)
    start = frozen_prediction(system, sub_frozen, offsets[idx])
    path = follow_load(system, rows[idx].copy(), start, sub_frozen.solved)
    _fill(out, design, system, path, idx, offsets[idx], rows[idx])
    return out


def _frozen_states(
    design: Design, poses: FloatArray, wrenches_p: FloatArray, completed: np.ndarray
) -> EquilibriumBatch:
    """The frozen solution at each pose under its wrench about P (one wrench when the
    load point is P or the same offset everywhere; pose by pose otherwise)."""
    if np.allclose(wrenches_p, wrenches_p[0], rtol=0, atol=0):
        batch = loaded_states(design, poses, wrenches_p[0])
    else:
        parts = [loaded_states(design, poses[i : i + 1], wrenches_p[i]) for i in range(len(poses))]
        batch = _concat_frozen(parts)
    batch.refusal[~completed] = Refusal.UNREACHABLE
    return batch


def _concat_frozen(parts: list[EquilibriumBatch]) -> EquilibriumBatch:
    fields = EquilibriumBatch.__dataclass_fields__
    values = {}
    for name in fields:
        items = [getattr(b, name) for b in parts]
        values[name] = items[0] if name == "wrench" else np.concatenate(items, axis=0)
    return EquilibriumBatch(**values)


def _take_frozen(batch: EquilibriumBatch, idx: np.ndarray) -> EquilibriumBatch:
    fields = EquilibriumBatch.__dataclass_fields__
    return EquilibriumBatch(
        **{
            name: getattr(batch, name) if name == "wrench" else getattr(batch, name)[idx]
            for name in fields
        }
    )


def _empty(
    design: Design,
    poses: FloatArray,
    wrench: FloatArray,
    b: FloatArray,
    refusal: RefusalArray,
    frozen: EquilibriumBatch,
    offsets: FloatArray,
    sizes: list[int],
) -> MovingBatch:
    k, n = poses.shape[0], len(design.legs)
    frozen_k = np.zeros((k, 6, 6))
    good = frozen.solved
    for i in np.flatnonzero(good):
        frozen_k[i] = stiffness_b_from_stiffness_a(frozen.stiffness[i], np.eye(3), -offsets[i])
    return MovingBatch(
        poses=poses,
        wrench=wrench,
        tool_point=b,
        refusal=refusal.astype(np.int8),
        displaced_poses=poses.copy(),
        twist=np.zeros((k, 6)),
        stiffness=np.zeros((k, 6, 6)),
        elastic_stiffness=np.zeros((k, 6, 6)),
        frozen_stiffness=frozen_k,
        leg_wrenches=np.zeros((k, n, 6)),
        coordinates=tuple(np.zeros((k, c)) for c in sizes),
        actuator_forces=np.zeros((k, n)),
        actuator_displacements=np.zeros((k, n)),
        actuator_stiffness=np.tile([leg.locked_stiffness() for leg in design.legs], (k, 1)),
        factor=np.zeros(k),
        unstable_between=np.full((k, 2), np.nan),
        steps=np.zeros(k, dtype=int),
        iterations=np.full(k, -1),
        stability=np.full(k, np.nan),
        frozen=frozen,
    )


def _fill(
    out: MovingBatch,
    design: Design,
    system: PlatformChains,
    path: PathResult,
    idx: np.ndarray,
    offsets: FloatArray,
    wrench: FloatArray,
) -> None:
    """Write the solved rows ``idx`` of ``out`` (in place) from ``path`` (``wrench``:
    (len(idx), 6), the rows' wrenches)."""
    st = path.state
    found = path.refusal != Refusal.NO_EQUILIBRIUM
    r_new = st.rotation @ rotation(out.poses[idx])
    c_abs = out.poses[idx, :3] + offsets + st.translation
    p_new = c_abs - np.einsum("kij,j->ki", r_new, out.tool_point)
    displaced = pose_from_rotation(p_new, r_new, near=out.poses[idx])
    out.displaced_poses[idx] = np.where(found[:, None], displaced, out.poses[idx])
    out.twist[idx] = np.where(found[:, None], st.twist(), 0.0)
    out.stiffness[idx] = np.where(found[:, None, None], path.stiffness, 0.0)
    elastic = linearize(system, st, wrench, geometric=False)
    out.elastic_stiffness[idx] = np.where(found[:, None, None], elastic.stiffness, 0.0)
    out.leg_wrenches[idx] = st.wrenches
    for mine, theirs in zip(out.coordinates, st.coordinates, strict=True):
        mine[idx] = theirs
    for i, (leg, chain) in enumerate(zip(design.legs, system.chains, strict=True)):
        a = chain.actuator
        if a is None:  # a passive constraining leg: no actuator force (its defaults)
            continue
        x_a = st.coordinates[i][:, a]
        g = path.forces[i][:, a] - chain.parallel * x_a  # the drive's share (a flexure's)
        out.actuator_forces[idx, i] = g
        out.actuator_displacements[idx, i] = x_a
        out.actuator_stiffness[idx, i] = act.leg_tangent_stiffness(leg, g)
    out.factor[idx] = path.factor
    out.unstable_between[idx] = path.unstable_between
    out.steps[idx] = path.steps
    out.iterations[idx] = np.where(found, path.iterations, -1)
    out.stability[idx] = stability_index(path.stiffness)
    codes = path.refusal.copy()
    spans = system.strokes
    if spans is not None:
        beyond = np.any(np.abs(out.actuator_displacements[idx]) > spans, axis=1)
        codes = np.where((codes == 0) & beyond, Refusal.BEYOND_STROKE, codes)
    out.refusal[idx] = codes


@dataclass(frozen=True)
class MovingLoadedState:
    """The equilibrium with moving geometry at one pose (:class:`MovingBatch`'s fields,
    one pose; SI, axes of F_b; K_F at the displaced load point): what
    :func:`moving_loaded_state` returns (public as ``ppm_stiffness.MovingLoadedState``;
    ``MovingEquilibrium`` until 0.2)."""

    pose: FloatArray
    displaced_pose: FloatArray
    wrench: FloatArray
    tool_point: FloatArray
    twist: FloatArray
    stiffness_matrix: FloatArray
    elastic_stiffness: FloatArray
    frozen_stiffness: FloatArray
    leg_wrenches: FloatArray
    coordinates: tuple[FloatArray, ...]
    actuator_forces: FloatArray
    actuator_displacements: FloatArray
    actuator_stiffness: FloatArray
    steps: int
    iterations: int

    @property
    def geometric_stiffness(self) -> FloatArray:
        """K_F minus its elastic part: the geometric term (6, 6)."""
        return np.asarray(self.stiffness_matrix - self.elastic_stiffness)


def state_of(batch: MovingBatch, i: int) -> MovingLoadedState:
    """Pose ``i`` of a batch as a :class:`MovingLoadedState`."""
    return MovingLoadedState(
        pose=batch.poses[i],
        displaced_pose=batch.displaced_poses[i],
        wrench=batch.wrench if batch.wrench.ndim == 1 else batch.wrench[i],
        tool_point=batch.tool_point,
        twist=batch.twist[i],
        stiffness_matrix=batch.stiffness[i],
        elastic_stiffness=batch.elastic_stiffness[i],
        frozen_stiffness=batch.frozen_stiffness[i],
        leg_wrenches=batch.leg_wrenches[i],
        coordinates=tuple(x[i] for x in batch.coordinates),
        actuator_forces=batch.actuator_forces[i],
        actuator_displacements=batch.actuator_displacements[i],
        actuator_stiffness=batch.actuator_stiffness[i],
        steps=int(batch.steps[i]),
        iterations=int(batch.iterations[i]),
    )


def raise_moving_refusal(design: Design, batch: MovingBatch, i: int) -> None:
    """Raise the error of pose ``i``'s refusal code (nothing for 0)."""
    code = Refusal(int(batch.refusal[i]))
    if code == Refusal.NONE:
        return
    where = pose_label(batch.poses[i], design)
    if code in (Refusal.UNREACHABLE, Refusal.SINGULAR):
        raise_refusal(design, batch.frozen, i)
    if code == Refusal.NO_EQUILIBRIUM:
        raise EquilibriumError(
            f"no equilibrium with moving geometry found{where}: load stepping stopped at "
            f"{batch.factor[i]:.4g} times the load (the path may reach a limit point "
            "there; the load margin finds it)"
        )
    if code == Refusal.UNSTABLE:
        lo, hi = batch.unstable_between[i]
        raise EquilibriumError(
            f"the load is beyond the first instability{where}: the equilibrium path "
            f"loses stability between {lo:.4g} and {hi:.4g} times the load (the load "
            "margin gives the factor and the buckling mode)"
        )
    if code == Refusal.BEYOND_STROKE:
        check_actuator_travel(design, batch.actuator_displacements[i])
    raise code.error(f"{code.reason}{where}")  # pragma: no cover - raised above


def moving_loaded_state(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike | None = None,
    tool_point: ArrayLike | None = None,
) -> MovingLoadedState:
    """The equilibrium with moving geometry under ``wrench`` at one pose (module doc):
    the loaded state of :func:`ppm_stiffness.statics.loading.loaded_state` without its
    small-displacement assumption (public as ``ppm_stiffness.moving_loaded_state``;
    ``moving_equilibrium`` until 0.2).

    Parameters
    ----------
    design : Design
    wrench : array_like (6,) [N·m, N]
        (m_x, m_y, m_z, f_x, f_y, f_z) at the load point, axes of F_b.
    pose : array_like (n_task,) or (6,), optional
        The unloaded pose (task coordinates or a full pose); the home pose if None.
    tool_point : array_like (3,), optional
        The load point in the platform frame [m]; P if None.

    Returns
    -------
    MovingLoadedState

    Raises
    ------
    InputDataError
        A malformed wrench, pose or tool point; an actuator beyond its stroke.
    UnreachablePoseError, SingularConfigurationError
        As the frozen model, at the unloaded pose.
    EquilibriumError
        No equilibrium found, or the load path passes the first instability.
    """
    p = validate_pose(design, pose)
    batch = moving_states(design, p.reshape(1, 6), wrench, tool_point)
    raise_moving_refusal(design, batch, 0)
    return state_of(batch, 0)


#: The names of 0.2 (inside the package; ``ppm_stiffness.moving_equilibrium`` and
#: ``ppm_stiffness.MovingEquilibrium`` warn).
MovingEquilibrium = MovingLoadedState
moving_equilibrium = moving_loaded_state
