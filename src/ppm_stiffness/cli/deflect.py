"""``ppm-stiffness deflect``: platform deflection along a growing load (Fig. 9-10), for
any design: the paper's modes, any wrench direction (``--direction``), or multiples of
a wrench (``--mode wrench``)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    add_design_argument,
    add_overwrite_argument,
    add_pose_arguments,
    add_safety_factor_argument,
    add_tool_point_argument,
    check_input_path,
    check_option_angle,
    check_option_length,
    check_output_path,
    console,
    design_size_mm,
    eng,
    json_document,
    load_design_arg,
    parse_floats,
    parse_wrench,
    pose_from_args,
    tool_point_from_args,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.tolerances import (
    add_tolerance_arguments,
    curve_uncertainty,
    print_curve_uncertainty,
    read_tolerance_args,
)
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.core.names import ANGLE_COORDINATES, POSE_COORDINATES
from ppm_stiffness.statics.modes import CURVE_MODES, DIRECTION, METHODS

if TYPE_CHECKING:  # at run time imported where used: --help needs none of them
    import numpy as np
    from rich.table import Table

    from ppm_stiffness.core.conventions import FloatArray
    from ppm_stiffness.design import Design
    from ppm_stiffness.statics.deflection import DeflectionCurve
    from ppm_stiffness.statics.measurements import Measurements
    from ppm_stiffness.statics.moving_deflection import CurveStop, MovingDeflection

#: Default largest load of each mode [N or N·m] ("direction": 10 N, 0.5 N·m for a pure
#: moment).
DEFAULT_MAX = {
    "planar-force": 10.0,
    "moment": 0.5,
    "vertical-force": 20.0,
    DIRECTION: 10.0,
    "wrench": 1.0,
}
CSV_COLUMNS = ("phi_x_deg", "phi_y_deg", "phi_z_deg", "x_mm", "y_mm", "z_mm")
_MAX_POINTS = 100_000
#: A measurement row's pose is the curve's when every coordinate agrees to this [m, rad].
POSE_MATCH = 1e-9
#: Legs whose actuator forces and stiffnesses share one table (more: one table each).
_ONE_TABLE_LEGS = 3


def _load_table(title: str, unit: str) -> Table:
    """A table whose first column is the load [``unit``]: two blanks between columns,
    so that six of eng()'s widest cells (``-123.4e-15``) leave the load (up to six
    characters) and its header whole at 80 columns."""
    from rich import box
    from rich.table import Table

    t = Table(
        title=title,
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
        collapse_padding=True,
    )
    t.add_column(f"load \\[{unit}]", justify="right")
    return t


def _twist_table(title: str, unit: str, loads: np.ndarray, twists: np.ndarray) -> Table:
    """The deflections (n, 6) [rad, m] at each load as a table in deg and mm, the
    components that are round-off along the curve printed as 0
    (:func:`~ppm_stiffness.visuals.deflection.round_off_as_zero`, the figure's rule)."""
    import numpy as np

    from ppm_stiffness.core.conventions import TWIST_COMPONENTS
    from ppm_stiffness.visuals.deflection import round_off_as_zero

    scale = np.array([180 / math.pi] * 3 + [1e3] * 3)
    t = _load_table(f"{title} (axes of F_b): rotations phi \\[deg], displacements \\[mm]", unit)
    for name in TWIST_COMPONENTS:
        t.add_column(name, justify="right", no_wrap=True)
    shown = round_off_as_zero(twists) if np.size(twists) else np.zeros((0, 6))
    for k, load in enumerate(loads):
        t.add_row(f"{load:g}", *(eng(v) for v in shown[k] * scale))
    return t


def _actuator_forces_shown(curve: DeflectionCurve) -> FloatArray:
    """The actuator forces (n, n_legs) [N, N·m if rotary] as the tables print them: a
    leg's forces are round-off, 0, when their largest |value| along the curve is at
    most :data:`~ppm_stiffness.core.decoupling.DECOUPLED_TOLERANCE` of the largest
    actuator force or length-balanced load (|f|, |m| / ``LENGTH_SCALE``): the rule of
    :func:`~ppm_stiffness.visuals.deflection.round_off_as_zero` for the twists, with the
    load as a floor (a load the legs' constraints carry whole leaves the actuators only
    round-off, 1e-15 N against 10 N)."""
    import numpy as np

    from ppm_stiffness.core.conventions import BALANCE
    from ppm_stiffness.core.decoupling import DECOUPLED_TOLERANCE

    g = np.asarray(curve.actuator_forces, dtype=float)
    big = np.max(np.abs(g), axis=0, initial=0.0)
    load = np.max(np.abs(np.asarray(curve.wrenches) * BALANCE), initial=0.0)
    return np.asarray(g * (big > DECOUPLED_TOLERANCE * max(float(np.max(big, initial=0.0)), load)))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_tool_point_argument(parser)
    parser.add_argument(
        "--mode",
        choices=CURVE_MODES,
        help="planar force at angle --alpha, pure moment m_z, vertical force f_z (Fig. 9, "
        "axes of F_b, any design), 'direction': a load along --direction, or 'wrench': "
        "multiples 0..--max of --wrench (default: 'direction' with --direction, else the "
        "measurement file's mode, else planar-force)",
    )
    parser.add_argument(
        "--direction",
        metavar="FX,FY,FZ,MX,MY,MZ",
        help="a load along this wrench direction [N, N·m], axes of F_b, at the tool point, "
        "normalised: the load is the force's magnitude [N] (the moment in proportion), "
        "or a pure moment's [N·m]",
    )
    parser.add_argument(
        "--alpha",
        type=float,
        metavar="DEG",
        help="with --mode planar-force: direction of the force in the xy plane [deg] "
        f"(default {DEFAULT_ALPHA_DEG:g}, Fig. 10a)",
    )
    parser.add_argument(
        "--wrench",
        metavar="FX,FY,FZ,MX,MY,MZ",
        help="with --mode wrench: the wrench of load 1 [N, N·m], axes of F_b, at the tool "
        "point (P by default)",
    )
    parser.add_argument(
        "--max",
        type=float,
        metavar="LOAD",
        help="largest load [N, N·m for moment] (default: 10 N, 0.5 N·m, 20 N; along "
        "--direction 10 N or 0.5 N·m; --mode wrench 1)",
    )
    parser.add_argument(
        "--step", type=float, metavar="LOAD", help="load step (default: --max / 20)"
    )
    parser.add_argument(
        "--method",
        choices=METHODS,
        default="integrate",
        help="integrate the tangent stiffness along the load (default), its closed form, "
        "or 'linear': the unloaded K (actuators locked) for every load. With --geometry "
        "moving it is the frozen curve's method; the moving curve solves the equilibrium "
        "with the actuator law exactly (as 'integrate' and 'closed-form' do), so 'linear' "
        "is refused there",
    )
    parser.add_argument("--k-a", type=float, metavar="N/m^q", help="override actuator k_a")
    parser.add_argument(
        "--threshold",
        type=float,
        metavar="MM",
        help="override the locked-branch threshold of eq. (21) [mm]; 0 with --q 1 makes a "
        "linear actuator of stiffness k_a",
    )
    parser.add_argument("--q", type=float, help="override actuator exponent q, in (0, 1]")
    parser.add_argument("--csv", metavar="FILE", help="write load and the six twist components")
    parser.add_argument("--plot", metavar="FIG", help="write a Fig. 10-like figure")
    parser.add_argument(
        "--measurements",
        metavar="FILE.csv",
        help="measured deflections to overlay and compare (RMS differences)",
    )
    parser.add_argument(
        "--geometry",
        choices=("frozen", "moving"),
        default="frozen",
        help="'frozen' keeps the geometry of the unloaded pose (the paper's model, "
        "default); 'moving' adds the curve with the platform and legs moving under the "
        "load (docs/statics.md), which stops where the load path loses stability",
    )
    add_safety_factor_argument(parser, "the hinge stress along the (frozen) curve (default 1)")
    add_tolerance_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI)")


