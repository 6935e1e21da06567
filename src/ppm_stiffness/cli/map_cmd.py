"""``ppm-stiffness map``: k_phi, k_x, k_y over the workspace (paper Figures 6-7)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np
from rich.markup import escape
from rich.table import Table

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    add_design_argument,
    add_overwrite_argument,
    add_tool_point_argument,
    check_output_path,
    console,
    eng,
    json_document,
    load_design_arg,
    parse_floats,
    parse_wrench,
    progress,
    tool_point_from_args,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.tolerances import (
    add_tolerance_arguments,
    map_uncertainty,
    print_map_uncertainty,
    read_tolerance_args,
)
from ppm_stiffness.core.errors import InputDataError, UnreachablePoseError
from ppm_stiffness.design import Design
from ppm_stiffness.maps.workspace import DEFAULT_REFERENCE_FORCE, StiffnessMap, stiffness_map

DATA_SUFFIXES = (".csv", ".npz")
#: Largest grid accepted (points per axis): 10^8 poses.
MAX_GRID = 10_000
#: Peak memory per map pose [bytes], for --max-memory: measured with
#: ``/usr/bin/time -f %M ppm-stiffness map --grid 1000 [--data m.csv]``, 100 MB on the
#: built-in design and 160 MB on examples/3rrr.toml for 10^6 poses, of which about
#: 65 MB are the imports; rounded up.
BYTES_PER_POSE = 110
_UNITS = {"k_phi": "N·m/rad", "k_x": "N/m", "k_y": "N/m"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    add_design_argument(parser)
    parser.add_argument(
        "--phi",
        type=float,
        metavar="DEG",
        help="platform orientation [deg] (default: the design's workspace phi)",
    )
    parser.add_argument(
        "--actuators",
        default="max",
        metavar="max|min|FX,FY,FZ,MX,MY,MZ",
        help="'max': actuators locked; 'min': tangent stiffness of eq. (21) under "
        "--reference-force; or a wrench [N, N·m] at the tool point (axes of F_b): the "
        "loaded state at "
        "each pose (default: max); write --actuators=-5,0,... when FX is negative",
    )
    parser.add_argument(
        "--reference-force",
        type=float,
        default=DEFAULT_REFERENCE_FORCE,
        metavar="N",
        help="actuator load that defines 'min', each leg on its own law [N, or N·m for a "
        f"rotary actuator] (default {DEFAULT_REFERENCE_FORCE:g})",
    )
    parser.add_argument(
        "--grid", type=int, default=200, metavar="N", help="N x N grid points (default 200)"
    )
    parser.add_argument(
        "--bounds",
        metavar="XMIN,XMAX,YMIN,YMAX",
        help="grid extent [mm] (default: the workspace's bounding box at --phi); write "
        "--bounds=-20,10,-30,30 when the first number is negative",
    )
    add_tool_point_argument(parser)
    add_tolerance_arguments(parser)
    parser.add_argument("--out", metavar="FIG", help="write the figure (.png, .svg or .pdf)")
    parser.add_argument("--data", metavar="FILE", help="write the map data (.csv or .npz, SI)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument(
        "--max-memory",
        type=float,
        default=4.0,
        metavar="GB",
        help="refuse a grid whose estimated peak memory exceeds this (default 4 GB)",
    )
    parser.add_argument(
        "--json",
        action="store_true",
        help="print the summary as one JSON object (SI) instead of tables",
    )


def _parse_bounds(text: str | None) -> np.ndarray | None:
    if text is None:
        return None
    return np.array(parse_floats(text, 4, "--bounds", "XMIN,XMAX,YMIN,YMAX [mm]")) * 1e-3


def _summary_table(smap: StiffnessMap) -> Table:
    """One column per principal stiffness; rows: extremes, where they are, their ratio."""
    summary = smap.summary()
    table = Table(title="principal stiffness over the workspace", title_justify="left")
    table.add_column("")
    for name in summary:
        table.add_column(escape(f"{name} [{_UNITS[name]}]"), justify="right")
    rows = (
        ("min", "min", 1.0),
        ("  at x [mm]", "x_at_min", 1e3),
        ("  at y [mm]", "y_at_min", 1e3),
        ("max", "max", 1.0),
        ("  at x [mm]", "x_at_max", 1e3),
        ("  at y [mm]", "y_at_max", 1e3),
        ("max/min", "ratio", 1.0),
    )
    for label, key, factor in rows:
        table.add_row(escape(label), *(eng(s[key] * factor, 5) for s in summary.values()))
    return table


def run(args: argparse.Namespace) -> int:
    design = load_design_arg(args)
    check_output_path(args.out, "--out", FIGURE_FORMATS, overwrite=args.overwrite)
    check_output_path(args.data, "--data", DATA_SUFFIXES, overwrite=args.overwrite)
    if not 2 <= args.grid <= MAX_GRID:
        raise InputDataError(f"--grid must be between 2 and {MAX_GRID}, got {args.grid}")
    estimate = BYTES_PER_POSE * args.grid**2 / 1e9
    if not args.max_memory > 0:
        raise InputDataError(f"--max-memory must be > 0 GB, got {args.max_memory:g}")
    if estimate > args.max_memory:
        raise InputDataError(
            f"--grid {args.grid}: about {estimate:.3g} GB of memory estimated "
            f"({BYTES_PER_POSE} bytes per pose), above --max-memory {args.max_memory:g} GB; "
            "use a smaller grid or raise --max-memory"
        )
    phi = design.workspace.phi if args.phi is None else args.phi * math.pi / 180
    if not math.isfinite(phi):
        raise InputDataError("--phi must be finite")
    state = args.actuators.strip().lower()
    wrench = None
    if state not in ("max", "min"):
        if "," not in state:
            raise InputDataError(
                f"--actuators must be max, min or a wrench FX,FY,FZ,MX,MY,MZ, got {state!r}"
            )
        try:
            wrench = parse_wrench(args.actuators)
        except InputDataError as exc:
            raise InputDataError(f"--actuators: {exc}") from None
        state = "wrench"
    bounds = _parse_bounds(args.bounds)
    variables = read_tolerance_args(args, design)

    show = not (args.quiet or args.json)
    with progress("map", args.grid * args.grid, enabled=show) as advance:
        done_before = [0]

        def report(done: int, total: int) -> None:
            advance(done - done_before[0])
            done_before[0] = done

        smap = stiffness_map(
            design,
            phi=phi,
            actuators=state,
            grid=args.grid,
            wrench=wrench,
            progress=report,
            bounds=bounds,
            reference_force=args.reference_force,
            tool_point=tool_point_from_args(args, design),
        )

    if not np.any(smap.reachable):
        raise UnreachablePoseError(
            f"no grid point of the map is in the workspace at phi = "
            f"{math.degrees(smap.phi):.4g} deg: {smap.masked_text()}"
            + (" (check --bounds)" if args.bounds else "")
        )
    bands, unc = map_uncertainty(args, design, variables, smap, wrench)
    with output_files(args.overwrite) as out:
        if args.data:
            path = Path(args.data)
            if path.suffix.lower() == ".npz":
                smap.to_npz(out.temp(path, "--data"))
            else:
                with progress("writing " + path.name, smap.reachable.size, enabled=show) as advance:
                    smap.to_csv(out.temp(path, "--data"), advance)
        if args.out:
            from ppm_stiffness.visuals.maps import plot_stiffness_maps, save_map_figure

            if bands is None:
                fig = plot_stiffness_maps(smap)
            else:
                from ppm_stiffness.visuals.bands import plot_map_bands

                fig = plot_map_bands(smap, bands)
            save_map_figure(fig, out.temp(args.out, "--out"))
    if args.json:
        doc = _json(smap, design, args) | ({} if unc is None else {"uncertainty": unc})
        print(json_document("map", doc, _JSON_UNITS))
        return 0
    _print(smap, design, state, args)
    if unc is not None:
        print_map_uncertainty(unc)
    if args.data:
        console.print(f"data written to {escape(args.data)}")
    if args.out:
        console.print(f"figure written to {escape(args.out)}")
    return 0


_JSON_UNITS = {
    "phi": "rad",
    "grid.x_range": "m",
    "grid.y_range": "m",
    "actuator_stiffness": "N/m (N·m/rad for a rotary actuator): [lowest, highest] per leg",
    "wrench": "N·m, N (m_x, m_y, m_z, f_x, f_y, f_z) at the tool point",
    "tool_point": "m (platform frame)",
    "summary.k_phi": "N·m/rad (positions x_at_*, y_at_* in m; ratio 1)",
    "summary.k_x": "N/m (positions in m; ratio 1)",
    "summary.k_y": "N/m (positions in m; ratio 1)",
}


def _json(smap: StiffnessMap, design: Design, args: argparse.Namespace) -> dict[str, Any]:
    return {
        "design": design.name,
        "architecture": design.architecture,
        "phi": smap.phi,
        "actuators": smap.actuators,
        "actuator_stiffness": np.asarray(smap.actuator_stiffness).T.tolist(),
        "wrench": None if smap.wrench is None else smap.wrench,
        "tool_point": tool_point_from_args(args, design),
        "grid": {
            "nx": int(smap.x.size),
            "ny": int(smap.y.size),
            "x_range": [float(smap.x[0]), float(smap.x[-1])],
            "y_range": [float(smap.y[0]), float(smap.y[-1])],
        },
        "reachable_fraction": float(np.mean(smap.reachable)),
        "masked": smap.refusal_counts(),
        "summary": smap.summary(),
        "data": args.data,
        "figure": args.out,
    }


def _print(smap: StiffnessMap, design: Design, state: str, args: argparse.Namespace) -> None:
    k_lo, k_hi = smap.actuator_stiffness
    units = [leg.actuator_units()[2] for leg in design.legs]

    def _values(k: np.ndarray) -> str:
        return ", ".join(f"{v:.6g} {u}" for v, u in zip(k, units, strict=True))

    load_units = sorted({leg.actuator_units()[0] for leg in design.legs})
    reference = f"{args.reference_force:g} {' or '.join(load_units)}" + (
        " (each leg in its actuator's unit)" if len(load_units) > 1 else ""
    )
    console.print(
        f"φ = {math.degrees(smap.phi):.4g}°, actuators: {state}"
        + (f" (reference load {reference})" if state == "min" else "")
    )
    console.print(
        f"actuator stiffness ({state}): "
        + _values(k_lo)
        + ("" if np.allclose(k_lo, k_hi, equal_nan=True) else f" to {_values(k_hi)}")
    )
    x, y = smap.x * 1e3, smap.y * 1e3
    console.print(
        f"grid {x.size} x {y.size}: x in [{x[0]:.3f}, {x[-1]:.3f}] mm, y in "
        f"[{y[0]:.3f}, {y[-1]:.3f}] mm; {100 * np.mean(smap.reachable):.1f}% in the workspace"
    )
    if not np.all(smap.reachable):
        console.print(escape(smap.masked_text()))
    console.print(_summary_table(smap))
