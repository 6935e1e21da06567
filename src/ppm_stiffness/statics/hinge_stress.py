"""Notch hinges' stress and range of motion (issue 29 item 3; ``docs/flexures.md``,
"Stress and range of motion").

The model is the frozen, linear one of the stiffness: every leg is a serial chain of
massless bodies, so the wrench a leg carries is the same through all its joints. Under a
platform wrench W [N·m, N at P, F_b] and drive inputs dq (one per actuated leg), the
platform moves by the twist ``t = K^-1 (W + sum_i K_i j_i dq'_i)`` and leg i carries
``w_i = K_i (t - j_i dq'_i)`` (``sum_i w_i = W``), with K_i the leg's stiffness, j_i its
actuated joint's unit twist at P and dq'_i the offset of its actuator spring.

The drive input dq is the drive's free displacement (a piezo stack's unloaded stroke,
through its lever: an angle of the actuated joint [rad] for an R, a length [m] for a P):
for a rigid drive, the joint's displacement. A drive in parallel with a notch hinge
(stiffnesses k_a and k_h, one spring k = k_a + k_h in the leg, ``legs/chain.py``) turns
its joint by theta with ``k theta = M + k_a dq`` (M the moment of w_i about the joint's
axis): its spring's offset is ``dq' = (k_a / k) dq`` and the hinge itself carries only
``k_h theta`` of M, the drive the rest.

A hinge's loads are w_i moved to its centre c (``m_c = m_P - c x f``, c from P) in hinge
axes (x along the notch, z its rotation axis, y = z x x); along the notch the section at
x carries ``m_z(x) = m_z + (x_c - x) f_y``, ``m_y(x) = m_y - (x_c - x) f_z`` and the
axial force ``N = f_x``. Its peak normal stress is the largest over the notch's stations
of (Euler-Bernoulli, the section's corner where the three add)::

    sigma(x) = |N| / (b h) + K_t 6 |m_z(x)| / (b h^2) + 6 |m_y(x)| / (h b^2)

with h(x) the profile. K_t, the notch's stress concentration factor in in-plane bending
(:func:`stress_concentration`), multiplies the in-plane bending term only: axial and
out-of-plane bending are nominal, and the shear stresses of torsion (m_x) and of the
shear forces are left out (a flexure stage loads its hinges in in-plane bending; the
issue's model). Under a pure moment M about z the peak is ``K_t 6 M / (b t^2)`` at the
waist (``tests/test_hinge_stress.py``).

Range of motion. The stresses are sums of absolute values of linear functions of the
input, so sigma(s u) = |s| sigma(u): along an input direction u the first hinge reaches
``yield_strength / safety_factor`` at ``s = (yield / SF) / max_h sigma_h(u)``, the same
in both senses.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.core.solver import leg_stiffness
from ppm_stiffness.legs.chain import Joint, leg_springs, parallel_stiffness
from ppm_stiffness.legs.flexure_hinge import FlexureHinge

if TYPE_CHECKING:
    from ppm_stiffness.design import Design

#: Stations per profile segment where the stress is evaluated (the waist and the
#: segments' ends among them; sigma is smooth between them).
STATIONS = 257


def stress_concentration(hinge: FlexureHinge) -> float:
    """The notch's stress concentration factor K_t in in-plane bending.

    A given ``hinge.stress_concentration``, else: a right-circular notch (radius R,
    waist t), ``K_t = (1 + t / (2 R))^(9/20)``, the fit of Peterson's chart for a flat
    bar with opposite U-notches in bending (Pilkey W D, *Peterson's Stress Concentration
    Factors*, 2nd ed., Wiley 1997) given by Lobontiu N, *Compliant Mechanisms: Design of
    Flexure Hinges*, CRC Press 2003 (circular notch hinges); a plain leaf: 1.

    Raises
    ------
    DesignError
        Another profile without a given ``stress_concentration``.
    """
    if hinge.stress_concentration is not None:
        return float(hinge.stress_concentration)
    profile = hinge.profile
    if profile.profile == "circular":
        return float((1.0 + profile.thickness / (2.0 * profile.radius)) ** 0.45)
    if profile.profile == "leaf":
        return 1.0
    raise DesignError(
        f"hinge: no stress concentration factor is built in for a {profile.profile} "
        "profile; give stress_concentration (K_t in in-plane bending, >= 1)"
    )


def yield_strength(hinge: FlexureHinge) -> float:
    """The hinge material's yield strength [Pa], or raise DesignError naming it."""
    value = hinge.material.yield_strength
    if value is None:
        raise DesignError("hinge: its material has no yield_strength (needed for its range)")
    return float(value)


