"""The loaded state under a wrench at many poses, with the maps' masks.

:func:`loaded_poses` gives, at every pose, the equilibrium that
:func:`ppm_stiffness.statics.loading.loaded_state` computes, by the same code: the
statics module solves every pose of a chunk at once
(:func:`ppm_stiffness.statics.equilibrium.loaded_states`, of which the single-pose call
is the batch of one) and gives each pose its refusal code
(:class:`ppm_stiffness.core.refusals.Refusal`). This module chunks the poses, adds the
principal stiffnesses of the loaded K (the paper's decoupling,
:func:`ppm_stiffness.maps.batch.principal_from_matrices`) and turns the codes into
masks: where the single-pose call raises, the batch masks, by construction.
Wrenches and twists at P, axes of F_b, SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.refusals import Refusal, RefusalArray
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import as_poses
from ppm_stiffness.maps.batch import PLANAR_CHUNK, _masked, principal_from_matrices
from ppm_stiffness.statics.equilibrium import loaded_states


@dataclass(frozen=True)
class LoadedBatch:
    """The loaded state at many poses (SI). Arrays have the batch shape of the poses.

    ``refusal`` holds each pose's code (:class:`ppm_stiffness.core.refusals.Refusal`,
    0 exactly where ``loaded_state`` returns); the masks follow from it (each implies
    the one before):

    reachable
        every leg's IK solvable and its joint coordinates within limits;
    singular
        reachable, but singular with the actuators rigid (where ``loaded_state`` raises
        :class:`SingularConfigurationError` before solving);
    solved
        reachable, not singular, and Newton's method converged: the equilibrium exists
        and its values below are given;
    valid
        solved, within the small-displacement model (no actuator beyond its whole
        stroke, a platform rotation of at most
        :data:`~ppm_stiffness.statics.equilibrium.MAX_ROTATION`) and a positive
        definite loaded K: exactly where ``loaded_state`` returns without raising.

    Attributes
    ----------
    twist : numpy.ma.MaskedArray (..., 6)
        Platform twist (phi_x, phi_y, phi_z [rad], x, y, z [m]) at P, axes of F_b;
        masked where not ``solved``.
    actuator_forces, actuator_displacements, actuator_stiffness : numpy.ma.MaskedArray
        (..., n_legs): G_i [N or N·m], delta_i(G_i) [m or rad], the tangent stiffness
        of eq. (21) [N/m or N·m/rad]; masked where not ``solved``.
    k_phi, k_x, k_y : numpy.ma.MaskedArray (...)
        Principal stiffnesses of the loaded tangent K (paper decoupling), masked where
        not ``valid``.
    stiffness : ndarray (..., 6, 6) or None
        The loaded tangent K (zero where not valid), when asked for.
    iterations : ndarray of int (...)
        Newton iterations (0 for statically determinate forces; -1 where not solved).
    refusal : ndarray of int8 (...)
    """

    reachable: BoolArray
    singular: BoolArray
    solved: BoolArray
    valid: BoolArray
    twist: np.ma.MaskedArray
    actuator_forces: np.ma.MaskedArray
    actuator_displacements: np.ma.MaskedArray
    actuator_stiffness: np.ma.MaskedArray
    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    stiffness: FloatArray | None
    iterations: np.ndarray
    refusal: RefusalArray


def loaded_poses(
    design: Design,
    poses: ArrayLike,
    wrench: ArrayLike,
    *,
    matrices: bool = False,
    chunk_size: int | None = None,
) -> LoadedBatch:
    """The loaded state under ``wrench`` at many poses (module doc).

    Parameters
    ----------
    design : Design
        Any architecture, redundant designs included.
    poses : array_like, shape (..., 3)
        (x [m], y [m], phi [rad]) of P in F_b.
    wrench : array_like, shape (6,)
        (m_x, m_y, m_z [N·m], f_x, f_y, f_z [N]) at P, axes of F_b, the same at every
        pose (move a wrench given at a tool point with
        :func:`ppm_stiffness.core.conventions.wrench_b_from_wrench_a`).
    matrices : bool
        Also return the loaded tangent K (288 bytes per pose).
    chunk_size : int, optional
        Poses evaluated at once; default :data:`~ppm_stiffness.maps.batch.PLANAR_CHUNK`.

    Returns
    -------
    LoadedBatch
        At every ``valid`` pose the numbers of
        :func:`ppm_stiffness.statics.loading.loaded_state`.

    Raises
    ------
    InputDataError
        Poses not of shape (..., 3) or not finite; a wrench not of 6 finite values.
    """
    from ppm_stiffness.statics.loading import validate_wrench

    w = validate_wrench(wrench)
    p = np.asarray(poses, dtype=float)
    if p.shape[-1:] != (3,):
        raise InputDataError(f"poses must have shape (..., 3), got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InputDataError("poses must be finite")
    batch = p.shape[:-1]
    flat = p.reshape(-1, 3)
    n, n_legs = flat.shape[0], len(design.legs)
    step = max(int(chunk_size or PLANAR_CHUNK), 1)
    refusal = np.zeros(n, dtype=np.int8)
    twist = np.zeros((n, 6))
    per_leg = np.zeros((3, n, n_legs))
    fields = np.zeros((3, n))
    iterations = np.full(n, -1)
    mats = np.zeros((n, 6, 6)) if matrices else None
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        st = loaded_states(design, as_poses(flat[sl]), w)
        ok = st.refusal == 0
        refusal[sl] = st.refusal
        twist[sl] = st.twist
        per_leg[:, sl] = st.forces, st.displacements, st.actuator_stiffness
        pr = principal_from_matrices(np.where(ok[:, None, None], st.stiffness, np.eye(6)))
        fields[:, sl] = pr.k_phi, pr.k_x, pr.k_y
        iterations[sl] = st.iterations
        if mats is not None:
            mats[sl] = np.where(ok[:, None, None], st.stiffness, 0.0)
    valid = refusal == 0
    solved = valid | (refusal > Refusal.NO_EQUILIBRIUM)

    def by_solved(values: FloatArray) -> np.ma.MaskedArray:
        mask = np.broadcast_to(~solved.reshape((n,) + (1,) * (values.ndim - 1)), values.shape)
        data = np.where(mask, np.nan, values)
        out = np.ma.MaskedArray(data, mask=mask.copy(), fill_value=np.nan)
        return out.reshape(batch + values.shape[1:])

    return LoadedBatch(
        reachable=(refusal != Refusal.UNREACHABLE).reshape(batch),
        singular=(refusal == Refusal.SINGULAR).reshape(batch),
        solved=solved.reshape(batch),
        valid=valid.reshape(batch),
        twist=by_solved(twist),
        actuator_forces=by_solved(per_leg[0]),
        actuator_displacements=by_solved(per_leg[1]),
        actuator_stiffness=by_solved(per_leg[2]),
        k_phi=_masked(fields[0], valid).reshape(batch),
        k_x=_masked(fields[1], valid).reshape(batch),
        k_y=_masked(fields[2], valid).reshape(batch),
        stiffness=None if mats is None else mats.reshape(batch + (6, 6)),
        iterations=iterations.reshape(batch),
        refusal=refusal.reshape(batch),
    )
