"""Output functions for uncertainty bands (:func:`ppm_stiffness.fit.uncertainty.propagate`):
what ``analyze``, ``map`` and ``deflect`` compute, as functions of a design.

Each returns a callable ``Design -> ndarray`` of a fixed shape, NaN where the design
gives no value (an unreachable or singular pose). Stiffnesses at unloaded poses and
maps go through the batched model (:func:`ppm_stiffness.maps.batch.evaluate_poses`,
and :func:`ppm_stiffness.maps.workspace.stiffness_map` which uses it); a loaded pose
through the loaded equilibrium; a deflection curve through its closed form, the
equilibrium at each load (``deflect --method closed-form``, equal to the integrated
path to 1e-6).
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

#: Names of the values of :func:`pose_output`, in order (without a wrench: the first
#: 39; with one, also the twist of the tool point).
POSE_LABELS = (
    ["k_phi", "k_x", "k_y"]
    + [f"K[{TWIST_COMPONENTS[i]},{TWIST_COMPONENTS[j]}]" for i in range(6) for j in range(6)]
    + [f"twist_{c}" for c in TWIST_COMPONENTS]
)
#: Units of POSE_LABELS.
POSE_UNITS = (
    ["N·m/rad", "N/m", "N/m"]
    + [
        ("N·m/rad" if i < 3 and j < 3 else "N/m" if i >= 3 and j >= 3 else "N")
        for i in range(6)
        for j in range(6)
    ]
    + ["rad"] * 3
    + ["m"] * 3
)


def pose_output(
    pose: ArrayLike,
    tool_point: ArrayLike,
    wrench: ArrayLike | None = None,
    path: Literal["auto", "reduced", "general"] = "general",
) -> Callable[[Design], FloatArray]:
    """k_phi, k_x, k_y, K (36, row-major) at the tool point, and with a wrench (acting
    at the tool point) also the tool point's twist: shape (39,) or (45,).

    Unloaded: the batched model (``path`` of
    :func:`~ppm_stiffness.maps.batch.evaluate_poses`; the general path by default: at
    one pose it is faster than building a reduced form for every sampled design);
    loaded: the equilibrium with the actuator law (tangent K, as ``analyze --wrench``).
    """
    from ppm_stiffness.maps.batch import evaluate_poses, principal_from_matrices
    from ppm_stiffness.model import stiffness_at_tool_point, tool_offset
    from ppm_stiffness.statics.loading import loaded_state

    p = np.asarray(pose, dtype=float)
    tool = np.asarray(tool_point, dtype=float)
    offset = tool_offset(p, tool)
    w_tool = None if wrench is None else np.asarray(wrench, dtype=float)

    def output(design: Design) -> FloatArray:
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


#: :func:`~ppm_stiffness.fit.uncertainty.propagate`'s ``failed_value`` of
#: :func:`pose_output`: k_phi, k_x, k_y are 0 in a sample that is singular (or cannot
#: reach the pose); K's entries and the twist have no such limit and are left out.
#: It is also their ``lower_limit``: a stiffness is never negative.
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


def deflection_output(
    unit_wrench: ArrayLike, loads: ArrayLike, pose: ArrayLike, tool_point: ArrayLike
) -> Callable[[Design], FloatArray]:
    """Twists (n_loads, 6) [rad, m] of the tool point along ``loads * unit_wrench``
    (the equilibrium at each load)."""
    from ppm_stiffness.statics.deflection import deflection_path

    w = np.asarray(unit_wrench, dtype=float)
    x = np.asarray(loads, dtype=float)
    p = np.asarray(pose, dtype=float)
    tool = np.asarray(tool_point, dtype=float)

    def output(design: Design) -> FloatArray:
        return np.asarray(deflection_path(design, w, x, p, "closed-form", tool_point=tool).twists)

    return output


__all__ = ["POSE_LABELS", "POSE_UNITS", "deflection_output", "map_output", "pose_output"]