def stations(hinge: FlexureHinge) -> tuple[FloatArray, FloatArray]:
    """Stations x [m] along the notch (from its base-side end) and the thickness h [m]
    there: STATIONS per profile segment, its ends included."""
    xs, hs = [], []
    for u0, u1, shape in hinge.profile.segments():
        x, h, _ = shape(np.linspace(u0, u1, STATIONS))
        xs.append(x)
        hs.append(h)
    return np.concatenate(xs), np.concatenate(hs)


def peak_stress(hinge: FlexureHinge, loads: ArrayLike) -> FloatArray:
    """Peak normal stress [Pa] of a notch under loads at its centre (module doc).

    Parameters
    ----------
    hinge : FlexureHinge
    loads : array_like, shape (..., 6)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the notch's centre, hinge axes: the
        wrench the platform side applies to the base side.

    Returns
    -------
    ndarray, shape (...)
        max over the stations of sigma(x) [Pa], non-negative.
    """
    w = np.asarray(loads, dtype=float)
    x, h = stations(hinge)
    arm = hinge.length / 2.0 - x  # x_c - x
    b, k_t = hinge.width, stress_concentration(hinge)
    m_z = w[..., 2:3] + arm * w[..., 4:5]
    m_y = w[..., 1:2] - arm * w[..., 5:6]
    sigma = (
        np.abs(w[..., 3:4]) / (b * h)
        + k_t * 6.0 * np.abs(m_z) / (b * h**2)
        + 6.0 * np.abs(m_y) / (h * b**2)
    )
    return np.asarray(np.max(sigma, axis=-1))


@dataclass(frozen=True)
class HingeRecord:
    """One notch hinge of a design at a pose.

    Attributes
    ----------
    leg : int
        Its leg's index.
    name : str
        The joint's name in its leg.
    hinge : FlexureHinge
    centre : ndarray, shape (3,)
        Its centre from P [m], F_b.
    axes : ndarray, shape (3, 3)
        Columns: hinge x (along the notch), y, z (rotation axis) in F_b.
    share : float
        The part of the moment about its axis that the hinge carries under a platform
        wrench: k_h / (k_h + k_a) at a drive in parallel, else 1.
    drive : float
        Its moment per unit drive input from the drive's offset, k_h k_a / k [N·m/rad]
        at a drive in parallel (module doc), else 0.
    parallel : float
        k_h [N·m/rad] at a drive in parallel (the hinge's moment about its axis is
        ``k_h theta``, theta the joint's rotation), else 0.
    """

    leg: int
    name: str
    hinge: FlexureHinge
    centre: FloatArray
    axes: FloatArray
    share: float
    drive: float
    parallel: float = 0.0


