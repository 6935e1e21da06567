"""``ppm-stiffness deflect``: platform deflection along a growing load (Fig. 9-10)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np
from rich import box
from rich.markup import escape
from rich.table import Table

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    add_design_argument,
    add_overwrite_argument,
    add_pose_arguments,
    add_tool_point_argument,
    check_input_path,
    check_output_path,
    console,
    eng,
    json_document,
    load_design_arg,
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
from ppm_stiffness.core.conventions import TWIST_COMPONENTS
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.statics.deflection import (
    LOAD_UNITS,
    METHODS,
    MODES,
    DeflectionCurve,
    deflection_curve,
    deflection_path,
)
from ppm_stiffness.statics.measurements import (
    Measurements,
    check_mode,
    read_measurements,
    rms_differences,
)

#: Default largest load of each mode [N or N·m].
DEFAULT_MAX = {"planar-force": 10.0, "moment": 0.5, "vertical-force": 20.0, "wrench": 1.0}
CSV_COLUMNS = ("phi_x_deg", "phi_y_deg", "phi_z_deg", "x_mm", "y_mm", "z_mm")
_MAX_POINTS = 100_000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_tool_point_argument(parser)
    parser.add_argument(
        "--mode",
        choices=MODES + ("wrench",),
        help="planar force at angle --alpha, pure moment m_z, vertical force f_z (Fig. 9), "
        "or 'wrench': multiples 0..--max of --wrench (default: the measurement file's "
        "mode, else planar-force)",
    )
    parser.add_argument(
        "--alpha",
        type=float,
        default=45.0,
        metavar="DEG",
        help="direction of the planar force in the xy plane [deg] (default 45, Fig. 10a)",
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
        help="largest load [N, N·m for moment] (default: 10 N, 0.5 N·m, 20 N, 1)",
    )
    parser.add_argument(
        "--step", type=float, metavar="LOAD", help="load step (default: --max / 20)"
    )
    parser.add_argument(
        "--method",
        choices=METHODS,
        default="integrate",
        help="integrate the tangent stiffness along the load (default), its closed form, "
        "or 'linear': the unloaded K (actuators locked) for every load",
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
    add_tolerance_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI)")


def _load_grid(top: float, step: float) -> np.ndarray:
    if not (math.isfinite(top) and top > 0):
        raise InputDataError(f"--max must be a finite load > 0, got {top}")
    if not (math.isfinite(step) and step > 0):
        raise InputDataError(f"--step must be finite and > 0, got {step}")
    n = math.floor(top / step * (1 + 1e-12)) + 1
    if n > _MAX_POINTS:
        raise InputDataError(f"--max / --step gives {n} loads, more than {_MAX_POINTS}")
    grid = np.arange(n) * step
    return np.unique(np.append(grid[grid < top * (1 - 1e-12)], top))


def load_deflect_design(args: argparse.Namespace) -> Design:
    """The design with the actuator overrides (--k-a, --q, --threshold) applied."""
    design = load_design_arg(args)
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
        try:
            design.check_value(name, value)
        except DesignError as exc:  # blame the option, not a design key
            raise InputDataError(f"{options[name]}: {exc}") from None
    if overrides:
        design = design.with_parameters(overrides)
    return design


def compute(args: argparse.Namespace) -> tuple[DeflectionCurve, Measurements | None]:
    """The curve (and measurements) the command's options ask for."""
    design = load_deflect_design(args)
    pose = pose_from_args(args, design)
    meas = None
    if args.measurements is not None:
        meas = read_measurements(check_input_path(args.measurements, "--measurements"))
    mode = args.mode or (meas.mode if meas is not None and meas.mode else "planar-force")
    if mode not in MODES + ("wrench",):
        raise InputDataError(f"unknown loading mode {mode!r}")
    if (mode == "wrench") != (args.wrench is not None):
        raise InputDataError("--wrench goes with --mode wrench (and only with it)")
    if not math.isfinite(args.alpha):
        raise InputDataError("--alpha must be finite")
    if meas is not None:  # the file's mode and direction, before any load is computed
        check_mode(meas, mode, math.radians(args.alpha))
    top = DEFAULT_MAX[mode] if args.max is None else args.max
    loads = _load_grid(top, top / 20 if args.step is None else args.step)
    if meas is not None:
        measured = meas.load_values()
        loads = np.union1d(loads, measured[measured > 0])
    if mode == "wrench":
        w = parse_wrench(args.wrench)
        assert w is not None
        if not np.any(w):
            raise InputDataError("--wrench must not be zero")
        curve = deflection_path(
            design, w, loads, pose, args.method, tool_point=tool_point_from_args(args, design)
        )
    else:
        curve = deflection_curve(
            design,
            mode,
            loads,
            pose,
            math.radians(args.alpha),
            args.method,
            tool_point_from_args(args, design),
        )
    return curve, meas


def write_csv(curve: DeflectionCurve, path: str | Path) -> None:
    """Load and the six twist components (deg, mm), with the case in comments."""
    twist = curve.twists * np.array([180 / math.pi] * 3 + [1e3] * 3)
    p = curve.pose
    lines = [
        "# ppm-stiffness deflect: platform deflection at the tool point "
        "({:g}, {:g}, {:g}) mm, platform frame (0,0,0 is P), axes of F_b, from the "
        "unloaded pose".format(*(1e3 * curve.tool_point)),
        f"# mode: {curve.mode}",
    ]
    if curve.mode == "planar-force":
        lines.append(f"# alpha_deg: {math.degrees(curve.alpha):.12g}")
    lines += [
        f"# method: {curve.method}",
        f"# pose: x = {p[0] * 1e3:.6g} mm, y = {p[1] * 1e3:.6g} mm, "
        f"phi = {math.degrees(p[2]):.6g} deg",
        f"# load unit: {curve.load_unit}; wrench per unit load (mx,my,mz,fx,fy,fz): "
        + ",".join(f"{v:.6g}" for v in curve.unit_wrench),
        "load," + ",".join(CSV_COLUMNS),
    ]
    for load, row in zip(curve.loads, twist, strict=True):
        lines.append(f"{load:.12g}," + ",".join(f"{v + 0.0:.9g}" for v in row))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


