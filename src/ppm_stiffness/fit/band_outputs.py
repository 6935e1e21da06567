"""Output functions for uncertainty bands (:func:`ppm_stiffness.fit.uncertainty.propagate`):
what ``analyze``, ``map`` and ``deflect`` compute, as functions of a design.

Each returns a callable ``Design -> ndarray`` of a fixed shape, NaN where the design
gives no value (an unreachable or singular pose). Stiffnesses at unloaded poses of a
planar design and maps go through the batched model
(:func:`ppm_stiffness.maps.batch.evaluate_poses`, and
:func:`ppm_stiffness.maps.workspace.stiffness_map` which uses it), those of a spatial
design through :func:`ppm_stiffness.model.stiffness_at_pose`; a loaded pose through
the loaded equilibrium; a deflection curve through its closed form, the equilibrium at
each load (``deflect --method closed-form``, equal to the integrated path to 1e-6).

A pose is held at its task coordinates: each sampled design completes the dependent
ones (:mod:`ppm_stiffness.poses`; a tolerance on a tripod's geometry moves its
parasitic motion). The principal stiffnesses are the paper's k_phi, k_x, k_y for a
planar design and the spatial ones of :mod:`ppm_stiffness.core.principal` for a
spatial design (:func:`principal_quantities`). The natural frequencies of a design
with a mass model come from the modal analysis (:func:`modes_output`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import (
    TWIST_COMPONENTS,
    FloatArray,
    twist_b_from_twist_a,
    wrench_b_from_wrench_a,
)
from ppm_stiffness.design import Design

#: The principal stiffnesses of a planar design in :func:`pose_output` (the paper's),
#: with their units.
PLANAR_PRINCIPAL = (("k_phi", "N·m/rad"), ("k_x", "N/m"), ("k_y", "N/m"))
#: The principal stiffnesses of a spatial design in :func:`pose_output`
#: (:func:`ppm_stiffness.core.principal.principal_compliance_values` at the tool
#: point): rotational then translational, each in ascending order (1 is the worst
#: direction), with their units.
SPATIAL_PRINCIPAL = tuple(
    (f"k_{block}_{j}", unit)
    for block, unit in (("rot", "N·m/rad"), ("trans", "N/m"))
    for j in (1, 2, 3)
)
_K_LABELS = [f"K[{TWIST_COMPONENTS[i]},{TWIST_COMPONENTS[j]}]" for i in range(6) for j in range(6)]
_K_UNITS = [
    ("N·m/rad" if i < 3 and j < 3 else "N/m" if i >= 3 and j >= 3 else "N")
    for i in range(6)
    for j in range(6)
]
#: Names of the values of :func:`pose_output` for a planar design, in order (without a
#: wrench: the first 39; with one, also the twist of the tool point).
POSE_LABELS = (
    [name for name, _ in PLANAR_PRINCIPAL] + _K_LABELS + [f"twist_{c}" for c in TWIST_COMPONENTS]
)
#: Units of POSE_LABELS.
POSE_UNITS = [unit for _, unit in PLANAR_PRINCIPAL] + _K_UNITS + ["rad"] * 3 + ["m"] * 3


def principal_quantities(design: Design) -> tuple[tuple[str, str], ...]:
    """The principal stiffnesses (name, unit) that lead :func:`pose_output`'s values:
    :data:`PLANAR_PRINCIPAL` for a planar design, :data:`SPATIAL_PRINCIPAL` else."""
    return PLANAR_PRINCIPAL if design.planar else SPATIAL_PRINCIPAL


def pose_labels(design: Design, loaded: bool = False) -> tuple[list[str], list[str]]:
    """Names and units of :func:`pose_output`'s values for ``design`` (with the twist
    when ``loaded``)."""
    lead = principal_quantities(design)
    names = [n for n, _ in lead] + _K_LABELS
    units = [u for _, u in lead] + _K_UNITS
    if loaded:
        names += [f"twist_{c}" for c in TWIST_COMPONENTS]
        units += ["rad"] * 3 + ["m"] * 3
    return names, units


def _task(design: Design, pose: FloatArray) -> FloatArray:
    """The task coordinates of a full pose (6,) (a pose of task coordinates as is)."""
    from ppm_stiffness.poses import task_values

    if pose.shape == (6,) and len(design.task_coordinates) < 6:
        return task_values(design, pose)
    return pose


def pose_output(
    pose: ArrayLike,
    tool_point: ArrayLike,
    wrench: ArrayLike | None = None,
    path: Literal["auto", "reduced", "general"] = "general",
) -> Callable[[Design], FloatArray]:
    """The principal stiffnesses, K (36, row-major) at the tool point, and with a wrench
    (acting at the tool point) also the tool point's twist.

    A planar design: k_phi, k_x, k_y, K: shape (39,), or (45,) with the twist. A
    spatial design: the six of :data:`SPATIAL_PRINCIPAL`, K: shape (42,), or (48,)
    (:func:`pose_labels`).

    ``pose`` is the design's task coordinates or a full pose (6,) [m, rad]: each
    design is evaluated at its task coordinates (module doc). Unloaded, a planar design:
    the batched model (``path`` of :func:`~ppm_stiffness.maps.batch.evaluate_poses`;
    the general path by default: at one pose it is faster than building a reduced
    form for every sampled design); a spatial design:
    :func:`~ppm_stiffness.model.stiffness_at_pose`; loaded: the equilibrium with the
    actuator law (tangent K, as ``analyze --wrench``).
    """
    from ppm_stiffness.maps.batch import evaluate_poses, principal_from_matrices
    from ppm_stiffness.model import stiffness_at_tool_point, tool_offset
    from ppm_stiffness.statics.loading import loaded_state

    p = np.asarray(pose, dtype=float)
    tool = np.asarray(tool_point, dtype=float)
    offset = tool_offset(p, tool)
    w_tool = None if wrench is None else np.asarray(wrench, dtype=float)

    def output(design: Design) -> FloatArray:
        if not design.planar:
            return _spatial_pose_output(design, _task(design, p), tool, w_tool)
        size = 39 if w_tool is None else 45
        out = np.full(size, np.nan)
        if w_tool is None:
            batch = evaluate_poses(design, p[None, :], matrices=True, path=path)
            if not bool(batch.valid[0]):
                return out
            assert batch.stiffness is not None
            k = batch.stiffness[0]
        else:
            w_p = wrench_b_from_wrench_a(np.eye(3), offset) @ w_tool
            state = loaded_state(design, w_p, p)
            k = state.stiffness_matrix
            out[39:] = twist_b_from_twist_a(np.eye(3), -offset) @ state.twist
        k_t = stiffness_at_tool_point(k, p, tool)
        pr = principal_from_matrices(k_t[None])
        out[:3] = [pr.k_phi[0], pr.k_x[0], pr.k_y[0]]
        out[3:39] = k_t.ravel()
        return out

    return output


def _spatial_pose_output(
    design: Design, task: FloatArray, tool: FloatArray, wrench: FloatArray | None
) -> FloatArray:
    """:func:`pose_output` of a spatial design at its task coordinates ``task``."""
    from ppm_stiffness.core.principal import principal_compliance_values
    from ppm_stiffness.model import (
        stiffness_at_pose,
        stiffness_at_tool_point,
        tool_offset,
        validate_pose,
    )
    from ppm_stiffness.statics.loading import loaded_state

    full = validate_pose(design, task)  # an unreachable pose fails the sample
    offset = tool_offset(full, tool)
    out = np.full(42 if wrench is None else 48, np.nan)
    if wrench is None:
        k = stiffness_at_pose(design, full)
    else:
        state = loaded_state(design, wrench_b_from_wrench_a(np.eye(3), offset) @ wrench, full)
        k = state.stiffness_matrix
        out[42:] = twist_b_from_twist_a(np.eye(3), -offset) @ state.twist
    k_t = stiffness_at_tool_point(k, full, tool)
    rotational, translational = principal_compliance_values(k_t)
    out[:6] = np.concatenate([rotational, translational])
    out[6:42] = k_t.ravel()
    return out


def pose_failed_value(design: Design, loaded: bool = False) -> FloatArray:
    """:func:`~ppm_stiffness.fit.uncertainty.propagate`'s ``failed_value`` of
    :func:`pose_output` for ``design``: the principal stiffnesses are 0 in a sample
    that is singular (or cannot reach the pose); K's entries and the twist have no such
    limit and are left out (NaN). It is also their ``lower_limit``: a stiffness is
    never negative."""
    n = len(principal_quantities(design))
    return np.concatenate([np.zeros(n), np.full(36 + (6 if loaded else 0), np.nan)])


#: :func:`pose_failed_value` of a planar design with a wrench (its first 39 values
#: without one).
POSE_FAILED_VALUE = np.concatenate([np.zeros(3), np.full(42, np.nan)])
#: ... of :func:`map_output`: every field is a principal stiffness.
MAP_FAILED_VALUE = 0.0


def map_output(**map_arguments: object) -> Callable[[Design], FloatArray]:
    """The map's quantities over its grid, shape (n_quantities, nv, nu), NaN where the
    design gives no value: k_phi, k_x, k_y (3, ny, nx) for a planar design by default,
    the spatial principal stiffnesses for others (or those ``quantities`` names).

    ``map_arguments`` are those of :func:`ppm_stiffness.maps.workspace.stiffness_map`
    (give ``bounds``, so that every design is evaluated on the same grid:
    :meth:`~ppm_stiffness.maps.result.StiffnessMap.grid_arguments` of a nominal map
    gives them all).
    """
    from ppm_stiffness.maps.workspace import stiffness_map

    def output(design: Design) -> FloatArray:
        smap = stiffness_map(design, **map_arguments)  # type: ignore[arg-type]
        return np.stack([np.ma.filled(k.astype(float), np.nan) for k in smap.fields().values()])

    return output


#: :func:`modes_output`'s failed value and lower limit: a sample that cannot reach the
#: pose, or is singular there, has a zero frequency.
MODES_FAILED_VALUE = 0.0


def modes_output(
    pose: ArrayLike,
    tool_point: ArrayLike,
    wrench: ArrayLike | None = None,
    link_modes: int | None = None,
) -> Callable[[Design], FloatArray]:
    """The six natural frequencies (6,) [Hz, ascending] of a design with a mass model
    at ``pose`` (its task coordinates, module doc), locked or under ``wrench`` acting at
    the tool point (the loaded tangent K and actuator stiffnesses, as ``modes
    --wrench``): :func:`ppm_stiffness.dynamics.analysis.modal_analysis`. The masses
    are design parameters (``platform.mass``, ``leg*.<part>.mass``,
    ``leg*.actuator.carriage_mass``, ``leg*.actuator.rotor_inertia``, ...), so that a
    tolerance file moves them as it moves stiffnesses. ``link_modes``: each leg's own
    modes (None: the default, as ``modal_analysis``; 0: the legs condensed)."""
    p = np.asarray(pose, dtype=float)
    tool = np.asarray(tool_point, dtype=float)
    w = None if wrench is None else np.asarray(wrench, dtype=float)

    def output(design: Design) -> FloatArray:
        from ppm_stiffness.dynamics.analysis import modal_analysis

        result = modal_analysis(design, _task(design, p), w, tool, link_modes)
        return np.asarray(result.frequencies, dtype=float)

    return output


def deflection_output(
    unit_wrench: ArrayLike, loads: ArrayLike, pose: ArrayLike, tool_point: ArrayLike
) -> Callable[[Design], FloatArray]:
    """Twists (n_loads, 6) [rad, m] of the tool point along ``loads * unit_wrench``
    (the equilibrium at each load), any design; ``pose`` the task coordinates or a full
    pose (6,), each design evaluated at its task coordinates (module doc)."""
    from ppm_stiffness.statics.deflection import deflection_path

    w = np.asarray(unit_wrench, dtype=float)
    x = np.asarray(loads, dtype=float)
    p = np.asarray(pose, dtype=float)
    tool = np.asarray(tool_point, dtype=float)

    def output(design: Design) -> FloatArray:
        curve = deflection_path(design, w, x, _task(design, p), "closed-form", tool_point=tool)
        return np.asarray(curve.twists)

    return output


__all__ = [
    "PLANAR_PRINCIPAL",
    "POSE_LABELS",
    "POSE_UNITS",
    "SPATIAL_PRINCIPAL",
    "deflection_output",
    "map_output",
    "modes_output",
    "pose_failed_value",
    "pose_labels",
    "pose_output",
    "principal_quantities",
]