@dataclass(frozen=True)
class HingeModel:
    """The frozen linear model of a design's hinges at one pose (module doc).

    Attributes
    ----------
    leg_stiffness : ndarray, shape (n_legs, 6, 6)
    actuator_twists : ndarray, shape (n_legs, 6)
        j_i, the actuated joint's unit twist at P (zeros for a passive leg).
    offsets : ndarray, shape (n_legs,)
        dq'_i / dq_i: k_a / k of the actuator spring (1 without a hinge in parallel).
    hinges : list of HingeRecord
    """

    leg_stiffness: FloatArray
    actuator_twists: FloatArray
    offsets: FloatArray
    hinges: list[HingeRecord]

    @property
    def stiffness(self) -> FloatArray:
        """K at P (6, 6), the sum over legs."""
        return np.asarray(np.sum(self.leg_stiffness, axis=0))

    def inputs_to_twist(self) -> FloatArray:
        """Platform twist per unit drive input of each leg, shape (6, n_legs), W = 0."""
        forcing = np.einsum("lij,lj->il", self.leg_stiffness, self.actuator_twists) * self.offsets
        return np.asarray(np.linalg.solve(self.stiffness, forcing))

    def leg_wrenches(self, wrench: ArrayLike, inputs: ArrayLike) -> FloatArray:
        """Wrench w_i [N·m, N] each leg carries at P, shape (..., n_legs, 6), under the
        platform wrench (..., 6) and drive inputs (..., n_legs) (module doc)."""
        w = np.asarray(wrench, dtype=float)
        dq = np.asarray(inputs, dtype=float) * self.offsets
        forcing = w + np.einsum("lij,lj,...l->...i", self.leg_stiffness, self.actuator_twists, dq)
        t = np.linalg.solve(self.stiffness, forcing[..., None])[..., 0]
        rel = t[..., None, :] - dq[..., :, None] * self.actuator_twists
        return np.asarray(np.einsum("lij,...lj->...li", self.leg_stiffness, rel))

    def hinge_loads(self, wrench: ArrayLike, inputs: ArrayLike) -> FloatArray:
        """Loads (m; f) at each hinge's centre in its axes, shape (..., n_hinges, 6)."""
        legs = self.leg_wrenches(wrench, inputs)
        dq = np.asarray(inputs, dtype=float)
        out = []
        for h in self.hinges:
            w = legs[..., h.leg, :]
            m_c = w[..., :3] - np.cross(h.centre, w[..., 3:])
            m_local, f_local = m_c @ h.axes, w[..., 3:] @ h.axes
            m_local[..., 2] = h.share * m_local[..., 2] + h.drive * dq[..., h.leg]
            out.append(np.concatenate([m_local, f_local], axis=-1))
        return np.stack(out, axis=-2)

    def stresses(self, wrench: ArrayLike, inputs: ArrayLike) -> FloatArray:
        """Peak stress [Pa] of each hinge, shape (..., n_hinges)."""
        loads = self.hinge_loads(wrench, inputs)
        return np.stack(
            [peak_stress(h.hinge, loads[..., i, :]) for i, h in enumerate(self.hinges)], axis=-1
        )

    def carried_stresses(self, leg_wrenches: ArrayLike, rotations: ArrayLike) -> FloatArray:
        """Peak stress [Pa] of each hinge, shape (..., n_hinges), from the wrenches the
        legs carry (..., n_legs, 6) [N·m, N at P, F_b] and their actuated joints'
        displacements (..., n_legs) [rad or m] (a loaded state, the actuator law in
        the loop): a hinge in parallel with a drive bends by its joint's rotation
        theta, ``m_z = k_h theta``, the drive carrying the rest of the joint's moment."""
        legs = np.asarray(leg_wrenches, dtype=float)
        theta = np.asarray(rotations, dtype=float)
        out = []
        for h in self.hinges:
            w = legs[..., h.leg, :]
            m_c = w[..., :3] - np.cross(h.centre, w[..., 3:])
            m_local, f_local = m_c @ h.axes, w[..., 3:] @ h.axes
            if h.parallel > 0.0:
                m_local[..., 2] = h.parallel * theta[..., h.leg]
            out.append(peak_stress(h.hinge, np.concatenate([m_local, f_local], axis=-1)))
        return np.stack(out, axis=-1)

    def limits(self, safety_factor: float) -> FloatArray:
        """Allowed stress yield / SF [Pa] of each hinge, shape (n_hinges,)."""
        return np.array([yield_strength(h.hinge) / safety_factor for h in self.hinges])


