"""Uncertainty bands on any model output from parameter tolerances, and which
tolerance matters most.

An *output function* maps a design to an array of results of a fixed shape (K entries,
principal stiffnesses at poses, a map, a deflection curve), NaN where the design cannot
give one (an unreachable or singular pose); it may also raise a
:class:`~ppm_stiffness.core.errors.PPMStiffnessError` (the whole sample then counts
as failed). The tolerance variables z come from :mod:`ppm_stiffness.fit.tolerances`.

Methods:

``"first-order"``
    Linear propagation: ``sigma_y^2 = sum_j (dy/dz_j)^2 var(z_j)``, the derivatives by
    central differences (step :data:`FD_STEP` in z, i.e. 1 % of each tolerance's
    width); the band is nominal +- 2 sigma_y (labelled "±2σ, first order"). Cheap
    (two evaluations per variable) but wrong where y is far from linear within the
    tolerances: near a singularity, where a stiffness falls steeply to zero.
``"qmc"``
    Quasi-Monte Carlo: the output at N scrambled Sobol samples of z; the band is the
    5th to 95th percentile (labelled so). Right near singularities; the number of
    samples that failed (unreachable or singular: NaN or an error) is reported, per
    output and in total. Percentiles are over the samples that did not fail.

Sensitivity (both methods, from the first-order derivatives): the share of each
variable in the first-order variance, ``(dy/dz_j)^2 var(z_j) / sigma_y^2``.

A first-order band that reaches below an output's physical lower limit (a stiffness
below 0, ``lower_limit``) comes with a :class:`LinearisationWarning`: the tolerances
are then too wide for linear propagation and the band means nothing there; the QMC
method gives the band.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError, PPMStiffnessError
from ppm_stiffness.design import Design
from ppm_stiffness.fit.tolerances import (
    Z_VARIANCE,
    ToleranceVariable,
    design_at,
    sample_variables,
)

#: Propagation methods.
METHODS = ("first-order", "qmc")
#: Central-difference step in the tolerance variables z.
FD_STEP = 1e-2
#: Percentiles of the QMC band.
PERCENTILES = (5.0, 95.0)
#: Default number of QMC samples.
DEFAULT_SAMPLES = 64

OutputFunction = Callable[[Design], FloatArray]


class LinearisationWarning(UserWarning):
    """A first-order band reaches past an output's physical limit (a negative
    stiffness): the tolerances are too wide for linear propagation."""


@dataclass(frozen=True)
class Bands:
    """Uncertainty bands of an output (arrays of the output's shape, SI).

    Attributes
    ----------
    method : {"first-order", "qmc"}
    label : str
        What ``lower``/``upper`` are: "±2σ, first order" or "5th-95th percentile, QMC
        (N samples)".
    nominal, lower, upper : ndarray
    std : ndarray
        First-order sigma (first order), or the samples' standard deviation (QMC).
    samples : int
        Model evaluations of the band (QMC samples, or 2 per variable).
    failed : int
        Samples that were unreachable or singular somewhere (QMC); 0 for first order.
    failed_per_output : ndarray of int
        Per output, the samples that gave no value there.
    redrawn : int
        Tolerance values redrawn because they made a positive parameter <= 0 (QMC).
    labels : list of str
        The tolerance variables, in the order of ``derivatives``' first axis.
    derivatives : ndarray (n_variables, *shape)
        ``dy/dz_j`` (first-order, central differences).
    variances : ndarray (n_variables,)
        ``var(z_j)``.
    """

    method: str
    label: str
    nominal: FloatArray
    lower: FloatArray
    upper: FloatArray
    std: FloatArray
    samples: int
    failed: int
    failed_per_output: np.ndarray
    redrawn: int
    labels: list[str]
    derivatives: FloatArray
    variances: FloatArray

    def sensitivity(self) -> FloatArray:
        """Share of each variable in the first-order variance (n_variables, *shape)."""
        contrib = self.derivatives**2 * self.variances.reshape((-1,) + (1,) * self.nominal.ndim)
        total = contrib.sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.asarray(np.where(total > 0, contrib / total, 0.0))

    def ranking(self, index: tuple[int, ...] | int = ()) -> list[tuple[str, float]]:
        """Variables by their share of the variance of one output (largest first)."""
        share = self.sensitivity()[(slice(None),) + np.index_exp[index]]
        flat = np.asarray(share).reshape(len(self.labels), -1)
        mean = np.nanmean(flat, axis=1) if flat.shape[1] else np.zeros(len(self.labels))
        order = np.argsort(-mean)
        return [(self.labels[k], float(mean[k])) for k in order]


def _safe(output: OutputFunction, design: Design) -> FloatArray | None:
    try:
        return np.asarray(output(design), dtype=float)
    except PPMStiffnessError:
        return None


def derivatives(
    design: Design, variables: list[ToleranceVariable], output: OutputFunction, nominal: FloatArray
) -> FloatArray:
    """``dy/dz_j`` by central differences (n_variables, *shape); NaN where a perturbed
    design gives no value."""
    out = np.zeros((len(variables),) + nominal.shape)
    for j in range(len(variables)):
        values = []
        for sign in (1.0, -1.0):
            z = np.zeros(len(variables))
            z[j] = sign * FD_STEP
            y = _safe(output, design_at(design, variables, z))
            values.append(np.full(nominal.shape, np.nan) if y is None else y)
        out[j] = (values[0] - values[1]) / (2 * FD_STEP)
    return out


def propagate(
    design: Design,
    variables: list[ToleranceVariable],
    output: OutputFunction,
    method: str = "first-order",
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    progress: Callable[[float], None] | None = None,
    failed_value: ArrayLike | None = None,
    lower_limit: ArrayLike | None = None,
) -> Bands:
    """Bands of ``output`` under the tolerances (module doc).

    Parameters
    ----------
    design : Design
        The nominal design (catalogue values).
    variables : list of ToleranceVariable
    output : callable Design -> ndarray
    method : {"first-order", "qmc"}
    samples : int
        QMC samples (a power of 2 keeps Sobol's balance).
    seed : int
        Of the scrambled Sobol sequence.
    progress : callable(amount), optional
        Called with 1 after each model evaluation.
    failed_value : array_like, optional
        Broadcastable to the output's shape: the value an output takes in a QMC sample
        where the model gives none (unreachable or singular), e.g. 0 for a stiffness
        (a singular design has no stiffness in some direction). NaN entries, or None,
        leave such samples out of that output's percentiles; the band's label then
        says that they cover the successful samples only.
    lower_limit : array_like, optional
        Broadcastable to the output's shape: the smallest physical value of each output
        (0 for a stiffness; NaN: none). A first-order band below it gives a
        :class:`LinearisationWarning`.

    Raises
    ------
    InputDataError
        Unknown method, no variable, or too few samples.
    PPMStiffnessError
        From the nominal design (its output must exist).
    """
    if method not in METHODS:
        raise InputDataError(f"unknown tolerance method {method!r}; expected one of {METHODS}")
    if not variables:
        raise InputDataError("no tolerance variable")
    tick = progress or (lambda amount: None)
    nominal = np.asarray(output(design), dtype=float)
    var = np.array([Z_VARIANCE[v.distribution] for v in variables])
    deriv = derivatives(design, variables, output, nominal)
    tick(2 * len(variables))
    labels = [v.label for v in variables]
    if method == "first-order":
        std = np.sqrt(np.einsum("j,j...->...", var, deriv**2))
        failed_out = np.sum(~np.isfinite(deriv), axis=0)
        if lower_limit is not None:
            _warn_below_limit(nominal - 2 * std, nominal, lower_limit)
        return Bands(
            "first-order",
            "±2σ, first order",
            nominal,
            nominal - 2 * std,
            nominal + 2 * std,
            std,
            2 * len(variables),
            0,
            failed_out,
            0,
            labels,
            deriv,
            var,
        )
    z, redrawn = sample_variables(variables, samples, seed)
    values = np.full((samples,) + nominal.shape, np.nan)
    failed = 0
    for k in range(samples):
        y = _safe(output, design_at(design, variables, z[k]))
        tick(1)
        if y is None:
            failed += 1
            continue
        values[k] = y
        if not np.all(np.isfinite(y)[np.isfinite(nominal)]):
            failed += 1
    ok = np.isfinite(values)
    failed_out = np.sum(~ok, axis=0)
    left_out = failed_out
    if failed_value is not None:
        fill = np.broadcast_to(np.asarray(failed_value, dtype=float), nominal.shape)
        # failures ranked at their physical limit, where the nominal design has a value
        values = np.where(ok | ~np.isfinite(nominal), values, fill)
        left_out = np.sum(~np.isfinite(values), axis=0)
    left_out = np.where(np.isfinite(nominal), left_out, 0)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # outputs with no valid sample
        lower, upper = np.nanpercentile(values, PERCENTILES, axis=0)
        std = np.nanstd(values, axis=0)
    return Bands(
        "qmc",
        f"{PERCENTILES[0]:g}th-{PERCENTILES[1]:g}th percentile, QMC ({samples} samples)"
        + (", of the successful samples only" if np.any(left_out) else ""),
        nominal,
        np.asarray(lower),
        np.asarray(upper),
        np.asarray(std),
        samples,
        failed,
        failed_out,
        redrawn,
        labels,
        deriv,
        var,
    )


def _warn_below_limit(lower: FloatArray, nominal: FloatArray, limit: ArrayLike) -> None:
    """A :class:`LinearisationWarning` if a first-order lower bound is below the
    output's physical limit (where the nominal value is above it)."""
    import warnings

    floor = np.broadcast_to(np.asarray(limit, dtype=float), nominal.shape)
    with np.errstate(invalid="ignore"):
        below = np.isfinite(floor) & (nominal >= floor) & (lower < floor)
    if not np.any(below):
        return
    worst = np.unravel_index(np.argmin(np.where(below, lower - floor, np.inf)), below.shape)
    warnings.warn(
        f"the first-order band of {int(np.sum(below))} of {below.size} outputs reaches "
        "below its physical limit (a stiffness or frequency below zero, down to "
        f"{lower[worst]:.4g} for a nominal {nominal[worst]:.4g}): the tolerances are too "
        "wide for linear propagation and the band means nothing there; use the QMC method "
        "(--tolerance-method qmc)",
        LinearisationWarning,
        stacklevel=3,
    )


__all__ = [
    "DEFAULT_SAMPLES",
    "METHODS",
    "Bands",
    "LinearisationWarning",
    "OutputFunction",
    "derivatives",
    "propagate",
]
