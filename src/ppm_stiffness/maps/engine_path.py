"""The general batched path: the stiffness of any design at many poses, by the engine.

Per chunk of full poses (n, 6): every leg's batched inverse kinematics
(``leg.solve``) and reachability (``leg.reachable``: IK solvable, every joint
coordinate within its limits, U and S angle limits included), and at the reachable
poses only the batched engine of :mod:`ppm_stiffness.legs.engine` (any joint chain:
``reduce_chain`` then ``leg_stiffness`` per leg, K the sum over legs). This is the code
the single-pose API runs for a design that is not planar
(:func:`ppm_stiffness.model.stiffness_at_pose`, a batch of one), so the two agree to
rounding; the dense definition (:func:`ppm_stiffness.legs.chain.leg_springs` and the
bordered inverse of :mod:`ppm_stiffness.core.solver`) is the reference the tests hold
it to.

The legs' summed projector ``Pi`` (:mod:`ppm_stiffness.core.singularity`) comes from the
engine's wrench bases, orthonormal in length-balanced units: with ``B`` the legs' bases
side by side (balanced), ``Pi = B B^T`` (one batched product instead of a projector per
leg). Poses where a leg's IK has no solution never reach the engine, so no NaN leaks
into the results: they are masked.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, BoolArray, FloatArray
from ppm_stiffness.design import Design
from ppm_stiffness.legs import engine
from ppm_stiffness.legs.base import LegPose

#: Poses per chunk of the general path (the engine works on 4096 at a time inside it;
#: about 3 kB per pose and leg of temporaries).
GENERAL_CHUNK = 16384


def solve_chunk(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike,
    completed: BoolArray | None = None,
) -> tuple[FloatArray, list[LegPose], BoolArray]:
    """Per-pose actuator stiffness (n, n_legs), every leg's inverse kinematics and the
    reachability mask (n,) of a chunk of poses (n, 6) (or planar (n, 3)): ``completed``
    (the pose completion converged, :func:`ppm_stiffness.poses.full_poses`), every
    leg's IK solvable and its joint coordinates within limits."""
    p = np.asarray(poses, dtype=float)
    n = p.shape[0]
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), (n, len(design.legs)))
    with np.errstate(all="ignore"):
        leg_poses = [leg.solve(p) for leg in design.legs]
    reach = np.ones(n, dtype=bool) if completed is None else np.array(completed, dtype=bool)
    for leg, lp in zip(design.legs, leg_poses, strict=True):
        reach &= np.asarray(leg.reachable(lp), dtype=bool)
    return k_act, leg_poses, reach


def take(leg_pose: LegPose, index: np.ndarray) -> LegPose:
    """The poses ``index`` of a leg pose with one batch axis (``numpy.take`` along it:
    several times faster than fancy indexing for these (n, 3) arrays)."""
    n = leg_pose.poses.shape[0]
    return LegPose(
        poses=np.take(leg_pose.poses, index, axis=0),
        points={key: np.take(v, index, axis=0) for key, v in leg_pose.points.items()},
        coordinates={key: np.take(v, index, axis=0) for key, v in leg_pose.coordinates.items()},
        solvable=np.take(np.broadcast_to(leg_pose.solvable, (n,)), index, axis=0),
    )


def engine_stiffness(
    design: Design, leg_poses: list[LegPose], actuator_stiffness: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """K (m, 6, 6) at P and the legs' summed projector ``Pi`` (m, 6, 6) at m solved
    (reachable) poses, by :mod:`ppm_stiffness.legs.engine`; ``actuator_stiffness``
    (m, n_legs). Non-finite where a leg's passive joints are dependent."""
    m = actuator_stiffness.shape[0]
    total: FloatArray | None = None
    bases = []
    with np.errstate(all="ignore"):
        for i, (leg, lp) in enumerate(zip(design.legs, leg_poses, strict=True)):
            red = engine.reduce_chain(leg.chain(lp), m)
            column = actuator_stiffness[:, i]
            k_leg: FloatArray | float = column
            if m and np.all(column == column[0]):
                k_leg = float(column[0])  # one value at every pose
            k = engine.leg_stiffness(red, k_leg)
            if total is None:
                total = k
            else:
                total += k
            bases.append(red.basis)
        b = np.concatenate(bases, axis=2) * BALANCE[:, None]
        pi = b @ np.swapaxes(b, 1, 2)
    assert total is not None
    return total, pi


def reachable_stiffness(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike,
    completed: BoolArray | None = None,
) -> tuple[np.ndarray, FloatArray, FloatArray, BoolArray]:
    """K and ``Pi`` at the reachable poses of a chunk only: the indices (m,) of the
    reachable poses, K (m, 6, 6), ``Pi`` (m, 6, 6) and the reachability mask (n,)
    (inputs as :func:`general_stiffness`)."""
    k_act, leg_poses, reach = solve_chunk(design, poses, actuator_stiffness, completed)
    if reach.all():
        index = np.arange(reach.size)
        k, pi = engine_stiffness(design, leg_poses, np.ascontiguousarray(k_act))
        return index, k, pi, reach
    index = np.flatnonzero(reach)
    if index.size == 0:
        return index, np.zeros((0, 6, 6)), np.zeros((0, 6, 6)), reach
    sub = [take(lp, index) for lp in leg_poses]
    k, pi = engine_stiffness(design, sub, np.take(k_act, index, axis=0))
    return index, k, pi, reach


def general_stiffness(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike,
    completed: BoolArray | None = None,
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Stiffness at poses by the engine (any design), one chunk.

    Parameters
    ----------
    design : Design
    poses : array_like, shape (n, 6), or (n, 3) for a planar design
        Full poses (x, y, z [m], rx, ry, rz [rad]) of P in F_b (completed:
        :func:`ppm_stiffness.poses.full_poses`), or planar (x, y, phi).
    actuator_stiffness : array_like, shape (n, n_legs) or (n_legs,)
        Per pose and leg [N/m, or N·m/rad for a rotary actuator].
    completed : ndarray of bool (n,), optional
        The completion's mask; poses where it is False are not reachable.

    Returns
    -------
    stiffness : ndarray (n, 6, 6)
        K at P, axes of F_b (SI); zero where not reachable, NaN where a leg's passive
        joints are dependent.
    projector : ndarray (n, 6, 6)
        The legs' summed projector ``Pi``; zero where not reachable.
    reachable : ndarray of bool (n,)
    """
    index, k, pi, reach = reachable_stiffness(design, poses, actuator_stiffness, completed)
    if index.size == reach.size:
        return k, pi, reach
    total = np.zeros((reach.size, 6, 6))
    proj = np.zeros((reach.size, 6, 6))
    total[index], proj[index] = k, pi
    return total, proj, reach
