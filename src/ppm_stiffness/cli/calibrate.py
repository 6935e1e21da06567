"""``ppm-stiffness calibrate``: fit design parameters to a target stiffness matrix."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_overwrite_argument,
    add_pose_arguments,
    add_seed_argument,
    check_output_path,
    console,
    eng,
    json_document,
    load_design_arg,
    pose_from_args,
    progress,
    read_matrix_csv,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.core.errors import InputDataError

if TYPE_CHECKING:
    from ppm_stiffness.fit.calibration import CalibrationResult


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
    add_seed_argument(parser, "the random starting points")
    parser.add_argument("--out", metavar="FILE.toml", help="write the calibrated design here")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI)")


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
    from rich.markup import escape
    from rich.table import Table

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
    from ppm_stiffness.design import save_design  # here, not at the top: --help stays light
    from ppm_stiffness.fit.calibration import calibrate, evaluations_per_start

    budget = args.starts * evaluations_per_start(len(names))
    with progress("calibrate", budget) as advance:
        result = calibrate(
            design,
            target,
            names,
            bounds=_parse_bounds(args.bound),
            pose=pose,
            sigma=args.sigma,
            starts=args.starts,
            seed=args.seed,
            progress=advance,
        )
    if args.out:
        with output_files(args.overwrite) as out:
            save_design(result.design, out.temp(args.out, "--out"))
    if args.json:
        print(json_document("calibrate", _json(result, args.out), _JSON_UNITS))
        return 0
    _print(result)
    if args.out:
        console.print(f"calibrated design written to {escape(args.out)}")
    return 0


#: Units of the JSON document's values (parameters carry their own in ``parameters``).
_BLOCKS = "K_rr N·m/rad, K_rt N, K_tt N/m (order phi_x, phi_y, phi_z, x, y, z)"
_JSON_UNITS = {
    "parameters": "each in its own unit (parameters[i].unit)",
    "target": _BLOCKS,
    "fitted": _BLOCKS,
    "residuals": _BLOCKS,
    "cost": "1 (residuals divided by sigma)",
    "weighted_rms": "1 (residuals divided by sigma)",
    "singular_values": "1 (of the Jacobian of the weighted residuals, scaled parameters)",
}


def _json(result: CalibrationResult, out: str | None) -> dict[str, Any]:
    import numpy as np

    std = result.standard_deviations
    return {
        "parameters": [
            {
                "name": n,
                "unit": result.design.parameter_unit(n),
                "start": result.initial[i],
                "fit": result.values[i],
                "std": std[i] if np.isfinite(std[i]) else None,
                "lower": result.lower[i],
                "upper": result.upper[i],
            }
            for i, n in enumerate(result.names)
        ],
        "target": result.target,
        "fitted": result.fitted,
        "residuals": result.residuals,
        "cost": result.cost,
        "weighted_rms": result.weighted_rms,
        "singular_values": result.singular_values,
        "flat_directions": result.flat_directions(),
        "at_bound": result.at_bound,
        "design_written": out,
    }


def _print(result: CalibrationResult) -> None:
    import numpy as np
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.core.conventions import TWIST_COMPONENTS

    c = console
    t = Table(title="Fitted parameters", title_justify="left")
    for col in ("#", "parameter", "unit"):
        t.add_column(col, no_wrap=col != "parameter", overflow="fold")
    v = Table(title="Their fit (SI, each in its unit)", title_justify="left")
    for col in ("#", "start", "fit", "std (1σ)", "lower", "upper"):
        v.add_column(escape(col), justify="right")
    for i, n in enumerate(result.names):
        std = result.standard_deviations[i]
        t.add_row(str(i + 1), n, result.design.parameter_unit(n))
        v.add_row(
            str(i + 1),
            eng(result.initial[i], 5),
            eng(result.values[i], 5),
            "undetermined" if not np.isfinite(std) else eng(std, 3),
            eng(result.lower[i], 4),
            eng(result.upper[i], 4),
        )
    c.print(t)
    c.print(v)
    c.print(
        f"cost = {result.cost:.6g}, weighted RMS residual = {result.weighted_rms:.4g} "
        f"(residual / sigma over the upper triangle)"
    )
    r = Table(
        title="Residuals fitted - target (SI: N·m/rad | N | N/m by block)", title_justify="left"
    )
    r.add_column("")
    for lab in TWIST_COMPONENTS:
        r.add_column(lab, justify="right")
    scale = max(float(np.max(np.abs(result.target))), 1e-300)
    for lab, row in zip(TWIST_COMPONENTS, result.residuals, strict=True):
        # round-off (below 1e-12 of the target's largest entry) shown as 0
        r.add_row(lab, *(eng(v if abs(v) > 1e-12 * scale else 0.0, 3) for v in row))
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
