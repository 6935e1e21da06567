"""One analysis of a design at a pose (or of a given matrix), as plain data.

:func:`analyze_design` and :func:`analyze_matrix` return the object that
``ppm-stiffness analyze --json`` prints and that the report embeds, so both always
carry the same numbers. All values SI (m, rad, N, N·m, N/m, N·m/rad).
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import (
    FloatArray,
    twist_b_from_twist_a,
    wrench_b_from_wrench_a,
)
from ppm_stiffness.core.decoupling import Decoupling, Method, decouple
from ppm_stiffness.core.eigenscrews import ScrewSprings, eigenscrews
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.inputs import as_float_array
from ppm_stiffness.core.pose import POSE_COORDINATES
from ppm_stiffness.core.principal import principal_compliance
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.analysis import first_mode
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
    validate_pose,
)
from ppm_stiffness.statics.loading import loaded_state, validate_wrench

if TYPE_CHECKING:
    from ppm_stiffness.statics.moving import MovingEquilibrium


def eigenscrews_dict(springs: ScrewSprings) -> list[dict[str, Any]]:
    """The six screw springs as dicts (Table 4 columns)."""
    return [
        {
            "eigenvalue": float(springs.eigenvalues[i]),
            "eigenforce": float(springs.eigenforces[i]),
            "pitch": float(springs.pitches[i]),
            "axis": springs.axes[i].tolist(),
            "position": springs.positions[i].tolist(),
            "spring_constant": float(springs.spring_constants[i]),
        }
        for i in range(6)
    ]


def decoupling_dict(dec: Decoupling) -> dict[str, Any]:
    """The decoupling as plain data: method, M, d, K_rr, K_tt, residual_coupling and
    already_decoupled (K_rt is round-off: d = 0, residual_coupling = 0) (SI)."""
    return {
        "method": dec.method,
        "M": dec.M.tolist(),
        "d": dec.d.tolist(),
        "K_rr": dec.K_rr.tolist(),
        "K_tt": dec.K_tt.tolist(),
        "residual_coupling": dec.residual_coupling,
        "already_decoupled": dec.already_decoupled,
    }


def principal_dict(dec: Decoupling) -> dict[str, Any]:
    """Principal stiffnesses: ``values[j]`` with its unit direction ``directions[j]``
    (one direction per row; the library's Decoupling holds them as columns)."""
    return {
        "rotational": {
            "values": dec.rotational_values.tolist(),
            "directions": dec.rotational_directions.T.tolist(),
        },
        "translational": {
            "values": dec.translational_values.tolist(),
            "directions": dec.translational_directions.T.tolist(),
        },
    }


def principal_compliance_dict(k: ArrayLike) -> dict[str, Any]:
    """The spatial principal stiffnesses (:mod:`ppm_stiffness.core.principal`) of K, as
    plain data: ``values[j]`` with its unit direction ``directions[j]``."""
    pc = principal_compliance(k)
    return {
        "rotational": {
            "values": pc.rotational_values.tolist(),
            "directions": pc.rotational_directions.T.tolist(),
        },
        "translational": {
            "values": pc.translational_values.tolist(),
            "directions": pc.translational_directions.T.tolist(),
        },
        "worst_rotational": pc.worst_rotational,
        "worst_translational": pc.worst_translational,
    }


def analyze_matrix(stiffness: ArrayLike, method: Method = "paper") -> dict[str, Any]:
    """Eigenscrews and both decouplings of a matrix.

    The keys keep their meaning whatever ``method``: ``decoupling``/``principal`` are
    the paper's eq. (19), ``decoupling_least_squares``/``principal_least_squares`` the
    shift that minimises the coupling; ``method`` records which one was asked for (and
    is shown first); ``principal_compliance`` the spatial definitions
    (:mod:`ppm_stiffness.core.principal`: rotational from C_rr, translational from C_tt
    at the reference point of K, worst directions). ``eigenscrews_repeated`` lists the
    groups of springs (0-based indices into ``eigenscrews``) that share a repeated
    eigenvalue: inside a group the springs are one valid choice among many
    (:mod:`ppm_stiffness.core.eigenscrews`).
    """
    if method not in ("paper", "least-squares"):
        raise InputDataError(f"unknown decoupling method {method!r}")
    k = as_float_array(stiffness, "stiffness matrix")
    springs = eigenscrews(k)  # checks k (InputDataError)
    dec = decouple(k, "paper")
    best = decouple(k, "least-squares")
    return {
        "method": method,
        "stiffness_matrix": k.tolist(),
        "eigenscrews": eigenscrews_dict(springs),
        "eigenscrews_repeated": [list(g) for g in springs.repeated],
        "decoupling": decoupling_dict(dec),
        "principal": principal_dict(dec),
        "decoupling_least_squares": decoupling_dict(best),
        "principal_least_squares": principal_dict(best),
        "principal_compliance": principal_compliance_dict(k),
    }


#: The statics models of a loaded analysis: the paper's (geometry at the unloaded pose)
#: and the equilibrium with the geometry moving under the load
#: (:mod:`ppm_stiffness.statics.moving`).
GEOMETRIES = ("frozen", "moving")


def analyze_design(
    design: Design,
    pose: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
    method: Method = "paper",
    tool_point: ArrayLike | None = None,
    geometry: str = "frozen",
) -> dict[str, Any]:
    """Full analysis at a pose, unloaded or under ``wrench``, at the tool point.

    Parameters
    ----------
    design : Design
    pose : array_like (3,), optional
        (x [m], y [m], phi [rad]) of P in F_b; the workspace centre if None.
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] applied at the tool point, axes of F_b.
    method : {"paper", "least-squares"}
        The decoupling reported under ``decoupling``/``principal``.
    tool_point : array_like (3,), optional
        In the platform frame [m]; ``design.tool_point`` if None ((0, 0, 0) is P).
    geometry : {"frozen", "moving"}
        Under a wrench: the paper's model (the geometry of the unloaded pose), or the
        equilibrium with moving geometry (:mod:`ppm_stiffness.statics.moving`), whose
        loaded tangent K_F (at the displaced tool point) is then analysed (its
        symmetric part) and described under ``moving_geometry`` (see
        :func:`moving_geometry_dict`).

    Returns
    -------
    dict
        ``pose`` {x, y, phi}, ``architecture``, ``tool_point`` [m, F_p],
        ``actuator_units`` [force, displacement, stiffness] per leg,
        ``actuator_stiffness`` [n], ``stiffness_matrix`` (at the tool point, axes of
        F_b), ``eigenscrews``, ``decoupling``, ``principal`` (+ ``*_least_squares``);
        with a wrench also ``wrench``, ``actuator_forces``,
        ``actuator_displacements`` (delta(G), the integral of 1/K_act),
        ``actuator_secant_stiffness`` and ``twist`` (deflection of the tool point);
        ``geometry`` with a wrench, and ``moving_geometry`` with ``geometry="moving"``;
        with a mass model (``design.platform``) also ``first_frequency`` [Hz] and
        ``first_mode_direction`` (:mod:`ppm_stiffness.dynamics`; under a wrench, of
        the loaded tangent K).
    """
    if geometry not in GEOMETRIES:
        raise InputDataError(f"geometry must be one of {', '.join(GEOMETRIES)}, got {geometry!r}")
    if geometry == "moving" and wrench is None:
        raise InputDataError("--geometry moving needs a --wrench: the geometry moves under a load")
    p = validate_pose(design, pose)
    tool = np.asarray(design.tool_point if tool_point is None else tool_point, dtype=float)
    if tool.shape != (3,) or not np.all(np.isfinite(tool)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    offset = tool_offset(p, tool)  # tool point - P, axes of F_b
    out: dict[str, Any] = {
        "pose": {
            **{name: float(v) for name, v in zip(POSE_COORDINATES, p, strict=True)},
            "phi": float(p[5]),
        },
        "task_coordinates": list(design.task_coordinates),
        "architecture": design.architecture,
        "tool_point": tool.tolist(),
        "actuator_units": [list(leg.actuator_units()) for leg in design.legs],
    }
    if wrench is None:
        k_act = actuator_stiffness_vector(design, None)
        k = stiffness_at_pose(design, p, k_act)
    elif geometry == "moving":
        return _analyze_moving(design, p, validate_wrench(wrench), method, tool, out)
    else:
        w_tool = validate_wrench(wrench)
        w_p = wrench_b_from_wrench_a(np.eye(3), offset) @ w_tool  # moved from T to P
        state = loaded_state(design, w_p, p)
        k_act, k = state.actuator_stiffness, state.stiffness_matrix
        out["geometry"] = "frozen"
        out["wrench"] = w_tool.tolist()
        out["actuator_forces"] = state.actuator_forces.tolist()
        out["actuator_displacements"] = state.actuator_displacements.tolist()
        out["actuator_secant_stiffness"] = state.secant_stiffness.tolist()
        out["twist"] = (twist_b_from_twist_a(np.eye(3), -offset) @ state.twist).tolist()
    out["actuator_stiffness"] = np.asarray(k_act).tolist()
    k_tool = stiffness_at_tool_point(k, p, tool)
    out.update(analyze_matrix(k_tool, method))
    out.update(first_mode(design, p, k_tool, k_act, tool))
    return out


def _analyze_moving(
    design: Design,
    pose: FloatArray,
    wrench: FloatArray,
    method: Method,
    tool: FloatArray,
    out: dict[str, Any],
) -> dict[str, Any]:
    """:func:`analyze_design` with ``geometry="moving"``: the tables of the symmetric
    part of K_F, and ``moving_geometry``."""
    from ppm_stiffness.statics.moving import moving_equilibrium

    state = moving_equilibrium(design, wrench, pose, tool)
    k_f = state.stiffness_matrix
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = np.where(
            state.actuator_displacements != 0,
            state.actuator_forces
            / np.where(state.actuator_displacements != 0, state.actuator_displacements, 1.0),
            [leg.actuator.locked_stiffness for leg in design.legs],
        )
    out["geometry"] = "moving"
    out["wrench"] = wrench.tolist()
    out["actuator_forces"] = state.actuator_forces.tolist()
    out["actuator_displacements"] = state.actuator_displacements.tolist()
    out["actuator_secant_stiffness"] = secant.tolist()
    out["twist"] = state.twist.tolist()
    out["actuator_stiffness"] = state.actuator_stiffness.tolist()
    out.update(analyze_matrix(0.5 * (k_f + k_f.T), method))
    out["moving_geometry"] = moving_geometry_dict(design, state)
    return out


def moving_geometry_dict(design: Design, state: MovingEquilibrium) -> dict[str, Any]:
    """What ``analyze --geometry moving`` adds, as plain data (SI): the displaced pose,
    K_F in full (at the displaced tool point, axes of F_b), the frozen model's K at the
    tool point, their difference, the geometric term, the relative sizes of both
    (length-balanced Frobenius norms), K_F's antisymmetric part and the load margin
    (:mod:`ppm_stiffness.statics.margin`)."""
    from ppm_stiffness.statics.margin import MAX_FACTOR, MarginKind, load_margin
    from ppm_stiffness.statics.moving import relative_difference, relative_size

    k_f, k0 = state.stiffness_matrix, state.frozen_stiffness
    margin = load_margin(design, state.wrench, state.pose, state.tool_point)
    kinds = {
        MarginKind.NONE: "none",
        MarginKind.BIFURCATION: "bifurcation",
        MarginKind.LIMIT_POINT: "limit point",
        MarginKind.STROKE: "stroke",
    }
    return {
        "displaced_pose": {
            **{n: float(v) for n, v in zip(POSE_COORDINATES, state.displaced_pose, strict=True)},
            "phi": float(state.displaced_pose[5]),
        },
        "reference_point": "the displaced tool point (P when no tool point is set)",
        "stiffness_matrix": k_f.tolist(),
        "frozen_stiffness_matrix": k0.tolist(),
        "difference": (k_f - k0).tolist(),
        "relative_difference": relative_difference(k_f, k0),
        "geometric_stiffness": state.geometric_stiffness.tolist(),
        "relative_geometric": relative_size(state.geometric_stiffness, k_f),
        "asymmetry": relative_size(0.5 * (k_f - k_f.T), k_f),
        "load_steps": state.steps,
        "newton_iterations": state.iterations,
        "load_margin": {
            "factor": margin.factor,
            "kind": kinds[margin.kind],
            "searched_up_to": margin.searched_up_to,
            "max_factor": MAX_FACTOR,
            "mode": None if margin.mode is None else margin.mode.tolist(),
            "mode_direction": margin.mode_name,
            "description": margin.describe(),
        },
    }


def to_jsonable(obj: Any) -> Any:
    """Numpy arrays and scalars to lists and floats, refusing NaN."""
    if isinstance(obj, dict):
        return {k: to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        value = float(obj)
        if math.isnan(value):
            raise InputDataError("internal error: a NaN reached the output")
        if math.isinf(value):
            return None  # e.g. the spring constant of a zero-pitch screw: undefined
        return value
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


#: Version of the layout of every ``--json`` document (``docs/schemas/``): bumped when
#: a key changes meaning or disappears (``docs/compatibility.md``).
JSON_SCHEMA_VERSION = 1

#: Keys every JSON document starts with (:func:`json_document`).
ENVELOPE_KEYS = ("schema_version", "ppm_stiffness_version", "command", "units")

#: SI units of the values of :func:`analyze_design` (keys, or ``a.b`` paths).
ANALYSIS_UNITS = {
    "pose": "x, y, z [m], rx, ry, rz [rad] (phi = rz)",
    "tool_point": "m (platform frame)",
    "stiffness_matrix": "K_rr N·m/rad, K_rt N, K_tt N/m (order phi_x, phi_y, phi_z, x, y, z)",
    "actuator_stiffness": "N/m (N·m/rad for a rotary actuator): see actuator_units",
    "eigenscrews.eigenvalue": "N",
    "eigenscrews.eigenforce": "N",
    "eigenscrews.pitch": "m/rad",
    "eigenscrews.position": "m",
    "eigenscrews.spring_constant": "N/m",
    "decoupling.M": "N/m",
    "decoupling.d": "m",
    "decoupling.K_rr": "N·m/rad",
    "decoupling.K_tt": "N/m",
    "principal.rotational.values": "N·m/rad",
    "principal.translational.values": "N/m",
    "principal_compliance.rotational.values": "N·m/rad",
    "principal_compliance.translational.values": "N/m (at the tool point)",
    "principal_compliance.worst_rotational": "N·m/rad",
    "principal_compliance.worst_translational": "N/m (at the tool point)",
    "wrench": "N·m, N (m_x, m_y, m_z, f_x, f_y, f_z), at the tool point",
    "actuator_forces": "N (N·m for a rotary actuator)",
    "actuator_displacements": "m (rad for a rotary actuator)",
    "actuator_secant_stiffness": "N/m (N·m/rad for a rotary actuator)",
    "twist": "rad, m (phi_x, phi_y, phi_z, x, y, z) of the tool point",
    "moving_geometry.displaced_pose": "x, y, z [m], rx, ry, rz [rad] (phi = rz)",
    "moving_geometry.stiffness_matrix": "K_rr N·m/rad, K_rt N, K_tt N/m (displaced tool point)",
    "moving_geometry.frozen_stiffness_matrix": "K_rr N·m/rad, K_rt N, K_tt N/m",
    "moving_geometry.difference": "K_rr N·m/rad, K_rt N, K_tt N/m",
    "moving_geometry.geometric_stiffness": "K_rr N·m/rad, K_rt N, K_tt N/m",
    "moving_geometry.relative_difference": "1 (length-balanced Frobenius norm)",
    "moving_geometry.relative_geometric": "1 (length-balanced Frobenius norm)",
    "moving_geometry.asymmetry": "1 (length-balanced Frobenius norm)",
    "moving_geometry.load_margin.factor": "1 (times the wrench)",
    "moving_geometry.load_margin.mode": "rad, m (a twist of unit length-balanced norm)",
    "first_frequency": "Hz",
}


def json_document(command: str, payload: dict[str, Any], units: dict[str, str]) -> str:
    """The JSON text a command prints with ``--json`` (and the report embeds).

    Every document starts with ``schema_version`` (:data:`JSON_SCHEMA_VERSION`),
    ``ppm_stiffness_version``, ``command`` and ``units`` (key or ``a.b`` path -> SI
    unit of the values under it), then the command's own keys.
    """
    from ppm_stiffness import __version__

    head = {
        "schema_version": JSON_SCHEMA_VERSION,
        "ppm_stiffness_version": __version__,
        "command": command,
        "units": units,
    }
    return dump_json({**head, **payload})


def dump_json(obj: Any) -> str:
    """JSON text of an analysis (or any nested data), as ``analyze --json`` prints it."""
    return json.dumps(to_jsonable(obj), indent=2, allow_nan=False)