def _load_grid(top: float, step: float) -> np.ndarray:
    import numpy as np

    if not (math.isfinite(top) and top > 0):
        raise InputDataError(f"--max must be a finite load > 0, got {top}")
    if not (math.isfinite(step) and step > 0):
        raise InputDataError(f"--step must be finite and > 0, got {step}")
    if step > top:
        raise InputDataError(
            f"--step {step:g} is larger than --max {top:g}: the curve would have no load "
            f"between 0 and --max; give --step <= {top:g} (default --max / 20)"
        )
    n = math.floor(top / step * (1 + 1e-12)) + 1
    if n > _MAX_POINTS:
        raise InputDataError(f"--max / --step gives {n} loads, more than {_MAX_POINTS}")
    grid = np.arange(n) * step
    return np.unique(np.append(grid[grid < top * (1 - 1e-12)], top))


def load_deflect_design(args: argparse.Namespace) -> Design:
    """The design with the actuator overrides (--k-a, --q, --threshold) applied."""
    design = load_design_arg(args)
    _check_threshold(args, design)
    overrides = {
        name: value
        for name, value in (
            ("actuator.k_a", args.k_a),
            ("actuator.q", args.q),
            (
                "actuator.threshold_displacement",
                None if args.threshold is None else args.threshold * 1e-3,
            ),
        )
        if value is not None
    }
    options = {
        "actuator.k_a": "--k-a",
        "actuator.q": "--q",
        "actuator.threshold_displacement": "--threshold",
    }
    for name, value in overrides.items():
        if name == "actuator.q" and "actuator.k_a" in overrides:
            continue  # --q 1 --k-a K: one stiffness, checked with it below
        try:
            design.check_value(name, value)
        except DesignError as exc:  # blame the option, not a design key
            text = f"{options[name]}: {exc}"
            if name == "actuator.threshold_displacement":  # the option is in mm, the key in m
                why = str(exc).split(": ", 1)[1].split("; did you mean")[0]
                text = f"--threshold {args.threshold:g} mm: {why}"
            raise InputDataError(text) from None
    if overrides:
        try:
            design = design.with_parameters(overrides)
        except DesignError as exc:
            raise InputDataError(f"{', '.join(options[n] for n in overrides)}: {exc}") from None
    return design