def _hinge_records(leg: Any, index: int, chain: list[Any], k_total: float) -> list[HingeRecord]:
    """The notch hinges of one chain leg at its pose; ``k_total`` its actuator spring's
    stiffness (the drive and a hinge in parallel with it)."""
    elements = getattr(leg, "elements", None)
    if elements is None:
        return []
    joints = {e.name: e for e in chain if isinstance(e, Joint)}
    out = []
    for i, element in enumerate(elements):
        hinge = getattr(element, "hinge", None)
        if hinge is None:
            continue
        name = leg.element_name(i)
        joint = joints[name]
        z = np.asarray(joint.axis, dtype=float).reshape(3)
        x = np.asarray(joint.axis2, dtype=float).reshape(3)
        x = x - (x @ z) * z
        x = x / np.linalg.norm(x)
        share, drive, k_h = 1.0, 0.0, 0.0
        if joint.actuated:
            k_h = parallel_stiffness(chain)
            share, drive = k_h / k_total, k_h * (k_total - k_h) / k_total
        centre = np.asarray(joint.point, dtype=float).reshape(3)
        axes = np.stack([x, np.cross(z, x), z], axis=1)
        out.append(HingeRecord(index, name, hinge, centre, axes, share, drive, k_h))
    return out


def hinge_model(design: Design, pose: ArrayLike | None = None) -> HingeModel:
    """The frozen linear model of the design's notch hinges at a pose (module doc).

    Parameters
    ----------
    design : Design
    pose : array_like or None
        Task coordinates or a full pose [m, rad]; None: home.

    Raises
    ------
    DesignError
        The design has no notch hinge.
    UnreachablePoseError, SingularConfigurationError
        As the stiffness at that pose.
    """
    from ppm_stiffness.model import actuator_stiffness_vector, full_pose, solve_legs

    p = full_pose(design, pose)
    k_act = actuator_stiffness_vector(design, None)
    stiff, twists, offsets, hinges = [], [], [], []
    for i, (leg, lp) in enumerate(zip(design.legs, solve_legs(design, p), strict=True)):
        chain = list(leg.chain(lp))
        springs = leg_springs(chain, k_act[i])
        stiff.append(leg_stiffness(springs))
        a, k_total = springs.actuator_index, np.inf
        twist, offset = np.zeros(6), 0.0
        if a is not None:
            twist = np.asarray(springs.screws[..., :, a], dtype=float).reshape(6)
            k_total = 1.0 / float(np.reshape(springs.compliance[..., a, a], -1)[0])
            offset = (k_total - parallel_stiffness(chain)) / k_total
        twists.append(twist)
        offsets.append(offset)
        hinges += _hinge_records(leg, i, chain, k_total)
    if not hinges:
        raise DesignError("the design has no notch hinge (a joint's hinge table)")
    model = HingeModel(np.array(stiff), np.array(twists), np.array(offsets), hinges)
    if not np.all(np.isfinite(model.stiffness)) or np.linalg.cond(model.stiffness) > 1e15:
        raise SingularConfigurationError("the stiffness is singular: no hinge loads")
    return model


def has_hinges(design: Design) -> bool:
    """Whether a joint of the design is a notch hinge."""
    return any(
        getattr(e, "hinge", None) is not None
        for leg in design.legs
        for e in getattr(leg, "elements", [])
    )


def has_yield_strengths(design: Design) -> bool:
    """Whether every notch hinge of the design has its material's yield strength."""
    return all(
        e.hinge.material.yield_strength is not None
        for leg in design.legs
        for e in getattr(leg, "elements", [])
        if getattr(e, "hinge", None) is not None
    )


#: Twist component of each pose coordinate (order (phi; v), ``core/conventions.py``).
TWIST_INDEX = {"x": 3, "y": 4, "z": 5, "rx": 0, "ry": 1, "rz": 2}


