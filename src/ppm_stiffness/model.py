"""The Cartesian stiffness of a design at a pose: the single-pose API.

Joins each leg's inverse kinematics and joint chain (:mod:`ppm_stiffness.legs`) and
the engines (:mod:`ppm_stiffness.legs.planar` for planar designs,
:mod:`ppm_stiffness.legs.engine` for any chain; both the model of
:mod:`ppm_stiffness.core.solver`). A pose is given as the design's task coordinates or
a full pose (x, y, z, rx, ry, rz) [m, rad] (:mod:`ppm_stiffness.poses`): for a planar
design ``(x, y, phi)`` as ever. Matrices are at P with the axes of F_b (see
:mod:`ppm_stiffness.core.conventions`) unless a function says "at the tool point".

A pose is refused when a leg cannot reach it (:class:`UnreachablePoseError`) or when it
is singular (:class:`SingularConfigurationError`): K not finite, or the legs'
transmitted wrenches nearly failing to span every direction, by the transmission index
of :mod:`ppm_stiffness.core.singularity` (at or below
:data:`~ppm_stiffness.core.singularity.SINGULARITY_TOLERANCE` = 1e-6) -- the one test
the maps and the loaded states use too. It depends on the joints' geometry only, not
on how stiff the parts are.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import (
    FloatArray,
    length_balanced,
    stiffness_b_from_stiffness_a,
)
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.core.singularity import (
    SINGULARITY_TOLERANCE,
    assemble_blocks,
    basis_projector,
    block_projector,
    nonsingular,
    nonsingular_blocks,
    transmission_index,
)
from ppm_stiffness.core.solver import LegSprings, leg_stiffness
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import leg_label
from ppm_stiffness.legs import engine, planar
from ppm_stiffness.legs.base import LegPose, as_poses
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.poses import full_pose, home_pose, task_values

#: For a stiffness matrix given without its design (a measured or target K,
#: ``analyze --matrix``): smallest admissible ratio of the smallest to the largest
#: eigenvalue of the length-balanced matrix (:func:`check_nonsingular`). Without the
#: legs' joints only the spread of K can be judged; the model's own poses are judged by
#: the transmission index instead (module doc).
MATRIX_RATIO_TOLERANCE = 1e-6


def workspace_centre(design: Design) -> FloatArray:
    """The task coordinates of the design's home pose (:func:`ppm_stiffness.poses
    .home_pose`): (x, y, phi) [m, m, rad] for a planar design."""
    return task_values(design, home_pose(design))


def locked_actuator_stiffness(design: Design) -> FloatArray:
    """Each leg's locked actuator stiffness (n_legs,) [N/m or N·m/rad]; ``inf`` for a
    passive constraining leg (:meth:`~ppm_stiffness.legs.base.LegModel.locked_stiffness`:
    it has no actuator column, so the value enters nothing)."""
    return np.array([leg.locked_stiffness() for leg in design.legs])


def parallel_stiffnesses(design: Design) -> FloatArray:
    """Each leg's elastic stiffness in parallel with its drive (n_legs,) [N/m or
    N·m/rad] (:meth:`~ppm_stiffness.legs.base.LegModel.parallel_stiffness`; 0 without
    one)."""
    return np.array([leg.parallel_stiffness() for leg in design.legs])


def actuator_stiffness_vector(design: Design, actuator_stiffness: ArrayLike | None) -> FloatArray:
    """Per-leg actuator stiffness (n_legs,); the locked values when None is given."""
    n = len(design.legs)
    if actuator_stiffness is None:
        return locked_actuator_stiffness(design)
    k = np.asarray(actuator_stiffness, dtype=float)
    if k.shape == ():
        k = np.full(n, float(k))
    if k.shape[-1] != n:
        raise DesignError(f"expected {n} actuator stiffnesses, got {k.shape[-1]}")
    return checked_actuator_stiffness(design, k)


def checked_actuator_stiffness(design: Design, k_act: FloatArray) -> FloatArray:
    """Actuator stiffnesses (..., n_legs) [N/m or N·m/rad], finite and > 0 for every
    actuated leg; a passive constraining leg's entry is ``inf`` whatever was given (it
    has no actuator column: its value enters nothing).

    Raises
    ------
    DesignError
        An actuated leg's stiffness not finite or not > 0.
    """
    actuated = np.array([leg.actuator is not None for leg in design.legs])
    given = k_act[..., actuated]
    if not np.all(np.isfinite(given)) or np.any(given <= 0):
        raise DesignError("actuator stiffness must be finite and > 0")
    if actuated.all():
        return k_act
    out = np.array(k_act, dtype=float, copy=True)
    out[..., ~actuated] = np.inf
    return out


def validate_pose(design: Design, pose: ArrayLike | None) -> FloatArray:
    """One full pose (6,) [m, rad] from task coordinates or a full pose (the home pose if
    None), or raise (:func:`ppm_stiffness.poses.full_pose`)."""
    return full_pose(design, pose)


def solve_legs(design: Design, pose: ArrayLike) -> list[LegPose]:
    """Inverse kinematics of every leg at one pose, raising if it is unreachable."""
    p = full_pose(design, pose)
    out = []
    for i, leg in enumerate(design.legs):
        lp = leg.solve(p)
        leg.check(lp, leg_label(i))
        out.append(lp)
    return out


def leg_springs_at_pose(
    design: Design, pose: ArrayLike, actuator_stiffness: ArrayLike | None = None
) -> list[LegSprings]:
    """Virtual springs of every leg at one reachable pose (raises if unreachable)."""
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    return [
        leg_springs(leg.chain(lp), k_act[i])
        for i, (leg, lp) in enumerate(zip(design.legs, solve_legs(design, pose), strict=True))
    ]


def actuator_screws_at_pose(design: Design, pose: ArrayLike) -> FloatArray:
    """Unit twist of each leg's actuated joint at P (n_legs, 6): ``G_i = a_i . w_i``."""
    return np.array(
        [
            leg.actuator_screw(lp)
            for leg, lp in zip(design.legs, solve_legs(design, pose), strict=True)
        ]
    )


def eigenvalue_ratio(stiffness: ArrayLike) -> FloatArray:
    """Smallest over largest eigenvalue of the length-balanced K, shape (...)."""
    eig = np.linalg.eigvalsh(length_balanced(stiffness))
    return np.asarray(eig[..., 0] / eig[..., -1])


def check_nonsingular(stiffness: FloatArray, where: str = "") -> None:
    """Raise :class:`SingularConfigurationError` if a matrix given without its design
    (a measured or target K) is not finite, not positive definite, or its
    length-balanced eigenvalue ratio is at or below :data:`MATRIX_RATIO_TOLERANCE`.

    The model's poses are not judged this way (a very stiff structure spreads K's
    eigenvalues without losing any stiffness): see :func:`check_transmission`.
    """
    if not np.all(np.isfinite(stiffness)):
        raise SingularConfigurationError(f"stiffness matrix is not finite{where}")
    eig = np.linalg.eigvalsh(length_balanced(stiffness))
    if eig[-1] <= 0 or eig[0] < -MATRIX_RATIO_TOLERANCE * eig[-1]:
        raise SingularConfigurationError(
            f"stiffness matrix is not positive definite{where}: smallest eigenvalue "
            f"{eig[0]:.3g} (length-balanced units)"
        )
    if eig[0] <= MATRIX_RATIO_TOLERANCE * eig[-1]:
        raise SingularConfigurationError(
            f"singular configuration{where}: stiffness eigenvalue ratio "
            f"{eig[0] / eig[-1]:.2e} below {MATRIX_RATIO_TOLERANCE:.0e}"
        )


def singular_message(stiffness: FloatArray, projector: FloatArray, where: str = "") -> str:
    """Why a pose is singular, for :class:`SingularConfigurationError` (one pose:
    K (6, 6) and the legs' summed projector ``Pi`` (6, 6))."""
    if not np.all(np.isfinite(stiffness)):
        return (
            f"stiffness matrix is not finite{where}: a leg's passive joints are dependent "
            "or it is rigid along a wrench it transmits"
        )
    tau = float(transmission_index(projector))
    return (
        f"singular configuration{where}: the legs' transmitted wrenches leave a direction "
        f"unresisted (transmission index {tau:.2e}, at or below {SINGULARITY_TOLERANCE:.0e})"
    )


def check_transmission(
    ok: bool | np.bool_, stiffness: FloatArray, projector: FloatArray, where: str = ""
) -> None:
    """Raise :class:`SingularConfigurationError` unless ``ok``, the decision of
    :func:`ppm_stiffness.core.singularity.nonsingular` (or ``nonsingular_blocks``) and
    a finite K at this pose, with the message of :func:`singular_message`."""
    if not ok:
        raise SingularConfigurationError(singular_message(stiffness, projector, where))


def pose_label(pose: ArrayLike, design: Design | None = None) -> str:
    """`` at pose (x mm, y mm, phi deg)`` for messages about a planar design's pose; the
    pose of a spatial design (``design.planar`` False), or one out of the plane (z, rx
    or ry not 0), in full: `` at pose (x = .. mm, y = .. mm, z = .. mm, rx = .. deg,
    ry = .. deg, rz = .. deg)``."""
    p = as_poses(pose)
    if np.any(p[[2, 3, 4]] != 0) or (design is not None and not design.planar):
        from ppm_stiffness.poses import format_pose

        return f" at pose ({format_pose(p)})"
    return f" at pose ({p[0] * 1e3:.2f} mm, {p[1] * 1e3:.2f} mm, {np.degrees(p[5]):.2f} deg)"


def transmission_blocks(legs: list[planar.LegBlocks]) -> tuple[planar.Sym3, planar.Sym3]:
    """``Pi`` by blocks (in-plane, out-of-plane upper triangles): the sum of the legs'
    projectors onto the wrenches they transmit (:mod:`ppm_stiffness.core.singularity`)."""
    return planar.sum_blocks(
        (
            block_projector(blk.inplane.basis, planar.IN_PLANE),
            block_projector(blk.outplane.basis, planar.OUT_OF_PLANE),
        )
        for blk in legs
    )


def planar_stiffness(
    design: Design, leg_poses: list[LegPose], actuator_stiffness: FloatArray
) -> tuple[FloatArray, FloatArray, bool] | None:
    """K (6, 6), the legs' summed projector ``Pi`` (6, 6) and the nonsingularity
    decision at one pose by the planar engine (:mod:`ppm_stiffness.legs.planar`), from
    every leg's solved pose; None if a chain is not planar. The same model as
    :func:`ppm_stiffness.core.solver.cartesian_stiffness` of the legs' springs, in
    closed form per block (no 22 x 22 matrices, no cross products of arrays)."""
    legs, blocks = [], []
    with np.errstate(all="ignore"):
        for leg, lp, k_act in zip(design.legs, leg_poses, actuator_stiffness, strict=True):
            found = planar.leg_blocks(leg.chain(lp))
            if found is None:
                return None
            blocks.append(found)
            legs.append(planar.leg_stiffness_blocks(found, float(k_act)))
        k_in, k_out = planar.sum_blocks(legs)
        p_in, p_out = transmission_blocks(blocks)
        ok = bool(nonsingular_blocks(p_in, p_out, ()))
    k = assemble_blocks(k_in, k_out, ())
    ok = ok and bool(np.all(np.isfinite(k)))
    return k, assemble_blocks(p_in, p_out, ()), ok


def stiffness_at_pose(
    design: Design, pose: ArrayLike | None = None, actuator_stiffness: ArrayLike | None = None
) -> FloatArray:
    """Cartesian stiffness matrix of the platform at P, shape (6, 6).

    Parameters
    ----------
    design : Design
    pose : array_like, shape (n_task,) or (6,), optional
        The task coordinates ((x [m], y [m], phi [rad]) for a planar design) or the full
        pose of P in F_b (:mod:`ppm_stiffness.poses`); the home pose if None.
    actuator_stiffness : array_like, shape (n_legs,) or scalar, optional
        [N/m, or N·m/rad for a rotary actuator]; the locked values if None.

    Returns
    -------
    ndarray, shape (6, 6)
        At P, axes of F_b, blocks [[K_rr, K_rt], [K_rt^T, K_tt]] in N·m/rad, N, N/m.

    Raises
    ------
    InputDataError, UnreachablePoseError, SingularConfigurationError
    """
    p = full_pose(design, pose)
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    k, pi, ok = _stiffness_and_transmission(design, solve_legs(design, p), k_act)
    check_transmission(ok, k, pi, pose_label(p, design))
    return k


def _stiffness_and_transmission(
    design: Design, leg_poses: list[LegPose], actuator_stiffness: FloatArray
) -> tuple[FloatArray, FloatArray, bool]:
    """K (6, 6), the legs' summed projector ``Pi`` (6, 6) and the nonsingularity
    decision at one solved pose: the planar engine for a planar design, the batched
    engine (:mod:`ppm_stiffness.legs.engine`) on one pose for any other."""
    if design.planar:
        found = planar_stiffness(design, leg_poses, actuator_stiffness)
        if found is not None:
            return found
    reductions = [
        engine.reduce_chain(leg.chain(lp), 1)
        for leg, lp in zip(design.legs, leg_poses, strict=True)
    ]
    k = engine.platform_stiffness(reductions, actuator_stiffness)[0]
    pi = np.sum([basis_projector(r.basis[0]) for r in reductions], axis=0)
    ok = bool(nonsingular(transmission_index(pi))) and bool(np.all(np.isfinite(k)))
    return k, pi, ok


def transmission_at_pose(design: Design, pose: ArrayLike | None = None) -> float:
    """The transmission index at one pose (:mod:`ppm_stiffness.core.singularity`): in
    [0, 1], 0 at a singular pose; the pose is refused as singular at or below
    :data:`SINGULARITY_TOLERANCE`. It depends on the joints' geometry only.

    Raises
    ------
    UnreachablePoseError
    """
    p = full_pose(design, pose)
    _, pi, _ = _stiffness_and_transmission(
        design, solve_legs(design, p), locked_actuator_stiffness(design)
    )
    return float(transmission_index(pi))


def leg_stiffnesses_at_pose(
    design: Design, pose: ArrayLike | None = None, actuator_stiffness: ArrayLike | None = None
) -> list[FloatArray]:
    """Each leg's 6x6 stiffness at P (their sum is :func:`stiffness_at_pose`)."""
    p = full_pose(design, pose)
    return [leg_stiffness(leg) for leg in leg_springs_at_pose(design, p, actuator_stiffness)]


def tool_offset(pose: ArrayLike, tool_point: ArrayLike) -> FloatArray:
    """Tool point relative to P in F_b components [m]: ``R @ tool_point`` at a full pose
    (..., 6) (a planar pose (x, y, phi) is read as one)."""
    return pose6.platform_offset(as_poses(pose), np.asarray(tool_point, dtype=float))


def stiffness_at_tool_point(
    stiffness_p: ArrayLike, pose: ArrayLike, tool_point: ArrayLike
) -> FloatArray:
    """K expressed at the tool point (axes of F_b) from K at P (eq. 16).

    Parameters
    ----------
    stiffness_p : array_like (6, 6), at P, axes of F_b.
    pose : array_like (6,) [m, rad], or a planar (x, y, phi)
    tool_point : array_like (3,)
        In the platform frame F_p [m].
    """
    # Frame A: at P; frame B: at the tool point T, same axes. A's origin seen from B
    # is P - T.
    return stiffness_b_from_stiffness_a(stiffness_p, np.eye(3), -tool_offset(pose, tool_point))
