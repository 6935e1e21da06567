"""One analysis of a design at a pose (or of a given matrix), typed and as plain data.

:func:`analyze_design` (public as ``ppm_stiffness.analyze``) returns an
:class:`Analysis`, :func:`analyze_matrix` a :class:`MatrixAnalysis`; their
``to_dict()`` is the object that ``ppm-stiffness analyze --json`` prints and that the
report embeds, so both always carry the same numbers. All values SI (m, rad, N, N·m,
N/m, N·m/rad).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields
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
from ppm_stiffness.core.principal import PrincipalCompliance, principal_compliance
from ppm_stiffness.core.results import DeprecatedMapping
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.analysis import first_mode
from ppm_stiffness.leading import default_method, lead, leading_keys
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
    validate_pose,
)
from ppm_stiffness.statics.loading import loaded_state, validate_wrench

if TYPE_CHECKING:
    from ppm_stiffness.statics.margin import LoadMargin
    from ppm_stiffness.statics.moving import MovingLoadedState


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


def principal_compliance_dict(k: ArrayLike | PrincipalCompliance) -> dict[str, Any]:
    """The spatial principal stiffnesses (:mod:`ppm_stiffness.core.principal`) of K (or
    already computed), as plain data: ``values[j]`` with its unit direction
    ``directions[j]``."""
    pc = k if isinstance(k, PrincipalCompliance) else principal_compliance(k)
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


def pose_dict(pose: FloatArray) -> dict[str, float]:
    """A full pose (6,) as ``{x, y, z, rx, ry, rz, phi}`` [m, rad] (phi = rz)."""
    return {
        **{name: float(v) for name, v in zip(POSE_COORDINATES, pose, strict=True)},
        "phi": float(pose[5]),
    }


@dataclass(frozen=True, eq=False)
class MatrixAnalysis(DeprecatedMapping):
    """Eigenscrews, both decouplings and the spatial principal stiffnesses of one K
    (:func:`analyze_matrix`; SI).

    Attributes
    ----------
    method : {"paper", "least-squares"}
        The decoupling asked for (shown first by ``analyze``).
    stiffness_matrix : ndarray (6, 6)
        The matrix analysed [N·m/rad, N, N/m], order (phi_x, phi_y, phi_z, x, y, z).
    eigenscrews : ScrewSprings
        The six screw springs (eq. 5-11); ``eigenscrews.repeated`` the groups that
        share a repeated eigenvalue.
    decoupling : Decoupling
        The paper's eq. (19), whatever ``method`` (a spatial design's tables and JSON
        lead with ``decoupling_least_squares``: :mod:`ppm_stiffness.leading`; on the
        hexapod eq. (19) doubles the coupling, residual 2.0).
    decoupling_least_squares : Decoupling
        The shift that minimises the coupling.
    principal_compliance : PrincipalCompliance
        Rotational from C_rr, translational from C_tt at the reference point of K.
    """

    method: Method
    stiffness_matrix: FloatArray
    eigenscrews: ScrewSprings
    decoupling: Decoupling
    decoupling_least_squares: Decoupling
    principal_compliance: PrincipalCompliance

    def matrix_dict(self) -> dict[str, Any]:
        """The keys of :func:`analyze_matrix`'s dict of 0.2 (module doc)."""
        return {
            "method": self.method,
            "stiffness_matrix": self.stiffness_matrix.tolist(),
            "eigenscrews": eigenscrews_dict(self.eigenscrews),
            "eigenscrews_repeated": [list(g) for g in self.eigenscrews.repeated],
            "decoupling": decoupling_dict(self.decoupling),
            "principal": principal_dict(self.decoupling),
            "decoupling_least_squares": decoupling_dict(self.decoupling_least_squares),
            "principal_least_squares": principal_dict(self.decoupling_least_squares),
            "principal_compliance": principal_compliance_dict(self.principal_compliance),
        }

    def to_dict(self) -> dict[str, Any]:
        """Plain data (lists, floats, strings): the dict ``analyze_matrix`` returned in
        0.2 and that ``analyze --matrix --json`` prints."""
        return self.matrix_dict()