def parse_direction(text: str) -> np.ndarray:
    """``--direction FX,FY,FZ,MX,MY,MZ`` as the library's (m_x, m_y, m_z, f_x, f_y,
    f_z), not normalised; refused when zero."""
    import numpy as np

    values = parse_floats(text, 6, "--direction", "FX,FY,FZ,MX,MY,MZ")
    if not any(values):
        raise InputDataError(
            "--direction must not be zero: give the load's direction FX,FY,FZ,MX,MY,MZ"
        )
    return np.array(values[3:] + values[:3])


def _mode(args: argparse.Namespace, meas: Measurements | None) -> str:
    """The loading mode of the options (module doc), checked against --direction and
    --wrench."""
    if args.direction is not None:
        if args.mode not in (None, DIRECTION):
            raise InputDataError(
                f"--direction goes with --mode {DIRECTION} (the mode it implies), not "
                f"--mode {args.mode}"
            )
        mode = DIRECTION
    else:
        mode = args.mode or (meas.mode if meas is not None and meas.mode else "planar-force")
    if mode not in CURVE_MODES:
        raise InputDataError(f"unknown loading mode {mode!r}")
    if args.wrench is not None and mode != "wrench":
        raise InputDataError("--wrench goes with --mode wrench (and only with it)")
    return mode


#: Default --alpha [deg]: the planar force at 45 deg (Fig. 10a).
DEFAULT_ALPHA_DEG = 45.0


def _check_alpha(args: argparse.Namespace, mode: str) -> None:
    """--alpha finite, within +-360 deg, and given only with the planar force (the one
    mode it sets; any other ignored it); filled in with its default."""
    if args.alpha is None:
        args.alpha = DEFAULT_ALPHA_DEG
        return
    if not math.isfinite(args.alpha):
        raise InputDataError("--alpha must be finite")
    if mode != "planar-force":
        raise InputDataError(
            f"--alpha {args.alpha:g}: it sets the direction of the planar force, unused "
            f"with --mode {mode}; give it with --mode planar-force only"
        )
    check_option_angle("--alpha", args.alpha)


def _check_threshold(args: argparse.Namespace, design: Design) -> None:
    """--threshold [mm] finite and not beyond the design's size (an actuator's
    deflection cannot exceed it: a likely unit slip, um typed as mm;
    :func:`~ppm_stiffness.cli.common.check_option_length`)."""
    if args.threshold is None:
        return
    if not math.isfinite(args.threshold):
        raise InputDataError(f"--threshold must be finite, got {args.threshold}")
    check_option_length("--threshold", args.threshold, design_size_mm(design), factor=1)


def _check_pose(design: Design, meas: Measurements, pose: np.ndarray) -> None:
    """Refuse measurements whose pose columns give another pose than the curve's (they
    were ignored: a curve at the home pose was compared with rows measured elsewhere)."""
    import numpy as np

    if meas.poses is None:
        return
    from ppm_stiffness.poses import format_pose
    from ppm_stiffness.statics.measurements import measured_poses

    at = measured_poses(design, meas)
    off = np.flatnonzero(np.any(np.abs(at - pose) > POSE_MATCH, axis=1))
    if off.size:
        k = int(off[0])
        raise InputDataError(
            f"{meas.row_label(k)}: the measurements are at pose ({format_pose(at[k])}), "
            f"the model curve at ({format_pose(pose)}): give that pose with the pose "
            "options (--x, --y, --z, --rx, --ry, --rz, the design's task coordinates)"
        )