def input_directions(design: Design, model: HingeModel) -> list[dict[str, Any]]:
    """The input directions of the range of motion (``docs/flexures.md``): each drive
    alone (its free displacement, W = 0), then, when the drives are as many as the task
    coordinates, the platform's displacement along each task coordinate made by the
    drives (the other task coordinates held at 0; the twist component, rad or m).

    Returns
    -------
    list of dict
        ``name``, ``unit`` and ``inputs`` (n_legs,) [rad or m per unit of the direction].
    """
    driven = [i for i in range(len(design.legs)) if model.offsets[i] > 0.0]
    out: list[dict[str, Any]] = []
    for i in driven:
        unit = design.legs[i].actuator_units()[1]  # rad or m
        inputs = np.zeros(len(design.legs))
        inputs[i] = 1.0
        out.append({"name": f"drive {i + 1}", "unit": unit, "inputs": inputs})
    task = list(design.task_coordinates)
    if driven and len(driven) == len(task):
        g = model.inputs_to_twist()[[TWIST_INDEX[c] for c in task]][:, driven]
        if np.linalg.cond(g) < 1e12:
            per = np.linalg.solve(g, np.eye(len(task)))
            for k, name in enumerate(task):
                inputs = np.zeros(len(design.legs))
                inputs[driven] = per[:, k]
                unit = "rad" if name.startswith("r") else "m"
                out.append({"name": f"platform {name}", "unit": unit, "inputs": inputs})
    return out


def hinge_summary(
    design: Design,
    pose: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
    safety_factor: float = 1.0,
) -> dict[str, Any]:
    """Each hinge's stress and the range of motion along each input direction.

    Parameters
    ----------
    design : Design
        With notch hinges (:func:`has_hinges`).
    pose : array_like or None
        Task coordinates or a full pose; None: home.
    wrench : array_like, shape (6,), optional
        (m; f) [N·m, N] at P, axes of F_b: each hinge's stress under it, its utilisation
        (stress / allowed) and the range as a multiple of the wrench.
    safety_factor : float
        Allowed stress = yield strength / safety_factor (> 0).

    Returns
    -------
    dict
        ``safety_factor``; ``directions`` (name, unit, the stage's range and the
        hinge that limits it); ``hinges``: leg (1-based), name, allowed_stress [Pa],
        stress_per_unit and range per direction, and under a wrench ``stress`` [Pa],
        ``utilisation`` and ``wrench_range`` (multiple of the wrench).
    """
    if not (np.isfinite(safety_factor) and safety_factor > 0.0):
        raise DesignError(f"safety factor {safety_factor!r}: must be positive and finite")
    model = hinge_model(design, pose)
    limits = model.limits(safety_factor)
    directions = input_directions(design, model)
    zero = np.zeros(6)
    per_unit = [model.stresses(zero, d["inputs"]) for d in directions]
    hinges: list[dict[str, Any]] = []
    for j, h in enumerate(model.hinges):
        pairs = list(zip(directions, per_unit, strict=True))
        row: dict[str, Any] = {
            "leg": h.leg + 1,
            "name": h.name,
            "allowed_stress": float(limits[j]),
            "stress_per_unit": {d["name"]: float(s[j]) for d, s in pairs},
            "range": {d["name"]: _ratio(limits[j], s[j]) for d, s in pairs},
        }
        hinges.append(row)
    out_dirs = []
    for d, s in zip(directions, per_unit, strict=True):
        ranges = [_ratio(lim, v) for lim, v in zip(limits, s, strict=True)]
        j = int(np.argmin(ranges))
        out_dirs.append(
            {
                "name": d["name"],
                "unit": d["unit"],
                "range": ranges[j],
                "limiting_hinge": f"leg{model.hinges[j].leg + 1}.{model.hinges[j].name}",
                "drive_inputs": [float(v) for v in d["inputs"]],
            }
        )
    result: dict[str, Any] = {
        "safety_factor": float(safety_factor),
        "directions": out_dirs,
        "hinges": hinges,
    }
    if wrench is not None:
        sigma = model.stresses(np.asarray(wrench, dtype=float), np.zeros(len(design.legs)))
        for j, row in enumerate(hinges):
            row["stress"] = float(sigma[j])
            row["utilisation"] = float(sigma[j] / limits[j])
            row["wrench_range"] = _ratio(limits[j], sigma[j])
    return result


def _ratio(limit: float, stress: float) -> float:
    """limit / stress, inf where the hinge is unloaded."""
    return float(limit / stress) if stress > 0.0 else float("inf")


# -- per pose figures for maps and optimisation (docs/flexures.md, "Range over the
# -- workspace") ------------------------------------------------------------------------


