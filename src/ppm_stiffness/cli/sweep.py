"""``ppm-stiffness sweep``: the summary figures of a design over its required region
for every value of one or more parameters (a grid, or a Sobol sample); f1 where the
design has a mass model, the load margin with ``--load-margin`` (or ``--quantity
load-margin``)."""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path
from typing import Any

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    add_design_argument,
    add_overwrite_argument,
    add_seed_argument,
    add_wrench_argument,
    check_output_path,
    console,
    err_console,
    json_document,
    load_design_arg,
    parse_wrench,
    progress,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.study_options import (
    add_execution_arguments,
    add_f1_argument,
    add_load_margin_argument,
    add_region_argument,
    check_workers,
    executor_label,
    figure_cell,
    margin_note,
    region_from_args,
    region_json,
    region_text,
    study_link_modes,
)
from ppm_stiffness.core.errors import InputDataError

#: Rows of the printed table (the best designs by --quantity).
TOP_ROWS = 10


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    parser.add_argument(
        "--vary",
        action="append",
        required=True,
        metavar="NAME=LO:HI:N",
        help="a parameter (name or glob, as `calibrate --list-parameters` prints it) from "
        "LO to HI [SI] in N values; repeat for more (with --sample sobol: NAME=LO:HI)",
    )
    parser.add_argument(
        "--sample",
        default="grid",
        metavar="grid|sobol:N",
        help="every combination of the --vary values (default), or N scrambled Sobol "
        "points (N a power of 2)",
    )
    add_seed_argument(parser, "the Sobol sample's scrambling")
    add_region_argument(parser)
    add_wrench_argument(parser)
    add_load_margin_argument(parser)
    add_f1_argument(parser)
    add_execution_arguments(parser)
    parser.add_argument(
        "--quantity",
        default="worst-k-translational",
        metavar="Q",
        help="what the table ranks and the picture shows: an objective of `optimize` or "
        "a summary figure such as k_phi_p5 (default worst-k-translational)",
    )
    parser.add_argument("--csv", metavar="FILE", help="write one row per design (SI)")
    parser.add_argument(
        "--out", metavar="FIG", help="write a heat map (2 variables) or curves (1 variable)"
    )
    parser.add_argument("--json", action="store_true", help="print a JSON document (SI)")
    add_overwrite_argument(parser)


def _parse_sample(text: str) -> tuple[str, int | None]:
    kind, _, count = text.strip().lower().partition(":")
    if kind == "grid" and not count:
        return "grid", None
    if kind == "sobol":
        try:
            return "sobol", int(count)
        except ValueError:
            pass
    raise InputDataError(f"--sample must be grid or sobol:N (N a power of 2), got {text!r}")


def _rows(result: Any, names: list[str]) -> list[dict[str, Any]]:
    """One dict per design done: the variables' values, covers, the figures ``names``."""
    rows = []
    for point, s in zip(result.points, result.summaries, strict=False):
        row: dict[str, Any] = {
            v.name: float(x) for v, x in zip(result.variables, point, strict=True)
        }
        row["covers"] = s.covers
        row.update({n: s.figures()[n] for n in names})
        rows.append(row)
    return rows


def _write_csv(
    path: Path, fields: list[str], rows: list[dict[str, Any]], partial: str | None
) -> None:
    """One row per design done; an interrupted sweep's file starts with a ``#`` line
    saying so (``partial: interrupted after 37 of 100 designs; ...``)."""
    with path.open("w", newline="", encoding="utf-8") as fh:
        if partial is not None:
            fh.write(f"# {partial}\n")
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)


