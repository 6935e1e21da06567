"""One chunk of poses through the fastest exact path: K, the masks and the principal
stiffnesses, for :func:`ppm_stiffness.maps.batch.evaluate_poses` and the maps.

Three paths, chosen by the design's properties (:func:`select_path`):

- the **reduced P-P-R form** (:mod:`ppm_stiffness.maps.reduced_path`) when every leg
  offers one (:meth:`ppm_stiffness.legs.base.LegModel.reduced_form`);
- the **planar engine** (:mod:`ppm_stiffness.maps.planar_path`) for a planar design
  (``design.planar``) whose chains are planar;
- the **general path** (:mod:`ppm_stiffness.maps.engine_path`, the batched engine of
  :mod:`ppm_stiffness.legs.engine`) for any design, spatial ones included.

Each gives K at P and the legs' summed projector; the singularity decision is
:mod:`ppm_stiffness.maps.transmission`'s. The principal stiffnesses asked for are then
computed from K, moved to the tool point when one is given (its offset ``R t`` per
pose): the paper's k_phi, k_x, k_y (:mod:`ppm_stiffness.maps.paper_principal`, planar
designs) and the spatial rotational and translational values
(:mod:`ppm_stiffness.maps.principal_batch`). Poses are full poses (n, 6), completed.
"""

from __future__ import annotations

from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.maps.engine_path import GENERAL_CHUNK, reachable_stiffness
from ppm_stiffness.maps.paper_principal import (
    Principal,
    principal_from_entries,
    principal_from_matrices,
)
from ppm_stiffness.maps.planar_path import PLANAR_CHUNK, planar_engine_entries
from ppm_stiffness.maps.principal_batch import principal_values, stiffness_at_points
from ppm_stiffness.maps.reduced_leg import ReducedLeg, reduce_design, reduced_design
from ppm_stiffness.maps.reduced_path import (
    REDUCED_CHUNK,
    PlanarEntries,
    assemble,
    planar_entries,
    reduced_projector,
)
from ppm_stiffness.maps.transmission import nonsingular_from_entries, nonsingular_from_matrices

Path = Literal["auto", "reduced", "planar", "general"]
PATHS = ("auto", "reduced", "planar", "general")


def select_path(design: Design, path: Path = "auto") -> tuple[ReducedLeg, ...] | None:
    """The reduced legs to use, or None for the planar engine or the general path.

    ``"auto"``: the reduced path when every leg offers it, else the planar engine for a
    planar design, else the general path; ``"planar"``: the planar engine (falling back
    to the general path for chains that are not planar); ``"general"``: always the
    general path (the engine of any design); ``"reduced"``: the reduced path or
    :class:`~ppm_stiffness.core.errors.DesignError`.
    """
    if path not in PATHS:
        raise InputDataError(f"path must be 'auto', 'reduced', 'planar' or 'general', got {path!r}")
    if path in ("general", "planar"):
        return None
    if path == "reduced":
        return reduce_design(design)
    return reduced_design(design)


def uses_planar_engine(design: Design, path: Path) -> bool:
    """Whether a chunk without reduced legs tries the planar engine first."""
    return path == "planar" or (path == "auto" and design.planar)


def default_chunk(legs: tuple[ReducedLeg, ...] | None, planar: bool = True) -> int:
    """Poses per chunk by path: :data:`~ppm_stiffness.maps.reduced_path.REDUCED_CHUNK`,
    :data:`~ppm_stiffness.maps.planar_path.PLANAR_CHUNK` or
    :data:`~ppm_stiffness.maps.engine_path.GENERAL_CHUNK`."""
    if legs is not None:
        return REDUCED_CHUNK
    return PLANAR_CHUNK if planar else GENERAL_CHUNK


def masked(values: FloatArray, valid: BoolArray) -> np.ma.MaskedArray:
    """``values`` masked (NaN data) where not ``valid`` (broadcast over trailing axes)."""
    v = np.asarray(values, dtype=float)
    ok = np.asarray(valid, dtype=bool).reshape(np.shape(valid) + (1,) * (v.ndim - np.ndim(valid)))
    mask = np.broadcast_to(~ok, v.shape)
    return np.ma.MaskedArray(np.where(mask, np.nan, v), mask=mask.copy(), fill_value=np.nan)