def require_hinge_figures(design: Design) -> None:
    """Refuse a design whose hinge range or stroke stress is not defined.

    Raises
    ------
    DesignError
        No notch hinge, a hinge without its material's yield strength, no driven leg,
        or drives of both kinds (rotary and linear: the range has no single unit).
    """
    if not has_hinges(design):
        raise DesignError(
            f"design {design.name!r} has no notch hinge (a joint's hinge table): its "
            "hinge range and stress are not defined"
        )
    if not has_yield_strengths(design):
        raise DesignError(
            f"design {design.name!r}: a hinge's material has no yield_strength (needed "
            "for the hinge range and stress)"
        )
    kinds = {leg.actuated_kind() for leg in design.legs if leg.is_actuated()}
    if not kinds:
        raise DesignError(f"design {design.name!r} has no drive: no hinge range")
    if len(kinds) > 1:
        raise DesignError(
            f"design {design.name!r} has rotary and linear drives: the hinge range "
            "(the smallest drive range, rad or m) has no single unit"
        )


def drive_range(design: Design, pose: ArrayLike | None = None) -> float:
    """The smallest over the drives of each drive's range alone at a pose [rad for
    rotary drives, m for linear ones]: its free displacement (the other drives held,
    W = 0) at which the first hinge reaches its yield strength (safety factor 1), as
    the "drive i" rows of :func:`hinge_summary`; inf if no hinge is loaded."""
    return _drive_range(design, hinge_model(design, pose))


def _drive_range(design: Design, model: HingeModel) -> float:
    limits = model.limits(1.0)
    best = np.inf
    for d in input_directions(design, model):
        if d["name"].startswith("drive "):
            sigma = model.stresses(np.zeros(6), d["inputs"])
            best = min(best, min(_ratio(lim, s) for lim, s in zip(limits, sigma, strict=True)))
    return float(best)


def stroke_corners(design: Design) -> FloatArray:
    """The drive inputs [rad or m] at the corners of the drives' strokes, shape
    (2^n_driven, n_legs): each driven leg's actuated coordinate at either limit (as the
    design gives them, from the hinge's rest), 0 for a passive leg.

    Raises
    ------
    DesignError
        A driven leg without a finite stroke.
    """
    bounds: list[tuple[float, ...]] = []
    for i, leg in enumerate(design.legs):
        if not leg.is_actuated():
            bounds.append((0.0,))
            continue
        lo, hi = leg.limits().get(leg.ACTUATED_COORDINATE, (-np.inf, np.inf))
        if not (np.isfinite(lo) and np.isfinite(hi)):
            raise DesignError(
                f"leg {i + 1}: the hinge stress at full stroke needs the drive's stroke "
                "(finite limits of its actuated joint)"
            )
        bounds.append((float(lo), float(hi)))
    grids = np.meshgrid(*[np.array(b) for b in bounds], indexing="ij")
    return np.stack([g.reshape(-1) for g in grids], axis=-1)


def stroke_stress(design: Design, pose: ArrayLike | None = None) -> float:
    """The largest hinge stress [Pa] at a pose with the drives anywhere within their
    strokes (W = 0): the stress is convex in the inputs (module doc), so its maximum
    over the box of strokes is at one of :func:`stroke_corners`."""
    return _stroke_stress(hinge_model(design, pose), stroke_corners(design))


def _stroke_stress(model: HingeModel, corners: FloatArray) -> float:
    return float(np.max(model.stresses(np.zeros(6), corners)))


def pose_figures(
    design: Design, poses: ArrayLike, stress: bool = False
) -> tuple[FloatArray, FloatArray]:
    """:func:`drive_range` and, with ``stress``, :func:`stroke_stress` (else NaN) at
    each pose (n, 6 or the task coordinates), each shape (n,): a loop over the poses,
    the frozen hinge model built once per pose (about 0.1 s each for the shipped
    3-RRR stage, most of it the hinges' compliance quadrature). NaN where the pose is
    unreachable or singular."""
    from ppm_stiffness.core.errors import UnreachablePoseError

    p = np.asarray(poses, dtype=float)
    corners = stroke_corners(design) if stress else None
    ranges, stresses = np.full(p.shape[0], np.nan), np.full(p.shape[0], np.nan)
    for k in range(p.shape[0]):
        try:
            model = hinge_model(design, p[k])
        except (SingularConfigurationError, UnreachablePoseError):
            continue
        ranges[k] = _drive_range(design, model)
        if corners is not None:
            stresses[k] = _stroke_stress(model, corners)
    return ranges, stresses


