"""Batched stiffness and principal stiffnesses of any design at many poses.

:func:`evaluate_poses` gives, at every pose, the numbers of the single-pose API
(:func:`ppm_stiffness.model.stiffness_at_pose`, then
:func:`ppm_stiffness.core.decoupling.decouple` with ``method="paper"`` for a planar
design, :func:`ppm_stiffness.core.principal.principal_compliance` for any), masked
exactly where it raises (:class:`~ppm_stiffness.core.refusals.Refusal`: unreachable,
singular). Poses are the design's task coordinates or full poses
(:mod:`ppm_stiffness.poses`); the dependent coordinates are completed chunk by chunk.

The work is done by chunks (:mod:`ppm_stiffness.maps.chunks`) on one of three exact
paths, chosen by the design's properties: the reduced P-P-R form
(:mod:`ppm_stiffness.maps.reduced_path`), the planar engine
(:mod:`ppm_stiffness.maps.planar_path`) or the general path, the batched engine of any
joint chain (:mod:`ppm_stiffness.maps.engine_path`); the tests hold them equal to each
other and to the dense definition (:mod:`ppm_stiffness.core.solver`).

Quantities. A planar design gets the paper's decoupling: ``k_phi``, ``k_x``, ``k_y``
and the shift ``d`` (:mod:`ppm_stiffness.maps.paper_principal`), as ever; any design
may get the spatial principal stiffnesses ``rotational`` and ``translational``
(:mod:`ppm_stiffness.maps.principal_batch`, the definitions of
:mod:`ppm_stiffness.core.principal`), by default those that are not planar. Asking a
design that is not planar for ``k_phi`` raises :class:`DesignError`. Matrices at P
(principal stiffnesses at the tool point when one is given), axes of F_b, SI.

This module also re-exports the names of the paths' modules that older code imports
from it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.core.refusals import Refusal, RefusalArray, first_refusal, refusal_counts
from ppm_stiffness.design import Design
from ppm_stiffness.maps.chunks import (
    Path,
    chunk_result,
    default_chunk,
    masked,
    select_path,
    uses_planar_engine,
)
from ppm_stiffness.maps.engine_path import GENERAL_CHUNK, general_stiffness
from ppm_stiffness.maps.paper_principal import (
    PLANAR_TOLERANCE,
    Principal,
    decouple_batch,
    is_planar,
    principal_from_entries,
    principal_from_matrices,
)
from ppm_stiffness.maps.planar_path import PLANAR_CHUNK, planar_engine_entries
from ppm_stiffness.maps.principal_batch import tool_offsets
from ppm_stiffness.maps.reduced_leg import (
    IN_PLANE,
    OUT_OF_PLANE,
    ReducedLeg,
    reduce_design,
    reduce_leg,
    reduced_design,
)
from ppm_stiffness.maps.reduced_path import (
    REDUCED_CHUNK,
    PlanarEntries,
    assemble,
    entries_from_matrices,
    planar_entries,
    reduced_projector,
)
from ppm_stiffness.maps.transmission import (
    nonsingular_from_entries,
    nonsingular_from_matrices,
    nonsingular_projector,
)
from ppm_stiffness.model import actuator_stiffness_vector, checked_actuator_stiffness
from ppm_stiffness.poses import full_poses

__all__ = [
    "GENERAL_CHUNK",
    "IN_PLANE",
    "OUT_OF_PLANE",
    "PLANAR_CHUNK",
    "PLANAR_TOLERANCE",
    "REDUCED_CHUNK",
    "BatchResult",
    "PaperFields",
    "Path",
    "PlanarEntries",
    "Principal",
    "ReducedLeg",
    "assemble",
    "chunk_result",
    "decouple_batch",
    "default_chunk",
    "entries_from_matrices",
    "evaluate_poses",
    "general_stiffness",
    "is_planar",
    "nonsingular_from_entries",
    "nonsingular_from_matrices",
    "nonsingular_projector",
    "planar_engine_entries",
    "planar_entries",
    "principal_from_entries",
    "principal_from_matrices",
    "reduce_design",
    "reduce_leg",
    "reduced_design",
    "reduced_projector",
    "select_path",
    "stiffness_matrix",
]

#: Kept for older imports: ``masked`` of :mod:`ppm_stiffness.maps.chunks`.
_masked = masked


@dataclass(frozen=True)
class PaperFields:
    """The paper's principal stiffnesses of a planar design (eq. 19), arrays of the batch
    shape: k_phi [N·m/rad], k_x, k_y [N/m] masked where not valid; d (..., 3) [m] the
    decoupling shift (zero where not valid)."""

    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    d: FloatArray


class PaperAccess:
    """``k_phi``, ``k_x``, ``k_y`` and ``d`` of a batch's :class:`PaperFields`, or
    :class:`DesignError` for a design that is not planar (it has none)."""

    paper: PaperFields | None

    def _paper(self) -> PaperFields:
        if self.paper is None:
            raise DesignError(
                "k_phi, k_x, k_y and d are the paper's planar principal stiffnesses: this "
                "design is not planar; use rotational and translational"
            )
        return self.paper

    @property
    def k_phi(self) -> np.ma.MaskedArray:
        """[N·m/rad] ``f_rr[2]`` of the paper's decoupling (planar designs)."""
        return self._paper().k_phi

    @property
    def k_x(self) -> np.ma.MaskedArray:
        """[N/m] ``f_tt[0]`` (planar designs)."""
        return self._paper().k_x

    @property
    def k_y(self) -> np.ma.MaskedArray:
        """[N/m] ``f_tt[1]`` (planar designs)."""
        return self._paper().k_y

    @property
    def d(self) -> FloatArray:
        """(..., 3) [m] the paper's decoupling shift (planar designs)."""
        return self._paper().d


