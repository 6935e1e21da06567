"""One modal analysis of a design at a pose, typed (:class:`ModalAnalysis`) and as
plain data (its ``to_dict()``: ``ppm-stiffness modes --json``), and the first natural
frequency that ``analyze`` adds.

K is the locked actuators' stiffness, or the loaded tangent one under a wrench
(:func:`ppm_stiffness.statics.loading.loaded_state`); M is built with the same
actuator stiffnesses (:mod:`ppm_stiffness.dynamics.mass`). Each leg's own lowest
modes with the platform held are added (``link_modes`` per leg, default
:data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`; 0: the static
condensation alone; :mod:`ppm_stiffness.dynamics.legmodes`). Both are expressed at the
tool point (P unless the design or the caller sets one): the frequencies do not depend
on it, the mode shapes are the tool point's twists. SI: Hz, kg, kg·m^2, rad, m.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, wrench_b_from_wrench_a
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.pose import POSE_COORDINATES
from ppm_stiffness.core.results import DeprecatedMapping
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.mass import mass_matrix_at_pose, moving_mass, require_mass_model
from ppm_stiffness.dynamics.modes import Modes, mode_shapes, reduced_mode_shapes
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
    validate_pose,
)

#: SI units of the values of :func:`modal_analysis` (keys, or ``a.b`` paths).
MODES_UNITS = {
    "pose": "x, y, z [m], rx, ry, rz [rad] (phi = rz)",
    "tool_point": "m (platform frame)",
    "actuator_stiffness": "N/m (N·m/rad for a rotary actuator)",
    "wrench": "N·m, N (m_x, m_y, m_z, f_x, f_y, f_z), at the tool point",
    "stiffness_matrix": "K_rr N·m/rad, K_rt N, K_tt N/m (order phi_x, phi_y, phi_z, x, y, z)",
    "mass_matrix": "M_rr kg·m^2, M_rt kg·m, M_tt kg (order phi_x, phi_y, phi_z, x, y, z)",
    "masses": "kg",
    "frequencies": "Hz",
    "modes.frequency": "Hz",
    "modes.shape": "rad, m (phi_x, phi_y, phi_z, x, y, z) of the tool point, unit "
    "length-balanced norm (rotations times 0.1 m)",
    "modes.share": "1 (share of the balanced norm squared)",
    "modes.platform_share": "1 (the platform body's share of the mode's kinetic energy)",
    "link_modes": "fixed-interface modes per leg (Craig-Bampton; 0: static condensation)",
}


def modes_dict(modes: Modes) -> dict[str, Any]:
    """The frequencies and mode shapes as plain data (with the legs' own modes, each
    mode's ``platform_share``)."""
    listed: list[dict[str, Any]] = []
    for j in range(6):
        mode: dict[str, Any] = {
            "frequency": float(modes.frequencies[j]),
            "shape": modes.shapes[j].tolist(),
            "direction": modes.directions[j],
            "share": float(modes.shares[j]),
        }
        if modes.platform_shares is not None:
            mode["platform_share"] = float(modes.platform_shares[j])
        listed.append(mode)
    return {
        "frequencies": modes.frequencies.tolist(),
        "modes": listed,
        "modes_repeated": [list(g) for g in modes.repeated],
    }


def machine_modes(
    design: Design,
    pose: FloatArray,
    tool_pair: tuple[FloatArray, FloatArray],
    p_pair: tuple[FloatArray, FloatArray],
    actuator_stiffness: ArrayLike,
    tool_point: ArrayLike,
    link_modes: int,
) -> Modes:
    """The machine's six lowest modes: condensed (``link_modes`` 0: :func:`mode_shapes`
    of K and M at the tool point ``tool_pair``, as before issue 30), or with each leg's
    ``link_modes`` fixed-interface modes (:mod:`ppm_stiffness.dynamics.legmodes`),
    solved with K and M at P (``p_pair``: the frequencies do not depend on the tool
    point) and the twists moved to the tool point."""
    from ppm_stiffness.core.conventions import twist_b_from_twist_a
    from ppm_stiffness.dynamics.legmodes import (
        design_leg_modes,
        reduced_matrices,
        stack_leg_modes,
    )
    from ppm_stiffness.dynamics.mass import platform_mass_matrix

    if link_modes == 0:
        return mode_shapes(*tool_pair)
    legs = design_leg_modes(design, pose, actuator_stiffness, link_modes)
    kr, mr = reduced_matrices(*p_pair, *stack_leg_modes(legs))
    to_tool = twist_b_from_twist_a(np.eye(3), -tool_offset(pose, tool_point))
    return reduced_mode_shapes(kr[0], mr[0], platform_mass_matrix(design, pose), to_tool)


def _state(
    design: Design, p: FloatArray, wrench: ArrayLike | None, offset: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray | None]:
    """K at P and the actuator stiffnesses, locked or loaded (the wrench acts at the
    tool point, ``offset`` from P), and the wrench at the tool point (None locked)."""
    if wrench is None:
        k_act = actuator_stiffness_vector(design, None)
        return stiffness_at_pose(design, p, k_act), k_act, None
    from ppm_stiffness.statics.loading import loaded_state, validate_wrench

    w_tool = validate_wrench(wrench)
    w_p = wrench_b_from_wrench_a(np.eye(3), offset) @ w_tool
    state = loaded_state(design, w_p, p)
    return state.stiffness_matrix, state.actuator_stiffness, w_tool


@dataclass(frozen=True, eq=False)
class ModalAnalysis(DeprecatedMapping):
    """One modal analysis at a pose (:func:`modal_analysis`; SI, axes of F_b, at the
    tool point).

    Attributes
    ----------
    pose : ndarray (6,)
        The full pose (x, y, z [m], rx, ry, rz [rad]) of P in F_b.
    task_coordinates : tuple of str
    architecture : str
    tool_point : ndarray (3,)
        [m, platform frame].
    state : {"locked", "loaded"}
    actuator_stiffness : ndarray (n_legs,)
        [N/m or N·m/rad]: locked, or the tangent ones under the wrench.
    wrench : ndarray (6,) or None
        [N·m, N] at the tool point, axes of F_b (loaded).
    stiffness_matrix, mass_matrix : ndarray (6, 6)
        K [N·m/rad, N, N/m] and M [kg·m^2, kg·m, kg] at the tool point.
    masses : dict of str to float
        ``platform``, ``links``, ``carriages`` and ``total`` [kg].
    modes : Modes
        Frequencies [Hz, ascending], shapes, directions and shares.
    """

    pose: FloatArray
    task_coordinates: tuple[str, ...]
    architecture: str
    tool_point: FloatArray
    state: str
    actuator_stiffness: FloatArray
    wrench: FloatArray | None
    stiffness_matrix: FloatArray
    mass_matrix: FloatArray
    masses: dict[str, float]
    modes: Modes
    link_modes: int = 0

    @property
    def frequencies(self) -> FloatArray:
        """The natural frequencies (6,) [Hz], ascending."""
        return self.modes.frequencies

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the dict ``modal_analysis`` returned in 0.2, key for key and in
        its order, that ``modes --json`` prints (after its envelope)."""
        out: dict[str, Any] = {
            "pose": {
                **{name: float(v) for name, v in zip(POSE_COORDINATES, self.pose, strict=True)},
                "phi": float(self.pose[5]),
            },
            "task_coordinates": list(self.task_coordinates),
            "architecture": self.architecture,
            "tool_point": self.tool_point.tolist(),
            "state": self.state,
            "actuator_stiffness": self.actuator_stiffness.tolist(),
        }
        if self.wrench is not None:
            out["wrench"] = self.wrench.tolist()
        out["stiffness_matrix"] = self.stiffness_matrix.tolist()
        out["mass_matrix"] = self.mass_matrix.tolist()
        out["masses"] = dict(self.masses)
        out.update(modes_dict(self.modes))
        if self.link_modes:
            out["link_modes"] = self.link_modes
        return out

    def to_json(self) -> str:
        """The text ``ppm-stiffness modes --json`` prints for this analysis."""
        from ppm_stiffness.analysis import json_document

        return json_document("modes", self.to_dict(), MODES_UNITS)


def modal_analysis(
    design: Design,
    pose: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
    tool_point: ArrayLike | None = None,
    link_modes: int | None = None,
) -> ModalAnalysis:
    """Natural frequencies and mode shapes at a pose, locked or under a wrench.

    Parameters
    ----------
    design : Design
        With a mass model.
    pose : array_like (n_task,) or (6,), optional
        Task coordinates or a full pose [m, rad]; the home pose if None.
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the tool point, axes of F_b: the
        loaded tangent K and the tangent actuator stiffnesses are used.
    tool_point : array_like (3,), optional
        [m, platform frame]; ``design.tool_point`` if None.
    link_modes : int, optional
        Each leg's own modes with the platform held (Craig-Bampton,
        :mod:`ppm_stiffness.dynamics.legmodes`); 0: the static condensation alone;
        None: :data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`.

    Returns
    -------
    ModalAnalysis
        Typed fields; ``to_dict()`` gives the dict of 0.2 and of ``modes --json``:
        ``pose``, ``task_coordinates``, ``architecture``, ``tool_point``, ``state``
        ("locked" or "loaded"), ``actuator_stiffness``, (``wrench``),
        ``stiffness_matrix`` and ``mass_matrix`` at the tool point, ``masses``
        (platform, links, carriages, total [kg]), ``frequencies`` [Hz, ascending],
        ``modes`` (frequency, shape, direction, share each) and ``modes_repeated``.

    Raises
    ------
    DesignError
        No mass model.
    InputDataError, UnreachablePoseError, SingularConfigurationError, EquilibriumError
    """
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    require_mass_model(design)
    count = resolve_link_modes(link_modes)
    p = validate_pose(design, pose)
    tool = np.asarray(design.tool_point if tool_point is None else tool_point, dtype=float)
    if tool.shape != (3,) or not np.all(np.isfinite(tool)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    offset = tool_offset(p, tool)
    k_p, k_act, w_tool = _state(design, p, wrench, offset)
    m_p = mass_matrix_at_pose(design, p, k_act)
    k_t = stiffness_at_tool_point(k_p, p, tool)
    m_t = stiffness_at_tool_point(m_p, p, tool)  # M transforms as K
    return ModalAnalysis(
        pose=p,
        task_coordinates=tuple(design.task_coordinates),
        architecture=design.architecture,
        tool_point=tool,
        state="locked" if w_tool is None else "loaded",
        actuator_stiffness=np.asarray(k_act, dtype=float),
        wrench=w_tool,
        stiffness_matrix=k_t,
        mass_matrix=m_t,
        masses=moving_mass(design),
        modes=machine_modes(design, p, (k_t, m_t), (k_p, m_p), k_act, tool, count),
        link_modes=count,
    )


def first_mode(
    design: Design,
    pose: ArrayLike,
    stiffness_tool: ArrayLike,
    actuator_stiffness: ArrayLike,
    tool_point: ArrayLike,
    link_modes: int | None = None,
) -> dict[str, Any]:
    """``first_frequency`` [Hz] and ``first_mode_direction`` for ``analyze``, or {} when
    the design has no mass model (with the legs' own modes: ``link_modes`` as
    :func:`modal_analysis`; then also ``first_mode_platform_share``, the platform
    body's share of the mode's kinetic energy).

    Parameters
    ----------
    pose : array_like (6,)
        A full pose, checked already.
    stiffness_tool : array_like (6, 6)
        K at the tool point (locked or loaded).
    actuator_stiffness : array_like (n_legs,)
        The actuator stiffnesses K was built with (the mass matrix uses them too).
    tool_point : array_like (3,) [m, platform frame]
    """
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    if not design.has_mass_model:
        return {}
    count = resolve_link_modes(link_modes)
    p = np.asarray(pose, dtype=float)
    k_t = np.asarray(stiffness_tool, dtype=float)
    m_p = mass_matrix_at_pose(design, p, actuator_stiffness)
    m_t = stiffness_at_tool_point(m_p, p, tool_point)
    from ppm_stiffness.core.conventions import twist_b_from_twist_a

    to_tool = twist_b_from_twist_a(np.eye(3), -tool_offset(p, tool_point))
    k_p = to_tool.T @ k_t @ to_tool  # K_tool = T^-T K_P T^-1
    pairs = (k_t, m_t), (k_p, m_p)
    modes = machine_modes(design, p, *pairs, actuator_stiffness, tool_point, count)
    out: dict[str, Any] = {
        "first_frequency": float(modes.frequencies[0]),
        "first_mode_direction": modes.directions[0],
    }
    if modes.platform_shares is not None:
        out["first_mode_platform_share"] = float(modes.platform_shares[0])
    return out
