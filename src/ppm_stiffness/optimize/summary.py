"""Summary figures of one design over its required region (one function for
``compare``, ``sweep`` and ``optimize``).

:func:`summarize` evaluates every grid pose of the region
(:func:`ppm_stiffness.optimize.region.region_poses`, the design's task coordinates)
with the batched model (:func:`ppm_stiffness.maps.batch.evaluate_poses`, actuators
locked) and reduces them to a handful of numbers (:class:`RegionSummary`):

- ``covered_fraction``: the share of grid poses that are reachable and not singular;
  the design *covers* the region when it is 1;
- the minimum, mean and 5th percentile (linear interpolation between order statistics,
  ``numpy.percentile``) over the covered poses of the principal stiffnesses at the
  design's tool point (P unless it sets one):

  - a planar design: k_x, k_y [N/m] and k_phi [N·m/rad], those of the paper's
    decoupling (eq. 19) as ``analyze`` prints them;
  - any other design: ``k_translational`` [N/m] and ``k_rotational`` [N·m/rad], the
    smallest (worst-direction) spatial principal stiffnesses of each pose
    (:mod:`ppm_stiffness.core.principal`: 1/lambda_max of C_tt at the tool point and of
    C_rr); the other family is NaN;

- ``f1`` [Hz] (min, mean, 5th percentile) for a design with a mass model (its
  ``[platform]`` table): the first natural frequency of ``K v = omega^2 M v``
  (:mod:`ppm_stiffness.dynamics`) at each covered pose, the actuators locked, or
  under a wrench the loaded tangent K and tangent actuator stiffnesses as ``modes``
  uses them; NaN without a mass model;
- under a wrench (m_x, m_y, m_z, f_x, f_y, f_z [N·m, N], axes of F_b, acting at the
  tool point), from the loaded equilibrium at every covered pose
  (:func:`ppm_stiffness.optimize.loaded.loaded_region`): ``max_displacement`` [m] and
  ``max_rotation`` [rad], for a planar design the largest |(dx, dy)| of the tool point
  and |phi_z| (in the plane, as ever), for any other the largest norm of the tool
  point's 3-D translation and of the platform's rotation vector. Where the loaded
  state cannot be solved at a covered pose (a load beyond the small-displacement model,
  no equilibrium, a singular loaded K) the worst case is unknown: both are +inf, the
  loaded f1 is NaN, and ``loaded_failures`` counts those poses;
- ``load_margin`` [1], when asked for, under the wrench: the smallest load margin
  (:mod:`ppm_stiffness.optimize.margin`) over the margin sub-grid of the region (its
  corner poses, ``margin_poses`` of them), not over every grid pose;
- with ``hinges``, for a design with notch hinges whose materials give their yield strength
  (:mod:`ppm_stiffness.statics.hinge_stress`, docs/flexures.md), over the covered
  poses: ``hinge_range_min`` [rad or m, the drives' unit], the smallest of
  :func:`~ppm_stiffness.statics.hinge_stress.drive_range` (each drive's range alone to
  yield, the smallest over the drives), and ``hinge_stress_max`` [Pa], the largest of
  :func:`~ppm_stiffness.statics.hinge_stress.stroke_stress` (the largest hinge stress
  with the drives anywhere within their strokes; NaN without strokes). A loop over the
  poses, the frozen hinge model built per pose.

- with ``reach``, for a design with a candidate region (``[workspace.candidate]``, larger
  than the required one): ``candidate_share`` [1], the share of the candidate grid's
  poses reached without refusal (every leg's inverse kinematics solvable, joint
  coordinates within limits, not singular: the required region's coverage test,
  :func:`candidate_share`). Every other figure stays over the required region.

Beside the figures, three attributes of the record (not table figures: the JSON
documents of ``compare`` and ``sweep`` keep their keys), for the objectives of
``optimize`` (docs/optimization.md):

- under a wrench, ``actuator_force_max`` [N] and ``actuator_torque_max`` [N·m]: the
  largest |G_i| over the covered poses of the loaded state's actuator forces
  (frozen geometry, as ``analyze --wrench``), over the linear drives and over the
  rotary drives (NaN for a kind the design does not have; +inf where a loaded state
  fails);
- with ``condition``: ``condition_max`` [1], the largest over the covered poses of the
  2-norm condition number of the length-balanced K at the tool point, the actuators
  locked, unloaded (:func:`balanced_condition`).

A figure that has no value (no covered pose; no wrench; no mass model) is NaN in the
record and ``None`` in :meth:`RegionSummary.figures`, never a number.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.loaded import loaded_region, shift, tool_offsets
from ppm_stiffness.optimize.region import region_poses

#: Percentile of the stiffness figures named ``*_p5``.
PERCENTILE = 5.0
_STATS = (("min", "min"), ("mean", "mean"), ("p5", "5th pct"))

#: The per-pose quantities reduced to statistics: name -> (SI unit, family).
STATISTICS: dict[str, tuple[str, str]] = {
    "k_x": ("N/m", "paper"),
    "k_y": ("N/m", "paper"),
    "k_phi": ("N·m/rad", "paper"),
    "k_translational": ("N/m", "principal"),
    "k_rotational": ("N·m/rad", "principal"),
    "f1": ("Hz", "mass"),
}
_LABELS = {
    "k_translational": "worst k_trans",
    "k_rotational": "worst k_rot",
}

#: Every figure of a summary, in table order: name -> SI unit.
FIGURE_UNITS: dict[str, str] = {
    "covered_fraction": "1",
    **{
        f"{k}_{stat}": unit
        for k, (unit, _) in STATISTICS.items()
        if k != "f1"
        for stat, _ in _STATS
    },
    "max_displacement": "m",
    "max_rotation": "rad",
    **{f"f1_{stat}": "Hz" for stat, _ in _STATS},
    "load_margin": "1",
    "hinge_range_min": "rad or m",
    "hinge_stress_max": "Pa",
}

#: Short descriptions of the figures, for tables and docs.
FIGURE_LABELS: dict[str, str] = {
    "covered_fraction": "covered fraction",
    **{f"{k}_{stat}": f"{_LABELS.get(k, k)} {text}" for k in STATISTICS for stat, text in _STATS},
    "max_displacement": "max |(dx, dy)|",
    "max_rotation": "max |phi_z|",
    "load_margin": "load margin (corners)",
    "hinge_range_min": "hinge range min",
    "hinge_stress_max": "hinge stress at stroke max",
}
#: The figures every JSON document carries (the schemas' required keys since version
#: 1): covered fraction and the paper's k_x, k_y, k_phi (null for a design that is not
#: planar).
PAPER_FIGURES = (
    "covered_fraction",
    *(f"{k}_{s}" for k in ("k_x", "k_y", "k_phi") for s, _ in _STATS),
)
#: Labels of the loaded figures of a design that is not planar (3-D norms).
SPATIAL_LABELS = {"max_displacement": "max |d|", "max_rotation": "max |phi|"}
#: The figures that need a wrench.
LOADED_FIGURES = ("max_displacement", "max_rotation")


def figure_names(
    planar: bool, *, wrench: bool = False, mass: bool = False, margin: bool = False
) -> list[str]:
    """The figures that apply, in table order: the stiffness family of a planar design
    (k_x, k_y, k_phi) or of any other (k_translational, k_rotational); the loaded ones
    with a wrench; f1 with a mass model; the load margin when asked for."""
    family = "paper" if planar else "principal"
    names = ["covered_fraction"]
    names += [f"{k}_{s}" for k, (_, fam) in STATISTICS.items() if fam == family for s, _ in _STATS]
    if wrench:
        names += list(LOADED_FIGURES)
    if mass:
        names += [f"f1_{s}" for s, _ in _STATS]
    if margin:
        names.append("load_margin")
    return names


def figure_label(name: str, planar: bool = True) -> str:
    """The table label of a figure (the loaded ones say 3-D norms for a design that is
    not planar)."""
    return FIGURE_LABELS[name] if planar else SPATIAL_LABELS.get(name, FIGURE_LABELS[name])


@dataclass(frozen=True)
class RegionSummary:
    """Summary figures of one design over a region (SI, module doc).

    Attributes
    ----------
    values : dict
        Figure name (:data:`FIGURE_UNITS`) -> value; NaN where there is none.
    poses : int
        Grid poses of the region.
    covered : int
        Poses reachable and not singular.
    loaded_failures : int
        Covered poses whose loaded state could not be solved (0 without a wrench).
    error : str or None
        Why the design could not be evaluated at all (e.g. parameter values the design
        schema refuses); then nothing is covered.
    first_loaded_failure : tuple of float or None
        The task values of the first pose whose loaded state failed.
    planar : bool
        The design is planar (its stiffness figures are k_x, k_y, k_phi).
    margin_poses : int
        Poses of the margin sub-grid evaluated (0: no load margin asked for).
    moving_mass : float
        The mass of every body moving with the platform [kg] (:func:`_moving_mass`);
        NaN without a mass model. Not one of the region's figures: it does not depend
        on the pose.
    candidate_share : float
        The share of the candidate region's grid poses reached [1]
        (:func:`candidate_share`); NaN unless asked for (``reach``) of a design with a
        ``[workspace.candidate]``.
    candidate_poses : int
        Grid poses of the candidate region evaluated (0: not asked for).
    actuator_force_max, actuator_torque_max : float
        Under a wrench, the largest |actuator force| [N] of the linear drives and
        |torque| [N·m] of the rotary ones over the covered poses (module doc).
    condition_max : float
        The largest condition number of the length-balanced K over the covered poses
        [1] (:func:`balanced_condition`), when asked for.
    check_poses, check_refused : int
        The cheap check's poses and how many of them it refused
        (:mod:`ppm_stiffness.optimize.precheck`; 0, 0: not checked).
    maps : bool
        The region's maps were computed (False: a design the check refused, its
        figures NaN).
    """

    values: dict[str, float]
    poses: int
    covered: int
    loaded_failures: int = 0
    error: str | None = None
    first_loaded_failure: tuple[float, ...] | None = field(default=None)
    planar: bool = True
    margin_poses: int = 0
    moving_mass: float = math.nan
    candidate_share: float = math.nan
    candidate_poses: int = 0
    actuator_force_max: float = math.nan
    actuator_torque_max: float = math.nan
    condition_max: float = math.nan
    check_poses: int = 0
    check_refused: int = 0
    maps: bool = True

    @property
    def refused_by_check(self) -> bool:
        """The cheap check refused a corner of the region or the home pose."""
        return self.check_refused > 0

    @property
    def covers(self) -> bool:
        """Every grid pose reachable and not singular (and no evaluation error)."""
        return self.error is None and self.poses > 0 and self.covered == self.poses

    @property
    def covered_fraction(self) -> float:
        return self.values["covered_fraction"]

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def figures(self) -> dict[str, float | None]:
        """The figures for JSON and CSV: NaN as None (a missing value, never a number)."""
        return {k: (None if math.isnan(v) else v) for k, v in self.values.items()}

    @classmethod
    def failed(cls, poses: int, error: str, planar: bool = True) -> RegionSummary:
        """The record of a design that could not be evaluated (``error`` says why)."""
        values = {name: math.nan for name in FIGURE_UNITS}
        values["covered_fraction"] = 0.0
        return cls(values=values, poses=poses, covered=0, error=error, planar=planar)


def _statistics(values: FloatArray, prefix: str) -> dict[str, float]:
    if values.size == 0 or not np.all(np.isfinite(values)):
        return {f"{prefix}_{s}": math.nan for s, _ in _STATS}
    return {
        f"{prefix}_min": float(np.min(values)),
        f"{prefix}_mean": float(np.mean(values)),
        f"{prefix}_p5": float(np.percentile(values, PERCENTILE)),
    }


def _paper(
    design: Design, poses: FloatArray, matrices: bool
) -> tuple[BoolArray, FloatArray, FloatArray | None]:
    """A planar design: covered mask (n,), (k_x, k_y, k_phi) (3, n) at the tool point
    and K at P (n, 6, 6) when asked for."""
    from ppm_stiffness.maps import batch

    tool = np.asarray(design.tool_point, dtype=float)
    at_tool = bool(np.any(tool))
    res = batch.evaluate_poses(design, poses, matrices=at_tool or matrices)
    valid = np.asarray(res.valid, dtype=bool)
    k = np.stack([np.asarray(res.k_x.filled(np.nan)), np.asarray(res.k_y.filled(np.nan))])
    k = np.concatenate([k, np.asarray(res.k_phi.filled(np.nan))[None]])
    if at_tool and np.any(valid):
        assert res.stiffness is not None
        a = shift(tool_offsets(design, poses[valid]))
        k_t = a @ res.stiffness[valid] @ np.swapaxes(a, -1, -2)
        pr = batch.principal_from_matrices(k_t)
        k[:, valid] = np.stack([pr.k_x, pr.k_y, pr.k_phi])
    return valid, k, res.stiffness


def _principal(
    design: Design, poses: FloatArray, matrices: bool
) -> tuple[BoolArray, FloatArray, FloatArray | None, FloatArray]:
    """Any design: covered mask (n,), the worst translational (at the tool point) and
    rotational principal stiffnesses (2, n), K at P (n, 6, 6) when asked for and the
    full poses (n, 6)."""
    from ppm_stiffness.maps import batch

    res = batch.evaluate_poses(
        design, poses, matrices=matrices, principal=True, tool_point=design.tool_point
    )
    valid = np.asarray(res.valid, dtype=bool)
    assert res.translational is not None and res.rotational is not None
    k = np.stack(
        [
            np.asarray(res.translational[..., 0].filled(np.nan)),
            np.asarray(res.rotational[..., 0].filled(np.nan)),
        ]
    )
    return valid, k, res.stiffness, np.asarray(res.poses)


def first_frequencies(
    design: Design,
    poses: FloatArray,
    stiffness: FloatArray,
    actuator_stiffness: ArrayLike | None = None,
    link_modes: int = 0,
) -> FloatArray:
    """The first natural frequency [Hz] (n,) from K at P (n, 6, 6) at full poses (n, 6),
    the legs' motion with ``actuator_stiffness`` (n, n_legs) (locked if None); NaN
    where K or M is not finite. Frequencies do not depend on the reference point.
    ``link_modes``: each leg's own modes with the platform held
    (:func:`ppm_stiffness.dynamics.batch.first_frequencies`); 0: the legs condensed."""
    from ppm_stiffness.dynamics.mass import mass_matrix
    from ppm_stiffness.dynamics.modes import natural_frequencies

    if poses.shape[0] == 0:
        return np.zeros(0)
    if link_modes:
        from ppm_stiffness.dynamics import batch
        from ppm_stiffness.model import actuator_stiffness_vector

        k_act = (
            actuator_stiffness_vector(design, None)
            if actuator_stiffness is None
            else actuator_stiffness
        )
        return batch.first_frequencies(design, poses, stiffness, k_act, link_modes=link_modes)[0]
    m = mass_matrix(design, poses, actuator_stiffness)
    return np.asarray(natural_frequencies(stiffness, m)[:, 0])


def summarize(
    design: Design,
    region: RequiredRegionModel,
    wrench: ArrayLike | None = None,
    margin: bool = False,
    frequencies: bool = True,
    hinges: bool = False,
    reach: bool = False,
    condition: bool = False,
    link_modes: int | None = None,
) -> RegionSummary:
    """The summary figures of ``design`` over ``region`` (module doc).

    Parameters
    ----------
    design : Design
        Any architecture, planar or spatial.
    region : RequiredRegionModel
        The grid of poses over the design's task coordinates
        (:func:`ppm_stiffness.optimize.region.region_of`).
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N], axes of F_b, at the tool point; adds
        ``max_displacement`` and ``max_rotation`` (NaN without it), and the loaded f1.
    margin : bool
        Also the load margin of ``wrench`` (needs it) on the margin sub-grid.
    frequencies : bool
        The f1 figures when the design has a mass model (False: NaN; the mass matrices
        cost several times the stiffness: about 0.07 s against 0.01 s for the 405
        poses of a planar example's region).
    hinges : bool
        The hinge figures (``hinge_range_min``, ``hinge_stress_max``; NaN without):
        about 0.1 s per pose for the shipped 3-RRR stage.
    reach : bool
        The share of the design's candidate region reached (``candidate_share``; NaN
        for a design without ``[workspace.candidate]``).
    condition : bool
        Also ``condition_max`` (the length-balanced K's condition number; NaN without).
    link_modes : int, optional
        The f1 figures with each leg's own modes with the platform held (Craig-Bampton,
        :mod:`ppm_stiffness.dynamics.legmodes`), this many per leg; None: the default
        (:data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`, as ``analyze``,
        ``modal_analysis`` and ``stiffness_map``); 0: the legs condensed statically.

    Returns
    -------
    RegionSummary

    Raises
    ------
    InputDataError
        A wrench not of 6 finite values, or ``margin`` without a wrench.
    DesignError
        A region not over the design's task coordinates.
    """
    from ppm_stiffness.core.errors import InputDataError
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes
    from ppm_stiffness.statics.loading import validate_wrench

    link_modes = resolve_link_modes(link_modes)
    w = None if wrench is None else validate_wrench(wrench)
    if margin and w is None:
        raise InputDataError("the load margin needs a wrench (--wrench)")
    task = tuple(region.ranges())
    if task != tuple(design.task_coordinates):
        raise DesignError(
            f"the region's ranges ({', '.join(task)}) must be the design's task "
            f"coordinates ({', '.join(design.task_coordinates)})"
        )
    poses = region_poses(region).reshape(-1, len(task))
    mass = design.has_mass_model and frequencies
    locked_f1 = mass and w is None
    names: tuple[str, ...] = ("k_x", "k_y", "k_phi")
    full: FloatArray | None = None
    want_k = locked_f1 or condition
    if design.planar:
        covered, k, stiffness = _paper(design, poses, want_k)
    else:
        covered, k, stiffness, full = _principal(design, poses, want_k)
        names = ("k_translational", "k_rotational")
    values: dict[str, float] = {n: math.nan for n in FIGURE_UNITS}
    values["covered_fraction"] = float(np.mean(covered))
    for row, name in enumerate(names):
        values.update(_statistics(k[row, covered], name))
    if locked_f1:
        assert stiffness is not None
        if full is None:
            from ppm_stiffness.poses import full_poses

            full = full_poses(design, poses)[0].reshape(-1, 6)
        f1 = first_frequencies(design, full[covered], stiffness[covered], None, link_modes)
        values.update(_statistics(f1, "f1"))
    cond = math.nan
    if condition and np.any(covered):
        assert stiffness is not None
        cond = float(np.max(balanced_condition(design, poses[covered], stiffness[covered])))
    failures = 0
    first: tuple[float, ...] | None = None
    efforts = (math.nan, math.nan)
    if w is not None and np.any(covered):
        state = loaded_region(design, poses[covered], w, matrices=mass)
        solved = state.solved
        failures = int(np.count_nonzero(~solved))
        assert state.forces is not None
        efforts = actuator_efforts(design, state.forces)
        if failures:
            values["max_displacement"] = values["max_rotation"] = math.inf
            first = tuple(float(v) for v in poses[covered][~solved][0])
        else:
            d, phi = state.tool_motion()
            if design.planar:  # in the plane, as ever
                disp, rot = np.hypot(d[:, 0], d[:, 1]), np.abs(phi[:, 2])
            else:
                disp, rot = np.linalg.norm(d, axis=1), np.linalg.norm(phi, axis=1)
            values["max_displacement"] = float(np.max(disp))
            values["max_rotation"] = float(np.max(rot))
            if mass:
                assert state.stiffness is not None and state.poses is not None
                f1 = first_frequencies(
                    design, state.poses, state.stiffness, state.actuator_stiffness, link_modes
                )
                values.update(_statistics(f1, "f1"))
    if hinges and np.any(covered):
        values.update(_hinge_figures(design, poses[covered]))
    margin_count = 0
    if margin and w is not None:
        from ppm_stiffness.optimize.margin import margin_poses, region_margins

        sub = margin_poses(region)
        margins, refused = region_margins(design, sub, w)
        margin_count = int(sub.shape[0])
        if not np.any(refused):
            values["load_margin"] = float(np.min(margins))
    summary = RegionSummary(
        values=values,
        poses=int(poses.shape[0]),
        covered=int(np.count_nonzero(covered)),
        loaded_failures=failures,
        first_loaded_failure=first,
        planar=design.planar,
        margin_poses=margin_count,
        moving_mass=_moving_mass(design),
        actuator_force_max=efforts[0],
        actuator_torque_max=efforts[1],
        condition_max=cond,
    )
    return _with_candidate(summary, design) if reach else summary


def candidate_share(design: Design, candidate: RequiredRegionModel) -> tuple[float, int]:
    """The share [1] of the grid poses of ``candidate`` that ``design`` reaches without
    refusal, and the number of grid poses.

    A pose is reached when the single-pose analysis
    (:func:`ppm_stiffness.model.stiffness_at_pose`) accepts it: completed, every leg's
    inverse kinematics solvable, joint coordinates within limits, not singular (the
    batched :func:`ppm_stiffness.maps.batch.evaluate_poses`, its ``valid`` mask).
    """
    from ppm_stiffness.maps import batch

    poses = region_poses(candidate).reshape(-1, len(candidate.grid))
    res = batch.evaluate_poses(design, poses, principal=False)
    return float(np.mean(np.asarray(res.valid, dtype=bool))), int(poses.shape[0])


def _with_candidate(summary: RegionSummary, design: Design) -> RegionSummary:
    """``summary`` with ``candidate_share`` and ``candidate_poses`` of the design's
    candidate region (unchanged without one)."""
    from dataclasses import replace

    candidate = design.workspace.candidate
    if candidate is None:
        return summary
    share, count = candidate_share(design, candidate)
    return replace(summary, candidate_share=share, candidate_poses=count)


def drive_units(design: Design) -> list[str | None]:
    """Each leg's drive force unit, N (linear) or N·m (rotary); None for a passive leg
    (no actuator: a Tricept's central leg)."""
    return [None if leg.actuator is None else leg.actuator_units()[0] for leg in design.legs]


def actuator_efforts(design: Design, forces: FloatArray) -> tuple[float, float]:
    """The largest |actuator force| [N] over the linear drives and |torque| [N·m]
    over the rotary ones of loaded states ``forces`` (n, n_legs) [each leg's kind];
    NaN for a kind the design does not have, +inf where a row is NaN (a loaded state
    that failed: the worst case is unknown). Passive legs are neither."""
    units = np.array(drive_units(design), dtype=object)
    out = []
    for kind in (units == "N", units == "N·m"):
        if not np.any(kind) or forces.shape[0] == 0:
            out.append(math.nan)
            continue
        g = np.abs(forces[:, kind])
        out.append(math.inf if np.any(np.isnan(g)) else float(np.max(g)))
    return out[0], out[1]


def balanced_condition(design: Design, poses: FloatArray, stiffness: FloatArray) -> FloatArray:
    """The condition number (n,) [1] of the length-balanced stiffness at the tool point.

    Parameters
    ----------
    design : Design
    poses : ndarray (n, n_task)
        Task coordinates of P in F_b [m, rad].
    stiffness : ndarray (n, 6, 6)
        K at P, axes of F_b [N·m/rad, N, N/m].

    Returns
    -------
    ndarray (n,)
        ``cond_2(S K_T S)``: K_T = A K A^T moved to the tool point
        (:func:`~ppm_stiffness.optimize.loaded.shift`; P without one), S = diag(1/L,
        1/L, 1/L, 1, 1, 1), L = :data:`~ppm_stiffness.core.conventions.LENGTH_SCALE`
        = 0.1 m (:func:`~ppm_stiffness.core.conventions.length_balanced`): every entry
        in N/m, so that a rotation of L·phi and a displacement of the same length
        weigh alike. K_T is symmetric positive definite: the ratio of its largest to
        its smallest balanced eigenvalue. Invariant under a rotation of the base frame
        (S commutes with diag(R, R)); not under a change of the reference point or of
        L.
    """
    from ppm_stiffness.core.conventions import length_balanced

    k = np.asarray(stiffness, dtype=float)
    if np.any(np.asarray(design.tool_point, dtype=float)) and k.shape[0]:
        a = shift(tool_offsets(design, poses))
        k = a @ k @ np.swapaxes(a, -1, -2)
    return np.asarray(np.linalg.cond(length_balanced(k)))


def _hinge_figures(design: Design, poses: FloatArray) -> dict[str, float]:
    """``hinge_range_min`` and ``hinge_stress_max`` over the covered poses (module
    doc); empty for a design without them (they stay NaN)."""
    from ppm_stiffness.statics.hinge_stress import (
        pose_figures,
        require_hinge_figures,
        stroke_corners,
    )

    try:
        require_hinge_figures(design)
    except DesignError:
        return {}
    try:
        stroke_corners(design)
        strokes = True
    except DesignError:
        strokes = False
    ranges, stresses = pose_figures(design, poses, strokes)
    out = {"hinge_range_min": float(np.min(ranges))}
    if strokes:
        out["hinge_stress_max"] = float(np.max(stresses))
    return out


def _moving_mass(design: Design) -> float:
    """The total moving mass [kg] of a design with a mass model, else NaN
    (:func:`ppm_stiffness.dynamics.mass.moving_mass`: the platform's mass, every link's
    ``mass``, a parallelogram's two bars, every actuator's carriage; a rotor's inertia
    is not a mass and does not count)."""
    if not design.has_mass_model or design.platform is None:
        return math.nan
    from ppm_stiffness.dynamics.mass import moving_mass

    return moving_mass(design)["total"]


#: The cheap-check modes of :func:`summarize_candidate`.
CHECKS = ("none", "skip", "record")


def candidate_task(
    design: Design,
    values: Mapping[str, float] | None,
    region: RequiredRegionModel,
    wrench: ArrayLike | None = None,
    *,
    margin: bool = False,
    frequencies: bool = True,
    hinges: bool = False,
    reach: bool = False,
    condition: bool = False,
    check: str = "none",
    link_modes: int | None = None,
) -> tuple[Any, ...]:
    """The argument tuple of :func:`summarize_candidate` for one design, what an
    executor sends (``run_ordered(executor, summarize_candidate, tasks)``): its order
    written here once, every option by name at the call site."""
    return (
        design,
        values,
        region,
        wrench,
        margin,
        frequencies,
        hinges,
        reach,
        condition,
        check,
        link_modes,
    )


def summarize_candidate(
    design: Design,
    values: Mapping[str, float] | None,
    region: RequiredRegionModel,
    wrench: ArrayLike | None = None,
    margin: bool = False,
    frequencies: bool = True,
    hinges: bool = False,
    reach: bool = False,
    condition: bool = False,
    check: str = "none",
    link_modes: int | None = None,
) -> RegionSummary:
    """:func:`summarize` of ``design`` with parameters ``values`` (name or glob -> SI
    value) set: the task one worker runs for one design (the design travels, not the
    maps). Parameter values the design schema refuses give a :meth:`RegionSummary.failed`
    record (nothing covered) instead of an error, so that an optimiser can step over
    them.

    ``check``: ``"none"``; ``"skip"``, the cheap check first
    (:mod:`ppm_stiffness.optimize.precheck`), and a design it refuses returned without
    its maps (``maps`` False, its figures NaN); ``"record"``, the check and the maps of
    every design (the check's outcome recorded: an optimiser ranks the design as with
    ``"skip"``).
    """
    from ppm_stiffness.optimize.executors import limit_threads
    from ppm_stiffness.optimize.variables import apply_values

    limit_threads()
    if values:
        try:
            design = apply_values(design, dict(values))
        except DesignError as exc:
            return RegionSummary.failed(math.prod(region.grid), str(exc), design.planar)
    if check not in CHECKS:
        from ppm_stiffness.core.errors import InputDataError

        raise InputDataError(f"check must be one of {', '.join(CHECKS)}, got {check!r}")
    if check == "none" or tuple(region.ranges()) != tuple(design.task_coordinates):
        return summarize(
            design, region, wrench, margin, frequencies, hinges, reach, condition, link_modes
        )
    from dataclasses import replace

    from ppm_stiffness.optimize.precheck import refused_check_poses

    n, refused = refused_check_poses(design, region)
    if refused and check == "skip":
        # the maps' figures unknown (NaN, ``maps`` False says why); the moving mass is
        # the design's, as in the "record" mode
        values = {name: math.nan for name in FIGURE_UNITS}
        poses = math.prod(region.grid)
        return RegionSummary(
            values,
            poses,
            0,
            planar=design.planar,
            moving_mass=_moving_mass(design),
            check_poses=n,
            check_refused=refused,
            maps=False,
        )
    full = summarize(
        design, region, wrench, margin, frequencies, hinges, reach, condition, link_modes
    )
    return replace(full, check_poses=n, check_refused=refused)


def summary_names(summaries: Sequence[RegionSummary], wrench: bool, mass: bool) -> list[str]:
    """The figures to show for summaries of designs of one kind (planar or not)."""
    planar = all(s.planar for s in summaries)
    margin = any(s.margin_poses for s in summaries)
    return figure_names(planar, wrench=wrench, mass=mass, margin=margin)
