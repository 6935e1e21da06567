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
Any design: poses are task coordinates or full poses (:mod:`ppm_stiffness.poses`), and
the principal stiffnesses are the paper's k_phi, k_x, k_y for a planar design and the
spatial rotational and translational ones (:mod:`ppm_stiffness.maps.principal_batch`)
when asked for (by default for a design that is not planar). Wrenches and twists at P,
axes of F_b, SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.refusals import Refusal, RefusalArray
from ppm_stiffness.design import Design
from ppm_stiffness.maps.batch import PaperAccess, PaperFields, check_poses
from ppm_stiffness.maps.chunks import masked
from ppm_stiffness.maps.paper_principal import principal_from_matrices
from ppm_stiffness.maps.planar_path import PLANAR_CHUNK
from ppm_stiffness.maps.principal_batch import principal_values, stiffness_at_points, tool_offsets
from ppm_stiffness.maps.result import PRINCIPAL
from ppm_stiffness.statics.equilibrium import loaded_states


@dataclass(frozen=True)
class LoadedBatch(PaperAccess):
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
    paper : PaperFields or None
        The paper's k_phi, k_x, k_y and shift d of the loaded tangent K (planar designs;
        at the tool point), masked where not ``valid``; also as the properties
        ``k_phi``, ``k_x``, ``k_y``.
    rotational, translational : numpy.ma.MaskedArray (..., 3) or None
        The spatial principal stiffnesses of the loaded tangent K (ascending;
        translational at the tool point), masked where not ``valid``, if asked for.
    stiffness : ndarray (..., 6, 6) or None
        The loaded tangent K at P (zero where not valid), when asked for.
    iterations : ndarray of int (...)
        Newton iterations (0 for statically determinate forces; -1 where not solved).
    refusal : ndarray of int8 (...)
    poses : ndarray (..., 6)
        The full poses (completed).
    """

    reachable: BoolArray
    singular: BoolArray
    solved: BoolArray
    valid: BoolArray
    twist: np.ma.MaskedArray
    actuator_forces: np.ma.MaskedArray
    actuator_displacements: np.ma.MaskedArray
    actuator_stiffness: np.ma.MaskedArray
    paper: PaperFields | None
    rotational: np.ma.MaskedArray | None
    translational: np.ma.MaskedArray | None
    stiffness: FloatArray | None
    iterations: np.ndarray
    refusal: RefusalArray
    poses: FloatArray


def loaded_poses(
    design: Design,
    poses: ArrayLike,
    wrench: ArrayLike,
    *,
    matrices: bool = False,
    chunk_size: int | None = None,
    tool_point: ArrayLike | None = None,
    principal: bool | None = None,
) -> LoadedBatch:
    """The loaded state under ``wrench`` at many poses (module doc).

    Parameters
    ----------
    design : Design
        Any architecture, redundant designs included.
    poses : array_like, shape (..., n_task) or (..., 6)
        Task coordinates ((x [m], y [m], phi [rad]) for a planar design) or full poses
        of P in F_b (:mod:`ppm_stiffness.poses`).
    wrench : array_like, shape (6,)
        (m_x, m_y, m_z [N·m], f_x, f_y, f_z [N]) at P, axes of F_b, the same at every
        pose (move a wrench given at a tool point with
        :func:`ppm_stiffness.core.conventions.wrench_b_from_wrench_a`).
    matrices : bool
        Also return the loaded tangent K (288 bytes per pose).
    chunk_size : int, optional
        Poses evaluated at once; default
        :data:`~ppm_stiffness.maps.planar_path.PLANAR_CHUNK`.
    tool_point : array_like (3,), optional
        [m, platform frame]: the principal stiffnesses are those of the loaded K there
        (the wrench stays at P); P if None.
    principal : bool, optional
        Also give ``rotational`` and ``translational``; default: for a design that is not
        planar.

    Returns
    -------
    LoadedBatch
        At every ``valid`` pose the numbers of
        :func:`ppm_stiffness.statics.loading.loaded_state`.

    Raises
    ------
    InputDataError
        Poses of another width or not finite; a wrench not of 6 finite values.
    """
    from ppm_stiffness.statics.loading import validate_wrench

    w = validate_wrench(wrench)
    p = check_poses(design, poses)
    tool = np.zeros(3) if tool_point is None else np.asarray(tool_point, dtype=float)
    if tool.shape != (3,) or not np.all(np.isfinite(tool)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    paper = design.planar
    spatial = (not design.planar) if principal is None else bool(principal)
    batch = p.shape[:-1]
    flat = p.reshape(-1, p.shape[-1])
    n, n_legs = flat.shape[0], len(design.legs)
    step = max(int(chunk_size or PLANAR_CHUNK), 1)
    refusal = np.zeros(n, dtype=np.int8)
    twist = np.zeros((n, 6))
    full = np.zeros((n, 6))
    per_leg = np.zeros((3, n, n_legs))
    fields = np.zeros((5, n))
    values = np.zeros((2, n, 3))
    iterations = np.full(n, -1)
    mats = np.zeros((n, 6, 6)) if matrices else None
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        st = loaded_states(design, flat[sl], w)
        ok = st.refusal == 0
        refusal[sl] = st.refusal
        twist[sl] = st.twist
        full[sl] = st.poses
        per_leg[:, sl] = st.forces, st.displacements, st.actuator_stiffness
        k = np.where(ok[:, None, None], st.stiffness, np.eye(6))
        if np.any(tool):
            k = stiffness_at_points(k, tool_offsets(st.poses, tool))
        if paper:
            pr = principal_from_matrices(k)
            fields[:, sl] = pr.k_phi, pr.k_x, pr.k_y, pr.d_x, pr.d_y
        if spatial:
            values[0, sl], values[1, sl] = principal_values(k)
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

    paper_fields = None
    if paper:
        d = np.zeros((n, 3))
        d[:, :2] = np.where(valid[:, None], fields[3:].T, 0.0)
        k_phi, k_x, k_y = (masked(fields[i], valid).reshape(batch) for i in range(3))
        paper_fields = PaperFields(k_phi, k_x, k_y, d.reshape(batch + (3,)))
    return LoadedBatch(
        reachable=(refusal != Refusal.UNREACHABLE).reshape(batch),
        singular=(refusal == Refusal.SINGULAR).reshape(batch),
        solved=solved.reshape(batch),
        valid=valid.reshape(batch),
        twist=by_solved(twist),
        actuator_forces=by_solved(per_leg[0]),
        actuator_displacements=by_solved(per_leg[1]),
        actuator_stiffness=by_solved(per_leg[2]),
        paper=paper_fields,
        rotational=masked(values[0], valid).reshape(batch + (3,)) if spatial else None,
        translational=masked(values[1], valid).reshape(batch + (3,)) if spatial else None,
        stiffness=None if mats is None else mats.reshape(batch + (6, 6)),
        iterations=iterations.reshape(batch),
        refusal=refusal.reshape(batch),
        poses=full.reshape(batch + (6,)),
    )


def moving_columns(
    design: Design,
    poses: FloatArray,
    wrench: FloatArray,
    tool: FloatArray,
    *,
    paper: bool,
    spatial: bool,
) -> tuple[RefusalArray, FloatArray, dict[str, FloatArray]]:
    """The equilibrium with moving geometry at full poses (n, 6) under ``wrench`` (6,)
    at the tool point (``map --actuators WRENCH --geometry moving``).

    The same numbers as ``analyze --wrench ... --geometry moving`` at each pose
    (:func:`ppm_stiffness.statics.moving.moving_states`, of which
    :func:`~ppm_stiffness.statics.moving.moving_loaded_state` is the batch of one): the
    quantities are those of the symmetric part of K_F at the displaced tool point.

    Returns
    -------
    codes : ndarray of int8 (n,)
        The refusal codes (:class:`~ppm_stiffness.core.refusals.Refusal`), 0 exactly
        where ``moving_loaded_state`` returns.
    actuator_stiffness : ndarray (n, n_legs)
        The actuators' tangent stiffness at the moving equilibrium.
    columns : dict of str to ndarray (n,)
        k_phi, k_x, k_y (``paper``) and the six spatial principal stiffnesses
        (``spatial``), NaN where refused.
    """
    from ppm_stiffness.statics.moving import moving_states

    res = moving_states(design, poses, wrench, tool)
    ok = res.refusal == 0
    k_f = res.stiffness
    k = np.where(ok[:, None, None], 0.5 * (k_f + np.swapaxes(k_f, -1, -2)), np.eye(6))
    columns: dict[str, FloatArray] = {}
    if paper:
        pr = principal_from_matrices(k)
        columns |= {"k_phi": pr.k_phi, "k_x": pr.k_x, "k_y": pr.k_y}
    if spatial:
        rot, tra = principal_values(k)
        columns |= {n: (rot if j < 3 else tra)[:, j % 3] for j, n in enumerate(PRINCIPAL)}
    columns = {n: np.where(ok, np.asarray(v, dtype=float), np.nan) for n, v in columns.items()}
    return res.refusal.astype(np.int8), np.asarray(res.actuator_stiffness), columns


def margin_column(
    design: Design, poses: FloatArray, wrench: FloatArray, tool: FloatArray
) -> tuple[RefusalArray, FloatArray]:
    """The ``load_margin`` map quantity at full poses (n, 6): the load factor up to which
    the load path ``lambda * wrench`` (at the tool point, moving geometry) is stable and
    within the model, from :func:`ppm_stiffness.statics.margin.margin_batch` (the load
    margin of ``analyze --geometry moving`` at each pose): the first instability's factor
    (a bifurcation or a limit point), else the factor where an actuator reaches its whole
    stroke, else :data:`~ppm_stiffness.statics.margin.MAX_FACTOR` (no instability in the
    range searched).

    Returns
    -------
    codes : ndarray of int8 (n,)
        ``UNREACHABLE`` or ``SINGULAR`` where the unloaded pose is refused, else 0.
    values : ndarray (n,)
        The factor (dimensionless), NaN where refused.
    """
    from ppm_stiffness.statics.equilibrium import loaded_states
    from ppm_stiffness.statics.margin import MAX_FACTOR, MarginKind, margin_batch

    batch = margin_batch(design, poses, wrench, tool)
    kind = batch.kind
    values = np.where(
        np.isfinite(batch.factor),
        batch.factor,
        np.where(kind == MarginKind.STROKE, batch.searched_up_to, MAX_FACTOR),
    )
    refused = kind == MarginKind.REFUSED
    codes = np.zeros(poses.shape[0], dtype=np.int8)
    if np.any(refused):
        codes[refused] = loaded_states(design, poses[refused], np.zeros(6)).refusal
        codes[refused & (codes == 0)] = Refusal.UNREACHABLE  # completion failed
    return codes, np.where(refused, np.nan, values)


def with_margin(
    design: Design, poses: FloatArray, wrench: FloatArray, tool: FloatArray, codes: RefusalArray
) -> tuple[RefusalArray, FloatArray]:
    """The ``load_margin`` column at full poses (n, 6) beside a loaded state's refusal
    codes (n,): computed where those are 0 (:func:`margin_column`), NaN elsewhere; the
    codes with the margin's refusals added."""
    values = np.full(poses.shape[0], np.nan)
    ok = np.flatnonzero(codes == 0)
    out = codes.copy()
    if ok.size:
        extra, values[ok] = margin_column(design, np.take(poses, ok, axis=0), wrench, tool)
        out[ok] = extra
    return out, values
