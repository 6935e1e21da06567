"""``ppm-stiffness map``: principal stiffnesses over a 2-D slice of the workspace (paper
Figures 6-7): k_phi, k_x, k_y of a planar design over x-y at a given phi, the spatial
principal stiffnesses of any design over any two task coordinates (``--axes``) with the
others fixed by the pose options (``--z``, ``--rx``, ...)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    actuator_stiffness_text,
    add_design_argument,
    add_link_modes_argument,
    add_overwrite_argument,
    add_pose_arguments,
    add_tool_point_argument,
    check_option_angle,
    check_option_length,
    check_output_path,
    console,
    design_size_mm,
    eng,
    json_document,
    link_modes_from_args,
    load_design_arg,
    parse_floats,
    parse_wrench,
    pose_options_given,
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
from ppm_stiffness.core.names import DEFAULT_REFERENCE_FORCE, POSE_INDEX

if TYPE_CHECKING:  # the design schema and the maps load when a map is made, not for --help
    import numpy as np
    from rich.table import Table

    from ppm_stiffness.design import Design
    from ppm_stiffness.maps.result import StiffnessMap

DATA_SUFFIXES = (".csv", ".npz")
#: Largest grid accepted (points per axis): 10^8 poses.
MAX_GRID = 10_000
#: Peak memory per map pose [bytes], for --max-memory: measured with
#: ``/usr/bin/time -f %M ppm-stiffness map --grid 1000 [--data m.csv]``, 100 MB on the
#: built-in design and 160 MB on examples/3rrr.toml for 10^6 poses, of which about
#: 65 MB are the imports; rounded up. A map of the six spatial principal stiffnesses
#: needs :data:`BYTES_PER_QUANTITY` more per quantity beyond three: measured likewise
#: 156 MB (175 MB with --data m.csv) on examples/hexapod_6ups.toml and 177 MB (197 MB)
#: on an rx-ry map of examples/3prs.toml (with its three dependent coordinates).
BYTES_PER_POSE = 110
BYTES_PER_QUANTITY = 15
#: Quantities per table of the summary (so that it fits 80 columns).
_PER_TABLE = 3


def add_arguments(parser: argparse.ArgumentParser) -> None:

    add_overwrite_argument(parser)
    add_design_argument(parser)
    parser.add_argument(
        "--axes",
        metavar="A,B",
        help="the two task coordinates of the grid, e.g. x,y or rx,ry (default: x,y when "
        "the design has them, else its first two task coordinates)",
    )
    add_pose_arguments(parser)
    parser.add_argument(
        "--quantities",
        metavar="SET[,NAME...]",
        help="paper: k_phi, k_x, k_y (planar designs, their default); principal: the "
        "six spatial principal stiffnesses rotational_min, rotational_mid, "
        "rotational_max [N·m/rad], translational_min, translational_mid, "
        "translational_max [N/m] (any design, the others' default); all: both; "
        "and, comma-separated, quantity names, e.g. paper,load-margin (the load margin "
        "of the --actuators wrench, moving geometry) or f1,translational_min (f1: the "
        "first natural frequency [Hz], with the legs' own modes as 'analyze' and 'modes' "
        "(--link-modes); a design with a mass model) or hinge_range (the "
        "smallest drive's range to yield [rad or m], notch hinges with yield strengths)",
    )
    parser.add_argument(
        "--geometry",
        choices=("frozen", "moving"),
        default="frozen",
        help="with --actuators WRENCH: 'frozen' keeps the unloaded geometry (the paper's "
        "statics, default); 'moving' the equilibrium with moving geometry (K_F's "
        "symmetric part at the displaced tool point)",
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
        metavar="N",
        help="with --actuators min: the actuator load that defines 'min', each leg on its "
        f"own law [N, or N·m for a rotary actuator] (default {DEFAULT_REFERENCE_FORCE:g})",
    )
    parser.add_argument(
        "--grid", type=int, default=200, metavar="N", help="N x N grid points (default 200)"
    )
    parser.add_argument(
        "--bounds",
        metavar="AMIN,AMAX,BMIN,BMAX",
        help="grid extent along the two axes [mm or deg] (default: the reachable extent "
        "of the slice); write --bounds=-20,10,-30,30 when the first number is negative",
    )
    add_tool_point_argument(parser)
    add_link_modes_argument(parser, "f1")
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


def _axes(text: str | None) -> tuple[str, str] | None:
    if text is None:
        return None
    names = [n.strip() for n in text.split(",")]
    if len(names) != 2 or not all(names):
        raise InputDataError(f"--axes must be two task coordinates A,B (e.g. rx,ry), got {text!r}")
    return names[0], names[1]


def _fixed(args: argparse.Namespace, design: Design, axes: tuple[str, str]) -> dict[str, float]:
    """The pose options given [mm, deg] as fixed coordinates [m, rad]: task coordinates
    that are not axes (:func:`~ppm_stiffness.cli.common.pose_options_given`)."""
    return pose_options_given(args, design, axes)


def _parse_bounds(text: str | None, axes: tuple[str, str], design: Design) -> np.ndarray | None:
    """--bounds [mm, deg] in SI; a likely unit slip refused: an angle beyond +-360 deg,
    a length far beyond the design's size (:func:`~ppm_stiffness.cli.common
    .check_option_length`), or lengths of one axis within +-1 mm while the other's reach
    100 times further (metres mixed with mm)."""
    import numpy as np

    from ppm_stiffness.maps.slices import cli_scale

    if text is None:
        return None
    (fa, ua), (fb, ub) = cli_scale(axes[0]), cli_scale(axes[1])
    spec = f"{axes[0]}_min,{axes[0]}_max [{ua}],{axes[1]}_min,{axes[1]}_max [{ub}]"
    values = np.array(parse_floats(text, 4, "--bounds", spec))
    _check_bounds_units(values, axes, (ua, ub), design)
    return values / np.array([fa, fa, fb, fb])


def _check_bounds_units(
    values: np.ndarray, axes: tuple[str, str], units: tuple[str, str], design: Design
) -> None:
    """The unit-slip checks of :func:`_parse_bounds` on its values (4,) [mm or deg]."""
    import numpy as np

    from ppm_stiffness.cli.study_options import METRE_LIKE_MM

    size = design_size_mm(design) if "mm" in units else math.nan
    for k, (axis, unit) in enumerate(zip(axes, units, strict=True)):
        for v in values[2 * k : 2 * k + 2]:
            if unit == "deg":
                check_option_angle(f"--bounds {axis}", float(v))
            else:
                check_option_length(f"--bounds {axis}", float(v), size)
    if units == ("mm", "mm"):
        reach = [float(np.max(np.abs(values[2 * k : 2 * k + 2]))) for k in (0, 1)]
        small = int(np.argmin(reach))
        if 0 < reach[small] <= METRE_LIKE_MM and reach[1 - small] > 100 * reach[small]:
            ends = ",".join(f"{1e3 * v:g}" for v in values[2 * small : 2 * small + 2])
            raise InputDataError(
                f"--bounds: {axes[small]} within +-{reach[small]:g} mm but "
                f"{axes[1 - small]} up to {reach[1 - small]:g} mm: both are in mm (if "
                f"{axes[small]}'s ends are metres, write {ends})"
            )


def _header(name: str, unit: str) -> str:
    text = f"{name} [{unit}]"
    return text if len(text) <= 16 else f"{name}\n[{unit}]"


def _table_heading(names: list[str]) -> str:
    """What the summary tables show: "principal stiffness" when every quantity is one
    (the paper's or the spatial ones), "load margin" or "first natural frequency"
    alone, else "quantities"."""
    from ppm_stiffness.maps.result import PAPER, PRINCIPAL

    if all(n in PAPER or n in PRINCIPAL for n in names):
        return "principal stiffness"
    alone = {"load_margin": "load margin", "f1": "first natural frequency"}
    return alone[names[0]] if len(names) == 1 and names[0] in alone else "quantities"


def _summary_tables(smap: StiffnessMap) -> list[Table]:
    """Per table up to three quantities, one column each; rows: the extremes, where
    they are (in mm or deg), their ratio."""
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.maps.slices import cli_scale

    summary = smap.summary()
    names = list(summary)
    a, b = smap.axes
    (fa, ua), (fb, ub) = cli_scale(a), cli_scale(b)
    rows = (
        ("min", "min", 1.0),
        (f"  at {a} [{ua}]", f"{a}_at_min", fa),
        (f"  at {b} [{ub}]", f"{b}_at_min", fb),
        ("max", "max", 1.0),
        (f"  at {a} [{ua}]", f"{a}_at_max", fa),
        (f"  at {b} [{ub}]", f"{b}_at_max", fb),
        ("max/min", "ratio", 1.0),
    )
    tables = []
    for start in range(0, len(names), _PER_TABLE):
        group = names[start : start + _PER_TABLE]
        what = _table_heading(names)
        title = f"{what} over the workspace" if start == 0 else None
        table = Table(title=title, title_justify="left")
        table.add_column("")
        for name in group:
            table.add_column(escape(_header(name, smap.unit(name))), justify="right")
        for label, key, factor in rows:
            cells = [eng(summary[name][key] * factor, 5) for name in group]
            table.add_row(escape(label), *cells)
        tables.append(table)
    return tables


def _estimate(args: argparse.Namespace, design: Design) -> None:
    """Refuse a grid whose estimated peak memory exceeds --max-memory."""
    from ppm_stiffness.maps.workspace import quantity_names

    n_quantities = len(quantity_names(design, args.quantities))
    per_pose = BYTES_PER_POSE + BYTES_PER_QUANTITY * max(n_quantities - 3, 0)
    estimate = per_pose * args.grid**2 / 1e9
    if not args.max_memory > 0:
        raise InputDataError(f"--max-memory must be > 0 GB, got {args.max_memory:g}")
    if estimate > args.max_memory:
        raise InputDataError(
            f"--grid {args.grid}: about {estimate:.3g} GB of memory estimated "
            f"({per_pose} bytes per pose), above --max-memory {args.max_memory:g} GB; "
            "use a smaller grid or raise --max-memory"
        )


def run(args: argparse.Namespace) -> int:
    import numpy as np
    from rich.markup import escape

    from ppm_stiffness.maps.slices import map_slice
    from ppm_stiffness.maps.workspace import quantity_names, stiffness_map

    design = load_design_arg(args)
    check_output_path(args.out, "--out", FIGURE_FORMATS, overwrite=args.overwrite)
    check_output_path(args.data, "--data", DATA_SUFFIXES, overwrite=args.overwrite)
    if not 2 <= args.grid <= MAX_GRID:
        raise InputDataError(f"--grid must be between 2 and {MAX_GRID}, got {args.grid}")
    _estimate(args, design)
    axes = map_slice(design, _axes(args.axes)).axes
    # the fixed coordinates: the home pose's, replaced by the pose options given
    fixed = _home_fixed(design, axes) | _fixed(args, design, axes)
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
    if args.reference_force is not None and state != "min":
        raise InputDataError(
            f"--reference-force {args.reference_force:g}: it sets the actuator load that "
            f"defines --actuators min, unused with --actuators {state}"
        )
    if args.reference_force is None:
        args.reference_force = DEFAULT_REFERENCE_FORCE
    link_modes = link_modes_from_args(
        args, "f1" in quantity_names(design, args.quantities), "f1 in --quantities"
    )
    bounds = _parse_bounds(args.bounds, axes, design)
    variables = read_tolerance_args(args, design)
    if args.geometry == "moving" and variables is not None:
        raise InputDataError("--tolerances works with the frozen geometry only")

    show = not (args.quiet or args.json)
    with progress("map", args.grid * args.grid, enabled=show) as advance:
        done_before = [0]

        def report(done: int, total: int) -> None:
            advance(done - done_before[0])
            done_before[0] = done

        smap = stiffness_map(
            design,
            actuators=state,
            grid=args.grid,
            wrench=wrench,
            progress=report,
            axes=axes,
            fixed=fixed,
            bounds=bounds,
            reference_force=args.reference_force,
            tool_point=tool_point_from_args(args, design),
            quantities=args.quantities,
            geometry=args.geometry,
            link_modes=link_modes,
        )

    if not np.any(smap.reachable):
        where = _slice_text(smap)
        raise UnreachablePoseError(
            "no grid point of the map is in the workspace"
            + (f" at {where}" if where else "")
            + f": {smap.masked_text()}"
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
        print(json_document("map", doc, _json_units(smap)))
        return 0
    _print(smap, design, state, args)
    if unc is not None:
        print_map_uncertainty(unc)
    if args.data:
        console.print(f"data written to {escape(args.data)}")
    if args.out:
        console.print(f"figure written to {escape(args.out)}")
    return 0


def _home_fixed(design: Design, axes: tuple[str, str]) -> dict[str, float]:
    """The home pose's values of the task coordinates that are not axes [m, rad]."""
    from ppm_stiffness.poses import home_pose

    home = home_pose(design)
    return {n: float(home[POSE_INDEX[n]]) for n in design.task_coordinates if n not in axes}


def _slice_text(smap: StiffnessMap) -> str:
    """``"rz = 0 deg"``: the fixed coordinates in mm and deg."""
    from ppm_stiffness.maps.slices import cli_scale

    parts = []
    for name, value in smap.fixed.items():
        scale, unit = cli_scale(name)
        parts.append(f"{name} = {value * scale:.4g} {unit}")
    return ", ".join(parts)


def _json_units(smap: StiffnessMap) -> dict[str, str]:

    ua, ub = smap.units()
    units = {
        "phi": "rad",
        "axes.range": "the axis' unit (m or rad)",
        "fixed": "m (x, y, z), rad (rx, ry, rz)",
        "grid.x_range": f"{ua} (the first axis, {smap.axes[0]})",
        "grid.y_range": f"{ub} (the second axis, {smap.axes[1]})",
        "actuator_stiffness": "N/m (N·m/rad for a rotary actuator): [lowest, highest] per leg",
        "wrench": "N·m, N (m_x, m_y, m_z, f_x, f_y, f_z) at the tool point",
        "tool_point": "m (platform frame)",
    }
    a, b = smap.axes
    for name in smap.quantities:
        units[f"summary.{name}"] = (
            f"{smap.unit(name)} (positions {a}_at_* in {ua}, {b}_at_* in {ub}; ratio 1)"
        )
    return units


def _json(smap: StiffnessMap, design: Design, args: argparse.Namespace) -> dict[str, Any]:
    import numpy as np

    from ppm_stiffness.maps.slices import unit_of

    return {
        "design": design.name,
        "architecture": design.architecture,
        "axes": [
            {
                "name": name,
                "unit": unit_of(name),
                "points": int(values.size),
                "range": [float(values[0]), float(values[-1])],
            }
            for name, values in zip(smap.axes, (smap.u, smap.v), strict=True)
        ],
        "fixed": dict(smap.fixed),
        "dependent_coordinates": list(smap.dependent),
        "quantities": {name: smap.unit(name) for name in smap.quantities},
        "phi": smap.fixed.get("rz"),
        "actuators": smap.actuators,
        "geometry": smap.geometry,
        "link_modes": smap.link_modes,
        "actuator_stiffness": np.asarray(smap.actuator_stiffness).T.tolist(),
        "wrench": None if smap.wrench is None else smap.wrench,
        "tool_point": tool_point_from_args(args, design),
        "grid": {
            "nx": int(smap.u.size),
            "ny": int(smap.v.size),
            "x_range": [float(smap.u[0]), float(smap.u[-1])],
            "y_range": [float(smap.v[0]), float(smap.v[-1])],
        },
        "reachable_fraction": float(np.mean(smap.reachable)),
        "masked": smap.refusal_counts(),
        "summary": smap.summary(),
        "data": args.data,
        "figure": args.out,
    }


def _print(smap: StiffnessMap, design: Design, state: str, args: argparse.Namespace) -> None:
    import numpy as np
    from rich.markup import escape

    from ppm_stiffness.maps.slices import cli_scale

    k_lo, k_hi = smap.actuator_stiffness
    units = [leg.actuator_units()[2] for leg in design.legs]

    def _values(k: np.ndarray) -> str:
        return ", ".join(
            actuator_stiffness_text(v, ".6g", u) for v, u in zip(k, units, strict=True)
        )

    load_units = sorted({leg.actuator_units()[0] for leg in design.legs})
    reference = f"{args.reference_force:g} {' or '.join(load_units)}" + (
        " (each leg in its actuator's unit)" if len(load_units) > 1 else ""
    )
    where = _slice_text(smap)
    console.print(
        escape(f"{smap.axes[0]}-{smap.axes[1]} map" + (f" at {where}" if where else ""))
        + f", actuators: {state}"
        + (f" (reference load {reference})" if state == "min" else "")
        + (f", geometry {smap.geometry}" if state == "wrench" else "")
    )
    console.print(
        f"actuator stiffness ({state}): "
        + _values(k_lo)
        + ("" if np.allclose(k_lo, k_hi, equal_nan=True) else f" to {_values(k_hi)}")
    )
    (fa, ua), (fb, ub) = cli_scale(smap.axes[0]), cli_scale(smap.axes[1])
    a, b = smap.u * fa, smap.v * fb
    console.print(
        f"grid {a.size} x {b.size}: {smap.axes[0]} in [{a[0]:.3f}, {a[-1]:.3f}] {ua}, "
        f"{smap.axes[1]} in [{b[0]:.3f}, {b[-1]:.3f}] {ub}; "
        f"{100 * np.mean(smap.reachable):.1f}% in the workspace"
    )
    if np.any(smap.tool_point):
        console.print(f"at the tool point {np.round(1e3 * smap.tool_point, 4).tolist()} mm")
    if not np.all(smap.reachable):
        console.print(escape(smap.masked_text()))
    for table in _summary_tables(smap):
        console.print(table)
    if "load_margin" in smap.quantities:
        from ppm_stiffness.statics.margin import MAX_FACTOR

        margin = np.ma.filled(smap.quantities["load_margin"].astype(float), np.nan)
        capped = int(np.sum(margin >= MAX_FACTOR))
        if capped:
            console.print(
                f"load_margin {MAX_FACTOR:g} is the end of the search: no instability and no "
                f"stroke end up to {MAX_FACTOR:g} times the wrench at {capped} of "
                f"{int(np.sum(np.isfinite(margin)))} poses"
            )