@dataclass(frozen=True)
class BatchResult(PaperAccess):
    """Stiffness of many poses (SI). Arrays have the batch shape of the poses.

    Attributes
    ----------
    valid : ndarray of bool
        Reachable and not singular (the transmission index of
        :mod:`ppm_stiffness.core.singularity`, K finite): where
        :func:`ppm_stiffness.model.stiffness_at_pose` returns.
    reachable : ndarray of bool
        Completed (:func:`ppm_stiffness.poses.full_poses`), every leg's IK solvable and
        its joint coordinates within limits.
    refusal : ndarray of int8
        0 where valid, else :attr:`Refusal.UNREACHABLE` or :attr:`Refusal.SINGULAR`.
    poses : ndarray (..., 6)
        The full poses (x, y, z [m], rx, ry, rz [rad]), dependent coordinates completed
        (the parasitic motion of a tripod; where the completion failed, its last
        iterate).
    stiffness : ndarray (..., 6, 6) or None
        K at P (zero where not valid), when asked for.
    path : {"reduced", "planar", "general"}
        Which path computed them ("general" if any chunk needed it).
    paper : PaperFields or None
        The paper's k_phi, k_x, k_y and shift d (planar designs; at the tool point).
    rotational, translational : numpy.ma.MaskedArray (..., 3) or None
        The spatial principal stiffnesses [N·m/rad], [N/m] (translational at the tool
        point), ascending (index 0 the worst direction), masked where not valid;
        None unless asked for (``principal``).
    tool_point : ndarray (3,)
        The tool point of the principal stiffnesses [m, platform frame].
    """

    valid: BoolArray
    reachable: BoolArray
    refusal: RefusalArray
    poses: FloatArray
    stiffness: FloatArray | None
    path: str
    paper: PaperFields | None
    rotational: np.ma.MaskedArray | None
    translational: np.ma.MaskedArray | None
    tool_point: FloatArray


def actuator_stiffness_per_pose(
    design: Design, actuator_stiffness: ArrayLike | None, batch: tuple[int, ...], n: int
) -> FloatArray:
    """Actuator stiffness (n, n_legs) from None (locked), (n_legs,) or (..., n_legs)."""
    n_legs = len(design.legs)
    if actuator_stiffness is None:
        return np.broadcast_to(actuator_stiffness_vector(design, None), (n, n_legs))
    k_in = np.asarray(actuator_stiffness, dtype=float)
    try:
        k_act = np.broadcast_to(k_in, batch + (n_legs,)).reshape(n, n_legs)
    except ValueError:
        raise DesignError(
            f"actuator stiffness of shape {k_in.shape} does not fit {n} poses of {n_legs} legs"
        ) from None
    return checked_actuator_stiffness(design, k_act)