def curve_stresses(design: Design, curve: Any, safety_factor: float = 1.0) -> dict[str, Any]:
    """The largest hinge stress at each load of a frozen-geometry deflection curve
    (:class:`~ppm_stiffness.statics.deflection.DeflectionCurve`, the actuator law in
    the loop) and its ratio to the allowed stress.

    Each leg carries ``w_i = K_i^S (t - a_i delta_i)`` (the equilibrium of
    :mod:`ppm_stiffness.statics.equilibrium`, t the platform twist at P, delta_i the
    actuated joint's displacement), through all its joints; each hinge's peak stress
    from it (:meth:`HingeModel.carried_stresses`). For a linear law this is
    :meth:`HingeModel.stresses` under the load (tested).

    Parameters
    ----------
    design : Design
        With notch hinges whose materials give their yield strengths.
    curve : DeflectionCurve
    safety_factor : float
        Allowed stress = yield strength / safety_factor (> 0).

    Returns
    -------
    dict
        ``safety_factor``; at each load the hinge nearest its allowed stress (the
        most stressed one when the hinges share a material): ``hinge`` (n,) its name
        (``leg<i>.<name>``; "" where no hinge is loaded), ``stress`` (n,) [Pa] its
        peak stress, ``utilisation`` (n,) its stress / (yield / SF).
    """
    from ppm_stiffness.core.conventions import twist_b_from_twist_a
    from ppm_stiffness.model import tool_offset
    from ppm_stiffness.statics.structures import LegStructures

    if not (np.isfinite(safety_factor) and safety_factor > 0.0):
        raise DesignError(f"safety factor {safety_factor!r}: must be positive and finite")
    model = hinge_model(design, curve.pose)
    offset = tool_offset(curve.pose, curve.tool_point)
    at_p = np.asarray(curve.twists) @ twist_b_from_twist_a(np.eye(3), offset).T
    terms = LegStructures(design, curve.pose).terms
    delta = np.asarray(curve.actuator_displacements, dtype=float)
    rel = at_p[:, None, :] - delta[..., None] * terms.actuator[0][None]
    legs = np.einsum("lij,klj->kli", terms.rigid[0], rel)
    sigma = model.carried_stresses(legs, delta)  # (n, n_hinges)
    return _most_utilised(model, sigma, safety_factor)


def _most_utilised(model: HingeModel, sigma: FloatArray, safety_factor: float) -> dict[str, Any]:
    """At each load (rows of ``sigma`` (n, n_hinges) [Pa]) the hinge nearest its
    allowed stress (:func:`curve_stresses`' return)."""
    ratio = sigma / model.limits(safety_factor)
    names = [f"leg{h.leg + 1}.{h.name}" for h in model.hinges]
    # the first hinge within round-off of the largest ratio (symmetric hinges tie)
    worst = np.argmax(ratio >= (1.0 - 1e-9) * np.max(ratio, axis=1, keepdims=True), axis=1)
    rows = np.arange(sigma.shape[0])
    return {
        "safety_factor": float(safety_factor),
        "stress": sigma[rows, worst],
        "hinge": [names[j] if sigma[k, j] > 0 else "" for k, j in enumerate(worst)],
        "utilisation": ratio[rows, worst],
    }


