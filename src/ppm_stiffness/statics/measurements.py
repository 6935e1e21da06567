"""Measured deflections: reading them and comparing them with a model curve.

File format (CSV, UTF-8)::

    # free comments; "key: value" comments are kept as metadata, e.g.
    # mode: planar-force
    # alpha_deg: 45
    load,phi_z_deg,x_mm,y_mm
    1.0,0.0512,0.071,0.019
    ...

The header row names the columns: ``load`` (N, or N·m for the moment mode; also
accepted as ``load_N`` / ``load_Nm``), then any subset of the twist components
``phi_x_deg, phi_y_deg, phi_z_deg`` [deg] and ``x_mm, y_mm, z_mm`` [mm] of the
platform centre P in F_b, measured from the unloaded pose. Every row must give every
listed column. A ``mode`` metadata line, when present, must agree with the loading
mode it is compared with.

RMS differences (what :func:`rms_differences` reports). For each load k, the
orientation error is the Euclidean norm of (model - measured) over the orientation
columns present, and the position error the norm over the position columns present;
each RMS is ``sqrt(mean_k error_k^2)``. With one column (phi_z for the camera's
planar modes, z for the dial indicator) it is the plain RMS of that component; with
x and y it is the RMS of the in-plane position error distance, which is how we read
the paper's "RMS based differences of the orientation/positioning errors". The RMS of
each component is reported too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.csvio import read_commented_csv
from ppm_stiffness.statics.deflection import DeflectionCurve

#: Column name of each twist component in a measurement file, and its factor to SI.
COMPONENT_COLUMNS = ("phi_x_deg", "phi_y_deg", "phi_z_deg", "x_mm", "y_mm", "z_mm")
COMPONENT_FACTORS = (math.pi / 180,) * 3 + (1e-3,) * 3
LOAD_COLUMNS = ("load", "load_N", "load_Nm")
ORIENTATION = (0, 1, 2)
POSITION = (3, 4, 5)


@dataclass(frozen=True)
class Measurements:
    """Measured platform deflections (SI).

    Attributes
    ----------
    loads : ndarray, shape (n,)
        [N, or N·m]
    twists : ndarray, shape (n, 6)
        (phi_x, phi_y, phi_z, x, y, z) [rad, m]; NaN where not measured.
    components : tuple of int
        Indices of the measured components.
    metadata : dict
        ``key: value`` comment lines.
    source : str
    """

    loads: FloatArray
    twists: FloatArray
    components: tuple[int, ...]
    metadata: dict[str, str] = field(default_factory=dict)
    source: str = ""

    @property
    def mode(self) -> str | None:
        return self.metadata.get("mode")


def read_measurements(path: str | Path) -> Measurements:
    """Read a measurement CSV (format in the module docstring).

    Raises
    ------
    InputDataError
        Missing file, unknown or duplicated column, missing load column, a row of
        the wrong length, a non-numeric or non-finite value, no data.
    """
    p = Path(path)
    comments, rows = read_commented_csv(p)
    metadata: dict[str, str] = {}
    for comment in comments:
        key, sep, value = comment.partition(":")
        if sep and key.strip() and " " not in key.strip():
            metadata[key.strip()] = value.strip()
    if len(rows) < 2:
        raise InputDataError(f"{p}: needs a header row and at least one data row")
    header = [c.strip() for c in rows[0]]
    allowed = LOAD_COLUMNS + COMPONENT_COLUMNS
    unknown = [c for c in header if c not in allowed]
    if unknown or len(set(header)) != len(header):
        raise InputDataError(
            f"{p}: columns must be one of {', '.join(LOAD_COLUMNS)} and any of "
            f"{', '.join(COMPONENT_COLUMNS)} (each once); got {header}"
        )
    load_cols = [i for i, c in enumerate(header) if c in LOAD_COLUMNS]
    comp = [COMPONENT_COLUMNS.index(c) for c in header if c in COMPONENT_COLUMNS]
    if len(load_cols) != 1 or not comp:
        raise InputDataError(f"{p}: needs one load column and at least one component column")
    values = np.full((len(rows) - 1, len(header)), np.nan)
    for k, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise InputDataError(
                f"{p}: data row {k + 1} has {len(row)} fields, the header has {len(header)}"
            )
        try:
            values[k] = [float(v) for v in row]
        except ValueError:
            raise InputDataError(f"{p}: data row {k + 1} is not numeric: {row}") from None
    if not np.all(np.isfinite(values)):
        raise InputDataError(f"{p}: every value must be finite")
    loads = values[:, load_cols[0]]
    if np.any(loads < 0):
        raise InputDataError(f"{p}: loads must be >= 0")
    twists = np.full((loads.size, 6), np.nan)
    for j, c in enumerate(header):
        if c in COMPONENT_COLUMNS:
            i = COMPONENT_COLUMNS.index(c)
            twists[:, i] = values[:, j] * COMPONENT_FACTORS[i]
    return Measurements(loads, twists, tuple(sorted(comp)), metadata, str(p))


def check_compatible(curve: DeflectionCurve, measurements: Measurements) -> None:
    """Raise if the measurements state a mode or alpha other than the curve's."""
    mode = measurements.mode
    if mode is not None and mode != curve.mode:
        raise InputDataError(
            f"{measurements.source}: measurements are for mode {mode!r}, the model curve "
            f"is {curve.mode!r}"
        )
    alpha = measurements.metadata.get("alpha_deg")
    if alpha is not None and curve.mode == "planar-force":
        try:
            a = float(alpha)
        except ValueError:
            raise InputDataError(f"{measurements.source}: alpha_deg is not a number") from None
        if abs(a - math.degrees(curve.alpha)) > 1e-6:
            raise InputDataError(
                f"{measurements.source}: measurements are for alpha = {a:g} deg, the model "
                f"curve for {math.degrees(curve.alpha):g} deg"
            )


