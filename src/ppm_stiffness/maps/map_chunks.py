"""One block of rows of a map's grid: its refusal codes and quantities, under each
actuator state (:func:`ppm_stiffness.maps.workspace.stiffness_map` calls it per chunk).

With constant actuator stiffnesses ("max", "min") the poses go through
:func:`ppm_stiffness.maps.chunks.chunk_result` (the reduced, planar or general path),
or, for a planar design's x-y slice on the reduced path at P, through the reduced form
broadcast over the grid's axes (no per-pose copies). Under a wrench they go through
:func:`ppm_stiffness.maps.loaded.loaded_poses`, the wrench moved from the tool point to
P at each pose's orientation. The quantities are named as in
:data:`ppm_stiffness.maps.result.QUANTITIES`; the first natural frequency ``f1`` is
computed from the chunk's own K and actuator stiffnesses
(:mod:`ppm_stiffness.dynamics.batch`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.refusals import Refusal, RefusalArray, first_refusal
from ppm_stiffness.design import Design
from ppm_stiffness.maps.chunks import chunk_result
from ppm_stiffness.maps.loaded import loaded_poses, moving_columns, with_margin
from ppm_stiffness.maps.paper_principal import principal_from_entries
from ppm_stiffness.maps.principal_batch import tool_offsets
from ppm_stiffness.maps.reduced_leg import ReducedLeg
from ppm_stiffness.maps.reduced_path import planar_entries, reduced_projector
from ppm_stiffness.maps.result import EXTRA, PAPER, PRINCIPAL, QUANTITIES
from ppm_stiffness.maps.slices import MapSlice
from ppm_stiffness.maps.transmission import nonsingular_from_entries
from ppm_stiffness.poses import full_poses

#: Names of the quantity sets :func:`quantity_names` accepts.
QUANTITY_SETS = ("paper", "principal", "all")


def quantity_names(design: Design, quantities: str | Sequence[str] | None) -> tuple[str, ...]:
    """The quantities of a map: None, the design's default ("paper" for a planar design,
    "principal" otherwise); "paper" (k_phi, k_x, k_y: planar designs only), "principal"
    (the six spatial values), "all" (both, for a planar design); or names of
    :data:`~ppm_stiffness.maps.result.QUANTITIES`.

    Raises
    ------
    InputDataError
        An unknown name, or the paper's quantities for a design that is not planar.
    DesignError
        ``f1`` for a design without a mass model (no ``[platform]`` table);
        ``hinge_range`` for a design without notch hinges or their yield strengths.
    """
    if quantities is None:
        quantities = "paper" if design.planar else "principal"
    if isinstance(quantities, str) and "," in quantities:  # e.g. "paper,load-margin"
        items = [q.strip() for q in quantities.split(",")]
        parts = [quantity_names(design, q if q in QUANTITY_SETS else [q]) for q in items]
        return tuple(dict.fromkeys(n for part in parts for n in part))
    if isinstance(quantities, str) and quantities.replace("-", "_") in QUANTITIES:
        quantities = [quantities]  # one name, e.g. "f1" or "load-margin"
    if isinstance(quantities, str):
        if quantities not in QUANTITY_SETS:
            raise InputDataError(
                f"quantities must be one of {', '.join(QUANTITY_SETS)} or a list of "
                f"{', '.join(QUANTITIES)}, got {quantities!r}"
            )
        sets = {"paper": PAPER, "principal": PRINCIPAL, "all": PAPER + PRINCIPAL}
        names = sets[quantities] if design.planar or quantities != "all" else PRINCIPAL
    else:
        names = tuple(
            n.replace("-", "_") if n.replace("-", "_") in EXTRA else n for n in quantities
        )
        unknown = [n for n in names if n not in QUANTITIES]
        if unknown or not names:
            raise InputDataError(
                f"unknown map quantity {', '.join(unknown) or '(none)'}: choose from "
                f"{', '.join(QUANTITIES)}"
            )
    if "f1" in names:  # the first natural frequency needs a mass model
        from ppm_stiffness.dynamics.mass import require_mass_model

        require_mass_model(design)
    if "hinge_range" in names:  # notch hinges with their yield strengths
        from ppm_stiffness.statics.hinge_stress import require_hinge_figures

        require_hinge_figures(design)
    if not design.planar and any(n in PAPER for n in names):
        raise InputDataError(
            f"k_phi, k_x, k_y are the paper's planar principal stiffnesses: {design.name!r} "
            "is not planar; use the principal stiffnesses (quantities 'principal')"
        )
    return tuple(dict.fromkeys(names))


def _spatial_columns(rot: FloatArray, tra: FloatArray) -> dict[str, FloatArray]:
    return {name: (rot if k < 3 else tra)[:, k % 3] for k, name in enumerate(PRINCIPAL)}


def _loaded_chunk(
    design: Design,
    full: FloatArray,
    wrench_tool: FloatArray,
    offsets: FloatArray | None,
    tool: FloatArray,
    spatial: bool,
    matrices: bool = False,
) -> tuple[np.ndarray, FloatArray, dict[str, FloatArray], FloatArray | None]:
    """Codes (n,), actuator stiffness (n, n_legs), quantities of the loaded states at
    full poses (n, 6), the wrench moved from the tool point to P per orientation
    (``offsets``: T - P, (3,) for every pose or (n, 3)), and with ``matrices`` their
    tangent K (n, 6, 6) at P."""
    n = full.shape[0]
    groups = [np.arange(n)]
    moments = np.zeros((1, 3))
    if offsets is not None and np.ndim(offsets) == 1:  # one orientation
        moments = np.cross(offsets, wrench_tool[3:])[None]  # m_P = m_T + r x f
    elif offsets is not None:
        unique, inverse = np.unique(offsets, axis=0, return_inverse=True)
        groups = [np.flatnonzero(inverse.reshape(-1) == g) for g in range(unique.shape[0])]
        moments = np.cross(unique, wrench_tool[3:])
    codes = np.zeros(n, dtype=np.int8)
    k_act = np.zeros((n, len(design.legs)))
    columns: dict[str, FloatArray] = {}
    k_all = np.zeros((n, 6, 6)) if matrices else None
    for rows, extra in zip(groups, moments, strict=True):
        w_p = wrench_tool.copy()
        w_p[:3] += extra
        poses = full if rows.size == n else np.take(full, rows, axis=0)
        res = loaded_poses(
            design, poses, w_p, tool_point=tool, principal=spatial, matrices=matrices
        )
        codes[rows] = res.refusal
        if k_all is not None and res.stiffness is not None:
            k_all[rows] = res.stiffness
        k_act[rows] = np.ma.getdata(res.actuator_stiffness)
        found: dict[str, FloatArray] = {}
        if res.paper is not None:
            found |= {n: getattr(res.paper, n).filled(np.nan) for n in PAPER}
        if res.rotational is not None and res.translational is not None:
            found |= _spatial_columns(
                res.rotational.filled(np.nan), res.translational.filled(np.nan)
            )
        for name, values in found.items():
            columns.setdefault(name, np.full(n, np.nan))[rows] = values
    return codes, k_act, columns, k_all


class MapPlan(NamedTuple):
    """What every block of rows of a map shares (validated by the map)."""

    design: Design
    slice: MapSlice
    legs: tuple[ReducedLeg, ...] | None
    planar: bool
    tool: FloatArray
    actuator_stiffness: FloatArray | None
    wrench: FloatArray | None
    paper: bool
    spatial: bool
    #: under a wrench: "frozen" (the paper's statics) or "moving" (maps/loaded.py)
    geometry: str = "frozen"
    #: the load_margin quantity (maps/loaded.py, :func:`margin_column`)
    margin: bool = False
    #: the first natural frequency f1 (:mod:`ppm_stiffness.dynamics.batch`)
    dynamics: bool = False
    #: the hinge range (:func:`ppm_stiffness.statics.hinge_stress.drive_range`)
    hinges: bool = False
    #: f1's fixed-interface modes per leg (:mod:`ppm_stiffness.dynamics.legmodes`; 0:
    #: the legs condensed)
    link_modes: int = 0


def _with_f1(
    plan: MapPlan,
    full: FloatArray,
    k: FloatArray | None,
    k_act: FloatArray,
    codes: RefusalArray,
    ok: BoolArray,
    columns: dict[str, FloatArray],
) -> tuple[RefusalArray, BoolArray]:
    """Add ``f1`` to the columns; the poses where it fails refused as singular."""
    from ppm_stiffness.dynamics.batch import first_frequencies, refuse_failed

    assert k is not None
    f1, f1_ok = first_frequencies(plan.design, full, k, k_act, ok, plan.link_modes)
    columns["f1"] = f1
    return refuse_failed(codes, ok, f1_ok), ok & f1_ok


def grid_rows(
    plan: MapPlan, u: FloatArray, v: FloatArray
) -> tuple[RefusalArray, BoolArray, dict[str, FloatArray], FloatArray | None, FloatArray | None]:
    """The grid points (u (nu,) x v (nv,)) of a block of rows, flattened (v slowest):
    refusal codes, the valid mask, the quantities by name, the full poses (None on the
    broadcast reduced form, planar) and under a wrench the actuator stiffnesses."""
    design, sl, tool = plan.design, plan.slice, plan.tool
    at_tool = bool(np.any(tool))
    k_const = plan.actuator_stiffness
    if (
        plan.legs is not None
        and k_const is not None
        and not at_tool
        and not plan.spatial
        and not plan.dynamics
        and not plan.hinges
        and sl.axes == ("x", "y")
    ):
        # the reduced form broadcasts over the grid axes (no per-pose copies)
        phi = sl.fixed["rz"]
        with np.errstate(all="ignore"):
            e, reach = planar_entries(plan.legs, u[None, :], v[:, None], phi, k_const)
            pr = principal_from_entries(e)
            pi = reduced_projector(plan.legs, phi)
        ok = (reach & nonsingular_from_entries(e, pi)).reshape(-1)
        checks = [(Refusal.UNREACHABLE, reach.reshape(-1)), (Refusal.SINGULAR, ok)]
        columns = {"k_phi": pr.k_phi, "k_x": pr.k_x, "k_y": pr.k_y}
        return first_refusal(ok.shape, checks), ok, columns, None, None
    task = sl.task_values(u[None, :], v[:, None]).reshape(-1, len(sl.task))
    full, completed = full_poses(design, task)
    offsets = tool_offsets(full, tool) if at_tool else None  # (3,) at one orientation
    if k_const is None:
        assert plan.wrench is not None
        if plan.geometry == "moving":
            codes, k_act, columns = moving_columns(
                design, full, plan.wrench, tool, paper=plan.paper, spatial=plan.spatial
            )
            k_loaded = None
        else:
            codes, k_act, columns, k_loaded = _loaded_chunk(
                design, full, plan.wrench, offsets, tool, plan.spatial, plan.dynamics
            )
        if plan.margin:
            codes, columns["load_margin"] = with_margin(design, full, plan.wrench, tool, codes)
        ok = codes == 0
        if plan.dynamics:
            codes, ok = _with_f1(plan, full, k_loaded, k_act, codes, ok, columns)
        return codes, ok, columns, full, k_act
    res = chunk_result(
        design,
        plan.legs,
        full,
        np.broadcast_to(k_const, (full.shape[0], len(design.legs))),
        plan.planar,
        matrices=plan.dynamics,
        completed=None if np.all(completed) else completed,
        offsets=offsets,
        paper=plan.paper,
        spatial=plan.spatial,
    )
    checks = [(Refusal.UNREACHABLE, res.reachable), (Refusal.SINGULAR, res.valid)]
    columns = {}
    if res.paper is not None:
        columns = {"k_phi": res.paper.k_phi, "k_x": res.paper.k_x, "k_y": res.paper.k_y}
    if res.rotational is not None and res.translational is not None:
        columns |= _spatial_columns(res.rotational, res.translational)
    codes, ok = first_refusal(res.valid.shape, checks), res.valid
    if plan.dynamics:
        codes, ok = _with_f1(plan, full, res.stiffness, k_const, codes, ok, columns)
    if plan.hinges:
        columns["hinge_range"] = _hinge_column(design, full, ok)
    return codes, ok, columns, full, None


def _hinge_column(design: Design, full: FloatArray, ok: BoolArray) -> FloatArray:
    """The hinge range (n,) at the valid full poses (n, 6), NaN elsewhere: a loop over
    the poses (:func:`ppm_stiffness.statics.hinge_stress.pose_figures`)."""
    from ppm_stiffness.statics.hinge_stress import pose_figures

    out = np.full(full.shape[0], np.nan)
    rows = np.flatnonzero(ok)
    out[rows] = pose_figures(design, full[rows])[0]
    return out
