"""``ppm-stiffness compare``: summary figures of several designs over one required
region, side by side (with f1 where a design has a mass model, the load margin with
``--load-margin``), and their stiffness maps on one colour scale per quantity. The
designs must share their task coordinates."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    add_overwrite_argument,
    add_wrench_argument,
    check_input_path,
    check_output_path,
    console,
    err_console,
    json_document,
    parse_wrench,
    progress,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.study_options import (
    MAP_GRID,
    add_execution_arguments,
    add_f1_argument,
    add_load_margin_argument,
    add_region_argument,
    check_workers,
    executor_label,
    figure_cell,
    margin_note,
    region_box,
    region_from_args,
    region_json,
    region_maps,
    region_text,
    study_link_modes,
)
from ppm_stiffness.core.errors import InputDataError

#: Designs per printed table (more go to further tables: each fits 80 columns).
COLUMNS_PER_TABLE = 4


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--design",
        metavar="FILE",
        action="append",
        help="a TOML design file; repeat for each design (default: the built-in 3-PPR)",
    )
    add_region_argument(parser)
    add_wrench_argument(parser)
    add_load_margin_argument(parser)
    add_f1_argument(parser)
    add_execution_arguments(parser)
    parser.add_argument(
        "--out", metavar="FIG", help="write the maps side by side (.png, .svg or .pdf)"
    )
    parser.add_argument(
        "--map-grid",
        type=int,
        default=MAP_GRID,
        metavar="N",
        help=f"grid points per axis of the maps (default {MAP_GRID})",
    )
    parser.add_argument("--json", action="store_true", help="print a JSON document (SI)")
    add_overwrite_argument(parser)


def _labels(paths: list[str | None]) -> list[str]:
    labels = ["built-in" if p is None else Path(p).stem for p in paths]
    return [
        f"{label} ({i + 1})" if labels.count(label) > 1 else label for i, label in enumerate(labels)
    ]


def run(args: argparse.Namespace) -> int:
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.design import default_design, load_design
    from ppm_stiffness.optimize.executors import Interrupted, open_executor
    from ppm_stiffness.optimize.summary import (
        FIGURE_UNITS,
        PAPER_FIGURES,
        figure_label,
        figure_names,
    )
    from ppm_stiffness.optimize.sweep import summarize_designs
    from ppm_stiffness.statics.hinge_stress import has_hinges

    paths: list[str | None] = list(args.design) if args.design else [None]
    designs = [
        default_design() if p is None else load_design(check_input_path(p, "--design"))
        for p in paths
    ]
    labels = _labels(paths)
    check_output_path(args.out, "--out", FIGURE_FORMATS, overwrite=args.overwrite)
    if not 2 <= args.map_grid <= 1000:
        raise InputDataError(f"--map-grid must be between 2 and 1000, got {args.map_grid}")
    check_workers(args)
    region = region_from_args(args, designs)
    wrench = parse_wrench(args.wrench)
    if args.load_margin and wrench is None:
        raise InputDataError("--load-margin needs --wrench (the load whose margin it finds)")
    link_modes = study_link_modes(args, not args.no_f1)

    start = time.perf_counter()
    with (
        open_executor(args.workers, args.scheduler) as executor,
        progress("compare", len(designs), enabled=not args.quiet) as advance,
    ):
        try:
            summaries = summarize_designs(
                designs,
                region,
                wrench=wrench,
                executor=executor,
                progress=advance,
                margin=args.load_margin,
                frequencies=not args.no_f1,
                hinges=any(has_hinges(d) for d in designs),
                link_modes=link_modes,
            )
        except Interrupted:
            raise KeyboardInterrupt from None
    wall = time.perf_counter() - start

    if args.out:
        from ppm_stiffness.visuals.comparison import plot_maps_side_by_side
        from ppm_stiffness.visuals.maps import save_map_figure

        maps = region_maps(designs, region, args.map_grid)
        fig = plot_maps_side_by_side(maps, labels, region_box(region))
        with output_files(args.overwrite) as out:
            save_map_figure(fig, out.temp(args.out, "--out"))
    planar = designs[0].planar
    names = figure_names(
        planar,
        wrench=wrench is not None,
        mass=any(d.has_mass_model for d in designs) and not args.no_f1,
        margin=args.load_margin,
    )
    hinged = [d for d in designs if has_hinges(d)]
    if hinged:  # a design with notch hinges: its range and stress (null for the others)
        names += ["hinge_range_min", "hinge_stress_max"]
    keys = list(dict.fromkeys([*PAPER_FIGURES, *names]))  # the schema's keys always
    units_of = dict(FIGURE_UNITS)
    drives = {leg.actuator_units()[1] for d in hinged for leg in d.legs if leg.is_actuated()}
    if len(drives) == 1:  # the hinge range in the drives' one unit
        units_of["hinge_range_min"] = drives.pop()
    if args.json:
        payload = {
            "region": region_json(region),
            "wrench": None if wrench is None else wrench.tolist(),
            "executor": executor_label(args),
            "wall_time": wall,
            "link_modes": link_modes if not args.no_f1 else None,
            "designs": [
                {
                    "label": label,
                    "file": path,
                    "name": d.name,
                    "architecture": d.architecture,
                    "poses": s.poses,
                    "covered": s.covered,
                    "covers": s.covers,
                    "loaded_failures": s.loaded_failures,
                    "task_coordinates": list(d.task_coordinates),
                    "mass_model": d.has_mass_model,
                    "load_margin_poses": s.margin_poses,
                    "figures": {n: s.figures()[n] for n in keys},
                }
                for label, path, d, s in zip(labels, paths, designs, summaries, strict=True)
            ],
        }
        units = {"region": "m, m, rad", "wrench": "N·m, N", "wall_time": "s"}
        units.update({f"figures.{n}": units_of[n] for n in keys})
        print(json_document("compare", payload, units))
    else:
        console.print(f"region: {region_text(region)}")
        for first in range(0, len(designs), COLUMNS_PER_TABLE):
            part = slice(first, first + COLUMNS_PER_TABLE)
            table = Table(title="summary over the required region")
            table.add_column(escape("figure [unit]"), no_wrap=True)
            for label in labels[part]:
                table.add_column(escape(label), justify="right", max_width=12, overflow="fold")
            table.add_row("architecture", *[d.architecture for d in designs[part]])
            for n in names:
                cells = [figure_cell(s.figures()[n]) for s in summaries[part]]
                label = figure_label(n, planar)
                table.add_row(escape(f"{label} [{units_of[n]}]"), *cells)
            console.print(table)
        for label, s in zip(labels, summaries, strict=True):
            if not s.covers:
                console.print(
                    f"{escape(label)}: does not cover the region ({s.poses - s.covered} of "
                    f"{s.poses} poses unreachable or singular); its figures are over the "
                    "covered poses"
                )
            if s.loaded_failures:
                console.print(
                    f"{escape(label)}: the loaded state fails at {s.loaded_failures} poses "
                    "(worst deflection unbounded: inf)"
                )
        if args.load_margin:
            console.print(margin_note(summaries[0].margin_poses))
        if not args.quiet:  # --quiet: no progress bar and no timing line
            err_console.print(f"{len(designs)} designs in {wall:.3g} s ({executor_label(args)})")
    if args.out and not args.json:
        console.print(f"maps written to {escape(args.out)}")
    return 0