def check_poses(design: Design, poses: ArrayLike) -> FloatArray:
    """Poses (..., n_task) or (..., 6), finite; a planar design's full poses in the plane
    (returned as its task coordinates (x, y, phi): they need no completion)."""
    p = np.asarray(poses, dtype=float)
    width = len(design.task_coordinates)
    if p.ndim == 0 or p.shape[-1] not in (width, 6):
        names = ", ".join(design.task_coordinates)
        raise InputDataError(
            f"poses must have shape (..., {width}) ({names}) or (..., 6) (x, y, z, rx, ry, "
            f"rz), got {p.shape}"
        )
    if not np.all(np.isfinite(p)):
        raise InputDataError("poses must be finite")
    if design.planar and p.shape[-1] == 6:
        if np.any(p[..., 2:5] != 0):
            raise InputDataError("a planar design's poses have z = rx = ry = 0")
        p = p[..., [0, 1, 5]]  # its task coordinates: nothing to complete
    return p


def evaluate_poses(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    *,
    matrices: bool = False,
    chunk_size: int | None = None,
    path: Path = "auto",
    tool_point: ArrayLike | None = None,
    principal: bool | None = None,
) -> BatchResult:
    """Stiffness and principal stiffnesses at many poses, any design.

    Parameters
    ----------
    design : Design
        Any architecture, planar or spatial.
    poses : array_like, shape (..., n_task) or (..., 6)
        The design's task coordinates (x [m], y [m], phi [rad] for a planar design) or
        full poses (:mod:`ppm_stiffness.poses`); a pose whose completion fails is
        unreachable.
    actuator_stiffness : array_like, shape (n_legs,) or (..., n_legs), optional
        [N/m, or N·m/rad for a rotary actuator]; each leg's locked value when None.
    matrices : bool
        Also return K at P (memory: 288 bytes per pose).
    chunk_size : int, optional
        Poses evaluated at once (bounds the temporary memory); default
        :func:`~ppm_stiffness.maps.chunks.default_chunk` by the path.
    path : {"auto", "reduced", "planar", "general"}
        :func:`~ppm_stiffness.maps.chunks.select_path`: ``"auto"`` takes the fastest
        exact path (the reduced form, else the planar engine for a planar design, else
        the general path).
    tool_point : array_like (3,), optional
        [m, platform frame]: the principal stiffnesses are those of K at that point
        (its offset from P at each pose's orientation); P if None.
    principal : bool, optional
        Also compute ``rotational`` and ``translational``; default: for a design that
        is not planar.

    Returns
    -------
    BatchResult
        Same numbers as the single-pose API (to rounding), masked where it raises.

    Raises
    ------
    InputDataError
        Poses of another width or not finite; a tool point not of 3 finite values;
        unknown path.
    DesignError
        Actuator stiffnesses of the wrong shape or not finite and positive; or
        ``path="reduced"`` for a design whose legs offer no reduced form.
    """
    p = check_poses(design, poses)
    tool = np.zeros(3) if tool_point is None else np.asarray(tool_point, dtype=float)
    if tool.shape != (3,) or not np.all(np.isfinite(tool)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    batch = p.shape[:-1]
    flat = p.reshape(-1, p.shape[-1])
    n = flat.shape[0]
    k_act = actuator_stiffness_per_pose(design, actuator_stiffness, batch, n)
    legs = select_path(design, path)
    planar = uses_planar_engine(design, path)
    paper = design.planar
    spatial = (not design.planar) if principal is None else bool(principal)
    step = max(int(chunk_size or default_chunk(legs, planar)), 1)
    used: set[str] = set()
    valid = np.zeros(n, dtype=bool)
    reach = np.zeros(n, dtype=bool)
    full = np.zeros((n, 6))
    out = np.zeros((5, n)) if paper else None
    values = np.zeros((2, n, 3)) if spatial else None
    mats = np.zeros((n, 6, 6)) if matrices else None
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        full[sl], completed = full_poses(design, flat[sl])
        offsets = tool_offsets(full[sl], tool) if np.any(tool) else None
        res = chunk_result(
            design,
            legs,
            full[sl],
            k_act[sl],
            planar,
            matrices,
            completed=None if np.all(completed) else completed,
            offsets=offsets,
            paper=paper,
            spatial=spatial,
        )
        used.add(res.path)
        valid[sl], reach[sl] = res.valid, res.reachable
        if out is not None and res.paper is not None:
            pr = res.paper
            out[:, sl] = pr.k_phi, pr.k_x, pr.k_y, pr.d_x, pr.d_y
        if values is not None and res.rotational is not None and res.translational is not None:
            values[0, sl], values[1, sl] = res.rotational, res.translational
        if mats is not None and res.stiffness is not None:
            mats[sl] = np.where(res.valid[:, None, None], res.stiffness, 0.0)
    fields = None
    if out is not None:
        d = np.zeros((n, 3))
        d[:, 0] = np.where(valid, out[3], 0.0)
        d[:, 1] = np.where(valid, out[4], 0.0)
        k_phi, k_x, k_y = (masked(out[i], valid).reshape(batch) for i in range(3))
        fields = PaperFields(k_phi, k_x, k_y, d.reshape(batch + (3,)))
    codes = first_refusal((n,), [(Refusal.UNREACHABLE, reach), (Refusal.SINGULAR, valid)])
    return BatchResult(
        valid=valid.reshape(batch),
        reachable=reach.reshape(batch),
        refusal=codes.reshape(batch),
        poses=full.reshape(batch + (6,)),
        stiffness=None if mats is None else mats.reshape(batch + (6, 6)),
        path="general" if "general" in used or not used else used.pop(),
        paper=fields,
        rotational=None if values is None else masked(values[0], valid).reshape(batch + (3,)),
        translational=None if values is None else masked(values[1], valid).reshape(batch + (3,)),
        tool_point=tool,
    )


def stiffness_matrix(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    *,
    refused: str = "raise",
    chunk_size: int | None = None,
) -> FloatArray:
    """K (..., 6, 6) at P, axes of F_b, at many poses: the batched
    :func:`ppm_stiffness.model.stiffness_at_pose` (as
    :func:`ppm_stiffness.dynamics.mass.mass_matrix` is the batched M).

    Parameters
    ----------
    design : Design
        Any architecture, planar or spatial.
    poses : array_like (..., n_task) or (..., 6)
        The design's task coordinates (``design.task_coordinates``) or full poses
        (x, y, z [m], rx, ry, rz [rad]) of P in F_b (:mod:`ppm_stiffness.poses`).
    actuator_stiffness : array_like (n_legs,) or (..., n_legs), optional
        [N/m or N·m/rad]; each leg's locked value when None.
    refused : {"raise", "nan"}
        What a pose the single-pose function refuses (unreachable or singular) gives:
        ``"raise"`` (default) raises that function's error, naming how many poses are
        refused and why, and the first of them; ``"nan"`` masks them with NaN, as maps
        do (:func:`evaluate_poses` gives the codes, ``refusal``).
    chunk_size : int, optional
        Poses evaluated at once (:func:`evaluate_poses`).

    Returns
    -------
    ndarray (..., 6, 6)
        [[K_rr, K_rt], [K_rt^T, K_tt]] in N·m/rad, N, N/m, equal to the single-pose
        K to round-off.

    Raises
    ------
    UnreachablePoseError, SingularConfigurationError
        With ``refused="raise"``, where a pose is refused.
    InputDataError
        Poses of another width or not finite; ``refused`` not one of the two.
    DesignError
        Actuator stiffnesses of the wrong shape, not finite or not positive.
    """
    if refused not in ("raise", "nan"):
        raise InputDataError(f"refused = {refused!r}: give 'raise' or 'nan'")
    batch = evaluate_poses(
        design,
        poses,
        actuator_stiffness,
        matrices=True,
        chunk_size=chunk_size,
        principal=False,
    )
    assert batch.stiffness is not None
    if refused == "raise" and not np.all(batch.valid):
        codes = np.asarray(batch.refusal).reshape(-1)
        first = int(np.flatnonzero(codes)[0])
        code = Refusal(int(codes[first]))
        counts = ", ".join(f"{n} {why}" for why, n in refusal_counts(codes).items())
        raise code.error(
            f"{counts} of {codes.size} poses refused (first: pose index {first}, "
            f"{code.reason}); pass refused='nan' to mask them"
        )
    return np.where(batch.valid[..., None, None], batch.stiffness, np.nan)