def analyze_matrix(stiffness: ArrayLike, method: Method = "paper") -> MatrixAnalysis:
    """Eigenscrews and both decouplings of a matrix.

    The fields keep their meaning whatever ``method``: ``decoupling`` (and the dict's
    ``principal``) is the paper's eq. (19), ``decoupling_least_squares`` (and
    ``principal_least_squares``) the shift that minimises the coupling; ``method``
    records which one was asked for (and is shown first); ``principal_compliance`` the
    spatial definitions (:mod:`ppm_stiffness.core.principal`: rotational from C_rr,
    translational from C_tt at the reference point of K, worst directions). The dict's
    ``eigenscrews_repeated`` lists the groups of springs (0-based indices into
    ``eigenscrews``) that share a repeated eigenvalue: inside a group the springs are
    one valid choice among many (:mod:`ppm_stiffness.core.eigenscrews`).

    Parameters
    ----------
    stiffness : array_like (6, 6)
        Symmetric positive definite [N·m/rad, N, N/m].
    method : {"paper", "least-squares"}

    Returns
    -------
    MatrixAnalysis

    Raises
    ------
    InputDataError
        An unknown method, or a matrix that is not 6x6, finite, symmetric and positive
        definite.
    """
    if method not in ("paper", "least-squares"):
        raise InputDataError(f"unknown decoupling method {method!r}")
    k = as_float_array(stiffness, "stiffness matrix")
    springs = eigenscrews(k)  # checks k (InputDataError)
    return MatrixAnalysis(
        method=method,
        stiffness_matrix=k,
        eigenscrews=springs,
        decoupling=decouple(k, "paper"),
        decoupling_least_squares=decouple(k, "least-squares"),
        principal_compliance=principal_compliance(k),
    )


#: The statics models of a loaded analysis: the paper's (geometry at the unloaded pose)
#: and the equilibrium with the geometry moving under the load
#: (:mod:`ppm_stiffness.statics.moving`).
GEOMETRIES = ("frozen", "moving")


@dataclass(frozen=True, eq=False)
class Analysis(MatrixAnalysis):
    """One analysis of a design at a pose (:func:`analyze_design`, public as
    ``ppm_stiffness.analyze``; SI, axes of F_b).

    The fields of :class:`MatrixAnalysis` are those of K at the tool point (under a
    wrench: the loaded tangent K; with ``geometry="moving"``: the symmetric part of
    K_F at the displaced tool point), and:

    Attributes
    ----------
    pose : ndarray (6,)
        The full pose (x, y, z [m], rx, ry, rz [rad]) of P in F_b.
    task_coordinates : tuple of str
        The design's task coordinates.
    architecture : str
    tool_point : ndarray (3,)
        [m, platform frame]; (0, 0, 0) is P.
    actuator_units : list of tuple of str
        (force, displacement, stiffness) units per leg.
    actuator_stiffness : ndarray (n_legs,)
        [N/m or N·m/rad]: locked, or the tangent ones under the wrench.
    geometry : {"frozen", "moving"} or None
        The statics model under a wrench; None unloaded.
    wrench : ndarray (6,) or None
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the tool point, axes of F_b.
    actuator_forces, actuator_displacements, actuator_secant_stiffness : ndarray or None
        (n_legs,) under the wrench [N, m, N/m; N·m, rad, N·m/rad for a rotary
        actuator]; the displacements are delta(G), the integral of 1/K_act.
    twist : ndarray (6,) or None
        The deflection of the tool point [rad, m] under the wrench.
    moving : MovingLoadedState or None
        The equilibrium with moving geometry (``geometry="moving"``).
    load_margin : LoadMargin or None
        Its load margin (``geometry="moving"``).
    first_frequency : float or None
        [Hz] with a mass model (not with ``geometry="moving"``).
    first_mode_direction : str or None
        The first mode's dominant direction, with ``first_frequency``.
    first_mode_platform_share : float or None
        With the legs' own modes: the platform body's share of the first mode's kinetic
        energy (near 0: a mode of the legs).
    planar : bool
        A planar design: its tables lead with the paper's eq. (19) unless ``method`` is
        the least-squares shift (:mod:`ppm_stiffness.leading`).
    """

    pose: FloatArray
    task_coordinates: tuple[str, ...]
    architecture: str
    tool_point: FloatArray
    actuator_units: list[tuple[str, str, str]]
    actuator_stiffness: FloatArray
    geometry: str | None = None
    wrench: FloatArray | None = None
    actuator_forces: FloatArray | None = None
    actuator_displacements: FloatArray | None = None
    actuator_secant_stiffness: FloatArray | None = None
    twist: FloatArray | None = None
    moving: MovingLoadedState | None = None
    load_margin: LoadMargin | None = None
    first_frequency: float | None = None
    first_mode_direction: str | None = None
    first_mode_platform_share: float | None = None
    planar: bool = True

    def to_dict(self) -> dict[str, Any]:
        """Plain data (lists, floats, strings): the dict ``analyze`` returned in 0.2,
        key for key and in its order, that ``analyze --json`` prints (after its
        envelope, :func:`json_document`)."""
        out: dict[str, Any] = {
            "pose": pose_dict(self.pose),
            "task_coordinates": list(self.task_coordinates),
            "architecture": self.architecture,
            "tool_point": self.tool_point.tolist(),
            "actuator_units": [list(u) for u in self.actuator_units],
        }
        if self.geometry is not None:
            out["geometry"] = self.geometry
            for name in (
                "wrench",
                "actuator_forces",
                "actuator_displacements",
                "actuator_secant_stiffness",
                "twist",
            ):
                out[name] = np.asarray(getattr(self, name)).tolist()
        out["actuator_stiffness"] = self.actuator_stiffness.tolist()
        out.update(self.matrix_dict())
        if self.moving is not None and self.load_margin is not None:
            out["moving_geometry"] = moving_geometry_dict(self.moving, self.load_margin)
        if self.first_frequency is not None:
            out["first_frequency"] = self.first_frequency
            out["first_mode_direction"] = self.first_mode_direction
            if self.first_mode_platform_share is not None:
                out["first_mode_platform_share"] = self.first_mode_platform_share
        out.update(leading_keys(self.planar, self.method))
        return lead(out)

    def to_json(self) -> str:
        """The text ``ppm-stiffness analyze --json`` prints for this analysis."""
        return json_document("analyze", self.to_dict(), ANALYSIS_UNITS)