#: SI units of the values of ``deflect --json``.
_JSON_UNITS = {
    "pose": "x, y [m], phi [rad]",
    "alpha_deg": "deg (the direction of the planar force)",
    "loads": "load_unit",
    "wrenches": "N·m, N (m_x, m_y, m_z, f_x, f_y, f_z) at the tool point",
    "twists": "rad, m (phi_x, phi_y, phi_z, x, y, z) of the tool point",
    "actuator_forces": "N (N·m for a rotary actuator)",
    "actuator_stiffness": "N/m (N·m/rad for a rotary actuator)",
    "actuator_displacements": "m (rad for a rotary actuator)",
    "rms_differences": "orientation_deg deg, position_mm mm",
}


def _json(curve: DeflectionCurve, rms: dict[str, Any] | None) -> dict[str, Any]:
    return {
        "mode": curve.mode,
        "alpha_deg": math.degrees(curve.alpha) if math.isfinite(curve.alpha) else None,
        "method": curve.method,
        "pose": {"x": curve.pose[0], "y": curve.pose[1], "phi": curve.pose[2]},
        "load_unit": curve.load_unit,
        "loads": curve.loads,
        "wrenches": curve.wrenches,
        "twists": curve.twists,
        "actuator_forces": curve.actuator_forces,
        "actuator_stiffness": curve.actuator_stiffness,
        "actuator_displacements": curve.actuator_displacements,
        "rms_differences": rms,
    }


def _print(curve: DeflectionCurve, rms: dict[str, Any] | None) -> None:
    c = console
    unit = LOAD_UNITS.get(curve.mode, "1")
    head = f"[bold]deflection, mode {curve.mode}"
    if curve.mode == "planar-force":
        head += f" (α = {math.degrees(curve.alpha):g}°)"
    p = curve.pose
    c.print(head + f", method {curve.method}[/bold]")
    c.print(
        f"pose: x = {p[0] * 1e3:.3f} mm, y = {p[1] * 1e3:.3f} mm, "
        f"phi = {math.degrees(p[2]):.3f} deg"
    )
    scale = np.array([180 / math.pi] * 3 + [1e3] * 3)
    t = Table(
        title="platform deflection at P (axes of F_b): rotations phi \\[deg], displacements \\[mm]",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    t.add_column(f"load \\[{unit}]", justify="right")
    for name in TWIST_COMPONENTS:
        t.add_column(name, justify="right", no_wrap=True)
    for k, load in enumerate(curve.loads):
        t.add_row(f"{load:g}", *(eng(v) for v in curve.twists[k] * scale))
    c.print(t)
    n_legs = curve.actuator_forces.shape[1]
    a = Table(
        title="actuators: force G \\[N] and tangent stiffness K \\[N/m] per leg "
        "(N·m and N·m/rad for a rotary actuator)",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    a.add_column(f"load \\[{unit}]", justify="right")
    for i in range(n_legs):
        a.add_column(f"G{i + 1}", justify="right")
    for i in range(n_legs):
        a.add_column(f"K{i + 1}", justify="right")
    for k, load in enumerate(curve.loads):
        a.add_row(
            f"{load:g}",
            *(eng(v) for v in curve.actuator_forces[k]),
            *(eng(v) for v in curve.actuator_stiffness[k]),
        )
    c.print(a)
    if rms is not None:
        o, q = rms["orientation_deg"], rms["position_mm"]
        c.print(
            f"RMS difference model - measured over {rms['n']} loads: orientation "
            f"{'n/a' if o is None else f'{o:.3f} deg'}, position "
            f"{'n/a' if q is None else f'{q:.3f} mm'}"
        )
        comps = ", ".join(f"{k} {v:.4f}" for k, v in rms["components"].items())
        c.print(f"  per component: {comps}")


def run(args: argparse.Namespace) -> int:
    check_output_path(args.csv, "--csv", (".csv",), overwrite=args.overwrite)
    check_output_path(args.plot, "--plot", FIGURE_FORMATS, overwrite=args.overwrite)
    design = load_deflect_design(args)
    variables = read_tolerance_args(args, design)
    curve, meas = compute(args)
    rms = rms_differences(curve, meas) if meas is not None else None
    bands, unc = curve_uncertainty(args, design, variables, curve)
    with output_files(args.overwrite) as out:
        if args.csv:
            write_csv(curve, out.temp(args.csv, "--csv"))
        if args.plot:
            from ppm_stiffness.visuals import save_figure, use_headless_backend
            from ppm_stiffness.visuals.deflection import plot_deflection_curves

            use_headless_backend()
            fig = plot_deflection_curves([curve], meas, bands=[bands])
            save_figure(fig, out.temp(args.plot, "--plot"))
    if args.json:
        doc = _json(curve, rms) | ({} if unc is None else {"uncertainty": unc})
        print(json_document("deflect", doc, _JSON_UNITS))
        return 0
    _print(curve, rms)
    if unc is not None:
        print_curve_uncertainty(curve, unc)
    if args.csv:
        console.print(f"wrote {escape(args.csv)}")
    if args.plot:
        console.print(f"wrote {escape(args.plot)}")
    return 0