def compute(
    args: argparse.Namespace,
) -> tuple[DeflectionCurve, Measurements | None, MovingDeflection | None]:
    """The curve (and measurements) the command's options ask for; with ``--geometry
    moving`` also both curves of :func:`~ppm_stiffness.statics.moving_deflection
    .moving_deflection` (the first is then its frozen curve)."""
    import numpy as np

    from ppm_stiffness.statics.deflection import (
        deflection_curve,
        deflection_path,
        direction_wrench,
        mode_wrench,
    )
    from ppm_stiffness.statics.measurements import (
        check_displacement_scale,
        check_mode,
        read_measurements,
    )

    design = load_deflect_design(args)
    pose = pose_from_args(args, design)
    meas = None
    if args.measurements is not None:
        meas = read_measurements(check_input_path(args.measurements, "--measurements"))
        check_displacement_scale(meas, 1e-3 * design_size_mm(design))
    mode = _mode(args, meas)
    _check_alpha(args, mode)
    unit: np.ndarray | None = None
    if mode == DIRECTION:
        if args.direction is not None:
            unit = direction_wrench(parse_direction(args.direction))
        elif meas is not None and meas.mode == DIRECTION:
            unit = meas.unit_wrench()  # the file's '# direction:' line
        else:
            raise InputDataError(f"--mode {DIRECTION} needs --direction FX,FY,FZ,MX,MY,MZ")
    elif mode == "wrench":
        unit = parse_wrench(args.wrench)
        if unit is None and meas is not None and meas.mode == "wrench":
            unit = meas.unit_wrench()  # the file's '# direction:' line
        if unit is None:
            raise InputDataError("--mode wrench needs --wrench FX,FY,FZ,MX,MY,MZ")
        if not np.any(unit):
            raise InputDataError("--wrench must not be zero")
    if meas is not None:  # the file's mode, direction and pose, before any load
        check_mode(meas, mode, math.radians(args.alpha), unit)
        _check_pose(design, meas, pose)
    top = args.max
    if top is None:
        pure_moment = unit is not None and not np.any(unit[3:])
        top = DEFAULT_MAX["moment" if mode == DIRECTION and pure_moment else mode]
    loads = _load_grid(top, top / 20 if args.step is None else args.step)
    if meas is not None:
        measured = meas.load_values()
        loads = np.union1d(loads, measured[measured > 0])
    tool = tool_point_from_args(args, design)
    if getattr(args, "geometry", "frozen") == "moving":
        from ppm_stiffness.statics.moving_deflection import moving_deflection

        alpha = math.radians(args.alpha) if mode == "planar-force" else math.nan
        w_hat = unit if unit is not None else mode_wrench(mode, math.radians(args.alpha))
        both = moving_deflection(design, w_hat, loads, pose, args.method, mode, alpha, tool)
        return both.frozen, meas, both
    if unit is not None:
        curve = deflection_path(design, unit, loads, pose, args.method, mode, tool_point=tool)
    else:
        curve = deflection_curve(
            design, mode, loads, pose, math.radians(args.alpha), args.method, tool
        )
    return curve, meas, None


def _pose_text(curve: DeflectionCurve, fmt: str) -> str:
    """The pose as ``x = .. mm, y = .. mm, phi = .. deg`` for a planar design, else
    every coordinate (x, y, z mm; rx, ry, rz deg), each number formatted by ``fmt``."""

    p = curve.pose
    if curve.planar:
        return (
            f"x = {p[0] * 1e3:{fmt}} mm, y = {p[1] * 1e3:{fmt}} mm, "
            f"phi = {math.degrees(p[5]):{fmt}} deg"
        )
    return ", ".join(
        f"{name} = {math.degrees(v):{fmt}} deg"
        if name in ANGLE_COORDINATES
        else f"{name} = {v * 1e3:{fmt}} mm"
        for name, v in zip(POSE_COORDINATES, p, strict=True)
    )


