"""Identify design parameters from a target stiffness matrix (bounded least squares).

A user with a measured or finite-element 6x6 stiffness matrix of their machine picks
the design parameters they do not know (``free``), gives bounds, and gets the values
that best reproduce the target, with the residuals and an honest statement of how well
each parameter is determined: the singular values of the Jacobian of the weighted
residuals with respect to the scaled parameters, the directions in parameter space
that the target cannot see (flat directions), and linearised standard deviations.

Residual of entry (i, j), i <= j: ``(K_ij(x) - T_ij) / sigma_ij``. ``sigma`` is the
uncertainty of the target entries in their own units; by default
``0.01 * sqrt(|T_ii T_jj|)`` (1 % of the natural scale of the entry, unit consistent).
For a printed matrix use half its last printed digit (the paper's (22): 5 N·m/rad, N
or N/m).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError, PPMStiffnessError
from ppm_stiffness.core.inputs import PRINTED_SYMMETRY_TOLERANCE, validate_stiffness_matrix
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import shared_parameter, tied_note
from ppm_stiffness.model import check_nonsingular, stiffness_at_pose

#: A singular value below this fraction of the largest marks a flat direction.
FLAT_RATIO = 1e-6
_UPPER = np.triu_indices(6)


@dataclass(frozen=True)
class CalibrationResult:
    """Outcome of :func:`calibrate` (SI units throughout).

    Attributes
    ----------
    design : Design
        The design with the fitted values.
    names : list of str
    initial, values, lower, upper, scales : ndarray, shape (n,)
        Start, fit, bounds, and the scales used to normalise the parameters.
    target, fitted : ndarray, shape (6, 6)
    sigma : ndarray, shape (6, 6)
    singular_values : ndarray, shape (n,)
        Of the Jacobian of the weighted residuals w.r.t. the scaled parameters.
    right_singular_vectors : ndarray, shape (n, n)
        Rows: directions in scaled-parameter space, same order as singular values.
    standard_deviations : ndarray, shape (n,)
        Linearised 1-sigma of each parameter (inf along flat directions).
    cost : float
        ``0.5 * sum(weighted residuals**2)``.
    at_bound : list of str
        Names of parameters that ended on a bound.
    """

    design: Design
    names: list[str]
    initial: FloatArray
    values: FloatArray
    lower: FloatArray
    upper: FloatArray
    scales: FloatArray
    target: FloatArray
    fitted: FloatArray
    sigma: FloatArray
    singular_values: FloatArray
    right_singular_vectors: FloatArray
    standard_deviations: FloatArray
    cost: float
    at_bound: list[str] = field(default_factory=list)

    @property
    def residuals(self) -> FloatArray:
        """``fitted - target``, shape (6, 6), in the units of each block."""
        return self.fitted - self.target

    @property
    def weighted_rms(self) -> float:
        """RMS of the weighted residuals over the upper triangle."""
        r = (self.residuals / self.sigma)[_UPPER]
        return float(np.sqrt(np.mean(r**2)))

    def flat_directions(self, ratio: float = FLAT_RATIO) -> list[dict[str, float]]:
        """Parameter combinations the target cannot determine.

        Each is a dict ``name -> component`` of a unit direction in scaled parameter
        space whose singular value is below ``ratio`` times the largest.
        """
        s = self.singular_values
        out = []
        for k in range(len(s)):
            if s[k] <= ratio * s[0]:
                vec = self.right_singular_vectors[k]
                out.append({n: float(v) for n, v in zip(self.names, vec, strict=True)})
        return out


def default_sigma(target: FloatArray) -> FloatArray:
    """1 % of ``sqrt(|T_ii T_jj|)`` per entry (see module doc)."""
    diag = np.sqrt(np.abs(np.diag(target)))
    return 0.01 * np.outer(diag, diag)


def default_bounds(name: str, value: float, unit: str = "") -> tuple[float, float]:
    """Bounds used when none are given: offsets +-0.5 m around their start, angles
    (``unit == "rad"``) +-pi around their start, positive parameters within a factor
    100 of their start."""
    key = name.rsplit(".", 1)[-1]
    if "offset" in key or key.startswith("centre"):
        return (value - 0.5, value + 0.5)
    if unit == "rad":
        return (value - np.pi, value + np.pi)
    if value > 0:
        return (value / 100.0, value * 100.0)
    return (value - 1.0, value + 1.0)


def evaluations_per_start(n_free: int) -> int:
    """Model evaluations one start of :func:`calibrate` is allotted for progress bars:
    its least-squares budget (``200 n_free`` steps) plus a 2-point finite-difference
    Jacobian (``n_free`` evaluations) per step. Most starts end well before it."""
    return 200 * n_free * (n_free + 1)


def _check_distinct(design: Design, names: list[str]) -> None:
    """Refuse two free parameters that set one (a linear actuator's ``locked_stiffness``
    and ``k_a``, :meth:`~ppm_stiffness.design.schema.Design.addressed`)."""
    shared = shared_parameter((name, design.addressed(name)) for name in names)
    if shared is not None:
        first, name, match = shared
        raise InputDataError(
            f"free parameters {first!r} and {name!r} both set {match!r}" + tied_note(match)
        )


def calibrate(
    design: Design,
    target: ArrayLike,
    free: Sequence[str],
    *,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    pose: ArrayLike | None = None,
    sigma: ArrayLike | float | None = None,
    starts: int = 1,
    seed: int = 0,
    model: Callable[[Design], FloatArray] | None = None,
    progress: Callable[[float], None] | None = None,
) -> CalibrationResult:
    """Fit the ``free`` parameters of ``design`` so that its stiffness matches ``target``.

    Parameters
    ----------
    design : Design
        Supplies the starting values and every fixed parameter.
    target : array_like, shape (6, 6)
        Target stiffness at ``pose`` (SI, at P, axes of F_b).
    free : sequence of str
        Dotted parameter names (``leg1.bearing_offset``...).
    bounds : mapping name -> (low, high), optional
        Missing names get :func:`default_bounds`.
    pose : array_like, shape (n_task,) or (6,), optional
        The design's task coordinates ((x, y, phi) [m, m, rad] for a planar design) or
        the full pose (x, y, z, rx, ry, rz) [m, rad] (:mod:`ppm_stiffness.poses`); the
        home pose if None.
    sigma : array_like (6, 6) or float, optional
        Uncertainty of the target entries; :func:`default_sigma` if None.
    starts : int
        Number of starting points: the design's values, then ``starts - 1`` uniform
        random points within the bounds (seeded). The lowest cost wins.
    seed : int
    model : callable, optional
        ``design -> K``; :func:`~ppm_stiffness.model.stiffness_at_pose` at ``pose``
        by default.
    progress : callable, optional
        Called with the number of model evaluations done since the last call; the
        total is :func:`evaluation_budget` ``(len(free), starts)``.

    Returns
    -------
    CalibrationResult
    """
    t = validate_stiffness_matrix(target, "target", PRINTED_SYMMETRY_TOLERANCE)
    try:
        check_nonsingular(t, " (target)")
    except PPMStiffnessError as exc:
        raise InputDataError(str(exc)) from None
    names = list(free)
    if not names:
        raise InputDataError("no free parameters given")
    if len(set(names)) != len(names):
        raise InputDataError("free parameters repeat a name")
    _check_distinct(design, names)
    x0 = np.array([design.parameter(n) for n in names])
    bnds = dict(bounds or {})
    unknown = set(bnds) - set(names)
    if unknown:
        raise InputDataError(f"bounds given for parameters that are not free: {sorted(unknown)}")
    units = [design.parameter_unit(n) for n in names]
    lo = np.array(
        [bnds.get(n, default_bounds(n, v, u))[0] for n, v, u in zip(names, x0, units, strict=True)]
    )
    hi = np.array(
        [bnds.get(n, default_bounds(n, v, u))[1] for n, v, u in zip(names, x0, units, strict=True)]
    )
    if np.any(lo >= hi):
        raise InputDataError("each bound must be (low, high) with low < high")
    for n in bnds:
        design.check_range(n, *bnds[n])
    x0 = np.clip(x0, lo, hi)
    if sigma is None:
        sig = default_sigma(t)
    else:
        sig = np.broadcast_to(np.asarray(sigma, dtype=float), (6, 6)).copy()
    if np.any(sig[_UPPER] <= 0) or not np.all(np.isfinite(sig)):
        raise InputDataError("sigma must be finite and > 0")
    scales = np.maximum(np.abs(x0), 1e-2 * (hi - lo))
    evaluate = model or (lambda d: stiffness_at_pose(d, pose))
    penalty = 1e6

    advance = progress or (lambda amount: None)
    calls = [0]  # model evaluations of the current start

    def residual(xs: FloatArray) -> FloatArray:
        calls[0] += 1
        advance(1)
        x = xs * scales
        try:
            k = evaluate(design.with_parameters(dict(zip(names, x, strict=True))))
        except PPMStiffnessError:
            return np.full(len(_UPPER[0]), penalty)
        return np.asarray(((k - t) / sig)[_UPPER])

    rng = np.random.default_rng(seed)
    candidates = [x0] + [rng.uniform(lo, hi) for _ in range(max(starts, 1) - 1)]
    best = None
    for start in candidates:
        from scipy.optimize import least_squares  # lazily: scipy is heavy to import

        sol = least_squares(
            residual,
            start / scales,
            bounds=(lo / scales, hi / scales),
            x_scale=1.0,
            xtol=1e-12,
            ftol=1e-12,
            gtol=1e-12,
            max_nfev=200 * len(names),
        )
        advance(max(evaluations_per_start(len(names)) - calls[0], 0))  # the start is done
        calls[0] = 0
        if best is None or sol.cost < best.cost:
            best = sol
    assert best is not None
    x = best.x * scales
    fitted_design = design.with_parameters(dict(zip(names, x, strict=True)))
    jac = np.asarray(best.jac)
    _, s, vt = np.linalg.svd(jac, full_matrices=False)
    s_full = np.zeros(len(names))
    s_full[: len(s)] = s
    vt_full = np.eye(len(names))
    vt_full[: vt.shape[0]] = vt
    finite = s_full > FLAT_RATIO * s_full[0]
    # Linearised covariance of the scaled parameters on the determined subspace;
    # a parameter with a visible share (> 5 %) of a flat direction is undetermined.
    var_scaled = (vt_full[finite] ** 2 / s_full[finite, None] ** 2).sum(axis=0)
    touched = (np.abs(vt_full[~finite]) > 0.05).any(axis=0)
    var_scaled = np.where(touched, np.inf, var_scaled)
    std = np.sqrt(var_scaled) * scales
    tol = 1e-6 * (hi - lo)
    at_bound = [
        n
        for n, v, a, b, eps in zip(names, x, lo, hi, tol, strict=True)
        if v - a < eps or b - v < eps
    ]
    return CalibrationResult(
        design=fitted_design,
        names=names,
        initial=x0,
        values=x,
        lower=lo,
        upper=hi,
        scales=scales,
        target=t,
        fitted=evaluate(fitted_design),
        sigma=sig,
        singular_values=s_full,
        right_singular_vectors=vt_full,
        standard_deviations=std,
        cost=float(best.cost),
        at_bound=at_bound,
    )
