"""``ppm-stiffness optimize``: the best design over a required region by differential
evolution (seeded; the same result on every executor), written as a design file. Any
design: the stiffness objectives are the worst-direction principal stiffnesses (the
paper's k_x, k_y, k_phi for a planar design), f1 needs a mass model and the load margin
a wrench (evaluated on the region's corner poses)."""

from __future__ import annotations

import argparse
import time
from typing import Any

from ppm_stiffness.cli.common import (
    F1_QUANTITIES,
    FIGURE_FORMATS,
    add_design_argument,
    add_link_modes_argument,
    add_overwrite_argument,
    add_seed_argument,
    add_wrench_argument,
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
from ppm_stiffness.cli.optimize_front import FRONT_OPTIONS, add_front_arguments, run_front
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.study_options import (
    MAP_GRID,
    add_execution_arguments,
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
)

#: Objectives, listed in --help (the optimize package defines them).
OBJECTIVE_NAMES = (
    "worst-k-translational",
    "worst-k-rotational",
    "max-displacement",
    "max-rotation",
    "first-frequency",
    "load-margin",
    "moving-mass",
    "range",
    "stress",
    "reachable-workspace",
    "actuator-effort",
    "actuator-force",
    "actuator-torque",
    "condition-number",
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    parser.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="NAME=LO:HI",
        help="a design variable: a parameter name or glob (as `calibrate "
        "--list-parameters` prints it; a glob's matches vary together) and its range "
        "[SI]; repeat for more (at least one, or a --choose with two or more --objective)",
    )
    parser.add_argument(
        "--objective",
        action="append",
        choices=OBJECTIVE_NAMES,
        help="repeat for a Pareto front of two or more objectives (pymoo: the 'pareto' "
        "extra); worst-k-translational: min over the region of the worst translational "
        "principal stiffness (planar: min(k_x, k_y)) [N/m], maximised; "
        "worst-k-rotational: of the worst rotational one (planar: k_phi) [N·m/rad], "
        "maximised; max-displacement: max displacement of the tool point under --wrench "
        "(planar: |(dx, dy)|) [m], minimised; max-rotation: max rotation under --wrench "
        "(planar: |phi_z|) [rad], minimised; first-frequency: min first natural "
        "frequency [Hz] (a mass model), maximised; load-margin: min load margin of "
        "--wrench over the region's corner poses [1], maximised; moving-mass: the mass "
        "of every body moving with the platform [kg] (a mass model), minimised; range: "
        "min over the region of the hinges' range, the smallest drive's free displacement "
        "to yield [rad or m], maximised; stress: max over the region of the largest hinge "
        "stress with the drives anywhere within their strokes [Pa], minimised (range and "
        "stress: notch hinges with yield strengths); reachable-workspace: the share of "
        "the design's [workspace.candidate] grid poses reached [1], maximised (the other "
        "figures stay over the required region); actuator-effort (effort in --constraint): max "
        "over the region of the largest |actuator force or torque| under --wrench [N or "
        "N·m, drives of one kind], minimised; actuator-force, actuator-torque: the same "
        "over the linear [N] or rotary [N·m] drives; condition-number: max over the "
        "region of the condition number of the length-balanced K (L = 0.1 m) [1], "
        "minimised (default worst-k-translational)",
    )
    parser.add_argument(
        "--constraint",
        action="append",
        default=[],
        metavar="Q<=V",
        help="QUANTITY<=VALUE or QUANTITY>=VALUE [SI], QUANTITY an objective name, f1 or a "
        "summary figure (k_phi_p5, f1_p5, load-margin, ...), e.g. range>=0.02 or "
        "stress<=2e8 for a flexure stage, effort<=50 (the drives' largest force or torque "
        "under --wrench); repeat for more",
    )
    parser.add_argument(
        "--budget",
        type=int,
        default=300,
        metavar="N",
        help="most design evaluations, the start design's included (default 300)",
    )
    add_seed_argument(parser, "the initial population and the evolution")
    add_region_argument(parser)
    add_wrench_argument(parser)
    add_link_modes_argument(parser, "first-frequency and f1 constraints")
    add_execution_arguments(parser)
    parser.add_argument(
        "--out",
        metavar="FILE",
        required=True,
        help="write the best design (.toml); with two or more --objective the design "
        "--pick chooses from the front",
    )
    add_front_arguments(parser)
    parser.add_argument(
        "--convergence", metavar="FIG", help="write the convergence picture (.png, .svg, .pdf)"
    )
    parser.add_argument(
        "--maps",
        metavar="FIG",
        help="write the start and best designs' stiffness maps (.png, .svg, .pdf)",
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


def _figures(summary: Any, names: list[str]) -> dict[str, float | None]:
    figures = summary.figures()
    return {n: figures[n] for n in names}


def _payload(
    result: Any,
    args: argparse.Namespace,
    region: Any,
    wrench: Any,
    wall: float,
    names: list[str],
    link_modes: int | None,
) -> dict[str, Any]:
    return {
        "link_modes": link_modes,
        "objective": result.objective.name,
        "objective_unit": result.objective.unit,
        "maximise": result.objective.maximise,
        "initial_objective": result.initial_objective,
        "best_objective": result.best_objective,
        "improvement": result.improvement,
        "evaluations": result.evaluations,
        "budget": args.budget,
        "refused_by_check": result.refused_by_check,
        "seed": args.seed,
        "population": result.population,
        "generations": result.generations,
        "interrupted": result.interrupted,
        "start_outside_ranges": [{"name": n, "value": v} for n, v in result.outside],
        "worse_than_start": result.worse_than_start,
        "initial_parameters": result.initial_parameters,
        "best_parameters": result.best_parameters,
        "variables": [
            {"name": v.name, "matches": list(v.matches), "lo": v.lo, "hi": v.hi, "unit": v.unit}
            for v in result.variables
        ],
        "constraints": [str(c) for c in result.constraints],
        "best_design": args.out,
        "region": region_json(region),
        "wrench": None if wrench is None else wrench.tolist(),
        "initial_figures": _figures(result.initial_summary, names),
        "best_figures": _figures(result.best_summary, names),
        "task_coordinates": list(result.best_design.task_coordinates),
        "load_margin_poses": result.best_summary.margin_poses,
        "history": [{"evaluations": n, "best_objective": b} for n, b in result.history],
        "executor": executor_label(args),
        "wall_time": wall,
        "convergence_figure": args.convergence,
        "maps_figure": args.maps,
    }


def run(args: argparse.Namespace) -> int:
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.core.errors import InputDataError
    from ppm_stiffness.design.io import dump_design
    from ppm_stiffness.optimize.executors import open_executor
    from ppm_stiffness.optimize.objectives import (
        OBJECTIVES,
        check_quantities,
        for_design,
        parse_constraint,
    )
    from ppm_stiffness.optimize.optimizer import (
        optimize_design,
        outside_note,
        outside_ranges,
        population_plan,
    )
    from ppm_stiffness.optimize.summary import FIGURE_UNITS, PAPER_FIGURES, figure_names
    from ppm_stiffness.optimize.variables import check_distinct, parse_variable

    names = args.objective or ["worst-k-translational"]
    if len(names) > 1:
        return run_front(args, names)
    given = [o for o, attr in FRONT_OPTIONS if getattr(args, attr) is not None]
    if given:
        raise InputDataError(f"{', '.join(given)}: only with two or more --objective")
    design = load_design_arg(args)
    check_output_path(args.out, "--out", (".toml",), overwrite=args.overwrite)
    check_output_path(args.convergence, "--convergence", FIGURE_FORMATS, overwrite=args.overwrite)
    check_output_path(args.maps, "--maps", FIGURE_FORMATS, overwrite=args.overwrite)
    if len({p for p in (args.out, args.convergence, args.maps) if p}) < sum(
        1 for p in (args.out, args.convergence, args.maps) if p
    ):
        raise InputDataError("--out, --convergence and --maps must be different files")
    if not 2 <= args.map_grid <= 1000:
        raise InputDataError(f"--map-grid must be between 2 and 1000, got {args.map_grid}")
    check_workers(args)
    variables = [parse_variable(t, design, count=False) for t in args.vary]
    check_distinct(variables)
    outside = outside_ranges(design, variables)
    population_plan(args.budget, len(variables), not outside)
    objective = for_design(OBJECTIVES[names[0]], design)
    constraints = [parse_constraint(t, design) for t in args.constraint]
    region = region_from_args(args, [design])
    wrench = parse_wrench(args.wrench)
    quantities = [objective, *(c.quantity for c in constraints)]
    check_quantities(design, quantities, wrench is not None)
    link_modes = link_modes_from_args(
        args, any(q.needs_frequencies for q in quantities), F1_QUANTITIES
    )
    f1_modes = f1_link_modes(link_modes, any(q.needs_frequencies for q in quantities))
    margin = any(q.needs_margin for q in quantities)
    shown = figure_names(
        design.planar, wrench=wrench is not None, mass=design.has_mass_model, margin=margin
    )
    names = list(dict.fromkeys([*PAPER_FIGURES, *shown, *FIGURE_UNITS]))
    if outside:  # one line on stderr, before the search
        import warnings

        warnings.warn(outside_note(outside), UserWarning, stacklevel=1)

    start = time.perf_counter()
    with (
        open_executor(args.workers, args.scheduler) as executor,
        progress("optimize", args.budget, enabled=not args.quiet) as advance,
    ):
        result = optimize_design(
            design,
            variables,
            objective,
            region,
            budget=args.budget,
            seed=args.seed,
            wrench=wrench,
            constraints=constraints,
            executor=executor,
            progress=advance,
            link_modes=link_modes,
        )
    wall = time.perf_counter() - start

    with output_files(args.overwrite) as out:
        note = result.partial_note()  # an interrupted run's file says so
        text = dump_design(result.best_design)
        out.temp(args.out, "--out").write_text(
            text if note is None else f"# {note}\n{text}", encoding="utf-8"
        )
        if args.convergence:
            from ppm_stiffness.visuals.maps import save_map_figure
            from ppm_stiffness.visuals.optimization import plot_convergence

            fig = plot_convergence(
                result.history, objective.name, objective.unit, objective.maximise
            )
            save_map_figure(fig, out.temp(args.convergence, "--convergence"))
        if args.maps:
            from ppm_stiffness.visuals.comparison import plot_maps_side_by_side
            from ppm_stiffness.visuals.maps import save_map_figure

            maps = region_maps([design, result.best_design], region, args.map_grid)
            fig = plot_maps_side_by_side(maps, ["start", "best"], region_box(region))
            save_map_figure(fig, out.temp(args.maps, "--maps"))

    code = 130 if result.interrupted else 0
    if args.json:
        units = {
            "initial_objective": objective.unit,
            "best_objective": objective.unit,
            "improvement": "1",
            "wall_time": "s",
            "region": "m, m, rad",
            "wrench": "N·m, N",
        }
        units.update({f"best_parameters.{v.name}": v.unit for v in variables})
        units.update({f"best_figures.{n}": FIGURE_UNITS[n] for n in names})
        payload = _payload(result, args, region, wrench, wall, names, f1_modes)
        print(json_document("optimize", payload, units))
        return code
    console.print(f"region: {region_text(region)}")
    console.print(
        f"{result.evaluations} evaluations of --budget {result.budget} (population "
        f"{result.population}, {result.generations} generation"
        f"{'' if result.generations == 1 else 's'}; {result.refused_by_check} refused by the "
        f"cheap check, without maps) in {wall:.3g} s, {executor_label(args)}"
        + (" [interrupted: best so far]" if result.interrupted else "")
    )
    table = Table(
        title=f"{objective.name} [{objective.unit}], "
        f"{'maximised' if objective.maximise else 'minimised'}"
    )
    table.add_column("", no_wrap=True)
    table.add_column("unit")
    table.add_column("start", justify="right")
    table.add_column("best", justify="right")
    table.add_row(
        escape(objective.name),
        escape(objective.unit),
        figure_cell(result.initial_objective),
        figure_cell(result.best_objective),
    )
    for c in constraints:
        table.add_row(
            escape(f"constraint {c}"),
            escape(c.quantity.unit),
            figure_cell(c.quantity.value(result.initial_summary)),
            figure_cell(c.quantity.value(result.best_summary)),
        )
    for v in variables:
        table.add_row(
            escape(v.name),
            escape(v.unit),
            figure_cell(result.initial_parameters[v.name]),
            figure_cell(result.best_parameters[v.name]),
        )
    console.print(table)
    worse = ""
    if result.worse_than_start:
        why = "lies outside the ranges" if result.outside else "misses a constraint"
        worse = f", worse than the start design (which {why})"
    console.print(
        f"improvement: x{result.improvement:.4g}{worse}; best design written to {escape(args.out)}"
    )
    if margin:
        console.print(margin_note(result.best_summary.margin_poses))
    for path, what in ((args.convergence, "convergence"), (args.maps, "maps")):
        if path:
            console.print(f"{what} written to {escape(path)}")
    if result.interrupted:
        err_console.print("interrupted: the best design so far is written")
    return code