class ChunkResult(NamedTuple):
    """One chunk of n poses (SI; arrays (n, ...), meaningless where not ``valid``).

    stiffness : ndarray (n, 6, 6) or None
        K at P, axes of F_b; None unless asked for (zero or NaN where not valid).
    reachable, valid : ndarray of bool (n,)
        Completed, IK solvable and within joint limits; and also not singular.
    paper : Principal or None
        The paper's decoupling and k_phi, k_x, k_y (at the tool point), if asked for.
    rotational, translational : ndarray (n, 3) or None
        The spatial principal stiffnesses (ascending; translational at the tool
        point), if asked for.
    path : {"reduced", "planar", "general"}
    """

    stiffness: FloatArray | None
    reachable: BoolArray
    valid: BoolArray
    paper: Principal | None
    rotational: FloatArray | None
    translational: FloatArray | None
    path: str


def _quantities(
    k: FloatArray, offsets: FloatArray | None, paper: bool, spatial: bool
) -> tuple[Principal | None, FloatArray | None, FloatArray | None]:
    """The principal stiffnesses asked for, from finite K (n, 6, 6) at P."""
    k_t = k if offsets is None else stiffness_at_points(k, offsets)
    pr = principal_from_matrices(k_t) if paper else None
    rot, tra = principal_values(k_t) if spatial else (None, None)
    return pr, rot, tra


def chunk_result(
    design: Design,
    legs: tuple[ReducedLeg, ...] | None,
    poses: FloatArray,
    actuator_stiffness: ArrayLike,
    planar: bool,
    matrices: bool = True,
    *,
    completed: BoolArray | None = None,
    offsets: FloatArray | None = None,
    paper: bool = True,
    spatial: bool = False,
) -> ChunkResult:
    """One chunk of full poses (n, 6) with actuator stiffness (n, n_legs) or (n_legs,).

    ``legs``: the reduced path; otherwise the planar engine when ``planar`` (and the
    chains are planar), else the general path. ``completed`` (n,): the completion's
    mask (all True if None). ``offsets`` (n, 3) or (3,): ``T - P`` [m, F_b] of the tool
    point where the principal stiffnesses are wanted (P if None). ``paper``,
    ``spatial``: which principal stiffnesses to compute; ``matrices``: also return K.
    """
    found: tuple[PlanarEntries, PlanarEntries, BoolArray] | None = None
    used = "general"
    if legs is not None:
        x, y, ph = poses[:, 0], poses[:, 1], poses[:, 5]
        with np.errstate(all="ignore"):
            e, reach = planar_entries(legs, x, y, ph, actuator_stiffness)
            found = e, reduced_projector(legs, ph), reach
        used = "reduced"
    elif planar:
        found = planar_engine_entries(design, poses, actuator_stiffness, completed)
        used = "planar" if found is not None else "general"
    if found is not None:
        e, pi, reach = found
        if completed is not None:
            reach = reach & completed
        with np.errstate(all="ignore"):
            valid = reach & nonsingular_from_entries(e, pi)
            k = assemble(e) if (matrices or offsets is not None or spatial) else None
            if k is None:
                pr = principal_from_entries(e) if paper else None
                return ChunkResult(None, reach, valid, pr, None, None, used)
            safe = np.where(valid[:, None, None], k, np.eye(6))
            if offsets is None and paper:  # the closed form on the entries, as ever
                pr = principal_from_entries(e)
                _, rot, tra = _quantities(safe, None, False, spatial)
            else:
                pr, rot, tra = _quantities(safe, offsets, paper, spatial)
        return ChunkResult(k if matrices else None, reach, valid, pr, rot, tra, used)
    index, k_sub, pi_sub, reach = reachable_stiffness(design, poses, actuator_stiffness, completed)
    n, every = reach.size, index.size == reach.size
    ok = nonsingular_from_matrices(k_sub, pi_sub)
    valid = ok if every else _scatter(ok, index, n, False)
    safe = np.where(ok[:, None, None], k_sub, np.eye(6))  # no NaN into the closed forms
    sub_offsets = offsets
    if offsets is not None and np.ndim(offsets) == 2 and not every:
        sub_offsets = np.take(offsets, index, axis=0)
    with np.errstate(all="ignore"):
        pr, rot, tra = _quantities(safe, sub_offsets, paper, spatial)
    if not every:
        rot = None if rot is None else _scatter(rot, index, n, np.nan)
        tra = None if tra is None else _scatter(tra, index, n, np.nan)
        if pr is not None:
            pr = Principal(*(_scatter(np.asarray(f), index, n, np.nan) for f in pr))
    k = None
    if matrices:
        k = k_sub if every else _scatter(k_sub, index, n, 0.0)
    return ChunkResult(k, reach, valid, pr, rot, tra, "general")


def _scatter(values: ArrayLike, index: np.ndarray, n: int, fill: float | bool) -> np.ndarray:
    """``values`` (m, ...) at rows ``index`` of an array (n, ...) filled with ``fill``."""
    v = np.asarray(values)
    out = np.full((n,) + v.shape[1:], fill, dtype=v.dtype)
    out[index] = v
    return out
