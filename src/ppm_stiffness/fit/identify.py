"""Identify element stiffnesses (any design parameters) from measured platform deflections.

Data: rows of (pose of P, wrench at P, measured twist of P), each measured component
with its noise sigma (:func:`measurement_rows`, from the file read by
:func:`ppm_stiffness.statics.measurements.read_measurements`). Poses are full 6-D poses
(x, y, z, rx, ry, rz) of any design, planar or spatial
(:func:`ppm_stiffness.statics.measurements.measured_poses`).

Model. The predicted twist of a row is the one ``deflect`` computes: the equilibrium
of the loaded manipulator with the nonlinear actuator law
(:func:`ppm_stiffness.statics.equilibrium.equilibrium`, where the deflection path of
:func:`ppm_stiffness.statics.deflection.deflection_path` ends; the springs are elastic,
so the twist does not depend on the loading history), passive joints eliminated exactly,
at the full pose. A row's pose is held at its task coordinates: the dependent ones are
completed by each design the fit evaluates (the same as the catalogue's unless a free
parameter moves the legs' constraints).

Parameters. ``free`` are names or globs of ``Design.scalar_parameter_names()``; a glob
(``leg*.guide.lateral``) is one parameter tying every match (their catalogue values
must be equal). The fit works in relative parameters ``theta_j = p_j / s_j`` with
``s_j = |p_j^0|`` (the catalogue value; 1 in SI for a zero catalogue value).

Residuals ``r = (predicted - measured) / sigma`` over every measured component.

Estimation, in two stages:

1. **Linear start in the compliances.** A stiffness-like parameter (unit N/m, N·m/rad or
   Pa, and an actuator law's k_a, a stiffness when q = 1) enters as its relative
   compliance ``u = p^0 / p``, any other as ``u = p / p^0``;
   the predictions are linearised in u at the catalogue (forward differences, step
   :data:`LINEAR_STEP`) and the weighted linear least-squares problem solved. Along a
   statically determinate load path with the actuators locked (in-plane loads on a
   3-leg planar design below the actuators' thresholds) the twist is exactly linear in
   the element compliances, and this start is the solution. Out of plane (three legs
   carry six out-of-plane constraints: a redundant path), in redundant designs and
   with powered actuators it is a linearisation, only a start.
2. **Nonlinear least squares** (``scipy.optimize.least_squares``, trust-region
   reflective, relative parameters bounded to ``[1e-3, 1e3]`` for positive catalogue
   values) through the full model. Skipped when the model is linear in u along the
   start's step (the model's residuals at the start equal the linear model's to
   :data:`LINEARITY_TOLERANCE` of the largest residual at the catalogue): the start
   is then the least-squares solution and the linear Jacobian exact there.

Uncertainty. With ``J`` the Jacobian of the weighted residuals in the relative
parameters at the solution (rows divided by sigma, columns relative), the covariance
of theta is ``(J^T J)^-1`` (the sigmas are taken as the true noise: no rescaling by
the residual; the weighted RMS says whether they were right), standard errors
``s_j sqrt(cov_jj)`` and the correlation matrix follow. An estimate at a bound of the
search (within :data:`BOUND_PROXIMITY`, 1 %, of ``RELATIVE_BOUNDS`` times its
catalogue value) is not a fitted value: the data pull it beyond the range (a measured
rotation of 90 deg put a 3-RPS actuator's k_a at exactly 1e-3 of its catalogue value
with a "standard error" of 0.0013 %). It is flagged (:class:`BoundWarning`,
``IdentificationResult.at_bound``), its standard error and correlations are NaN, and
the others' covariance is that of the remaining parameters, it held at the bound.

Identifiability. The singular values ``s_k`` of the scaled Jacobian measure how well
each combination ``v_k`` (right singular vector) of relative parameters is determined:
its 1-sigma is ``1 / s_k`` (relative). A combination is **unidentifiable** when
``1 / s_k > MAX_RELATIVE_SIGMA`` (1: the data cannot tell it to better than 100 %)
or ``s_k < RANK_RATIO * s_max`` (numerically flat). It is checked at the catalogue
values before the fit: unidentifiable combinations are named and refused
(:class:`~ppm_stiffness.core.errors.InputDataError`), unless
``fix_unidentifiable=True``: then the parameter with the largest weight in the
weakest combination is fixed at its catalogue value, repeatedly, until every remaining
combination is identifiable, with an :class:`IdentifiabilityWarning`.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import TWIST_COMPONENTS, FloatArray
from ppm_stiffness.core.errors import InputDataError, PPMStiffnessError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import shared_parameter, tied_note
from ppm_stiffness.statics.measurements import (
    COMPONENT_COLUMNS,
    Measurements,
    measured_poses,
)

#: A combination whose relative 1-sigma (1 / singular value) exceeds this is
#: unidentifiable (module doc).
MAX_RELATIVE_SIGMA = 1.0
#: A singular value below this fraction of the largest is numerically flat.
RANK_RATIO = 1e-8
#: Units of the parameters that enter the linear start as compliances.
STIFFNESS_UNITS = frozenset({"N/m", "N·m/rad", "Pa"})
#: Relative forward-difference step of the linear start.
LINEAR_STEP = 1e-4
#: Relative finite-difference step of the nonlinear fit's Jacobian.
FIT_STEP = 1e-7
#: The model counts as linear in u along the start's step when its residuals there
#: match the linear model's to this fraction of the largest residual at the catalogue.
#: Forward differences of a linear model are exact to rounding: measured 9e-12 on the
#: 3-PPR's linear paths, 2.4e-11 on the hexapod; the 3-RPS's path, not linear (each leg
#: transmits two wrenches), 1.5e-9 (1e-7 took it as linear: its start was 3.9e-8 off).
LINEARITY_TOLERANCE = 1e-10
#: Bounds of a positive parameter relative to its catalogue value during the fit.
RELATIVE_BOUNDS = (1e-3, 1e3)
#: An estimate within this relative distance of a bound is at the bound: the data pull it
#: beyond the search range, it is not a fitted value and has no standard error.
BOUND_PROXIMITY = 1e-2


def _stiffness_like(unit: str) -> bool:
    """A stiffness (N/m, N·m/rad, Pa) or an actuator law's coefficient k_a (N/m^q:
    a stiffness when q = 1)."""
    return unit in STIFFNESS_UNITS or unit.endswith("^q")


class IdentifiabilityWarning(UserWarning):
    """Parameters were fixed at their catalogue values because the data cannot
    determine them (``fix_unidentifiable=True``)."""


class BoundWarning(UserWarning):
    """An estimate ended at (within :data:`BOUND_PROXIMITY` of) a bound of the search
    (:data:`RELATIVE_BOUNDS` times its catalogue value): the measurements pull it
    beyond, so it is the bound, not a fit, and its standard error is not given."""


@dataclass(frozen=True)
class MeasurementRows:
    """Measurements ready for fitting (SI; twists and wrenches at P, axes of F_b).

    Attributes
    ----------
    poses : ndarray (n, 6) or (n, n_task) [m, rad]
        Full poses (x, y, z, rx, ry, rz) of P (:func:`measurement_rows`), or the
        design's task coordinates.
    wrenches : ndarray (n, 6) (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N]
    twists : ndarray (n, 6) [rad, m], NaN where not measured
    sigmas : ndarray (n, 6) [rad, m], 1-sigma noise; NaN where not measured
    labels : tuple of str
        Where each row comes from (``"FILE, line N"``), for errors; may be empty.
    """

    poses: FloatArray
    wrenches: FloatArray
    twists: FloatArray
    sigmas: FloatArray
    labels: tuple[str, ...] = ()

    @property
    def measured(self) -> np.ndarray:
        """Boolean mask (n, 6) of the measured components."""
        return np.asarray(np.isfinite(self.twists))

    @property
    def n_rows(self) -> int:
        return int(self.twists.shape[0])

    @property
    def n_values(self) -> int:
        """Number of measured scalar values (residuals)."""
        return int(self.measured.sum())

    def repeated(self, times: int) -> MeasurementRows:
        """The same rows ``times`` times over (as if each were measured again)."""
        poses, wrenches, twists, sigmas = (
            np.tile(a, (times, 1)) for a in (self.poses, self.wrenches, self.twists, self.sigmas)
        )
        return MeasurementRows(poses, wrenches, twists, sigmas, self.labels * times)

    def with_twists(self, twists: ArrayLike) -> MeasurementRows:
        """The same rows with other measured values (NaN kept where not measured)."""
        t = np.where(self.measured, np.asarray(twists, dtype=float), np.nan)
        return MeasurementRows(self.poses, self.wrenches, t, self.sigmas, self.labels)


def measurement_rows(
    design: Design, measurements: Measurements, sigma: Mapping[int, float] | None = None
) -> MeasurementRows:
    """Poses, wrenches, twists and sigmas of every row of a measurement file.

    Parameters
    ----------
    design : Design
        Completes the poses (the dependent coordinates; its home pose when the file
        has no pose columns).
    measurements : Measurements
        A file with wrench columns, or with a load column and a ``mode`` (and
        ``alpha_deg``) metadata line (the loading modes of ``deflect``).
    sigma : mapping component index (0-5) -> 1-sigma [rad or m], optional
        Noise of the components that have no ``sigma_*`` column.

    Returns
    -------
    MeasurementRows
        With full poses (n, 6).

    Raises
    ------
    InputDataError
        A load column without a mode; a row with a zero wrench; a missing task
        coordinate column or a dependent coordinate that disagrees with the legs (the
        file and the row's line named); a measured component with no sigma (or a sigma
        given both ways); a sigma that is not > 0.
    UnreachablePoseError
        A row's pose that the legs cannot reach (file and line named).
    """
    src = measurements.source
    n = measurements.n
    labels = tuple(measurements.row_label(k) for k in range(n))
    if measurements.wrenches is not None:
        wrenches = np.asarray(measurements.wrenches, dtype=float)
    else:
        unit = measurements.unit_wrench()
        if unit is None:
            raise InputDataError(
                f"{src}: a load column needs a '# mode:' line (planar-force, moment, "
                "vertical-force, or direction with a '# direction:' line) to say which "
                "wrench made the displacements"
            )
        wrenches = measurements.load_values()[:, None] * unit[None, :]
    zero = np.flatnonzero(~np.any(wrenches != 0, axis=1))
    if zero.size:
        raise InputDataError(
            f"{labels[zero[0]]}: a zero wrench: a displacement without a wrench says "
            "nothing about stiffness"
        )
    poses = measured_poses(design, measurements)
    sig = (
        np.full((n, 6), np.nan)
        if measurements.sigmas is None
        else np.array(measurements.sigmas, dtype=float)
    )
    for i, value in (sigma or {}).items():
        if not (math.isfinite(value) and value > 0):
            raise InputDataError(f"sigma of {COMPONENT_COLUMNS[i]} must be > 0, got {value}")
        if np.any(np.isfinite(sig[:, i])):
            raise InputDataError(
                f"{src}: the sigma of {COMPONENT_COLUMNS[i]} is given twice (a "
                f"sigma_{COMPONENT_COLUMNS[i]} column and an option)"
            )
        sig[:, i] = value
    twists = np.array(measurements.twists, dtype=float)
    for i in measurements.components:
        if not np.all(np.isfinite(sig[:, i])):
            raise InputDataError(
                f"{src}: no noise given for {COMPONENT_COLUMNS[i]}: add a column "
                f"sigma_{COMPONENT_COLUMNS[i]} or give it as an option (--sigma "
                f"{COMPONENT_COLUMNS[i]}=VALUE)"
            )
    sig[~np.isfinite(twists)] = np.nan
    return MeasurementRows(poses, wrenches, twists, sig, labels)


_T = TypeVar("_T")


def _row(label: str | None, fn: Callable[..., _T], *args: Any) -> _T:
    """``fn(*args)``, a library error raised again (same class) with the row's label
    in front, so that it names the file and the line it comes from."""
    try:
        return fn(*args)
    except PPMStiffnessError as exc:
        if label is None:
            raise
        raise type(exc)(f"{label}: {exc}") from None


def predict_twists(
    design: Design,
    poses: ArrayLike,
    wrenches: ArrayLike,
    labels: Sequence[str] = (),
) -> FloatArray:
    """Twist of P (n, 6) [rad, m] under each wrench at each pose: the loaded
    equilibrium with the nonlinear actuator law (what ``deflect`` computes).

    Parameters
    ----------
    design : Design
    poses : array_like (n, 6) or (n, n_task) [m, rad]
        Full poses or task coordinates: each row is evaluated at its task coordinates,
        the dependent ones completed by ``design`` (:mod:`ppm_stiffness.poses`).
    wrenches : array_like (n, 6) [N·m, N]
        At P, axes of F_b.
    labels : sequence of str
        One per row (e.g. ``"FILE, line N"``): they prefix the errors of a row's pose or
        load.

    Rows at the same pose share one set of springs.
    """
    from ppm_stiffness.poses import full_pose, full_poses, task_indices
    from ppm_stiffness.statics.equilibrium import LegStructures, equilibrium

    given = np.asarray(poses, dtype=float)
    w = np.asarray(wrenches, dtype=float)
    names = list(labels) if len(labels) else [None] * given.shape[0]
    task = given[:, list(task_indices(design))] if given.shape[-1] == 6 else given
    p, ok = full_poses(design, task)
    for bad in np.flatnonzero(~np.asarray(ok, dtype=bool)).tolist():
        _row(names[bad], full_pose, design, task[bad])  # raises, naming the row
    out = np.zeros((p.shape[0], 6))
    keys, inverse = np.unique(p, axis=0, return_inverse=True)
    for k, pose in enumerate(keys):
        rows = [int(r) for r in np.flatnonzero(inverse.ravel() == k)]
        st = _row(names[rows[0]], LegStructures, design, pose)
        for r in rows:
            out[r] = _row(names[r], equilibrium, design, w[r], pose, st).twist
    return out


@dataclass(frozen=True)
class Combination:
    """A combination of relative parameters and how well the data determine it.

    Attributes
    ----------
    singular_value : float
        Of the scaled Jacobian.
    relative_sigma : float
        Its 1-sigma, relative (``1 / singular_value``; inf when 0).
    weights : dict name -> component of the unit right singular vector
    """

    singular_value: float
    relative_sigma: float
    weights: dict[str, float]

    def describe(self, threshold: float = 0.1) -> str:
        """``leg1.guide.lateral +0.71, leg2.guide.lateral -0.71``: the names that
        weigh more than ``threshold``."""
        items = sorted(self.weights.items(), key=lambda kv: -abs(kv[1]))
        return ", ".join(f"{n} {v:+.2f}" for n, v in items if abs(v) > threshold)


def combinations(jacobian: ArrayLike, names: Sequence[str]) -> list[Combination]:
    """Every combination (strongest first) from the SVD of the scaled Jacobian
    (rows / sigma, relative-parameter columns), shape (m, n)."""
    j = np.asarray(jacobian, dtype=float)
    _, s, vt = np.linalg.svd(j, full_matrices=True)
    s = np.concatenate([s, np.zeros(len(names) - s.size)])  # fewer rows than parameters
    out = []
    for k in range(len(names)):
        sign = 1.0 if vt[k, np.argmax(np.abs(vt[k]))] >= 0 else -1.0
        out.append(
            Combination(
                float(s[k]),
                math.inf if s[k] == 0 else float(1.0 / s[k]),
                {n: float(sign * v) for n, v in zip(names, vt[k], strict=True)},
            )
        )
    return out


def unidentifiable(found: Sequence[Combination]) -> list[Combination]:
    """The combinations that fail the threshold of the module doc."""
    s_max = max((c.singular_value for c in found), default=0.0)
    return [
        c
        for c in found
        if c.relative_sigma > MAX_RELATIVE_SIGMA or c.singular_value <= RANK_RATIO * s_max
    ]


@dataclass(frozen=True)
class IdentificationResult:
    """Outcome of :func:`identify` (SI throughout).

    Attributes
    ----------
    design : Design
        The design with the identified values (fixed parameters at the catalogue).
    names : list of str
        The fitted parameters (names or globs as given, fixed ones removed).
    units : list of str
    catalogue, start, values, standard_errors : ndarray (n,)
        Catalogue (the design's) values, the linear start, the estimates and their
        1-sigma standard errors.
    correlation : ndarray (n, n)
    residual_rms : ndarray (6,)
        RMS of predicted - measured per twist component [rad, m]; NaN if not measured.
    weighted_rms : float
        RMS of the residuals divided by their sigma (about 1 when the sigmas are right).
    combinations : list of Combination
        At the solution, strongest first, of the parameters not at a bound (empty if
        every one is).
    fixed : list of str
        Parameters fixed at their catalogue values as unidentifiable.
    n_rows, n_values : int
    predicted : ndarray (n_rows, 6)
        Predicted twists at the estimates.
    nfev : int
        Model evaluations of the nonlinear fit (without its Jacobians).
    at_bound : dict name -> {"lower", "upper"}
        Parameters whose estimate is at a bound of the search (:class:`BoundWarning`):
        their standard error and correlations are NaN (not valid), the others'
        are computed with them held at the bound.
    """

    design: Design
    names: list[str]
    units: list[str]
    catalogue: FloatArray
    start: FloatArray
    values: FloatArray
    standard_errors: FloatArray
    correlation: FloatArray
    residual_rms: FloatArray
    weighted_rms: float
    combinations: list[Combination]
    fixed: list[str] = field(default_factory=list)
    n_rows: int = 0
    n_values: int = 0
    predicted: FloatArray = field(default_factory=lambda: np.zeros((0, 6)))
    nfev: int = 0
    at_bound: dict[str, str] = field(default_factory=dict)

    def bound_messages(self) -> list[str]:
        """One sentence per parameter at a bound: what happened and why its standard
        error is not given."""
        return [bound_message(n, side) for n, side in self.at_bound.items()]


def bound_message(name: str, side: str) -> str:
    """Why parameter ``name``'s estimate at the ``side`` bound is not a fitted value."""
    lo, hi = RELATIVE_BOUNDS
    factor = f"{lo:g}" if side == "lower" else f"{hi:g}"
    return (
        f"{name} is at the {side} bound of the search ({factor} x its catalogue value): "
        "the measurements pull it beyond the range the fit allows (a wrong measurement "
        "or unit, or a model that does not fit the data), so the estimate is the bound, "
        "not a fitted value, and it has no valid standard error"
    )


def _at_bound(
    names: Sequence[str], theta: FloatArray, lower: FloatArray, upper: FloatArray
) -> dict[str, str]:
    """The parameters whose relative value ``theta`` is within :data:`BOUND_PROXIMITY`
    of its bound (name -> ``"lower"`` or ``"upper"``)."""
    out = {}
    for name, t, lo, hi in zip(names, theta, lower, upper, strict=True):
        if np.isfinite(lo) and t <= lo * (1 + BOUND_PROXIMITY):
            out[name] = "lower"
        elif np.isfinite(hi) and t >= hi / (1 + BOUND_PROXIMITY):
            out[name] = "upper"
    return out


def _covariance(jac: FloatArray, free: np.ndarray) -> tuple[FloatArray, FloatArray]:
    """Standard errors (n,) and correlation (n, n) of the relative parameters from the
    scaled Jacobian (m, n), the parameters where ``free`` is False held fixed (NaN)."""
    n = jac.shape[1]
    se, corr = np.full(n, np.nan), np.full((n, n), np.nan)
    idx = np.flatnonzero(free)
    if idx.size == 0:
        return se, corr
    _, s, vt = np.linalg.svd(jac[:, idx], full_matrices=False)
    with np.errstate(divide="ignore"):
        inv_s2 = np.where(s > 0, 1.0 / s**2, np.inf)
    cov = (vt.T * inv_s2) @ vt
    se[idx] = np.sqrt(np.abs(np.diag(cov)))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr[np.ix_(idx, idx)] = cov / np.outer(se[idx], se[idx])
    return se, corr


def _free_parameters(design: Design, free: Sequence[str]) -> tuple[list[str], FloatArray]:
    names = [n.strip() for n in free if n.strip()]
    if not names:
        raise InputDataError("no free parameter given")
    # DesignError for an unknown name
    shared = shared_parameter((name, design.addressed(name)) for name in names)
    if shared is not None:
        first, name, match = shared
        raise InputDataError(
            f"free parameters {first!r} and {name!r} both address {match!r}" + tied_note(match)
        )
    return names, np.array([design.parameter(n) for n in names])


class _Problem:
    """Weighted residuals as a function of relative parameters."""

    def __init__(
        self, design: Design, rows: MeasurementRows, names: list[str], p0: FloatArray
    ) -> None:
        self.design, self.rows, self.names, self.p0 = design, rows, names, p0
        self.scale = np.where(p0 != 0, np.abs(p0), 1.0)
        self.stiff = np.array(
            [
                _stiffness_like(design.parameter_unit(n)) and v > 0
                for n, v in zip(names, p0, strict=True)
            ]
        )
        self.mask = rows.measured
        self._cache: dict[bytes, FloatArray] = {}

    def design_at(self, p: FloatArray) -> Design:
        return self.design.with_parameters(dict(zip(self.names, map(float, p), strict=True)))

    def predict(self, p: FloatArray) -> FloatArray:
        key = np.asarray(p, dtype=float).tobytes()
        if key not in self._cache:
            design = self.design_at(p)
            self._cache[key] = predict_twists(
                design, self.rows.poses, self.rows.wrenches, self.rows.labels
            )
        return self._cache[key]

    def weighted(self, predicted: FloatArray) -> FloatArray:
        r = (predicted - self.rows.twists) / self.rows.sigmas
        return np.asarray(r[self.mask])

    def residuals(self, theta: FloatArray) -> FloatArray:
        return self.weighted(self.predict(theta * self.scale))

    def jacobian(self, theta: FloatArray) -> FloatArray:
        """Forward-difference Jacobian of :meth:`residuals` (relative step FIT_STEP)."""
        r = self.residuals(theta)
        jac = np.zeros((r.size, theta.size))
        for j in range(theta.size):
            step = FIT_STEP * max(abs(theta[j]), 1.0)
            t = theta.copy()
            t[j] += step
            jac[:, j] = (self.residuals(t) - r) / step
        return jac

    def du_dtheta(self, theta: FloatArray) -> FloatArray:
        """Derivative of the linear start's variables u by theta (n,)."""
        return np.where(self.stiff, -1.0 / np.where(self.stiff, theta, 1.0) ** 2, 1.0)

    def p_from_u_inverse(self, p: FloatArray) -> FloatArray:
        """The linear start's variables u of parameters p (inverse of p_from_u)."""
        return np.asarray(
            np.where(
                self.stiff, self.p0 / np.where(self.stiff, p, 1.0), 1 + (p - self.p0) / self.scale
            )
        )

    def p_from_u(self, u: FloatArray) -> FloatArray:
        """Parameters from the linear start's variables (compliances for stiffnesses)."""
        compliance = self.p0 / np.where(self.stiff, u, 1.0)
        return np.asarray(np.where(self.stiff, compliance, self.p0 + self.scale * (u - 1)))

    def linear_jacobian(self) -> tuple[FloatArray, FloatArray]:
        """Residuals at the catalogue (m,) and their forward-difference Jacobian in u."""
        r0 = self.weighted(self.predict(self.p0))
        jac = np.zeros((r0.size, len(self.names)))
        for j in range(len(self.names)):
            u = np.ones(len(self.names))
            u[j] += LINEAR_STEP
            jac[:, j] = (self.weighted(self.predict(self.p_from_u(u))) - r0) / LINEAR_STEP
        return r0, jac


def _check_identifiable(
    problem: _Problem, jac_theta: FloatArray, fix: bool
) -> tuple[list[int], list[str]]:
    """Indices of the parameters kept and names of those fixed (or raise)."""
    keep = list(range(len(problem.names)))
    fixed: list[str] = []
    while keep:
        names = [problem.names[k] for k in keep]
        weak = unidentifiable(combinations(jac_theta[:, keep], names))
        if not weak:
            break
        if not fix:
            text = "; ".join(
                f"{c.describe()} (relative 1-sigma "
                + ("inf" if math.isinf(c.relative_sigma) else f"{c.relative_sigma:.3g}")
                + ")"
                for c in weak
            )
            raise InputDataError(
                f"the measurements cannot separate these parameter combinations: {text}; "
                "measure more poses or load directions, free fewer parameters, or fix "
                "them at their catalogue values (--fix-unidentifiable)"
            )
        worst = min(weak, key=lambda c: c.singular_value)
        name = max(worst.weights, key=lambda n: abs(worst.weights[n]))
        fixed.append(name)
        keep.remove(problem.names.index(name))
    if not keep:
        raise InputDataError(
            "the measurements determine none of the free parameters (all fixed as "
            f"unidentifiable: {', '.join(fixed)})"
        )
    return keep, fixed


def identify(
    design: Design,
    rows: MeasurementRows,
    free: Sequence[str],
    *,
    fix_unidentifiable: bool = False,
) -> IdentificationResult:
    """Fit the ``free`` parameters to measured platform deflections (module doc).

    Parameters
    ----------
    design : Design
        Its values are the catalogue values (start, and where fixed parameters stay).
    rows : MeasurementRows
        From :func:`measurement_rows`.
    free : sequence of str
        Parameter names or globs (``calibrate --list-parameters``).
    fix_unidentifiable : bool
        Fix unidentifiable parameters at their catalogue values (with an
        :class:`IdentifiabilityWarning`) instead of refusing.

    Returns
    -------
    IdentificationResult

    Raises
    ------
    InputDataError
        Too few measured values (at least one more than free parameters), overlapping
        or unidentifiable parameters.
    DesignError
        An unknown parameter name, or a glob whose matches differ.
    UnreachablePoseError, SingularConfigurationError, EquilibriumError
        From the model at a measured pose.
    """
    from scipy.optimize import least_squares

    names, p0 = _free_parameters(design, free)
    if rows.n_values <= len(names):
        raise InputDataError(
            f"too few measurements: {rows.n_values} measured values for {len(names)} free "
            f"parameters (at least {len(names) + 1} needed)"
        )
    problem = _Problem(design, rows, names, p0)
    r0, jac_u = problem.linear_jacobian()
    # d theta / d u at the catalogue: -1 for a compliance, +1 otherwise
    jac_theta = jac_u * np.where(problem.stiff, -1.0, 1.0)[None, :]
    keep, fixed = _check_identifiable(problem, jac_theta, fix_unidentifiable)
    if fixed:
        warnings.warn(
            "fixed at their catalogue values, the measurements cannot determine them: "
            + ", ".join(fixed),
            IdentifiabilityWarning,
            stacklevel=2,
        )
        names = [names[k] for k in keep]
        p0 = p0[keep]
        problem = _Problem(design, rows, names, p0)
        jac_u = jac_u[:, keep]
    # 1. linear start in the compliances
    du = np.linalg.lstsq(jac_u, -r0, rcond=None)[0]
    lo_rel, hi_rel = RELATIVE_BOUNDS
    u_free = np.asarray(1.0 + du, dtype=float)
    u = np.asarray(
        np.where(problem.stiff, np.clip(u_free, 1 / hi_rel, 1 / lo_rel), u_free), dtype=float
    )
    start = problem.p_from_u(u)
    # 2. nonlinear least squares in relative parameters
    positive = p0 > 0
    lower = np.where(positive, lo_rel, -np.inf)
    upper = np.where(positive, hi_rel, np.inf)
    theta0 = np.clip(start / problem.scale, lower, upper)
    # a start moved by the bounds is not the linear least-squares minimum
    clipped = bool(np.any(u != u_free) or np.any(theta0 != start / problem.scale))
    # Where the model is linear in u (a determinate path, actuators locked), the
    # residuals at the start equal the linear model's and its Jacobian is exact there:
    # the fit then starts with it (and ends at once: the start is the minimum).
    r_start = problem.residuals(theta0)
    u0 = problem.p_from_u_inverse(theta0 * problem.scale)
    r_linear = r0 + jac_u @ (u0 - 1.0)
    linear = float(np.max(np.abs(r_start - r_linear))) <= LINEARITY_TOLERANCE * max(
        float(np.max(np.abs(r0))), 1.0
    )
    linear_jac = jac_u * problem.du_dtheta(theta0)[None, :]
    if linear and not clipped:
        # the linear solution is the least-squares minimum: no second stage
        theta, jac_final, nfev = theta0, linear_jac, 0
    else:
        fit = least_squares(
            problem.residuals,
            theta0,
            jac=problem.jacobian,
            bounds=(lower, upper),
            x_scale=1.0,
            ftol=1e-10,
            xtol=1e-10,
            gtol=1e-10,
            max_nfev=200,
        )
        theta, jac_final, nfev = fit.x, np.asarray(fit.jac), int(fit.nfev)
    values = theta * problem.scale
    at_bound = _at_bound(names, theta, lower, upper)
    inside = np.array([n not in at_bound for n in names])
    # an estimate at a bound has no valid sigma, nor a combination that weighs on it
    final = combinations(jac_final[:, inside], [n for n in names if n not in at_bound])
    weak = unidentifiable(final)
    if weak:
        warnings.warn(
            "at the estimates the measurements hardly determine "
            + "; ".join(c.describe() for c in weak),
            IdentifiabilityWarning,
            stacklevel=2,
        )
    for name, side in at_bound.items():
        warnings.warn(bound_message(name, side), BoundWarning, stacklevel=2)
    se_theta, corr = _covariance(jac_final, inside)
    predicted = problem.predict(values)
    err = np.where(rows.measured, predicted - rows.twists, np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns: not measured
        rms = np.sqrt(np.nanmean(err**2, axis=0))
    weighted = problem.weighted(predicted)
    return IdentificationResult(
        design=problem.design_at(values),
        names=names,
        units=[design.parameter_unit(n) for n in names],
        catalogue=p0,
        start=start,
        values=values,
        standard_errors=se_theta * problem.scale,
        correlation=corr,
        residual_rms=rms,
        weighted_rms=float(np.sqrt(np.mean(weighted**2))),
        combinations=final,
        fixed=fixed,
        n_rows=rows.n_rows,
        n_values=rows.n_values,
        predicted=predicted,
        nfev=nfev,
        at_bound=at_bound,
    )


__all__ = [
    "BOUND_PROXIMITY",
    "MAX_RELATIVE_SIGMA",
    "RELATIVE_BOUNDS",
    "RANK_RATIO",
    "TWIST_COMPONENTS",
    "BoundWarning",
    "Combination",
    "IdentifiabilityWarning",
    "IdentificationResult",
    "MeasurementRows",
    "combinations",
    "bound_message",
    "identify",
    "measurement_rows",
    "predict_twists",
    "unidentifiable",
]