def write_csv(
    curve: DeflectionCurve,
    path: str | Path,
    moving: MovingDeflection | None = None,
    hinges: dict[str, Any] | None = None,
    moving_hinges: dict[str, Any] | None = None,
) -> None:
    """Load and the six twist components (deg, mm), with the case in comments; with
    ``hinges`` (:func:`~ppm_stiffness.statics.hinge_stress.curve_stresses`) the largest
    hinge stress [MPa] and its utilisation after them; with ``moving`` the
    moving-geometry curve's six components and ``K_F_vs_K`` after them (``moving_``
    columns, and ``moving_hinge_stress_max_MPa``, ``moving_hinge_utilisation`` with
    ``moving_hinges``), a cell empty where a curve has stopped (such a file is not a
    measurement file)."""
    import numpy as np

    from ppm_stiffness.statics.measurements import HINGE_COLUMNS, cli_order

    if moving is not None:
        _write_both_csv(curve, moving, path, hinges, moving_hinges)
        return
    twist = curve.twists * np.array([180 / math.pi] * 3 + [1e3] * 3)
    lines = [
        "# ppm-stiffness deflect: platform deflection at the tool point "
        "({:g}, {:g}, {:g}) mm, platform frame (0,0,0 is P), axes of F_b, from the "
        "unloaded pose".format(*(1e3 * curve.tool_point)),
        f"# mode: {curve.mode}",
    ]
    if curve.mode == "planar-force":
        lines.append(f"# alpha_deg: {math.degrees(curve.alpha):.12g}")
    if curve.mode in (DIRECTION, "wrench"):  # the load per unit, so that it reads back
        lines.append("# direction: " + ",".join(f"{v:.17g}" for v in cli_order(curve.unit_wrench)))
    lines += [
        f"# method: {curve.method}",
        f"# pose: {_pose_text(curve, '.6g')}",
        f"# load unit: {curve.load_unit}; wrench per unit load (mx,my,mz,fx,fy,fz): "
        + ",".join(f"{v:.6g}" for v in curve.unit_wrench),
        "load," + ",".join(CSV_COLUMNS + (HINGE_COLUMNS if hinges is not None else ())),
    ]
    if hinges is not None:
        lines.insert(-1, _hinge_csv_comment(hinges))
    for k, (load, row) in enumerate(zip(curve.loads, twist, strict=True)):
        cells = [f"{v + 0.0:.9g}" for v in row] + _hinge_cells(hinges, k)
        lines.append(f"{load:.12g}," + ",".join(cells))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


def _hinge_csv_comment(hinges: dict[str, Any]) -> str:
    return (
        "# hinge_stress_max_MPa: the largest notch-hinge peak stress along the frozen curve "
        "(moving_: the moving curve); "
        f"hinge_utilisation: its stress / (yield / SF), SF = {hinges['safety_factor']:g}"
    )


def _hinge_cells(hinges: dict[str, Any] | None, k: int) -> list[str]:
    """The hinge columns of row k (none without hinges)."""
    if hinges is None:
        return []
    return [f"{hinges['stress'][k] * 1e-6 + 0.0:.9g}", f"{hinges['utilisation'][k] + 0.0:.9g}"]


def _write_both_csv(
    curve: DeflectionCurve,
    moving: MovingDeflection,
    path: str | Path,
    hinges: dict[str, Any] | None = None,
    moving_hinges: dict[str, Any] | None = None,
) -> None:
    import numpy as np

    from ppm_stiffness.statics.measurements import HINGE_COLUMNS

    scale = np.array([180 / math.pi] * 3 + [1e3] * 3)
    m = moving.moving
    loads = np.union1d(curve.loads, m.loads)
    lines = [
        "# ppm-stiffness deflect --geometry moving: the frozen-geometry curve (the paper's "
        "model) and the moving-geometry one (moving_ columns: the tool point's finite "
        "rotation vector and displacement), tool point ({:g}, {:g}, {:g}) mm, platform "
        "frame, axes of F_b".format(*(1e3 * curve.tool_point)),
        f"# mode: {curve.mode}",
        f"# method: {curve.method} (frozen)",
        f"# pose: {_pose_text(curve, '.6g')}",
        f"# load unit: {curve.load_unit}; wrench per unit load (mx,my,mz,fx,fy,fz): "
        + ",".join(f"{v:.6g}" for v in curve.unit_wrench),
        *(f"# {line}" for line in moving.stops()),
        *([_hinge_csv_comment(hinges)] if hinges is not None else []),
        "load,"
        + ",".join(CSV_COLUMNS)
        + ","
        + ",".join(f"moving_{c}" for c in CSV_COLUMNS)
        + ",K_F_vs_K"
        + "".join(f",{c}" for c in (HINGE_COLUMNS if hinges is not None else ()))
        + "".join(f",moving_{c}" for c in (HINGE_COLUMNS if moving_hinges is not None else ())),
    ]

    def cells(values: np.ndarray, at: np.ndarray, load: float, n: int) -> list[str]:
        k = np.flatnonzero(at == load)
        if k.size == 0:
            return [""] * n
        return [f"{v + 0.0:.9g}" for v in np.atleast_1d(values[int(k[0])])]

    for load in loads:
        row = cells(curve.twists * scale, curve.loads, load, 6)
        row += cells(m.twists * scale, m.loads, load, 6)
        row += cells(moving.stiffness_difference, m.loads, load, 1)
        if hinges is not None:
            at = np.flatnonzero(curve.loads == load)
            row += _hinge_cells(hinges, int(at[0])) if at.size else ["", ""]
        if moving_hinges is not None:
            at = np.flatnonzero(m.loads == load)
            row += _hinge_cells(moving_hinges, int(at[0])) if at.size else ["", ""]
        lines.append(f"{load:.12g}," + ",".join(row))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


