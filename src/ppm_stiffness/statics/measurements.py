"""Measured deflections: one reader for every command, and comparison with a model curve.

File format (CSV, UTF-8)::

    # free comments; "key: value" comments are kept as metadata, e.g.
    # mode: planar-force
    # alpha_deg: 45
    load,phi_z_deg,x_mm,y_mm
    1.0,0.0512,0.071,0.019
    ...

Every column carries its unit in its name; a component that was not measured is
absent. The columns:

- the load, for files of one loading mode (``deflect --measurements``): ``load`` (N, or
  N·m for the moment mode; also accepted as ``load_N`` / ``load_Nm``), with the mode
  (and ``alpha_deg``) in ``key: value`` comments; the modes ``direction`` and
  ``wrench`` take a ``direction: FX,FY,FZ,MX,MY,MZ`` line (N, N·m, as ``deflect
  --direction`` and ``--wrench``: normalised for ``direction``, the wrench of load 1
  for ``wrench``; ``deflect --csv`` writes it);
- or the applied wrench at P per row, axes of F_b: any of ``fx_N, fy_N, fz_N, mx_Nm,
  my_Nm, mz_Nm`` (an absent component is zero);
- the pose of P per row (optional): ``pose_x_mm, pose_y_mm, pose_z_mm, pose_rx_deg,
  pose_ry_deg, pose_rz_deg`` (R = Rz Ry Rx, :mod:`ppm_stiffness.core.pose`), rz also
  written ``pose_phi_deg`` (one of the two). A file with pose columns gives every task
  coordinate of the design (``x, y, rz`` for a planar design: the files of
  ``pose_x_mm, pose_y_mm, pose_phi_deg`` load as before; ``z, rx, ry`` for a tripod;
  all six for a hexapod); it may also give dependent coordinates, which must be the
  ones the legs impose (:func:`measured_poses`, to :data:`POSE_AGREEMENT`). Without
  pose columns every row is at the design's home pose;
- the measured displacement of P in F_b, from the unloaded pose: any of the twist
  components ``phi_x_deg, phi_y_deg, phi_z_deg`` [deg] and ``x_mm, y_mm, z_mm`` [mm];
- optional noise of each measured component (1 sigma, same unit): ``sigma_`` followed
  by the component's column name, e.g. ``sigma_x_mm``.

Every row gives every listed column (no empty or NaN cell). A file gives a load column
or wrench columns, not both: displacements need the load that made them. A ``mode``
metadata line, when present, must name a loading mode (``alpha_deg`` a number,
``direction`` six numbers) and agree with the loading mode and direction it is compared
with (:func:`check_mode`, before any computation). Errors about a row name the file
and the row's line number (1-based, as a text editor counts, header and comments
included).

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

import difflib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError, PPMStiffnessError
from ppm_stiffness.core.pose import POSE_COORDINATES
from ppm_stiffness.csvio import header_columns, read_numbered_csv
from ppm_stiffness.design import Design
from ppm_stiffness.statics.deflection import (
    CURVE_MODES,
    DIRECTION,
    DeflectionCurve,
    direction_wrench,
    mode_wrench,
)

#: Column name of each twist component in a measurement file, and its factor to SI.
COMPONENT_COLUMNS = ("phi_x_deg", "phi_y_deg", "phi_z_deg", "x_mm", "y_mm", "z_mm")
COMPONENT_FACTORS = (math.pi / 180,) * 3 + (1e-3,) * 3
#: Noise column of each twist component (same unit as the component).
SIGMA_COLUMNS = tuple(f"sigma_{c}" for c in COMPONENT_COLUMNS)
LOAD_COLUMNS = ("load", "load_N", "load_Nm")
#: Wrench columns in the library's order (m_x, m_y, m_z, f_x, f_y, f_z), SI already.
WRENCH_COLUMNS = ("mx_Nm", "my_Nm", "mz_Nm", "fx_N", "fy_N", "fz_N")
#: Pose columns in pose order (x, y, z, rx, ry, rz) and their factors to SI.
POSE_COLUMNS = (
    "pose_x_mm",
    "pose_y_mm",
    "pose_z_mm",
    "pose_rx_deg",
    "pose_ry_deg",
    "pose_rz_deg",
)
POSE_FACTORS = (1e-3,) * 3 + (math.pi / 180,) * 3
#: The other name of ``pose_rz_deg`` (phi = rz; the name of planar files).
PHI_COLUMN = "pose_phi_deg"
#: A dependent coordinate given in a file agrees with the one the legs impose when they
#: differ by at most this, in the column's unit (mm or deg), times max(1, |value|):
#: six significant digits, or 1e-5 mm / 1e-5 deg near zero.
POSE_AGREEMENT = 1e-5
#: The model's hinge stress columns ``deflect --csv`` writes for a design with notch
#: hinges: read back (a curve file is a measurement file) and ignored.
HINGE_COLUMNS = ("hinge_stress_max_MPa", "hinge_utilisation")
ALL_COLUMNS = (
    LOAD_COLUMNS
    + POSE_COLUMNS
    + (PHI_COLUMN,)
    + WRENCH_COLUMNS
    + COMPONENT_COLUMNS
    + SIGMA_COLUMNS
    + HINGE_COLUMNS
)
ORIENTATION = (0, 1, 2)
POSITION = (3, 4, 5)


def cli_order(wrench: ArrayLike) -> FloatArray:
    """A wrench (m, f) (6,) in the order of the CLI and the files: (f_x, f_y, f_z, m_x,
    m_y, m_z)."""
    w = np.asarray(wrench, dtype=float)
    return np.concatenate([w[3:], w[:3]])


def library_order(values: ArrayLike) -> FloatArray:
    """(f_x, f_y, f_z, m_x, m_y, m_z) (the CLI's order) as the library's (m, f)."""
    v = np.asarray(values, dtype=float)
    return np.concatenate([v[3:], v[:3]])


@dataclass(frozen=True)
class Measurements:
    """Measured platform deflections (SI).

    Attributes
    ----------
    loads : ndarray, shape (n,), or None
        [N, or N·m] for a file with a load column; None for a file of wrenches.
    twists : ndarray, shape (n, 6)
        (phi_x, phi_y, phi_z, x, y, z) [rad, m]; NaN where not measured.
    components : tuple of int
        Indices of the measured components.
    metadata : dict
        ``key: value`` comment lines.
    source : str
    poses : ndarray, shape (n, 6), or None
        (x, y, z, rx, ry, rz) [m, rad] of P per row as given, NaN for a coordinate the
        file does not give (:func:`measured_poses` completes them); None when the file
        gives no pose.
    wrenches : ndarray, shape (n, 6), or None
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P, axes of F_b, per row; None for
        a file with a load column.
    sigmas : ndarray, shape (n, 6)
        1-sigma noise of each component [rad, m]; NaN where not given.
    lines : tuple of int
        Line number in the file (1-based) of each row; empty when not read from a file.
    pose_columns : tuple of str
        The pose columns the file gives, in pose order (``pose_phi_deg`` as written).
    """

    loads: FloatArray | None
    twists: FloatArray
    components: tuple[int, ...]
    metadata: dict[str, str] = field(default_factory=dict)
    source: str = ""
    poses: FloatArray | None = None
    wrenches: FloatArray | None = None
    sigmas: FloatArray | None = None
    lines: tuple[int, ...] = ()
    pose_columns: tuple[str, ...] = ()

    @property
    def mode(self) -> str | None:
        return self.metadata.get("mode")

    def unit_wrench(self) -> FloatArray | None:
        """The wrench per unit load (6,) (m, f) that the file's mode states (its
        ``mode``, ``alpha_deg`` (default 45) and ``direction`` lines); None without a
        mode."""
        mode = self.mode
        if mode is None:
            return None
        if mode in (DIRECTION, "wrench"):
            w = library_order(_numbers(self.metadata["direction"]))
            return direction_wrench(w) if mode == DIRECTION else w
        return mode_wrench(mode, math.radians(float(self.metadata.get("alpha_deg", "45"))))

    def row_label(self, k: int) -> str:
        """``"FILE, line N"`` for row ``k`` (from 0) in errors; ``"FILE, data row k+1"``
        when the line numbers are not known."""
        if k < len(self.lines):
            return f"{self.source}, line {self.lines[k]}"
        return f"{self.source}, data row {k + 1}"

    @property
    def n(self) -> int:
        """Number of rows."""
        return int(self.twists.shape[0])

    def load_values(self) -> FloatArray:
        """The load column (n,), or InputDataError for a file of wrenches."""
        if self.loads is None:
            raise InputDataError(
                f"{self.source}: needs a load column (load, load_N or load_Nm) with a "
                "'# mode:' line for a deflection curve; this file gives a wrench per row"
            )
        return self.loads


def _nearest(name: str) -> str:
    close = difflib.get_close_matches(name, ALL_COLUMNS, n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _check_header(p: Path, header: list[str]) -> None:
    for c in header:
        if c not in ALL_COLUMNS:
            raise InputDataError(
                f"{p}: unknown column {c!r}{_nearest(c)}; columns carry their unit in the "
                f"name: {', '.join(LOAD_COLUMNS)}; {', '.join(POSE_COLUMNS)} "
                f"({PHI_COLUMN} = pose_rz_deg); {', '.join(WRENCH_COLUMNS)}; "
                f"{', '.join(COMPONENT_COLUMNS)}; sigma_ + a component"
            )
    present = set(header)
    loads = present & set(LOAD_COLUMNS)
    wrench = present & set(WRENCH_COLUMNS)
    if len(loads) > 1:
        raise InputDataError(f"{p}: more than one load column: {sorted(loads)}")
    if not present & set(COMPONENT_COLUMNS):
        raise InputDataError(
            f"{p}: no displacement column: give any of {', '.join(COMPONENT_COLUMNS)}"
        )
    if not loads and not wrench:
        raise InputDataError(
            f"{p}: displacements with no wrench: give the load that made them, as wrench "
            f"columns ({', '.join(WRENCH_COLUMNS)}) or a load column with a '# mode:' line"
        )
    if loads and wrench:
        raise InputDataError(
            f"{p}: give either a load column or wrench columns, not both "
            f"({sorted(loads)[0]} and {sorted(wrench)[0]})"
        )
    if PHI_COLUMN in present and "pose_rz_deg" in present:
        raise InputDataError(
            f"{p}: columns {PHI_COLUMN!r} and 'pose_rz_deg' are the same coordinate "
            "(phi = rz): give one"
        )
    for s, c in zip(SIGMA_COLUMNS, COMPONENT_COLUMNS, strict=True):
        if s in present and c not in present:
            raise InputDataError(f"{p}: column {s!r} without the component {c!r} it is for")


#: Measured displacements beyond this fraction of the design's size get a warning
#: (:func:`check_displacement_scale`); beyond the size itself they are refused.
LARGE_DISPLACEMENT_FRACTION = 0.1


def check_displacement_scale(meas: Measurements, size: float) -> None:
    """Measured positions (``x_mm``, ``y_mm``, ``z_mm``) against the design's size.

    A platform's deflection under load beyond the design's size (the largest distance
    between two of its joints) is not a deflection: values in um under an ``_mm``
    header are the likely slip, refused naming the column, the row and the value. Beyond
    :data:`LARGE_DISPLACEMENT_FRACTION` of it an
    :class:`~ppm_stiffness.statics.actuator_fit.ImplausibleDataWarning` (as
    ``fit-actuator`` gives for a ``displacement_m`` column in mm): a compliant
    mechanism may deflect that far, but rarely.

    Parameters
    ----------
    meas : Measurements
    size : float
        The design's size [m] (> 0).

    Raises
    ------
    InputDataError
        A measured position beyond ``size``.
    """
    import warnings

    from ppm_stiffness.statics.actuator_fit import ImplausibleDataWarning

    pos = np.abs(meas.twists[:, POSITION])
    if not np.any(np.isfinite(pos)):
        return
    k, j = np.unravel_index(int(np.nanargmax(pos)), pos.shape)
    big, column = float(pos[k, j]), COMPONENT_COLUMNS[POSITION[int(j)]]
    value = f"{column} = {1e3 * meas.twists[k, POSITION[int(j)]]:g} mm"
    if big > size:
        raise InputDataError(
            f"{meas.row_label(int(k))}: {value}, beyond the design's size "
            f"({1e3 * size:.3g} mm, the largest distance between two joints): not a "
            f"deflection; the column takes mm (if these are um, divide by 1000)"
        )
    if big > LARGE_DISPLACEMENT_FRACTION * size:
        warnings.warn(
            f"{meas.row_label(int(k))}: {value}, more than "
            f"{LARGE_DISPLACEMENT_FRACTION:.0%} of the design's size ({1e3 * size:.3g} "
            "mm): check the column's unit (mm)",
            ImplausibleDataWarning,
            stacklevel=2,
        )


def read_measurements(path: str | Path) -> Measurements:
    """Read a measurement CSV (format in the module docstring).

    Raises
    ------
    InputDataError
        Missing file; unknown or duplicated column; no displacement column; no load or
        wrench column (displacements with no wrench); both pose_phi_deg and
        pose_rz_deg; a sigma column without its component; a row of the wrong length;
        an empty, non-numeric or non-finite value (the column is named); a negative
        load or a sigma <= 0; no data row; a malformed ``mode``, ``alpha_deg`` or
        ``direction`` line (or none with mode direction or wrench).
    """
    p = Path(path)
    data = read_numbered_csv(p)
    metadata = _metadata(p, data.comments, data.comment_lines)
    rows, lines = data.rows, data.row_lines[1:]
    if len(rows) < 2:
        raise InputDataError(f"{p}: needs a header row and at least one data row")
    header = header_columns(p, rows[0])
    _check_header(p, header)
    values = np.full((len(rows) - 1, len(header)), np.nan)
    for k, row in enumerate(rows[1:]):
        where = f"{p}, line {lines[k]}"
        if len(row) != len(header):
            raise InputDataError(f"{where}: {len(row)} fields, the header has {len(header)}")
        for j, v in enumerate(row):
            try:
                values[k, j] = float(v)
            except ValueError:
                raise InputDataError(
                    f"{where}, column {header[j]!r}: "
                    f"{'empty' if not v.strip() else repr(v.strip()) + ' is not numeric'}"
                ) from None
            if not math.isfinite(values[k, j]):
                raise InputDataError(
                    f"{where}, column {header[j]!r}: {v.strip()} (every value must be finite)"
                )
    col = {c: values[:, j] for j, c in enumerate(header)}
    n = values.shape[0]
    loads = next((col[c] for c in LOAD_COLUMNS if c in col), None)
    if loads is not None and np.any(loads < 0):
        k = int(np.argmax(loads < 0))
        raise InputDataError(f"{p}, line {lines[k]}: load {loads[k]:g}: loads must be >= 0")
    twists = np.full((n, 6), np.nan)
    sigmas = np.full((n, 6), np.nan)
    comp = []
    for i, (c, s) in enumerate(zip(COMPONENT_COLUMNS, SIGMA_COLUMNS, strict=True)):
        if c in col:
            comp.append(i)
            twists[:, i] = col[c] * COMPONENT_FACTORS[i]
        if s in col:
            if np.any(col[s] <= 0):
                k = int(np.argmax(col[s] <= 0))
                raise InputDataError(
                    f"{p}, line {lines[k]}, column {s!r}: {col[s][k]:g}: every sigma must be > 0"
                )
            sigmas[:, i] = col[s] * COMPONENT_FACTORS[i]
    poses = None
    given: list[str] = []
    for i, (c, f) in enumerate(zip(POSE_COLUMNS, POSE_FACTORS, strict=True)):
        name = PHI_COLUMN if c == "pose_rz_deg" and PHI_COLUMN in col else c
        if name in col:
            if poses is None:
                poses = np.full((n, 6), np.nan)
            poses[:, i] = col[name] * f
            given.append(name)
    wrenches = None
    if loads is None:
        wrenches = np.column_stack([col.get(c, np.zeros(n)) for c in WRENCH_COLUMNS])
    return Measurements(
        loads,
        twists,
        tuple(comp),
        metadata,
        str(p),
        poses,
        wrenches,
        sigmas,
        tuple(lines),
        tuple(given),
    )


def _numbers(text: str) -> list[float]:
    """Six comma-separated numbers (a ``direction`` line), or ValueError."""
    values = [float(v) for v in text.split(",")]
    if len(values) != 6 or not all(math.isfinite(v) for v in values) or not any(values):
        raise ValueError(text)
    return values


def measured_poses(design: Design, measurements: Measurements) -> FloatArray:
    """Full poses (n, 6) [m, rad] of the rows: the file's task coordinates completed by
    the legs (:func:`ppm_stiffness.poses.full_poses`); the home pose for every row of a
    file without pose columns.

    Raises
    ------
    InputDataError
        A task coordinate of the design without its column (the message names the
        design's task coordinates and their columns); a dependent coordinate given
        that differs from the one the legs impose by more than :data:`POSE_AGREEMENT`
        (the file and the row's line named).
    UnreachablePoseError
        A row's pose that no configuration of the legs reaches (file and line named).
    """
    from ppm_stiffness.poses import full_pose, full_poses, home_pose, task_indices

    n = measurements.n
    if measurements.poses is None:
        return np.tile(home_pose(design), (n, 1))
    given = np.all(np.isfinite(measurements.poses), axis=0)
    task = task_indices(design)

    def column(i: int) -> str:
        return PHI_COLUMN if i == 5 and design.planar else POSE_COLUMNS[i]

    missing = [i for i in task if not given[i]]
    if missing:
        names = ", ".join(design.task_coordinates)
        columns = ", ".join(column(i) for i in task)
        raise InputDataError(
            f"{measurements.source}: missing column {column(missing[0])!r}: the pose "
            f"columns give every task coordinate of this design ({names}: {columns}; "
            "the others follow from the legs)"
        )
    values = measurements.poses[:, list(task)]
    poses, ok = full_poses(design, values)
    for bad in np.flatnonzero(~np.asarray(ok, dtype=bool)).tolist():
        try:
            full_pose(design, values[bad])
        except PPMStiffnessError as exc:
            raise type(exc)(f"{measurements.row_label(bad)}: {exc}") from None
    factors = np.array([1.0 / f for f in POSE_FACTORS])  # SI to the columns' units
    written = {
        5 if c == PHI_COLUMN else POSE_COLUMNS.index(c): c for c in measurements.pose_columns
    }
    for i in (j for j in range(6) if given[j] and j not in task):
        file_value = measurements.poses[:, i] * factors[i]
        imposed = poses[:, i] * factors[i]
        off = np.abs(file_value - imposed) > POSE_AGREEMENT * np.maximum(np.abs(imposed), 1.0)
        if np.any(off):
            k = int(np.argmax(off))
            name = written[i]
            unit = name.rsplit("_", 1)[1]
            raise InputDataError(
                f"{measurements.row_label(k)}: {name} = {file_value[k]:.10g} disagrees with "
                f"the legs, which impose {POSE_COORDINATES[i]} = {imposed[k]:.10g} {unit} "
                "there: the task coordinates of this design are "
                f"{', '.join(design.task_coordinates)} (the others follow from the legs)"
            )
    return np.asarray(poses)


def _metadata(path: Path, comments: list[str], lines: list[int]) -> dict[str, str]:
    """The ``key: value`` comments; a ``mode`` that names no loading mode or an
    ``alpha_deg`` that is not a finite number is refused with its line."""
    metadata: dict[str, str] = {}
    mode_line = 0
    for comment, line in zip(comments, lines, strict=True):
        key, sep, value = comment.partition(":")
        key, value = key.strip(), value.strip()
        if not (sep and key and " " not in key):
            continue
        metadata[key] = value
        if key == "mode" and value not in CURVE_MODES:
            raise InputDataError(
                f"{path}, line {line}: '# mode: {value}' names no loading mode; expected "
                f"one of {', '.join(CURVE_MODES)}"
            )
        if key == "mode":
            mode_line = line
        if key == "direction":
            try:
                _numbers(value)
            except ValueError:
                raise InputDataError(
                    f"{path}, line {line}: '# direction: {value}' is not six finite numbers "
                    "FX,FY,FZ,MX,MY,MZ, not all zero (N, N·m)"
                ) from None
        if key == "alpha_deg":
            try:
                finite = math.isfinite(float(value))
            except ValueError:
                finite = False
            if not finite:
                raise InputDataError(
                    f"{path}, line {line}: '# alpha_deg: {value}' is not a finite number "
                    "(the planar force's direction [deg])"
                )
    if metadata.get("mode") in (DIRECTION, "wrench") and "direction" not in metadata:
        raise InputDataError(
            f"{path}, line {mode_line}: '# mode: {metadata['mode']}' needs a "
            "'# direction: FX,FY,FZ,MX,MY,MZ' line (N, N·m)"
        )
    return metadata


def check_mode(
    measurements: Measurements,
    mode: str,
    alpha: float,
    unit_wrench: ArrayLike | None = None,
) -> None:
    """Raise if the measurements state a loading mode, or for a planar force a
    direction, other than ``mode`` and ``alpha`` [rad] (the model's), or for the modes
    direction and wrench a wrench per unit load other than ``unit_wrench`` (m, f):
    checked before a curve is computed, so that a wrong file is not read as a wrong
    load.

    Raises
    ------
    InputDataError
        Naming the file, the mode (or direction) it states and the one asked for.
    """
    stated = measurements.mode
    if stated is not None and stated != mode:
        raise InputDataError(
            f"{measurements.source}: the measurements are for mode {stated!r} (its "
            f"'# mode:' line), the model curve for {mode!r}"
        )
    text = measurements.metadata.get("alpha_deg")
    if text is not None and mode == "planar-force":
        a = float(text)
        if abs(a - math.degrees(alpha)) > 1e-6:
            raise InputDataError(
                f"{measurements.source}: the measurements are for alpha = {a:g} deg (its "
                f"'# alpha_deg:' line), the model curve for {math.degrees(alpha):g} deg"
            )
    if stated in (DIRECTION, "wrench") and unit_wrench is not None:
        mine = measurements.unit_wrench()
        theirs = np.asarray(unit_wrench, dtype=float)
        assert mine is not None
        if not np.allclose(mine, theirs, rtol=1e-9, atol=1e-12 * np.max(np.abs(theirs))):
            stated_text, asked_text = (
                ",".join(f"{v:g}" for v in cli_order(u)) for u in (mine, theirs)
            )
            raise InputDataError(
                f"{measurements.source}: the measurements are for the load per unit "
                f"{stated_text} (FX,FY,FZ,MX,MY,MZ; its '# direction:' line), the model "
                f"curve for {asked_text}"
            )


def check_compatible(curve: DeflectionCurve, measurements: Measurements) -> None:
    """Raise if the measurements state a mode, alpha or direction other than the
    curve's (:func:`check_mode`)."""
    check_mode(measurements, curve.mode, curve.alpha, curve.unit_wrench)


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
    loads = measurements.load_values()
    model = model_at_loads(curve, loads)
    tol = 1e-9 * max(float(curve.loads[-1]), 1e-300)
    exact = all(np.min(np.abs(curve.loads - x)) <= tol for x in loads)
    factors = np.array(COMPONENT_FACTORS)
    err = (model - measurements.twists) / factors  # deg and mm
    out: dict[str, Any] = {"n": int(loads.size), "interpolated": not exact}
    for key, group in (("orientation_deg", ORIENTATION), ("position_mm", POSITION)):
        cols = [i for i in group if i in measurements.components]
        out[key] = float(np.sqrt(np.mean(np.sum(err[:, cols] ** 2, axis=1)))) if cols else None
    out["components"] = {
        COMPONENT_COLUMNS[i]: float(np.sqrt(np.mean(err[:, i] ** 2)))
        for i in measurements.components
    }
    return out
