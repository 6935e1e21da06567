"""``ppm-stiffness fit-actuator``: fit eq. (20) ``G = k_a delta^q`` to measured data."""

from __future__ import annotations

import argparse

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    add_overwrite_argument,
    check_input_path,
    check_output_path,
    console,
    json_document,
    load_design_arg,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.core.errors import InputDataError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    parser.add_argument(
        "data",
        metavar="DATA.csv",
        help="CSV with a header row 'displacement_mm,force_N' (or displacement_m); "
        "'#' lines are comments",
    )
    parser.add_argument("--plot", metavar="FIG", help="write data and fit (PNG, SVG, PDF)")
    parser.add_argument(
        "--design",
        metavar="FILE",
        help="design whose other values --write-design keeps (default: the built-in 3-PPR)",
    )
    parser.add_argument(
        "--write-design",
        metavar="OUT",
        help="write the design with actuator.k_a and actuator.q replaced by the fit",
    )
    parser.add_argument("--json", action="store_true", help="print the fit as one JSON object")


def run(args: argparse.Namespace) -> int:
    import numpy as np
    from rich.markup import escape

    from ppm_stiffness.design import save_design  # here, not at the top: --help stays light
    from ppm_stiffness.statics.actuator_fit import fit_power_law, read_force_displacement

    check_output_path(args.plot, "--plot", FIGURE_FORMATS, overwrite=args.overwrite)
    check_output_path(args.write_design, "--write-design", (".toml",), overwrite=args.overwrite)
    data = read_force_displacement(check_input_path(args.data, "DATA.csv"))
    fit = fit_power_law(data.displacement_m, data.force_n)
    if not (1e-6 < fit.q <= 1.0 and fit.k_a > 0.0):
        raise InputDataError(
            f"the fit gives k_a = {fit.k_a:.4g} N/m^q, q = {fit.q:.4g}: q outside (0, 1] or "
            "k_a <= 0, so the data do not follow a softening power law G = k_a delta^q "
            "(force must grow with displacement)"
        )
    if not (np.isfinite(fit.k_a_std) and np.isfinite(fit.q_std) and fit.q_std < fit.q):
        raise InputDataError(
            f"the fit is undetermined (q = {fit.q:.4g} +- {fit.q_std:.3g}): too few points "
            "or too little spread in displacement"
        )
    use_design = args.design is not None or args.write_design is not None
    design = load_design_arg(args) if use_design else None
    with output_files(args.overwrite) as files:
        if args.write_design:
            assert design is not None
            new = design.with_parameters({"actuator.k_a": fit.k_a, "actuator.q": fit.q})
            save_design(new, files.temp(args.write_design, "--write-design"))
        if args.plot:
            from ppm_stiffness.visuals import save_figure, use_headless_backend
            from ppm_stiffness.visuals.actuator import plot_actuator_fit

            use_headless_backend()
            ref = (design.actuator.k_a, design.actuator.q) if design is not None else None
            fig = plot_actuator_fit(
                data.displacement_m,
                data.force_n,
                fit,
                ref,
                title=f"actuator fit: {args.data}",
                reference_label="design law",
            )
            save_figure(fig, files.temp(args.plot, "--plot"))
    if args.json:
        out = dict(fit.as_dict(), source=args.data, displacement_unit=data.displacement_unit)
        units = {
            "k_a": "N/m^q (displacement in m)",
            "k_a_std": "N/m^q (displacement in m)",
            "q": "1",
            "q_std": "1",
            "residual_std": "N",
        }
        print(json_document("fit-actuator", out, units))
        return 0
    c = console
    c.print(
        f"[bold]actuator law G = k_a δ^q fitted to {escape(args.data)}[/bold] "
        f"(n = {fit.n}, displacement column in {data.displacement_unit})"
    )
    c.print(f"  k_a = {fit.k_a:.4f} ± {fit.k_a_std:.4f} N/m^q   (standard error)")
    c.print(f"  q   = {fit.q:.5f} ± {fit.q_std:.5f}")
    c.print(f"  correlation(k_a, q) = {fit.correlation:.3f}")
    c.print(f"  R² (force) = {fit.r_squared:.5f}, residual std = {fit.residual_std:.4g} N")
    if any("synthetic" in line.lower() for line in data.comments):
        c.print("  note: the data file says it is SYNTHETIC (not a measurement)")
    if args.write_design:
        c.print(f"  wrote design with the fitted k_a, q to {escape(args.write_design)}")
    if args.plot:
        c.print(f"  wrote figure {escape(args.plot)}")
    return 0