def _print_moving(moving: MovingDeflection) -> None:
    """The moving-geometry curve and where the curves stop."""
    from rich.markup import escape

    m = moving.moving
    console.print(
        "[bold]geometry moving[/bold]: the equilibrium with the platform and legs moving "
        "under each load (docs/statics.md); finite rotation vector and displacement"
    )
    console.print(
        _twist_table(
            "moving geometry: deflection at the tool point", m.load_unit, m.loads, m.twists
        )
    )
    if m.loads.size:
        console.print(
            f"||K_F - K|| / ||K|| at the load {m.loads[-1]:g}: "
            f"{100 * moving.stiffness_difference[-1]:.3g} % (each load: --json, --csv)"
        )
    for line in moving.stops():
        console.print(escape(line))


#: SI units of the values of ``deflect --json``.
_JSON_UNITS = {
    "pose": "x, y, z [m], rx, ry, rz [rad] (phi = rz): the unloaded pose of P",
    "tool_point": "m (platform frame)",
    "alpha_deg": "deg (the direction of the planar force)",
    "load_direction": "N·m, N per unit load (m_x, m_y, m_z, f_x, f_y, f_z) at the tool point",
    "loads": "load_unit",
    "wrenches": "N·m, N (m_x, m_y, m_z, f_x, f_y, f_z) at the tool point",
    "twists": "rad, m (phi_x, phi_y, phi_z, x, y, z) of the tool point",
    "loaded_poses": "m, rad (x, y, z, rx, ry, rz) of P under each load",
    "actuator_forces": "N (N·m for a rotary actuator)",
    "actuator_stiffness": "N/m (N·m/rad for a rotary actuator)",
    "actuator_displacements": "m (rad for a rotary actuator)",
    "rms_differences": "orientation_deg deg, position_mm mm",
    "hinge_stress": "stress: Pa (the peak stress of the hinge nearest its allowed stress "
    "at each load of the frozen curve); utilisation: stress / (yield / safety_factor)",
    "moving_geometry": "twists: rad, m (the tool point's finite rotation vector and "
    "displacement); displaced_poses: m, rad of P; loads, wrenches and actuator values as "
    "above; stiffness_difference: ||K_F - K|| / ||K|| (length-balanced); stopped: load "
    "in load_unit; hinge_stress: as above, along the moving curve",
}


def _stop_json(stop: CurveStop | None) -> dict[str, Any] | None:
    if stop is None:
        return None
    margin = stop.margin
    return {
        "load": stop.load,
        "reason": stop.reason,
        "instability_load": stop.instability_load,
        "margin_factor": None if margin is None else margin.factor,
        "mode_direction": None if margin is None else margin.mode_name,
    }


def _moving_json(moving: MovingDeflection, hinges: dict[str, Any] | None = None) -> dict[str, Any]:
    """What ``--geometry moving`` adds: the moving curve and where each curve stops (and
    the hinge stress along it, ``hinges``: :func:`~ppm_stiffness.statics.hinge_stress
    .moving_curve_stresses`)."""
    m = moving.moving
    extra = {} if hinges is None else {"hinge_stress": hinges}
    return extra | {
        "loads": m.loads,
        "wrenches": m.wrenches,
        "twists": m.twists,
        "displaced_poses": moving.displaced_poses,
        "actuator_forces": m.actuator_forces,
        "actuator_stiffness": m.actuator_stiffness,
        "actuator_displacements": m.actuator_displacements,
        "stiffness_difference": moving.stiffness_difference,
        "stopped": _stop_json(moving.moving_stop),
        "frozen_stopped": _stop_json(moving.frozen_stop),
    }


def _json(
    curve: DeflectionCurve,
    rms: dict[str, Any] | None,
    moving: MovingDeflection | None = None,
    hinges: dict[str, Any] | None = None,
    moving_hinges: dict[str, Any] | None = None,
) -> dict[str, Any]:

    pose = {name: float(v) for name, v in zip(POSE_COORDINATES, curve.pose, strict=True)}
    extra = {} if moving is None else {"moving_geometry": _moving_json(moving, moving_hinges)}
    if hinges is not None:
        extra = extra | {"hinge_stress": hinges}
    return extra | {
        "geometry": "frozen" if moving is None else "moving",
        "mode": curve.mode,
        "alpha_deg": math.degrees(curve.alpha) if math.isfinite(curve.alpha) else None,
        "method": curve.method,
        "pose": pose | {"phi": pose["rz"]},
        "task_coordinates": list(curve.task_coordinates),
        "tool_point": curve.tool_point,
        "load_direction": curve.unit_wrench,
        "load_unit": curve.load_unit,
        "loads": curve.loads,
        "wrenches": curve.wrenches,
        "twists": curve.twists,
        "loaded_poses": curve.loaded_poses(),
        "actuator_forces": curve.actuator_forces,
        "actuator_stiffness": curve.actuator_stiffness,
        "actuator_displacements": curve.actuator_displacements,
        "rms_differences": rms,
    }


