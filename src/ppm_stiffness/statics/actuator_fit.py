"""Fitting the actuator law ``G = k_a delta^q`` (eq. 20) to force-displacement data.

The measured quantity with the noise is the force (a load cell reading against a set
displacement), so the fit is a nonlinear least-squares fit on the force,
``min sum (G_j - k_a |delta_j|^q sign(delta_j))^2``, not a straight line in log-log
space: taking logarithms would weight the small forces far too much and bias k_a
and q when the noise is additive. Standard errors come from the covariance
``s^2 (J^T J)^-1`` at the optimum (``s^2`` the residual variance, n - 2 degrees of
freedom); R^2 is computed on the force. The law is odd, so pulls and pushes can be
mixed.

Data file (CSV): ``#`` comment lines anywhere, then a header row naming the
columns with their unit, then one row per measurement::

    # any comment, e.g. where the data come from
    displacement_mm,force_N
    0.0100,3.36
    ...

The displacement column is ``displacement_mm`` or ``displacement_m``; the force
column is ``force_N``. Other columns are ignored. Displacements beyond
:data:`MAX_PLAUSIBLE_DISPLACEMENT` (10 mm) in the header's unit give an
:class:`ImplausibleDataWarning`: an actuator's compliant displacement under load is far
smaller, so millimetres under a ``displacement_m`` header are the likely mistake (the
fit would be off by a factor 1000^q in k_a).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.csvio import header_columns, read_numbered_csv

#: Displacement column names and their factor to metres.
DISPLACEMENT_COLUMNS = {"displacement_mm": 1e-3, "displacement_m": 1.0}
FORCE_COLUMN = "force_N"
#: Largest plausible compliant displacement of an actuator under load [m]: the paper's
#: Fig. 4(b) reaches 1 mm; beyond 10 mm the values are likely in another unit.
MAX_PLAUSIBLE_DISPLACEMENT = 0.01


class ImplausibleDataWarning(UserWarning):
    """Data whose values are physically implausible in the unit their header states."""


@dataclass(frozen=True)
class PowerLawFit:
    """Result of :func:`fit_power_law`.

    Attributes
    ----------
    k_a : float
        Generalised actuation stiffness [N/m^q].
    q : float
        Exponent [-].
    k_a_std, q_std : float
        Standard errors (square roots of the covariance diagonal).
    r_squared : float
        Coefficient of determination of the force.
    n : int
        Number of data points.
    residual_std : float
        Residual standard deviation of the force [N] (n - 2 degrees of freedom).
    correlation : float
        Correlation coefficient of the k_a and q estimates.
    """

    k_a: float
    q: float
    k_a_std: float
    q_std: float
    r_squared: float
    n: int
    residual_std: float
    correlation: float

    def as_dict(self) -> dict[str, float | int]:
        return {
            "k_a": self.k_a,
            "q": self.q,
            "k_a_std": self.k_a_std,
            "q_std": self.q_std,
            "r_squared": self.r_squared,
            "n": self.n,
            "residual_std": self.residual_std,
            "correlation": self.correlation,
        }


def power_law_force(displacement: ArrayLike, k_a: float, q: float) -> FloatArray:
    """Force [N] of the odd law ``sign(delta) k_a |delta|^q``, delta in metres."""
    d = np.asarray(displacement, dtype=float)
    return np.asarray(np.sign(d) * k_a * np.abs(d) ** q)


def _validate(displacement_m: ArrayLike, force_n: ArrayLike) -> tuple[FloatArray, FloatArray]:
    d = np.asarray(displacement_m, dtype=float)
    g = np.asarray(force_n, dtype=float)
    if d.ndim != 1 or g.shape != d.shape:
        raise InputDataError(
            f"displacement and force must be 1-D arrays of equal length, got {d.shape} "
            f"and {g.shape}"
        )
    if not (np.all(np.isfinite(d)) and np.all(np.isfinite(g))):
        raise InputDataError("displacements and forces must be finite")
    nonzero = d != 0
    if np.count_nonzero(nonzero) < 3 or np.unique(np.abs(d[nonzero])).size < 2:
        raise InputDataError(
            "fitting k_a and q needs at least 3 points with at least 2 distinct "
            "nonzero displacements"
        )
    return d, g


def _initial_guess(d: FloatArray, g: FloatArray) -> tuple[float, float]:
    """k_a, q from a straight line in log-log space (starting point only)."""
    ok = (d != 0) & (np.sign(d) * g > 0)
    if np.count_nonzero(ok) >= 2 and np.unique(np.abs(d[ok])).size >= 2:
        slope, intercept = np.polyfit(np.log(np.abs(d[ok])), np.log(np.abs(g[ok])), 1)
        q0 = float(np.clip(slope, 0.01, 2.0))
        return float(np.exp(intercept)), q0
    return max(float(np.max(np.abs(g))), 1e-6), 0.5


def fit_power_law(displacement_m: ArrayLike, force_n: ArrayLike) -> PowerLawFit:
    """Least-squares fit of ``G = k_a delta^q`` (eq. 20) with additive force noise.

    Parameters
    ----------
    displacement_m : array_like, shape (n,)
        Actuator rod displacements [m] (signed; the law is odd).
    force_n : array_like, shape (n,)
        Measured forces [N].

    Returns
    -------
    PowerLawFit

    Raises
    ------
    InputDataError
        Malformed arrays, too few points, or a fit that does not converge.
    """
    d, g = _validate(displacement_m, force_n)
    n = d.size
    ad = np.abs(d)
    sd = np.sign(d)
    log_ad = np.log(np.where(ad > 0, ad, 1.0))

    def residual(x: FloatArray) -> FloatArray:
        return np.asarray(sd * x[0] * ad ** x[1] - g)

    def jacobian(x: FloatArray) -> FloatArray:
        p = sd * ad ** x[1]
        return np.column_stack([p, x[0] * p * log_ad])

    k0, q0 = _initial_guess(d, g)
    # Fit in (k_a, q) with k_a scaled: x_scale="jac" keeps the problem well balanced.
    from scipy.optimize import least_squares  # lazily: scipy is heavy to import

    sol = least_squares(
        residual,
        np.array([k0, q0]),
        jac=jacobian,
        bounds=([0.0, 0.0], [np.inf, np.inf]),
        x_scale="jac",
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
        max_nfev=2000,
    )
    if sol.status <= 0:
        raise InputDataError(f"the power-law fit did not converge: {sol.message}")
    k_a, q = (float(v) for v in sol.x)
    r = residual(sol.x)
    ssr = float(r @ r)
    dof = n - 2
    jac = jacobian(sol.x)
    try:
        cov = np.linalg.inv(jac.T @ jac) * (ssr / dof if dof > 0 else np.nan)
    except np.linalg.LinAlgError:
        raise InputDataError("the data do not determine both k_a and q") from None
    k_std, q_std = (float(v) for v in np.sqrt(np.abs(np.diag(cov))))
    corr = float(cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1])) if k_std * q_std > 0 else 0.0
    sst = float(np.sum((g - g.mean()) ** 2))
    r2 = 1.0 - ssr / sst if sst > 0 else float("nan")
    return PowerLawFit(k_a, q, k_std, q_std, r2, n, float(np.sqrt(ssr / dof)), corr)


@dataclass(frozen=True)
class ForceDisplacementData:
    """Force-displacement measurements read from CSV (SI).

    Attributes
    ----------
    displacement_m : ndarray, shape (n,) [m]
    force_n : ndarray, shape (n,) [N]
    comments : list of str
        The ``#`` comment lines, without the ``#``.
    displacement_unit : str
        "mm" or "m", as the file stated.
    """

    displacement_m: FloatArray
    force_n: FloatArray
    comments: list[str]
    displacement_unit: str


def read_force_displacement(path: str | Path) -> ForceDisplacementData:
    """Read an actuator force-displacement CSV (format in the module docstring)."""
    p = Path(path)
    data = read_numbered_csv(p)
    comments, rows = data.comments, data.rows
    if not rows:
        raise InputDataError(f"{p}: no header row and no data")
    header = header_columns(p, rows[0])
    disp_cols = [c for c in header if c in DISPLACEMENT_COLUMNS]
    if len(disp_cols) != 1 or FORCE_COLUMN not in header:
        raise InputDataError(
            f"{p}: the header row must name one displacement column "
            f"({' or '.join(DISPLACEMENT_COLUMNS)}) and a '{FORCE_COLUMN}' column, "
            f"got {header}"
        )
    i_d, i_f = header.index(disp_cols[0]), header.index(FORCE_COLUMN)
    d: list[float] = []
    f: list[float] = []
    for lineno, row in zip(data.row_lines[1:], rows[1:], strict=True):
        if len(row) != len(header):
            raise InputDataError(
                f"{p}, line {lineno}: {len(row)} fields, the header has {len(header)}"
            )
        try:
            d.append(float(row[i_d]))
            f.append(float(row[i_f]))
        except ValueError:
            raise InputDataError(f"{p}, line {lineno}: not numeric: {row}") from None
    factor = DISPLACEMENT_COLUMNS[disp_cols[0]]
    d_m = np.array(d) * factor
    f_n = np.array(f)
    if not (np.all(np.isfinite(d_m)) and np.all(np.isfinite(f_n))):
        raise InputDataError(f"{p}: displacements and forces must be finite")
    unit = disp_cols[0].removeprefix("displacement_")
    _check_plausible(p, d_m, unit)
    return ForceDisplacementData(d_m, f_n, comments, unit)


def _check_plausible(path: Path, displacement_m: FloatArray, unit: str) -> None:
    """An :class:`ImplausibleDataWarning` for displacements beyond
    :data:`MAX_PLAUSIBLE_DISPLACEMENT` (module doc)."""
    if displacement_m.size == 0:
        return
    big = float(np.max(np.abs(displacement_m)))
    if big <= MAX_PLAUSIBLE_DISPLACEMENT:
        return
    limit_mm = 1e3 * MAX_PLAUSIBLE_DISPLACEMENT
    hint = (
        "if the values are in mm, name the column displacement_mm"
        if unit == "m"
        else "check the column's unit"
    )
    warnings.warn(
        f"{path}: displacements up to {big / (1.0 if unit == 'm' else 1e-3):.4g} {unit} "
        f"under a 'displacement_{unit}' header, where an actuator's compliant "
        f"displacement under load stays well below {limit_mm:g} mm: {hint} (the fit "
        "takes the header's unit)",
        ImplausibleDataWarning,
        stacklevel=3,
    )