def analyze_design(
    design: Design,
    pose: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
    method: Method | None = None,
    tool_point: ArrayLike | None = None,
    geometry: str = "frozen",
) -> Analysis:
    """Full analysis at a pose, unloaded or under ``wrench``, at the tool point.

    Parameters
    ----------
    design : Design
    pose : array_like (n_task,) or (6,), optional
        The design's task coordinates (``design.task_coordinates``: (x [m], y [m],
        phi [rad]) for a planar design) or a full pose (x, y, z [m], rx, ry, rz [rad])
        of P in F_b (:mod:`ppm_stiffness.poses`); the home pose if None.
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] applied at the tool point, axes of F_b.
    method : {"paper", "least-squares"}, optional
        The decoupling shown first (``method``); both are computed. None: the paper's
        eq. (19) for a planar design, the least-squares shift for a spatial one
        (:func:`ppm_stiffness.leading.default_method`).
    tool_point : array_like (3,), optional
        In the platform frame [m]; ``design.tool_point`` if None ((0, 0, 0) is P).
    geometry : {"frozen", "moving"}
        Under a wrench: the paper's model (the geometry of the unloaded pose), or the
        equilibrium with moving geometry (:mod:`ppm_stiffness.statics.moving`), whose
        loaded tangent K_F (at the displaced tool point) is then analysed (its
        symmetric part) and kept in ``moving`` with its ``load_margin``.

    Returns
    -------
    Analysis
        Typed fields (:class:`Analysis`); ``to_dict()`` gives the dict of 0.2 and of
        ``analyze --json``: ``pose`` {x, y, z, rx, ry, rz, phi}, ``task_coordinates``,
        ``architecture``, ``tool_point``, ``actuator_units``, ``actuator_stiffness``,
        ``stiffness_matrix`` (at the tool point, axes of F_b), ``eigenscrews``,
        ``decoupling``, ``principal`` (+ ``*_least_squares``),
        ``principal_compliance``; with a wrench also ``geometry``, ``wrench``,
        ``actuator_forces``, ``actuator_displacements``, ``actuator_secant_stiffness``
        and ``twist``, and ``moving_geometry`` with ``geometry="moving"`` (see
        :func:`moving_geometry_dict`); with a mass model (``design.platform``) also
        ``first_frequency`` [Hz] and ``first_mode_direction``
        (:mod:`ppm_stiffness.dynamics`; under a wrench, of the loaded tangent K).

    Raises
    ------
    InputDataError, UnreachablePoseError, SingularConfigurationError, EquilibriumError
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
    head: dict[str, Any] = {
        "pose": p,
        "task_coordinates": tuple(design.task_coordinates),
        "architecture": design.architecture,
        "tool_point": tool,
        "actuator_units": [tuple(leg.actuator_units()) for leg in design.legs],
        "planar": design.planar,
    }
    if method is None:
        method = default_method(design.planar)
    if wrench is None:
        k_act = actuator_stiffness_vector(design, None)
        k = stiffness_at_pose(design, p, k_act)
        loaded: dict[str, Any] = {}
    elif geometry == "moving":
        return _analyze_moving(design, p, validate_wrench(wrench), method, tool, head)
    else:
        w_tool = validate_wrench(wrench)
        w_p = wrench_b_from_wrench_a(np.eye(3), offset) @ w_tool  # moved from T to P
        state = loaded_state(design, w_p, p)
        k_act, k = state.actuator_stiffness, state.stiffness_matrix
        loaded = {
            "geometry": "frozen",
            "wrench": w_tool,
            "actuator_forces": state.actuator_forces,
            "actuator_displacements": state.actuator_displacements,
            "actuator_secant_stiffness": state.secant_stiffness,
            "twist": twist_b_from_twist_a(np.eye(3), -offset) @ state.twist,
        }
    k_tool = stiffness_at_tool_point(k, p, tool)
    matrix = analyze_matrix(k_tool, method)
    mode = first_mode(design, p, k_tool, k_act, tool)
    return Analysis(
        **_matrix_fields(matrix),
        **head,
        actuator_stiffness=np.asarray(k_act, dtype=float),
        **loaded,
        first_frequency=mode.get("first_frequency"),
        first_mode_direction=mode.get("first_mode_direction"),
        first_mode_platform_share=mode.get("first_mode_platform_share"),
    )


def _matrix_fields(matrix: MatrixAnalysis) -> dict[str, Any]:
    """The fields of a :class:`MatrixAnalysis`, for an :class:`Analysis`."""
    return {f.name: getattr(matrix, f.name) for f in fields(MatrixAnalysis)}


def _analyze_moving(
    design: Design,
    pose: FloatArray,
    wrench: FloatArray,
    method: Method,
    tool: FloatArray,
    head: dict[str, Any],
) -> Analysis:
    """:func:`analyze_design` with ``geometry="moving"``: the tables of the symmetric
    part of K_F, the state and its load margin."""
    from ppm_stiffness.statics.margin import load_margin
    from ppm_stiffness.statics.moving import moving_loaded_state

    state = moving_loaded_state(design, wrench, pose, tool)
    k_f = state.stiffness_matrix
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = np.where(
            state.actuator_displacements != 0,
            state.actuator_forces
            / np.where(state.actuator_displacements != 0, state.actuator_displacements, 1.0),
            [leg.locked_stiffness() for leg in design.legs],
        )
    return Analysis(
        **_matrix_fields(analyze_matrix(0.5 * (k_f + k_f.T), method)),
        **head,
        actuator_stiffness=state.actuator_stiffness,
        geometry="moving",
        wrench=wrench,
        actuator_forces=state.actuator_forces,
        actuator_displacements=state.actuator_displacements,
        actuator_secant_stiffness=secant,
        twist=state.twist,
        moving=state,
        load_margin=load_margin(design, state.wrench, state.pose, state.tool_point),
    )


def moving_geometry_dict(state: MovingLoadedState, margin: LoadMargin) -> dict[str, Any]:
    """What ``analyze --geometry moving`` adds, as plain data (SI): the displaced pose,
    K_F in full (at the displaced tool point, axes of F_b), the frozen model's K at the
    tool point, their difference, the geometric term, the relative sizes of both
    (length-balanced Frobenius norms), K_F's antisymmetric part and the load margin
    (:mod:`ppm_stiffness.statics.margin`) ``margin`` of this state."""
    from ppm_stiffness.statics.margin import MAX_FACTOR, MarginKind
    from ppm_stiffness.statics.moving import relative_difference, relative_size

    k_f, k0 = state.stiffness_matrix, state.frozen_stiffness
    kinds = {
        MarginKind.NONE: "none",
        MarginKind.BIFURCATION: "bifurcation",
        MarginKind.LIMIT_POINT: "limit point",
        MarginKind.STROKE: "stroke",
    }
    return {
        "displaced_pose": pose_dict(state.displaced_pose),
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
    """Numpy arrays and scalars to lists and floats, refusing NaN (a typed result, by
    its ``to_dict()``)."""
    if isinstance(obj, DeprecatedMapping):
        return to_jsonable(obj.to_dict())
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
    "first_mode_platform_share": "1",
    "hinge_stress.hinges.allowed_stress": "Pa (yield strength / safety_factor)",
    "hinge_stress.hinges.stress": "Pa (under the wrench, frozen)",
    "hinge_stress.hinges.stress_per_unit": "Pa per rad (per m) of the direction's unit",
    "hinge_stress.hinges.range": "rad or m (the direction's unit; both senses)",
    "hinge_stress.hinges.utilisation": "1 (stress / allowed_stress)",
    "hinge_stress.hinges.wrench_range": "1 (times the wrench)",
    "hinge_stress.directions.range": "rad or m (its unit; the smallest over the hinges)",
    "hinge_stress.directions.drive_inputs": "rad or m per unit of the direction",
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