def _print_pose(curve: DeflectionCurve) -> None:
    """The unloaded pose: (x, y, phi) for a planar design; else the task coordinates,
    then the ones the legs complete (the parasitic motion)."""

    if curve.planar:
        console.print(f"pose: {_pose_text(curve, '.3f')}")
        return

    def text(names: list[str]) -> str:
        return ", ".join(
            f"{n} = {math.degrees(curve.pose[POSE_COORDINATES.index(n)]):.4f} deg"
            if n in ANGLE_COORDINATES
            else f"{n} = {curve.pose[POSE_COORDINATES.index(n)] * 1e3:.4f} mm"
            for n in names
        )

    task = list(curve.task_coordinates)
    head = "pose of P (R = Rz Ry Rx): "
    for start in range(0, len(task), 3):  # three coordinates a line
        console.print(head + text(task[start : start + 3]))
        head = "  "
    others = [n for n in POSE_COORDINATES if n not in task]
    if others:
        console.print(f"  parasitic (from the legs): {text(others)}")


def _print(curve: DeflectionCurve, rms: dict[str, Any] | None, moving: bool = False) -> None:
    """The frozen-geometry curve; ``moving``: the header says so (``--geometry moving``,
    whose curve :func:`_print_moving` prints after this one)."""
    import numpy as np

    c = console
    unit = curve.load_unit
    head = f"[bold]deflection, mode {curve.mode}"
    if curve.mode == "planar-force":
        head += f" (α = {math.degrees(curve.alpha):g}°)"
    geometry = "moving (the frozen curve first, then the moving one)" if moving else "frozen"
    c.print(head + f", method {curve.method}, geometry {geometry}[/bold]")
    _print_pose(curve)
    at = "T" if np.any(curve.tool_point) else "P"
    if at == "T":
        c.print(
            "tool point T (platform frame): ({:.3f}, {:.3f}, {:.3f}) mm".format(
                *(1e3 * curve.tool_point)
            )
        )
    if curve.mode in (DIRECTION, "wrench"):
        w = curve.unit_wrench
        c.print(f"load per {unit} (at {at}, axes of F_b):")
        c.print(
            f"  f = ({eng(w[3])}, {eng(w[4])}, {eng(w[5])}) N, "
            f"m = ({eng(w[0])}, {eng(w[1])}, {eng(w[2])}) N·m"
        )
    title = ("frozen geometry: " if moving else "") + f"platform deflection at {at}"
    c.print(_twist_table(title, unit, curve.loads, curve.twists))
    _print_actuators(curve)
    if rms is not None:
        o, q = rms["orientation_deg"], rms["position_mm"]
        c.print(
            f"RMS difference model - measured over {rms['n']} loads: orientation "
            f"{'n/a' if o is None else f'{o:.3f} deg'}, position "
            f"{'n/a' if q is None else f'{q:.3f} mm'}"
        )
        comps = ", ".join(f"{k} {v:.4f}" for k, v in rms["components"].items())
        c.print(f"  per component: {comps}")


def _print_hinges(curve: DeflectionCurve, hinges: dict[str, Any], geometry: str = "frozen") -> None:
    """The largest hinge stress at each load of ``curve`` and its utilisation."""
    from rich.markup import escape

    sf = hinges["safety_factor"]
    t = _load_table(
        f"notch hinges along the {geometry} curve: the hinge nearest yield / SF (SF = {sf:g})",
        curve.load_unit,
    )
    for name in ("stress \\[MPa]", "util.", "hinge"):
        t.add_column(name, justify="left" if name == "hinge" else "right", no_wrap=True)
    for k, load in enumerate(curve.loads):
        t.add_row(
            f"{load:g}",
            eng(hinges["stress"][k] * 1e-6),
            eng(hinges["utilisation"][k]),
            escape(hinges["hinge"][k] or "-"),
        )
    console.print(t)


def hinge_safety_factor(args: argparse.Namespace, design: Design) -> float | None:
    """The safety factor of the hinge stress along the curve (1 by default); None for a
    design without notch hinges or without every hinge's yield strength (where
    ``--safety-factor`` is refused)."""
    from ppm_stiffness.statics.hinge_stress import has_hinges, has_yield_strengths

    sf = args.safety_factor
    if not has_hinges(design):
        if sf is not None:
            raise InputDataError(
                "--safety-factor: the design has no notch hinge (a joint's hinge table)"
            )
        return None
    if not has_yield_strengths(design):
        if sf is not None:
            raise InputDataError("--safety-factor: a notch hinge's material has no yield_strength")
        return None
    if sf is not None and not (math.isfinite(sf) and sf > 0.0):
        raise InputDataError(f"--safety-factor {sf:g}: must be a positive number")
    return 1.0 if sf is None else float(sf)


