"""The legs' linear parts at one or many poses: what the loaded statics needs of the model.

Per pose and leg (module doc of :mod:`ppm_stiffness.statics.equilibrium`): ``K_i^S``,
the leg's stiffness with its actuator rigid; ``a_i``, the actuated joint's unit twist;
the leg's stiffness at any actuator stiffness (the loaded K); and per pose the legs'
summed projector ``Pi`` with the singularity decision of
:mod:`ppm_stiffness.core.singularity`. Built by the planar engine
(:mod:`ppm_stiffness.legs.planar`) for a planar design, else by the batched engine
(:mod:`ppm_stiffness.legs.engine`), exactly as
:func:`ppm_stiffness.model.stiffness_at_pose` chooses. One pose
and many poses run the same code: the single-pose API is a batch of one (a pose given
as (3,) is evaluated by the engine in plain float arithmetic); :class:`LegStructures`
keeps one pose's terms for several loads.

Twists and wrenches at P, axes of F_b, SI; arrays have a leading batch axis (k,).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import SingularConfigurationError
from ppm_stiffness.core.singularity import (
    assemble_blocks,
    basis_projector,
    nonsingular,
    nonsingular_blocks,
    transmission_index,
)
from ppm_stiffness.core.solver import bordered_stiffness
from ppm_stiffness.design import Design
from ppm_stiffness.legs import engine, planar
from ppm_stiffness.legs.base import LegPose
from ppm_stiffness.model import solve_legs, transmission_blocks, validate_pose


@dataclass(frozen=True)
class LegTerms:
    """The legs' linear parts at k poses (SI, at P, axes of F_b).

    Attributes
    ----------
    rigid : ndarray (k, n_legs, 6, 6)
        ``K_i^S``, each leg's stiffness with its actuator rigid (non-finite where a
        leg is rigid along a wrench it transmits).
    actuator : ndarray (k, n_legs, 6)
        ``a_i``, the actuated joint's unit twist.
    projector : ndarray (k, 6, 6)
        ``Pi``, the legs' summed projector onto their transmitted wrenches.
    nonsingular : ndarray of bool (k,)
        The singularity decision on ``Pi`` (:mod:`ppm_stiffness.core.singularity`).
    leg_stiffness : callable
        ``(k, n_legs)`` actuator stiffnesses -> the legs' stiffnesses (k, n_legs, 6, 6).
    stiffness : callable
        ``(k, n_legs)`` actuator stiffnesses -> their sum, K (k, 6, 6).
    """

    rigid: FloatArray
    actuator: FloatArray
    projector: FloatArray
    nonsingular: BoolArray
    leg_stiffness: Callable[[FloatArray], FloatArray]
    stiffness: Callable[[FloatArray], FloatArray]

    @property
    def size(self) -> int:
        return int(self.rigid.shape[0])

    def index(self) -> FloatArray:
        """The transmission index (k,) of :mod:`ppm_stiffness.core.singularity`."""
        return transmission_index(self.projector)


def bordered_or_nan(compliance6: FloatArray, passive: FloatArray) -> FloatArray:
    """:func:`~ppm_stiffness.core.solver.bordered_stiffness` of a batch (k, ...); NaN for
    the poses whose bordered matrix is singular (redone pose by pose when the batched
    inverse fails)."""
    try:
        return bordered_stiffness(compliance6, passive)
    except SingularConfigurationError:
        out = np.full(compliance6.shape[:-2] + (6, 6), np.nan)
        for n in range(compliance6.shape[0]):
            try:
                out[n] = bordered_stiffness(compliance6[n], passive[n])
            except SingularConfigurationError:
                continue
        return out


def _vec6(inplane: planar.Vec3 | None, outplane: planar.Vec3 | None, k: int) -> FloatArray:
    """A twist (k, 6) from its in-plane and out-of-plane block vectors."""
    v = np.zeros((k, 6))
    for block, idx in ((inplane, planar.IN_PLANE), (outplane, planar.OUT_OF_PLANE)):
        if block is not None:
            for c in range(3):
                v[:, idx[c]] = block[c]
    return v


def _planar_terms(design: Design, leg_poses: list[LegPose], k: int) -> LegTerms | None:
    blocks = []
    for leg, lp in zip(design.legs, leg_poses, strict=True):
        found = planar.leg_blocks(leg.chain(lp))
        if found is None:
            return None
        blocks.append(found)
    n = len(blocks)
    rigid = np.zeros((k, n, 6, 6))
    with np.errstate(all="ignore"):
        for i, b in enumerate(blocks):
            assemble_blocks(*planar.leg_stiffness_blocks(b, None), (k,), out=rigid[:, i])
        p_in, p_out = transmission_blocks(blocks)
        ok = np.broadcast_to(nonsingular_blocks(p_in, p_out, (k,)), (k,))
    actuator = np.stack([_vec6(b.inplane.twist, b.outplane.twist, k) for b in blocks], axis=1)

    def leg_stiffness(actuator_stiffness: FloatArray) -> FloatArray:
        k_act = np.asarray(actuator_stiffness, dtype=float)
        out = np.zeros((k, n, 6, 6))
        with np.errstate(all="ignore"):
            for i, b in enumerate(blocks):
                blk = planar.leg_stiffness_blocks(b, k_act[:, i])
                assemble_blocks(*blk, (k,), out=out[:, i])
        return out

    def stiffness(actuator_stiffness: FloatArray) -> FloatArray:
        k_act = np.asarray(actuator_stiffness, dtype=float)
        with np.errstate(all="ignore"):
            total = planar.sum_blocks(
                planar.leg_stiffness_blocks(b, k_act[:, i]) for i, b in enumerate(blocks)
            )
        return assemble_blocks(*total, (k,))

    projector = assemble_blocks(p_in, p_out, (k,))
    return LegTerms(rigid, actuator, projector, np.array(ok), leg_stiffness, stiffness)


def _engine_terms(design: Design, leg_poses: list[LegPose], k: int) -> LegTerms:
    """The terms by the batched engine (:mod:`ppm_stiffness.legs.engine`), any chain."""
    reductions = [
        engine.reduce_chain(leg.chain(lp), k)
        for leg, lp in zip(design.legs, leg_poses, strict=True)
    ]
    with np.errstate(all="ignore"):
        rigid = np.stack([engine.leg_stiffness(r, None) for r in reductions], axis=1)
    projector = np.sum([basis_projector(r.basis) for r in reductions], axis=0)
    actuator = np.stack([np.broadcast_to(r.twist, (k, 6)) for r in reductions], axis=1)

    def leg_stiffness(actuator_stiffness: FloatArray) -> FloatArray:
        k_act = np.asarray(actuator_stiffness, dtype=float)
        with np.errstate(all="ignore"):
            return np.stack(
                [engine.leg_stiffness(r, k_act[:, i]) for i, r in enumerate(reductions)], axis=1
            )

    ok = nonsingular(transmission_index(projector))
    return LegTerms(
        rigid,
        actuator,
        projector,
        ok,
        leg_stiffness,
        lambda k_act: leg_stiffness(k_act).sum(axis=1),
    )


def leg_terms(design: Design, leg_poses: list[LegPose]) -> LegTerms:
    """The legs' linear parts from every leg's solved poses (``leg.solve``), one pose
    (points of shape (3,)) or k poses ((k, 3)), solved at full poses (k, 6);
    reachability is the caller's.

    Returns
    -------
    LegTerms
        With k = 1 for one pose.
    """
    shape = np.shape(leg_poses[0].poses)[:-1]
    k = int(np.prod(shape)) if shape else 1
    found = _planar_terms(design, leg_poses, k) if design.planar else None
    return _engine_terms(design, leg_poses, k) if found is None else found


def take(leg_pose: LegPose, index: np.ndarray) -> LegPose:
    """The poses ``index`` of a leg pose with one batch axis."""
    return LegPose(
        poses=leg_pose.poses[index],
        points={key: v[index] for key, v in leg_pose.points.items()},
        coordinates={key: v[index] for key, v in leg_pose.coordinates.items()},
        solvable=np.broadcast_to(leg_pose.solvable, leg_pose.poses.shape[:-1])[index],
    )


def reachable_terms(
    design: Design, poses: FloatArray, completed: BoolArray | None = None
) -> tuple[BoolArray, LegTerms | None]:
    """Reachability (k,) of full poses (k, 6) (completed, every leg's IK solvable and its
    joint coordinates within limits) and the legs' terms at the reachable ones (None if
    there is none)."""
    single = poses.shape[0] == 1  # one pose: the engine in plain float arithmetic
    leg_poses = [leg.solve(poses[0] if single else poses) for leg in design.legs]
    reach = np.ones(poses.shape[0], dtype=bool) if completed is None else completed.copy()
    for leg, lp in zip(design.legs, leg_poses, strict=True):
        reach &= np.asarray(leg.reachable(lp), dtype=bool).reshape(-1)
    if single:
        return reach, (leg_terms(design, leg_poses) if reach[0] else None)
    index = np.flatnonzero(reach)
    if index.size == 0:
        return reach, None
    return reach, leg_terms(design, [take(lp, index) for lp in leg_poses])


class LegStructures:
    """The linear parts of every leg at one pose (springs built once), for several
    loads at the same pose (:func:`ppm_stiffness.statics.equilibrium.equilibrium`,
    deflection curves).

    Attributes
    ----------
    pose : ndarray (6,)
        The full pose (:mod:`ppm_stiffness.poses`).
    terms : LegTerms
        The batch of one pose.
    actuator : ndarray (n, 6)
        ``a_i``, the actuated joint's unit twist.

    Raises
    ------
    UnreachablePoseError
        If a leg cannot reach the pose.
    """

    def __init__(self, design: Design, pose: ArrayLike) -> None:
        self.design = design
        self.pose = validate_pose(design, pose)
        self.terms = leg_terms(design, solve_legs(design, self.pose))
        self.actuator = self.terms.actuator[0]

    @property
    def n_legs(self) -> int:
        return int(self.actuator.shape[0])

    def leg_stiffnesses(self, actuator_stiffness: ArrayLike) -> FloatArray:
        """Each leg's tangent stiffness (n, 6, 6) with the given actuator stiffnesses."""
        k = np.asarray(actuator_stiffness, dtype=float).reshape(1, -1)
        return np.asarray(self.terms.leg_stiffness(k)[0])

    def stiffness(self, actuator_stiffness: ArrayLike) -> FloatArray:
        """Cartesian stiffness (6, 6) at P with the given actuator stiffnesses."""
        return np.asarray(self.leg_stiffnesses(actuator_stiffness).sum(axis=0))