def model_at_loads(curve: DeflectionCurve, loads: ArrayLike) -> FloatArray:
    """Model twists (m, 6) at ``loads``: exact where a curve load matches, else linear
    interpolation (t = 0 at zero load). Raises if a load lies beyond the curve."""
    x = np.asarray(loads, dtype=float)
    cl, ct = curve.loads, curve.twists
    if cl[0] > 0:
        cl = np.concatenate([[0.0], cl])
        ct = np.vstack([np.zeros(6), ct])
    tol = 1e-9 * max(float(cl[-1]), 1e-300)
    if np.any(x > cl[-1] + tol):
        raise InputDataError(
            f"measured loads reach {x.max():g}, beyond the model curve's {cl[-1]:g}"
        )
    return np.column_stack([np.interp(x, cl, ct[:, j]) for j in range(6)])


def rms_differences(curve: DeflectionCurve, measurements: Measurements) -> dict[str, Any]:
    """RMS differences between a model curve and measurements.

    Returns
    -------
    dict
        ``orientation_deg`` and ``position_mm``: RMS over loads of the norm of the
        orientation [deg] / position [mm] error over the measured columns (None when
        no such column was measured); ``components``: RMS of each measured column in
        its file unit; ``n``: number of loads; ``interpolated``: whether the model was
        interpolated between curve loads.
    """
    check_compatible(curve, measurements)
    model = model_at_loads(curve, measurements.loads)
    tol = 1e-9 * max(float(curve.loads[-1]), 1e-300)
    exact = all(np.min(np.abs(curve.loads - x)) <= tol for x in measurements.loads)
    factors = np.array(COMPONENT_FACTORS)
    err = (model - measurements.twists) / factors  # deg and mm
    out: dict[str, Any] = {"n": int(measurements.loads.size), "interpolated": not exact}
    for key, group in (("orientation_deg", ORIENTATION), ("position_mm", POSITION)):
        cols = [i for i in group if i in measurements.components]
        out[key] = float(np.sqrt(np.mean(np.sum(err[:, cols] ** 2, axis=1)))) if cols else None
    out["components"] = {
        COMPONENT_COLUMNS[i]: float(np.sqrt(np.mean(err[:, i] ** 2)))
        for i in measurements.components
    }
    return out
