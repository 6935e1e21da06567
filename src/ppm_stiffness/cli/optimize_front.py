"""``ppm-stiffness optimize`` with two or more ``--objective``: a Pareto front (pymoo,
the 'pareto' extra), written as CSV and JSON, a picture, one design file per front
design on request, and the design a stated rule picks (``--pick``) as ``--out``."""

from __future__ import annotations

import argparse
import csv
import io
import json
import time
from pathlib import Path
from typing import Any

from ppm_stiffness.cli.common import (
    F1_QUANTITIES,
    FIGURE_FORMATS,
    check_output_path,
    console,
    err_console,
    f1_link_modes,
    json_document,
    link_modes_from_args,
    load_design_arg,
    parse_wrench,
    progress,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.study_options import (
    check_workers,
    executor_label,
    figure_cell,
    region_box,
    region_from_args,
    region_json,
    region_maps,
    region_text,
)

#: (option, attribute) of the options that apply to a front only.
FRONT_OPTIONS = (
    ("--choose", "choose"),
    ("--pick", "pick"),
    ("--front", "front"),
    ("--front-designs", "front_designs"),
    ("--front-figure", "front_figure"),
)
#: Suffixes of --front.
FRONT_FORMATS = (".csv", ".json")


def add_front_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of a multi-objective run."""
    parser.add_argument(
        "--choose",
        action="append",
        metavar="PART=FILE:TABLE",
        help="with two or more --objective: a catalogue choice, one entry of table TABLE "
        "of catalogue FILE (.toml) for part PART (a parameter prefix or glob, "
        "leg*.distal): every key of the entry sets PART.KEY; repeat for more",
    )
    parser.add_argument(
        "--pick",
        metavar="RULE",
        help="with two or more --objective: the front design written as --out: knee (the "
        "default: in objectives normalised over the front, the design farthest below "
        "the line, or hyperplane, through the extremes) or weights=W1,W2,... (the "
        "smallest max_i W_i f_i in normalised objectives, 0 the front's best: a larger "
        "weight favours that objective)",
    )
    parser.add_argument(
        "--front",
        action="append",
        metavar="FILE",
        help="with two or more --objective: write the front (.csv or .json: each "
        "design's variables, objectives and constraint quantities); repeat for both",
    )
    parser.add_argument(
        "--front-designs",
        metavar="DIR",
        help="with two or more --objective: write every front design as DIR/front_NNN.toml "
        "(NNN its row in --front; DIR must exist)",
    )
    parser.add_argument(
        "--front-figure",
        metavar="FIG",
        help="with two or more --objective: the front (two objectives) or a scatter matrix "
        "(more), start and chosen designs marked (.png, .svg, .pdf)",
    )


def _check_outputs(args: argparse.Namespace) -> list[str]:
    """Refuse bad output paths before any computation; the --front-designs directory."""
    from ppm_stiffness.core.errors import InputDataError

    if args.convergence:
        raise InputDataError(
            "--convergence: only with one --objective (a front has no single best so far)"
        )
    check_output_path(args.out, "--out", (".toml",), overwrite=args.overwrite)
    fronts = list(args.front or [])
    for path in fronts:
        check_output_path(path, "--front", FRONT_FORMATS, overwrite=args.overwrite)
    if len({Path(p).suffix.lower() for p in fronts}) < len(fronts):
        raise InputDataError("--front: give at most one .csv and one .json")
    check_output_path(args.front_figure, "--front-figure", FIGURE_FORMATS, overwrite=args.overwrite)
    check_output_path(args.maps, "--maps", FIGURE_FORMATS, overwrite=args.overwrite)
    paths = [p for p in (args.out, *fronts, args.front_figure, args.maps) if p]
    if len({str(Path(p).resolve()) for p in paths}) < len(paths):
        raise InputDataError("--out, --front, --front-figure and --maps must be different files")
    if args.front_designs is not None and not Path(args.front_designs).is_dir():
        raise InputDataError(
            f"--front-designs {args.front_designs}: not an existing directory (nothing is "
            "created on your behalf)"
        )
    if not 2 <= args.map_grid <= 1000:
        raise InputDataError(f"--map-grid must be between 2 and 1000, got {args.map_grid}")
    return fronts


def _rows(result: Any, chosen: int) -> list[dict[str, Any]]:
    """One record per front design: row, variables, objectives, constraint quantities."""
    rows = []
    for i, d in enumerate(result.front):
        row: dict[str, Any] = {"row": i, "chosen": i == chosen, "evaluation": d.evaluation}
        row.update({v.name: d.parameters[v.name] for v in result.variables})
        row.update({c.name: d.choices[c.name] for c in result.choices})
        row.update({q.name: x for q, x in zip(result.objectives, d.objectives, strict=True)})
        row.update({str(c): x for c, x in zip(result.constraints, d.constraints, strict=True)})
        rows.append(row)
    return rows


def _csv(result: Any, chosen: int) -> str:
    buffer = io.StringIO()
    rows = _rows(result, chosen)
    units = ["", "", ""] + [v.unit for v in result.variables] + ["entry"] * len(result.choices)
    units += [q.unit for q in result.objectives] + [c.quantity.unit for c in result.constraints]
    writer = csv.writer(buffer, lineterminator="\n")
    note = result.partial_note()
    if note is not None:
        buffer.write(f"# {note}\n")
    buffer.write("# units: " + ", ".join(u or "-" for u in units) + "\n")
    writer.writerow(list(rows[0]))
    for row in rows:
        writer.writerow(list(row.values()))
    return buffer.getvalue()


def _payload(
    result: Any,
    args: argparse.Namespace,
    region: Any,
    wrench: Any,
    wall: float,
    chosen: int,
    rule: str,
    designs: list[str],
    link_modes: int | None,
) -> dict[str, Any]:
    minimised = result.minimised()
    return {
        "objectives": [
            {"name": q.name, "unit": q.unit, "maximise": q.maximise} for q in result.objectives
        ],
        "variables": [
            {"name": v.name, "matches": list(v.matches), "lo": v.lo, "hi": v.hi, "unit": v.unit}
            for v in result.variables
        ],
        "constraints": [str(c) for c in result.constraints],
        "choices": [
            {"name": c.name, "catalogue": c.source, "entries": [n for n, _ in c.entries]}
            for c in result.choices
        ],
        "algorithm": result.algorithm,
        "evaluations": result.evaluations,
        "budget": result.budget,
        "refused_by_check": result.refused_by_check,
        "seed": args.seed,
        "population": result.population,
        "generations": result.generations,
        "interrupted": result.interrupted,
        "start_outside_ranges": [{"name": n, "value": v} for n, v in result.outside],
        "start": {
            "parameters": result.start.parameters,
            "choices": result.start.choices,
            "objectives": list(result.start.objectives),
            "constraints": list(result.start.constraints),
        },
        "front": [
            {
                "parameters": d.parameters,
                "choices": d.choices,
                "objectives": list(d.objectives),
                "constraints": list(d.constraints),
                "evaluation": d.evaluation,
                "design_file": designs[i] if designs else None,
            }
            for i, d in enumerate(result.front)
        ],
        "feasible_evaluated": int(result.feasible.shape[0]),
        "chosen": chosen,
        "pick": rule,
        "chosen_design": args.out,
        "front_ideal": [float(x) for x in minimised.min(axis=0) * _signs(result)],
        "front_nadir": [float(x) for x in minimised.max(axis=0) * _signs(result)],
        "history": [{"evaluations": n, "front_size": k} for n, k in result.history],
        "region": region_json(region),
        "wrench": None if wrench is None else wrench.tolist(),
        "task_coordinates": list(region.ranges()),
        "executor": executor_label(args),
        "wall_time": wall,
        "link_modes": link_modes,
        "front_files": list(args.front or []),
        "front_figure": args.front_figure,
        "maps_figure": args.maps,
    }


def _check_choices(design: Any, variables: list[Any], choices: list[Any]) -> None:
    """Refuse a parameter set by two options (a --vary and a --choose, or two
    --choose)."""
    from ppm_stiffness.core.errors import InputDataError

    owner = {m: f"--vary {v.name}" for v in variables for m in v.matches}
    for c in choices:
        for key in {k for i in range(len(c.entries)) for k in c.values(i)}:
            for m in design.addressed(key):
                if m in owner and owner[m] != f"--choose {c.name}":
                    raise InputDataError(
                        f"--choose {c.name} and {owner[m]} both set parameter {m!r}"
                    )
                owner[m] = f"--choose {c.name}"


def _signs(result: Any) -> Any:
    import numpy as np

    return np.array([-1.0 if q.maximise else 1.0 for q in result.objectives])


def run_front(args: argparse.Namespace, names: list[str]) -> int:
    """``optimize`` with objectives ``names`` (two or more)."""
    from ppm_stiffness.core.errors import InputDataError
    from ppm_stiffness.optimize.catalogue import parse_choice
    from ppm_stiffness.optimize.executors import open_executor
    from ppm_stiffness.optimize.objectives import (
        OBJECTIVES,
        check_quantities,
        for_design,
        parse_constraint,
    )
    from ppm_stiffness.optimize.optimizer import outside_note, outside_ranges
    from ppm_stiffness.optimize.pareto import choose, front_plan, optimize_front, parse_rule
    from ppm_stiffness.optimize.variables import check_distinct, parse_variable

    if len(set(names)) < len(names):
        raise InputDataError(f"--objective: each objective once, got {', '.join(names)}")
    rule_text = args.pick or "knee"
    rule = parse_rule(rule_text, len(names))
    design = load_design_arg(args)
    fronts = _check_outputs(args)
    check_workers(args)
    variables = [parse_variable(t, design, count=False) for t in args.vary]
    choices = [parse_choice(t, design) for t in args.choose or []]
    if variables or not choices:
        check_distinct(variables)
    _check_choices(design, variables, choices)
    outside = outside_ranges(design, variables)
    outside_choices = [c for c in choices if c.start(design) is None]
    front_plan(args.budget, not outside and not outside_choices)
    objectives = [for_design(OBJECTIVES[n], design) for n in names]
    constraints = [parse_constraint(t, design) for t in args.constraint]
    region = region_from_args(args, [design])
    wrench = parse_wrench(args.wrench)
    quantities = [*objectives, *(c.quantity for c in constraints)]
    check_quantities(design, quantities, wrench is not None)
    link_modes = link_modes_from_args(
        args, any(q.needs_frequencies for q in quantities), F1_QUANTITIES
    )
    f1_modes = f1_link_modes(link_modes, any(q.needs_frequencies for q in quantities))
    if outside or outside_choices:
        import warnings

        notes = [outside_note(outside)] if outside else []
        notes += [
            f"the start design is not a candidate: its {c.name} is no entry of {c.source}"
            for c in outside_choices
        ]
        for note in notes:
            warnings.warn(note, UserWarning, stacklevel=1)

    start = time.perf_counter()
    with (
        open_executor(args.workers, args.scheduler) as executor,
        progress("optimize", args.budget, enabled=not args.quiet) as advance,
    ):
        result = optimize_front(
            design,
            variables,
            objectives,
            region,
            budget=args.budget,
            seed=args.seed,
            wrench=wrench,
            constraints=constraints,
            executor=executor,
            progress=advance,
            choices=choices,
            link_modes=link_modes,
        )
        wall = time.perf_counter() - start
        chosen = choose(result, rule)
        comparison = None
        if not result.interrupted:
            from ppm_stiffness.optimize.chosen import compare_chosen

            comparison = compare_chosen(
                design,
                result,
                chosen,
                region,
                wrench=wrench,
                executor=executor,
                link_modes=link_modes,
            )
    designs = (
        [str(Path(args.front_designs) / f"front_{i:03d}.toml") for i in range(len(result.front))]
        if args.front_designs is not None
        else []
    )
    for path in designs:
        check_output_path(path, "--front-designs", (".toml",), overwrite=args.overwrite)
    _write(args, result, design, region, chosen, rule_text, fronts, designs, wrench, wall)

    code = 130 if result.interrupted else 0
    if args.json:
        units = {
            "start.objectives": ", ".join(q.unit for q in objectives),
            "front.objectives": ", ".join(q.unit for q in objectives),
            "wall_time": "s",
            "region": "m, m, rad",
            "wrench": "N·m, N",
        }
        units.update({f"front.parameters.{v.name}": v.unit for v in variables})
        payload = _payload(result, args, region, wrench, wall, chosen, rule_text, designs, f1_modes)
        payload["comparison"] = _comparison_json(comparison)
        print(json_document("optimize", payload, units))
        return code
    _print(args, result, region, wall, chosen, rule_text, fronts, designs)
    if comparison is not None:
        _print_comparison(comparison)
    return code


def _comparison_json(comparison: Any) -> list[dict[str, Any]] | None:
    """The chosen design against the start (None when the run was interrupted)."""
    import math

    if comparison is None:
        return None

    def value(x: float) -> float | None:
        return None if math.isnan(x) else x

    return [
        {
            "name": r.name,
            "unit": r.unit,
            "start": value(r.start),
            "chosen": value(r.chosen),
            "ratio": value(r.ratio),
        }
        for r in comparison.rows
    ]


def _print_comparison(comparison: Any) -> None:
    """The table of :func:`~ppm_stiffness.optimize.chosen.compare_chosen`."""
    from rich.markup import escape
    from rich.table import Table

    table = Table(
        title=f"chosen design (row {comparison.index}) against the start, as compare "
        "evaluates them (2 evaluations outside the budget)"
    )
    table.add_column(escape("figure [unit]"), no_wrap=True)
    for name in ("start", "chosen", "chosen/start"):
        table.add_column(name, justify="right")
    for r in comparison.rows:
        table.add_row(
            escape(f"{r.label} [{r.unit}]"),
            figure_cell(r.start),
            figure_cell(r.chosen),
            figure_cell(r.ratio),
        )
    console.print(table)


def _write(
    args: argparse.Namespace,
    result: Any,
    design: Any,
    region: Any,
    chosen: int,
    rule: str,
    fronts: list[str],
    designs: list[str],
    wrench: Any,
    wall: float,
) -> None:
    """Every output file, all or none (:func:`output_files`)."""
    from ppm_stiffness.design.io import dump_design

    note = result.partial_note()
    head = "" if note is None else f"# {note}\n"
    with output_files(args.overwrite) as out:
        text = dump_design(result.design(chosen, design, region))
        out.temp(args.out, "--out").write_text(head + text, encoding="utf-8")
        for path in fronts:
            if path.lower().endswith(".csv"):
                body = _csv(result, chosen)
            else:
                doc = {"partial": note, "units": _units(result), "front": _rows(result, chosen)}
                body = json.dumps(doc, indent=2, allow_nan=False, default=_none) + "\n"
            out.temp(path, "--front").write_text(body, encoding="utf-8")
        for i, path in enumerate(designs):
            text = dump_design(result.design(i, design, region))
            out.temp(path, "--front-designs").write_text(head + text, encoding="utf-8")
        if args.front_figure:
            from ppm_stiffness.visuals.maps import save_map_figure
            from ppm_stiffness.visuals.optimization import plot_front

            fig = plot_front(
                [d.objectives for d in result.front],
                result.feasible,
                result.start.objectives,
                chosen,
                [q.name for q in result.objectives],
                [q.unit for q in result.objectives],
                [q.maximise for q in result.objectives],
                rule,
                start_label=_start_label(result),
            )
            save_map_figure(fig, out.temp(args.front_figure, "--front-figure"))
        if args.maps:
            from ppm_stiffness.visuals.comparison import plot_maps_side_by_side
            from ppm_stiffness.visuals.maps import save_map_figure

            best = result.design(chosen, design, region)
            maps = region_maps([design, best], region, args.map_grid)
            fig = plot_maps_side_by_side(maps, ["start", "chosen"], region_box(region))
            save_map_figure(fig, out.temp(args.maps, "--maps"))


def _start_label(result: Any) -> str:
    """The start design's legend entry: saying so when it is infeasible (it misses a
    constraint or part of the region), as it then cannot be on the front."""
    import numpy as np

    from ppm_stiffness.optimize.pareto import constraint_values

    g = constraint_values(result.objectives, result.constraints, result.start.summary)
    return "start design" if np.all(g <= 0) else "start design (infeasible)"


def _none(value: Any) -> Any:  # pragma: no cover - every value is a number or a string
    raise TypeError(f"not JSON: {value!r}")


def _units(result: Any) -> dict[str, str]:
    units = {v.name: v.unit for v in result.variables}
    units.update({q.name: q.unit for q in result.objectives})
    units.update({str(c): c.quantity.unit for c in result.constraints})
    return units


def _print(
    args: argparse.Namespace,
    result: Any,
    region: Any,
    wall: float,
    chosen: int,
    rule: str,
    fronts: list[str],
    designs: list[str],
) -> None:
    from rich.markup import escape
    from rich.table import Table

    console.print(f"region: {region_text(region)}")
    console.print(
        f"{result.algorithm}: {result.evaluations} evaluations of --budget {result.budget} "
        f"(population {result.population}, {result.generations} generation"
        f"{'' if result.generations == 1 else 's'}; {result.refused_by_check} refused by the "
        f"cheap check, without maps) in {wall:.3g} s, {executor_label(args)}"
        + (" [interrupted: front so far]" if result.interrupted else "")
    )
    table = Table(title=f"Pareto front: {len(result.front)} designs; chosen ({rule}) marked *")
    table.add_column("#", justify="right")
    for q in result.objectives:
        table.add_column(
            escape(f"{q.name} [{q.unit}] {'max' if q.maximise else 'min'}"), justify="right"
        )
    for v in result.variables:
        table.add_column(escape(f"{v.name} [{v.unit}]"), justify="right")
    for c in result.choices:
        table.add_column(escape(c.name))
    table.add_row(
        "start",
        *(figure_cell(x) for x in result.start.objectives),
        *(figure_cell(result.start.parameters[v.name]) for v in result.variables),
        *(escape(result.start.choices[c.name] or "(none)") for c in result.choices),
    )
    for i, d in enumerate(result.front):
        table.add_row(
            f"{i}{'*' if i == chosen else ''}",
            *(figure_cell(x) for x in d.objectives),
            *(figure_cell(d.parameters[v.name]) for v in result.variables),
            *(escape(d.choices[c.name] or "") for c in result.choices),
        )
    console.print(table)
    console.print(f"chosen design (row {chosen}, {rule}) written to {escape(args.out)}")
    for path in fronts:
        console.print(f"front written to {escape(path)}")
    if designs:
        console.print(f"{len(designs)} front designs written to {escape(args.front_designs)}")
    for path, what in ((args.front_figure, "front figure"), (args.maps, "maps")):
        if path:
            console.print(f"{what} written to {escape(path)}")
    if result.interrupted:
        err_console.print("interrupted: the front so far is written")