def run(args: argparse.Namespace) -> int:
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.optimize.executors import open_executor
    from ppm_stiffness.optimize.objectives import check_quantities, quantity
    from ppm_stiffness.optimize.summary import FIGURE_UNITS, PAPER_FIGURES, figure_names
    from ppm_stiffness.optimize.sweep import sweep_designs, sweep_points
    from ppm_stiffness.optimize.variables import parse_variable

    design = load_design_arg(args)
    check_output_path(args.csv, "--csv", (".csv",), overwrite=args.overwrite)
    check_output_path(args.out, "--out", FIGURE_FORMATS, overwrite=args.overwrite)
    check_workers(args)
    sample, count = _parse_sample(args.sample)
    variables = [parse_variable(t, design, count=sample == "grid") for t in args.vary]
    if args.out and len(variables) > 2:
        raise InputDataError("--out draws one or two variables; this sweep has more")
    q = quantity(args.quantity)
    region = region_from_args(args, [design])
    wrench = parse_wrench(args.wrench)
    if q.needs_wrench and wrench is None:
        raise InputDataError(f"--quantity {q.name} needs --wrench")
    if args.load_margin and wrench is None:
        raise InputDataError("--load-margin needs --wrench (the load whose margin it finds)")
    check_quantities(design, [q], wrench is not None)
    if args.no_f1 and q.needs_mass:
        raise InputDataError(f"--quantity {q.name} is the first natural frequency: drop --no-f1")
    frequencies = design.has_mass_model and not args.no_f1
    link_modes = study_link_modes(args, frequencies)
    margin = args.load_margin or q.needs_margin
    total = len(sweep_points(variables, sample, count, args.seed))

    start = time.perf_counter()
    with (
        open_executor(args.workers, args.scheduler) as executor,
        progress("sweep", total, enabled=not args.quiet) as advance,
    ):
        result = sweep_designs(
            design,
            variables,
            region,
            wrench=wrench,
            sample=sample,
            count=count,
            seed=args.seed,
            executor=executor,
            progress=advance,
            margin=margin,
            frequencies=frequencies,
            hinges=q.needs_hinges,
            reach=q.needs_candidate,
            condition=q.needs_condition,
            link_modes=link_modes,
        )
    wall = time.perf_counter() - start
    names = figure_names(design.planar, wrench=wrench is not None, mass=frequencies, margin=margin)
    keys = list(dict.fromkeys([*PAPER_FIGURES, *names]))  # the schema's keys always
    rows = _rows(result, keys)
    values = [q.value(s) for s in result.summaries]
    for row, value in zip(rows, values, strict=True):  # the quantity swept, by its name
        row[q.name] = None if math.isnan(value) else value

    with output_files(args.overwrite) as out:
        if args.csv:
            fields = [v.name for v in variables] + ["covers", *dict.fromkeys([*names, q.name])]
            csv_rows = [{k: r[k] for k in fields} for r in rows]
            _write_csv(out.temp(args.csv, "--csv"), fields, csv_rows, result.partial_note())
        if args.out and rows:
            import numpy as np

            from ppm_stiffness.visuals.maps import save_map_figure
            from ppm_stiffness.visuals.optimization import plot_sweep

            done = len(result.summaries)
            shape = (
                tuple(v.count for v in variables)
                if sample == "grid" and len(variables) == 2 and not result.interrupted
                else None
            )
            fig = plot_sweep(
                result.points[:done],
                np.array(values, dtype=float),
                [s.covers for s in result.summaries],
                [v.name for v in variables],
                [v.unit for v in variables],
                q.name,
                q.unit,
                shape=shape,  # type: ignore[arg-type]
            )
            save_map_figure(fig, out.temp(args.out, "--out"))
    if args.json:
        payload = {
            "region": region_json(region),
            "wrench": None if wrench is None else wrench.tolist(),
            "sample": sample,
            "seed": args.seed if sample == "sobol" else None,
            "variables": [
                {
                    "name": v.name,
                    "matches": list(v.matches),
                    "lo": v.lo,
                    "hi": v.hi,
                    "count": v.count,
                    "unit": v.unit,
                }
                for v in variables
            ],
            "designs": len(rows),
            "planned": total,
            "interrupted": result.interrupted,
            "executor": executor_label(args),
            "wall_time": wall,
            "link_modes": link_modes if frequencies else None,
            "quantity": {"name": q.name, "unit": q.unit},
            "csv": args.csv,
            "figure": args.out,
            "rows": rows,
        }
        units = {"wall_time": "s", "region": "m, m, rad", "wrench": "N·m, N"}
        units.update({f"variables.{v.name}": v.unit for v in variables})
        units.update({f"rows.{n}": FIGURE_UNITS[n] for n in keys})
        units[f"rows.{q.name}"] = q.unit
        print(json_document("sweep", payload, units))
        return 130 if result.interrupted else 0
    console.print(f"region: {region_text(region)}")
    covering = sum(r["covers"] for r in rows)
    console.print(
        f"{len(rows)} designs ({covering} cover the region) in {wall:.3g} s, "
        f"{executor_label(args)}" + (" [interrupted]" if result.interrupted else "")
    )
    order = sorted(
        (i for i, r in enumerate(rows) if r["covers"] and values[i] == values[i]),
        key=lambda i: -values[i] if q.maximise else values[i],
    )[:TOP_ROWS]
    table = Table(title=f"best designs by {q.name} (covering the region)")
    for v in variables[:3]:
        table.add_column(
            escape(f"{v.name} [{v.unit}]"), justify="right", max_width=16, overflow="fold"
        )
    table.add_column(escape(f"{q.name} [{q.unit}]"), justify="right", max_width=16, overflow="fold")
    for i in order:
        table.add_row(
            *[figure_cell(float(x)) for x in result.points[i][:3]], figure_cell(values[i])
        )
    console.print(table)
    if margin:
        console.print(margin_note(result.summaries[0].margin_poses if result.summaries else 0))
    for path, what in ((args.csv, "table"), (args.out, "figure")):
        if path:
            console.print(f"{what} written to {escape(path)}")
    if result.interrupted:
        err_console.print("interrupted: the designs done so far are written")
        return 130
    return 0