def _print_actuators(curve: DeflectionCurve) -> None:
    """Actuator forces and tangent stiffnesses per leg: one table for up to three legs,
    one table each for more (so that six legs fit 80 columns)."""
    import numpy as np

    unit = curve.load_unit
    n_legs = curve.actuator_forces.shape[1]
    # a passive constraining leg has no actuator (zero force, infinite stiffness): no column
    legs = [i for i in range(n_legs) if np.any(np.isfinite(curve.actuator_stiffness[:, i]))]
    what = "force G \\[N] and tangent stiffness K \\[N/m] per leg"
    groups = [("G", _actuator_forces_shown(curve)), ("K", curve.actuator_stiffness)]
    tables = [groups] if n_legs <= _ONE_TABLE_LEGS else [[g] for g in groups]
    for n, group in enumerate(tables):
        if len(tables) == 1:
            title = f"actuators: {what} (N·m and N·m/rad for a rotary actuator)"
        elif n == 0:
            title = "actuator forces G \\[N] (N·m if rotary)"
        else:
            title = "actuator tangent stiffness K \\[N/m] (N·m/rad if rotary)"
        a = _load_table(title, unit)
        for name, _ in group:
            for i in legs:
                a.add_column(f"{name}{i + 1}", justify="right", no_wrap=True)
        for k, load in enumerate(curve.loads):
            a.add_row(f"{load:g}", *(eng(values[k][i]) for _, values in group for i in legs))
        console.print(a)
    passive = [str(i + 1) for i in range(n_legs) if i not in legs]
    if passive:
        console.print(f"leg(s) {', '.join(passive)}: passive (no actuator)")


def run(args: argparse.Namespace) -> int:
    from rich.markup import escape

    from ppm_stiffness.statics.hinge_stress import curve_stresses, moving_curve_stresses
    from ppm_stiffness.statics.measurements import rms_differences

    check_output_path(args.csv, "--csv", (".csv",), overwrite=args.overwrite)
    check_output_path(args.plot, "--plot", FIGURE_FORMATS, overwrite=args.overwrite)
    design = load_deflect_design(args)
    variables = read_tolerance_args(args, design)
    if args.geometry == "moving" and (variables is not None or args.measurements):
        raise InputDataError(
            "--tolerances and --measurements work with the frozen geometry only "
            "(leave out --geometry moving)"
        )
    if args.geometry == "moving" and args.method == "linear":
        raise InputDataError(
            "--method linear cannot be combined with --geometry moving: the moving curve "
            "solves the equilibrium with the actuator law, not with the unloaded K; use "
            "--method integrate or closed-form, or leave out --geometry moving"
        )
    sf = hinge_safety_factor(args, design)
    curve, meas, moving = compute(args)
    hinges = None if sf is None else curve_stresses(design, curve, sf)
    moving_hinges = (
        None if sf is None or moving is None else moving_curve_stresses(design, moving, sf)
    )
    rms = rms_differences(curve, meas) if meas is not None else None
    bands, unc = curve_uncertainty(args, design, variables, curve)
    with output_files(args.overwrite) as out:
        if args.csv:
            write_csv(curve, out.temp(args.csv, "--csv"), moving, hinges, moving_hinges)
        if args.plot:
            from ppm_stiffness.visuals import save_figure, use_headless_backend
            from ppm_stiffness.visuals.deflection import plot_deflection_curves

            use_headless_backend()
            if moving is None:
                fig = plot_deflection_curves([curve], meas, bands=[bands])
            else:  # one row: frozen solid, moving dashed
                fig = plot_deflection_curves([curve, moving.moving])
            save_figure(fig, out.temp(args.plot, "--plot"))
    if args.json:
        doc = _json(curve, rms, moving, hinges, moving_hinges) | (
            {} if unc is None else {"uncertainty": unc}
        )
        print(json_document("deflect", doc, _JSON_UNITS))
        return 0
    _print(curve, rms, moving is not None)
    if hinges is not None:
        _print_hinges(curve, hinges)
    if moving is not None:
        _print_moving(moving)
        if moving_hinges is not None:
            _print_hinges(moving.moving, moving_hinges, "moving")
    if unc is not None:
        print_curve_uncertainty(curve, unc)
    if args.csv:
        console.print(f"wrote {escape(args.csv)}")
    if args.plot:
        console.print(f"wrote {escape(args.plot)}")
    return 0
