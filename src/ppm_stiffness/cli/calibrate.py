"""``ppm-stiffness calibrate``: fit design parameters to a target stiffness matrix."""

from __future__ import annotations

import argparse

import numpy as np
from rich.table import Table

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_overwrite_argument,
    add_pose_arguments,
    check_output_path,
    console,
    load_design_arg,
    pose_from_args,
    read_matrix_csv,
)
from ppm_stiffness.core.conventions import TWIST_COMPONENTS
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import save_design
from ppm_stiffness.fit.calibration import calibrate

HELP = "identify design parameters from a target 6x6 stiffness matrix (bounded least squares)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    parser.add_argument(
        "--list-parameters",
        action="store_true",
        help="list the design's parameter names and values, then exit",
    )
    parser.add_argument(
        "--target",
        metavar="K.csv",
        help="target 6x6 stiffness matrix, SI, order phi_x,phi_y,phi_z,x,y,z",
    )
    parser.add_argument(
        "--free",
        metavar="NAMES",
        help="comma-separated parameters to fit, e.g. leg1.bearing_offset,guide.yaw",
    )
    parser.add_argument(
        "--bound",
        action="append",
        default=[],
        metavar="NAME=LOW:HIGH",
        help="bounds of a free parameter in SI (repeatable)",
    )
    add_design_argument(parser)
    add_pose_arguments(parser)
    parser.add_argument(
        "--sigma",
        type=float,
        metavar="S",
        help="uncertainty of every target entry in its SI unit (e.g. 5 for a "
        "matrix printed to 0.0001e5); default 1%% of sqrt(|T_ii T_jj|), which "
        "over-weights entries printed with few digits: for a printed matrix "
        "give half its last digit",
    )
    parser.add_argument(
        "--starts",
        type=int,
        default=1,
        help="number of starting points (first = the design's values)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="seed of the random starting points (default 0)"
    )
    parser.add_argument("--out", metavar="FILE.toml", help="write the calibrated design here")


def _parse_bounds(items: list[str]) -> dict[str, tuple[float, float]]:
    out: dict[str, tuple[float, float]] = {}
    for item in items:
        try:
            name, rng = item.split("=", 1)
            lo, hi = (float(v) for v in rng.split(":", 1))
        except ValueError:
            raise InputDataError(f"--bound must read NAME=LOW:HIGH, got {item!r}") from None
        out[name.strip()] = (lo, hi)
    return out


def run(args: argparse.Namespace) -> int:
    design = load_design_arg(args)
    if args.list_parameters:
        t = Table(title="Design parameters (SI)", title_justify="left")
        t.add_column("name")
        t.add_column("value", justify="right")
        t.add_column("unit")
        for name in design.scalar_parameter_names():
            t.add_row(name, f"{design.parameter(name):.6g}", design.parameter_unit(name))
        console.print(t)
        return 0
    if not args.target or not args.free:
        raise InputDataError("calibrate needs --target K.csv and --free NAMES")
    pose = pose_from_args(args, design)
    check_output_path(args.out, "--out", (".toml",), overwrite=args.overwrite)
    target = read_matrix_csv(args.target, "--target")
    names = [n.strip() for n in args.free.split(",") if n.strip()]
    if args.starts < 1:
        raise InputDataError("--starts must be >= 1")
    if args.sigma is not None and not args.sigma > 0:
        raise InputDataError("--sigma must be > 0")
    result = calibrate(
        design,
        target,
        names,
        bounds=_parse_bounds(args.bound),
        pose=pose,
        sigma=args.sigma,
        starts=args.starts,
        seed=args.seed,
    )
    c = console
    t = Table(title="Fitted parameters (SI)", title_justify="left")
    for col in ("parameter", "start", "fit", "std (1 sigma)", "lower", "upper"):
        t.add_column(col, justify="right")
    for i, n in enumerate(result.names):
        std = result.standard_deviations[i]
        t.add_row(
            n,
            f"{result.initial[i]:.6g}",
            f"{result.values[i]:.6g}",
            "undetermined" if not np.isfinite(std) else f"{std:.3g}",
            f"{result.lower[i]:.4g}",
            f"{result.upper[i]:.4g}",
        )
    c.print(t)
    c.print(
        f"cost = {result.cost:.6g}, weighted RMS residual = {result.weighted_rms:.4g} "
        f"(residual / sigma over the upper triangle)"
    )
    r = Table(title="Residuals fitted - target (SI: N·m/rad | N | N/m)", title_justify="left")
    r.add_column("")
    for lab in TWIST_COMPONENTS:
        r.add_column(lab, justify="right")
    for lab, row in zip(TWIST_COMPONENTS, result.residuals, strict=True):
        r.add_row(lab, *[f"{v:.3g}" for v in row])
    c.print(r)
    s = result.singular_values
    condition = f"condition {s[0] / s[-1]:.3g}" if s[-1] > 0 else "condition infinite"
    c.print(
        "singular values of the scaled Jacobian: "
        + ", ".join(f"{v:.3g}" for v in s)
        + f"  ({condition})"
    )
    for direction in result.flat_directions():
        parts = ", ".join(f"{n} {v:+.3f}" for n, v in direction.items() if abs(v) > 0.05)
        c.print(f"[yellow]flat direction (target cannot tell apart):[/yellow] {parts}")
    if result.at_bound:
        c.print(f"[yellow]at a bound:[/yellow] {', '.join(result.at_bound)}")
    if args.out:
        save_design(result.design, args.out)
        c.print(f"calibrated design written to {args.out}")
    return 0
