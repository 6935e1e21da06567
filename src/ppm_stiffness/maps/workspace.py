"""Stiffness maps over a 2-D slice of the workspace (paper Figures 6-7), any design.

:func:`stiffness_map` evaluates a grid over two task coordinates with the others fixed
(:mod:`ppm_stiffness.maps.slices`: the planar designs' x-y maps at a given phi, as
ever; a hexapod's x-y at a given z and orientation or rx-ry at a given position; a
tripod's rx-ry at a given z, ...), over the slice's reachable extent unless bounds are
given, and returns a :class:`~ppm_stiffness.maps.result.StiffnessMap` of the quantities
asked for: the paper's k_phi, k_x, k_y (planar designs, the default for them) and the
spatial principal stiffnesses (any design, the default for the others;
:mod:`ppm_stiffness.maps.result`).

Actuator states of a map (``actuators``), each leg with its own actuator law
(``design.legs[i].actuator``: linear [N/m] or rotary [N·m/rad]):

``"max"``
    every actuator locked: ``leg.actuator.locked_stiffness`` (eq. 21, small loads).
``"min"``
    every actuator at the tangent stiffness of eq. (20)-(21) of its own law under the
    reference load ``reference_force`` (default :data:`DEFAULT_REFERENCE_FORCE` = 10, in
    N for a linear actuator and N·m for a rotary one). The paper does not state its
    minimum; see docs/maps.md.
``"wrench"``
    the loaded state under ``wrench`` (m_x, m_y, m_z, f_x, f_y, f_z, axes of F_b, at
    the tool point: P by default) at each pose, as
    :func:`ppm_stiffness.statics.loading.loaded_state` computes it and by the same code
    (:func:`ppm_stiffness.maps.loaded.loaded_poses`, through
    :func:`ppm_stiffness.statics.equilibrium.loaded_states`, for every design); the
    principal stiffnesses are those of the loaded tangent K. The wrench is moved to P
    at each pose's orientation: poses that share it (an x-y map at a fixed orientation)
    are solved together; a map whose orientation varies with a tool point away from P
    solves one pose at a time (slower: about a millisecond per pose).

Masks. A grid pose is masked exactly where the single-pose API raises
(:func:`ppm_stiffness.model.stiffness_at_pose` with the task coordinates of the grid
point, and ``loaded_state`` under a wrench), and
:attr:`~ppm_stiffness.maps.result.StiffnessMap.refusal` says why
(:class:`ppm_stiffness.core.refusals.Refusal`: outside the joint limits, or the pose
completion failing; singular; no equilibrium; a load beyond the small-displacement
model; a loaded K not positive definite; with ``f1`` among the quantities, also a pose
where the modal analysis fails, as singular: :mod:`ppm_stiffness.dynamics.batch`). A
map never raises for a pose.

This module also re-exports the names of :mod:`ppm_stiffness.maps.bounds` and
:mod:`ppm_stiffness.maps.result` that older code imports from it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness._allocator import LARGE_MAP_POSES, tune_allocator
from ppm_stiffness.core.conventions import DEFAULT_REFERENCE_FORCE, FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.bounds import (
    _sampled_bounds,
    reachable_positions,
    workspace_bounds,
)
from ppm_stiffness.maps.chunks import default_chunk, select_path, uses_planar_engine
from ppm_stiffness.maps.map_chunks import QUANTITY_SETS, MapPlan, grid_rows, quantity_names
from ppm_stiffness.maps.result import PAPER, PRINCIPAL, QUANTITIES, StiffnessMap, load_npz
from ppm_stiffness.maps.slices import MapSlice, map_slice, slice_bounds, slice_grid
from ppm_stiffness.model import locked_actuator_stiffness
from ppm_stiffness.poses import dependent_indices
from ppm_stiffness.statics import actuator as act

__all__ = [
    "ACTUATOR_STATES",
    "DEFAULT_REFERENCE_FORCE",
    "QUANTITIES",
    "QUANTITY_SETS",
    "StiffnessMap",
    "_sampled_bounds",
    "load_npz",
    "map_slice",
    "minimum_actuator_stiffness",
    "quantity_names",
    "reachable_positions",
    "slice_bounds",
    "stiffness_map",
    "workspace_bounds",
    "workspace_grid",
]

ACTUATOR_STATES = ("max", "min", "wrench")


def workspace_grid(
    design: Design,
    phi: float = 0.0,
    grid: int | tuple[int, int] = 200,
    bounds: ArrayLike | None = None,
    legs: object = None,
) -> tuple[FloatArray, FloatArray]:
    """Grid axes x (nx,), y (ny,) [m] of a planar design's x-y map at ``phi`` over
    ``bounds`` or the workspace bounding box (:func:`~ppm_stiffness.maps.slices
    .slice_grid`). ``legs`` is accepted for compatibility and ignored."""
    del legs
    return slice_grid(design, map_slice(design, ("x", "y"), phi=phi), grid, bounds)


def minimum_actuator_stiffness(design: Design, reference_force: float) -> FloatArray:
    """The "min" actuator stiffness of each leg (n_legs,) [N/m or N·m/rad]: eq.
    (20)-(21) of the leg's own law under ``reference_force`` [N or N·m]; ``inf`` for a
    passive constraining leg (no actuator: the value enters nothing)."""
    if not np.isfinite(reference_force) or reference_force <= 0:
        raise InputDataError(f"reference force must be finite and > 0 N, got {reference_force}")
    return np.array(
        [
            np.inf
            if leg.actuator is None
            else float(act.stiffness_from_force(leg.actuator, reference_force))
            for leg in design.legs
        ]
    )


def _link_modes(link_modes: int | None) -> int:
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    return resolve_link_modes(link_modes)


def stiffness_map(
    design: Design,
    phi: float | None = None,
    actuators: str = "max",
    grid: int | tuple[int, int] = 200,
    wrench: ArrayLike | None = None,
    progress: Callable[[int, int], None] | None = None,
    *,
    axes: tuple[str, str] | list[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: ArrayLike | None = None,
    reference_force: float = DEFAULT_REFERENCE_FORCE,
    chunk_size: int | None = None,
    path: batch.Path = "auto",
    tool_point: ArrayLike | None = None,
    quantities: str | Sequence[str] | None = None,
    geometry: str = "frozen",
    link_modes: int | None = None,
) -> StiffnessMap:
    """A stiffness map over a 2-D slice of the task space, any design (module doc).

    Parameters
    ----------
    design : Design
    phi : float, optional
        rz [rad] of the slice (the planar orientation; 0 for a planar design when
        not given, as before), as ``fixed={"rz": phi}``.
    actuators : {"max", "min", "wrench"}
        Actuator state (module doc); each leg uses its own actuator law.
    grid : int or (nu, nv)
        Grid points along the two axes.
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N], axes of F_b, acting at the tool point
        (P by default); for "wrench" only.
    progress : callable(done, total), optional
        Called after each chunk with the number of poses done and the total.
    axes : (str, str), optional
        The two task coordinates of the grid; default x, y when the design has them,
        else its first two task coordinates (:func:`~ppm_stiffness.maps.slices
        .map_slice`).
    fixed : mapping of str to float, optional
        Values [m, rad] of the other task coordinates; default the home pose's.
    bounds : array_like (4,), optional
        (u_min, u_max, v_min, v_max) of the two axes [m or rad]; default the slice's
        reachable extent (:func:`~ppm_stiffness.maps.slices.slice_bounds`).
    reference_force : float
        [N, or N·m for a rotary actuator], defines the "min" state.
    chunk_size : int, optional
        Poses per chunk (memory bound); default by the path.
    path : {"auto", "reduced", "planar", "general"}
        :func:`~ppm_stiffness.maps.chunks.select_path`.
    tool_point : array_like (3,), optional
        Platform frame [m]; ``design.tool_point`` if None. The quantities are those of
        K at that point (a wrench of the "wrench" state acts there too); the grid and
        the masks are those of P.
    quantities : str or sequence of str, optional
        :func:`quantity_names`; ``load_margin`` under a wrench only.
    geometry : {"frozen", "moving"}
        Under a wrench: the paper's statics on the unloaded geometry, or the equilibrium
        with moving geometry (the symmetric part of K_F at the displaced tool point,
        :func:`ppm_stiffness.maps.loaded.moving_columns`).
    link_modes : int, optional
        For ``f1``: each leg's own modes with the platform held (Craig-Bampton,
        :mod:`ppm_stiffness.dynamics.legmodes`), as ``analyze`` and ``modes``; None:
        :data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`; 0: the legs
        condensed statically (the f1 of the maps before issue 30).

    Returns
    -------
    StiffnessMap

    Raises
    ------
    InputDataError
        Unknown actuator state, wrench missing or given for another state, bad grid,
        axes or fixed coordinates that are not task coordinates, unknown quantities.
    UnreachablePoseError
        No reachable pose in the slice (and no ``bounds`` given).
    """
    from ppm_stiffness.statics.loading import validate_wrench

    if actuators not in ACTUATOR_STATES:
        raise InputDataError(f"actuators must be one of {ACTUATOR_STATES}, got {actuators!r}")
    if (actuators == "wrench") != (wrench is not None):
        raise InputDataError('a wrench is needed for actuators="wrench" and only for it')
    if phi is not None and not np.isfinite(phi):
        raise InputDataError("phi must be finite")
    names = quantity_names(design, quantities)
    if wrench is None and (geometry != "frozen" or "load_margin" in names):
        raise InputDataError(
            "the moving geometry and the load_margin quantity need a wrench (actuators="
            '"wrench"): the geometry moves under a load'
        )
    if geometry not in ("frozen", "moving"):
        raise InputDataError(f"geometry must be 'frozen' or 'moving', got {geometry!r}")
    if geometry == "moving" and "f1" in names:
        raise InputDataError(
            "f1 is not mapped with moving geometry (the mass matrix is that of the "
            "unloaded pose): use geometry 'frozen', whose f1 under a wrench uses the "
            "loaded tangent K as `modes --wrench` does"
        )
    if "hinge_range" in names and actuators != "max":
        raise InputDataError(
            "hinge_range is mapped with the drives as the design gives them "
            '(actuators="max"), not under another actuator state'
        )
    paper = any(n in PAPER for n in names)
    spatial = any(n in PRINCIPAL for n in names)
    count = _link_modes(link_modes) if "f1" in names else 0
    sl = map_slice(design, axes, fixed, phi)
    legs = select_path(design, path)
    planar = uses_planar_engine(design, path)
    tool = np.asarray(design.tool_point if tool_point is None else tool_point, dtype=float)
    if tool.shape != (3,) or not np.all(np.isfinite(tool)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    u, v = slice_grid(design, sl, grid, bounds)
    if u.size * v.size >= LARGE_MAP_POSES:
        tune_allocator()  # once per process (ppm_stiffness._allocator)
    w = None if wrench is None else validate_wrench(wrench)
    k_locked = locked_actuator_stiffness(design)
    ref: float | None = None
    if actuators == "max":
        k_const: FloatArray | None = k_locked
    elif actuators == "min":
        ref = float(reference_force)
        k_const = minimum_actuator_stiffness(design, ref)
    else:
        k_const = None
    nv, nu = v.size, u.size
    rows = max(1, int(chunk_size or default_chunk(legs, planar)) // nu)
    n_legs = len(design.legs)
    values = {name: np.full((nv, nu), np.nan) for name in names}
    dep = [] if design.planar else list(dependent_indices(design))
    dependent = {f"{i}": np.full((nv, nu), np.nan) for i in dep}
    valid = np.zeros((nv, nu), dtype=bool)
    refusal = np.zeros((nv, nu), dtype=np.int8)
    k_lo, k_hi = np.full(n_legs, np.inf), np.full(n_legs, -np.inf)
    plan = MapPlan(
        design,
        sl,
        legs,
        planar,
        tool,
        k_const,
        w,
        paper,
        spatial,
        geometry,
        "load_margin" in names,
        "f1" in names,
        "hinge_range" in names,
        count,
    )
    for j0 in range(0, nv, rows):
        j1 = min(j0 + rows, nv)
        shape = (j1 - j0, nu)
        codes, ok, columns, full, k_act = grid_rows(plan, u, v[j0:j1])
        if k_act is not None and np.any(ok):
            k_lo = np.minimum(k_lo, k_act[ok].min(axis=0))
            k_hi = np.maximum(k_hi, k_act[ok].max(axis=0))
        refusal[j0:j1] = codes.reshape(shape)
        valid[j0:j1] = ok.reshape(shape)
        for name in names:
            values[name][j0:j1] = np.reshape(columns[name], shape)
        if full is not None:
            for i in dep:
                dependent[f"{i}"][j0:j1] = full[:, i].reshape(shape)
        if progress is not None:
            progress(j1 * nu, nv * nu)
    if k_const is not None:
        k_lo = k_hi = np.asarray(k_const, dtype=float)
    if not np.any(valid):
        k_lo = k_hi = np.full(n_legs, np.nan)
    return _result(
        design,
        sl,
        u,
        v,
        values,
        dependent,
        valid,
        refusal,
        actuators,
        np.stack([k_lo, k_hi]),
        w,
        ref,
        tool,
        geometry if w is not None else "frozen",
        count if "f1" in names else None,
    )


def _drive_unit(design: Design) -> str:
    """The drives' displacement unit (rad or m; one kind: ``require_hinge_figures``)."""
    return next((leg.actuator_units()[1] for leg in design.legs if leg.is_actuated()), "")


def _result(
    design: Design,
    sl: MapSlice,
    u: FloatArray,
    v: FloatArray,
    values: dict[str, FloatArray],
    dependent: dict[str, FloatArray],
    valid: np.ndarray,
    refusal: np.ndarray,
    actuators: str,
    actuator_stiffness: FloatArray,
    wrench: FloatArray | None,
    reference_force: float | None,
    tool: FloatArray,
    geometry: str = "frozen",
    link_modes: int | None = None,
) -> StiffnessMap:
    from ppm_stiffness.core.pose import POSE_COORDINATES

    def masked(data: FloatArray) -> np.ma.MaskedArray:
        data[~valid] = np.nan
        return np.ma.MaskedArray(data, mask=~valid, fill_value=np.nan)

    return StiffnessMap(
        axes=sl.axes,
        u=u,
        v=v,
        fixed=dict(sl.fixed),
        quantities={name: masked(data) for name, data in values.items()},
        reachable=valid,
        actuators=actuators,
        actuator_stiffness=actuator_stiffness,
        wrench=wrench,
        reference_force=reference_force,
        design_name=design.name,
        refusal=refusal,
        dependent={
            POSE_COORDINATES[int(i)]: np.where(valid, d, np.nan) for i, d in dependent.items()
        },
        tool_point=tool,
        geometry=geometry,
        drive_unit=_drive_unit(design) if "hinge_range" in values else "",
        link_modes=link_modes,
    )