def _rotation_column(screws: FloatArray, hinge: HingeRecord, c0: FloatArray) -> int:
    """The column of a leg's screw chain (6, n) (twists about c0) that is the hinge's
    rotation: about its axis z, through its centre."""
    z, r = hinge.axes[:, 2], hinge.centre - c0
    for n in range(screws.shape[1]):
        w, v = screws[:3, n], screws[3:, n]
        if abs(float(w @ z)) > 1.0 - 1e-9 and np.allclose(v, np.cross(r, w), atol=1e-12):
            return n
    raise DesignError(f"hinge {hinge.name}: no rotation about its axis in its leg's chain")


def _prefix(screws: FloatArray, coordinates: FloatArray, upto: int) -> tuple[FloatArray, ...]:
    """(R, p): the displacement of the chain's body before column ``upto``, the product
    of exp(s_k x_k) for k < upto (:func:`ppm_stiffness.legs.screw_chain.forward`)."""
    from ppm_stiffness.legs.screw_chain import se3_exp

    g = np.eye(4)
    if upto:
        rots, poss = se3_exp((screws[:, :upto] * coordinates[:upto]).T[None])
        for r_k, p_k in zip(rots[0], poss[0], strict=True):
            step = np.eye(4)
            step[:3, :3], step[:3, 3] = r_k, p_k
            g = g @ step
    return g[:3, :3], g[:3, 3]


def moving_hinge_loads(design: Design, moving: Any) -> tuple[HingeModel, FloatArray]:
    """Each hinge's loads (m; f) at its displaced centre, in its displaced axes, at each
    load of a moving-geometry curve (:class:`~ppm_stiffness.statics.moving_deflection
    .MovingDeflection`): the leg's wrench of the moving equilibrium (about the displaced
    load point) moved to the hinge's centre carried by the chain's solved coordinates
    (the bodies before the hinge's rotation); a hinge in parallel with a drive carries
    ``k_h delta`` about its axis (delta its joint's displacement).

    Returns
    -------
    (HingeModel, ndarray (n, n_hinges, 6))
        The hinges at the unloaded pose and their loads [N·m, N].
    """
    from ppm_stiffness.model import tool_offset
    from ppm_stiffness.statics.moving_path import platform_chains

    curve = moving.moving
    if moving.leg_wrenches is None or moving.coordinates is None:
        raise DesignError("the moving curve carries no equilibrium states")
    pose = np.asarray(curve.pose, dtype=float).reshape(1, 6)
    c0 = tool_offset(pose[0], curve.tool_point)
    model = hinge_model(design, pose[0])
    chains = platform_chains(design, pose, c0[None]).chains
    twists = np.asarray(curve.twists, dtype=float)
    delta = np.asarray(curve.actuator_displacements, dtype=float)
    out = np.zeros((twists.shape[0], len(model.hinges), 6))
    for j, h in enumerate(model.hinges):
        screws = chains[h.leg].screws[0]
        column = _rotation_column(screws, h, c0)
        for k in range(twists.shape[0]):
            rot, pos = _prefix(screws, moving.coordinates[h.leg][k], column)
            centre = rot @ (h.centre - c0) + pos
            axes = rot @ h.axes
            w = moving.leg_wrenches[k, h.leg]
            m_c = w[:3] + np.cross(twists[k, 3:] - centre, w[3:])
            m_local, f_local = m_c @ axes, w[3:] @ axes
            if h.parallel > 0.0:
                m_local[2] = h.parallel * delta[k, h.leg]
            out[k, j] = np.concatenate([m_local, f_local])
    return model, out


def moving_curve_stresses(
    design: Design, moving: Any, safety_factor: float = 1.0
) -> dict[str, Any]:
    """The largest hinge stress at each load of a moving-geometry curve and its ratio
    to the allowed stress (:func:`curve_stresses`' return), each hinge's peak stress
    from :func:`moving_hinge_loads`."""
    if not (np.isfinite(safety_factor) and safety_factor > 0.0):
        raise DesignError(f"safety factor {safety_factor!r}: must be positive and finite")
    model, loads = moving_hinge_loads(design, moving)
    sigma = np.stack(
        [peak_stress(h.hinge, loads[:, j]) for j, h in enumerate(model.hinges)], axis=-1
    ).reshape(loads.shape[0], len(model.hinges))
    return _most_utilised(model, sigma, safety_factor)
