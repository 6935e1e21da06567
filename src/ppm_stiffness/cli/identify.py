"""``ppm-stiffness identify``: element stiffnesses from measured platform deflections, for
any design (rows with 6-D poses, :mod:`ppm_stiffness.statics.measurements`)."""

from __future__ import annotations

import argparse
import math
from typing import Any

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_overwrite_argument,
    check_input_path,
    check_output_path,
    console,
    eng,
    json_document,
    load_design_arg,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.core.errors import InputDataError

#: Factor from SI to the unit in each measurement column name, and back.
_COLUMN_FACTORS = {"deg": math.pi / 180, "mm": 1e-3}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    parser.add_argument(
        "--measurements",
        metavar="DATA.csv",
        required=True,
        help="one row per measurement: the pose's task coordinates (optional; "
        "pose_x_mm,pose_y_mm,pose_phi_deg for a planar design, pose_z_mm,pose_rx_deg,"
        "pose_ry_deg for a tripod, all six pose_*_mm/_deg for a hexapod), fx_N..mz_Nm, "
        "measured phi_x_deg..z_mm, optional sigma_<column> (docs/identification.md); "
        "deflect's files (load column and '# mode:') also work",
    )
    parser.add_argument(
        "--free",
        metavar="NAME[,NAME...]",
        required=True,
        help="parameters to identify, names or globs of `calibrate --list-parameters` "
        "(a glob such as leg*.guide.yaw is one value for every leg)",
    )
    parser.add_argument(
        "--sigma",
        action="append",
        default=[],
        metavar="COLUMN=VALUE",
        help="1-sigma noise of a measured column without a sigma_ column, in the "
        "column's unit, e.g. --sigma x_mm=0.001,y_mm=0.001 --sigma phi_z_deg=0.002",
    )
    parser.add_argument(
        "--fix-unidentifiable",
        action="store_true",
        help="fix parameters the data cannot determine at their catalogue values (with "
        "a warning) instead of refusing",
    )
    parser.add_argument("--out", metavar="FILE.toml", help="write the identified design")
    add_overwrite_argument(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI)")


def parse_sigmas(items: list[str]) -> dict[int, float]:
    """``--sigma`` options as component index -> 1-sigma in SI."""
    from ppm_stiffness.statics.measurements import COMPONENT_COLUMNS

    out: dict[int, float] = {}
    for item in ",".join(items).split(","):
        if not item.strip():
            continue
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or name not in COMPONENT_COLUMNS:
            raise InputDataError(
                f"--sigma must read COLUMN=VALUE with COLUMN one of "
                f"{', '.join(COMPONENT_COLUMNS)}; got {item!r}"
            )
        try:
            value = float(text)
        except ValueError:
            raise InputDataError(f"--sigma {name}: {text!r} is not a number") from None
        if not (math.isfinite(value) and value > 0):
            raise InputDataError(f"--sigma {name} must be > 0, got {text}")
        index = COMPONENT_COLUMNS.index(name)
        if index in out:
            raise InputDataError(f"--sigma {name} given twice")
        out[index] = value * _COLUMN_FACTORS[name.rsplit("_", 1)[1]]
    return out


def _number(value: float) -> float | None:
    """A float for JSON, None where it is not valid (NaN: a parameter at a bound)."""
    return None if math.isnan(value) else float(value)


def _payload(result: Any, out: str | None) -> dict[str, Any]:
    from ppm_stiffness.core.conventions import TWIST_COMPONENTS

    return {
        "design": result.design.name,
        "parameters": [
            {
                "name": n,
                "unit": u,
                "catalogue": c,
                "start": s,
                "estimate": v,
                "standard_error": _number(e),
                "at_bound": result.at_bound.get(n),
            }
            for n, u, c, s, v, e in zip(
                result.names,
                result.units,
                result.catalogue,
                result.start,
                result.values,
                result.standard_errors,
                strict=True,
            )
        ],
        "warnings": result.bound_messages(),
        "correlation": [[_number(v) for v in row] for row in result.correlation],
        "residual_rms": {
            name: (None if math.isnan(v) else float(v))
            for name, v in zip(TWIST_COMPONENTS, result.residual_rms, strict=True)
        },
        "weighted_rms": result.weighted_rms,
        "combinations": [
            {
                "singular_value": c.singular_value,
                "relative_sigma": None if math.isinf(c.relative_sigma) else c.relative_sigma,
                "weights": c.weights,
            }
            for c in result.combinations
        ],
        "fixed": result.fixed,
        "n_rows": result.n_rows,
        "n_values": result.n_values,
        "identified_design": out,
    }


_UNITS = {
    "parameters": "each parameter's own SI unit ('unit')",
    "residual_rms": "rad (phi_x, phi_y, phi_z), m (x, y, z)",
    "weighted_rms": "1 (residual / sigma)",
    "correlation": "1",
    "combinations": "1 (relative parameters)",
}


def _print(result: Any, out: str | None) -> None:
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.core.conventions import TWIST_COMPONENTS, TWIST_UNITS

    c = console
    c.print(
        f"[bold]identified from {result.n_values} measured values in {result.n_rows} "
        f"rows[/bold] ({escape(result.design.name)})"
    )
    t = Table(box=box.SIMPLE, pad_edge=False)
    for col in ("parameter", "catalogue", "estimate", "1σ \\[%]", "unit"):
        t.add_column(col, justify="left" if col in ("parameter", "unit") else "right")
    for n, u, cat, v, e in zip(
        result.names,
        result.units,
        result.catalogue,
        result.values,
        result.standard_errors,
        strict=True,
    ):
        rel = 100 * e / abs(v) if v != 0 else math.inf
        sigma = (
            f"[yellow]at {result.at_bound[n]} bound[/yellow]"
            if n in result.at_bound
            else eng(rel, 3)
        )
        t.add_row(escape(n), eng(cat), eng(v), sigma, u)
    c.print(t)
    for message in result.bound_messages():
        c.print(f"[yellow]warning:[/yellow] {escape(message)}")
    rms = Table(title="residual RMS, predicted - measured", title_justify="left", box=box.SIMPLE)
    for name, unit in zip(TWIST_COMPONENTS, TWIST_UNITS, strict=True):
        rms.add_column(f"{name} \\[{'deg' if unit == 'rad' else 'mm'}]", justify="right")
    rms.add_row(
        *(
            "-" if math.isnan(v) else eng(v * (180 / math.pi if unit == "rad" else 1e3), 3)
            for unit, v in zip(TWIST_UNITS, result.residual_rms, strict=True)
        )
    )
    c.print(rms)
    c.print(
        f"weighted RMS (residual / sigma): {result.weighted_rms:.3g} (about 1 when the "
        "sigmas are right)"
    )
    if len(result.names) > 1:
        corr = Table(title="correlation", title_justify="left", box=box.SIMPLE, pad_edge=False)
        corr.add_column("")
        for k in range(len(result.names)):
            corr.add_column(f"p{k + 1}", justify="right")
        for k, row in enumerate(result.correlation):
            corr.add_row(f"p{k + 1}", *("-" if math.isnan(v) else f"{v:+.2f}" for v in row))
        if len(result.names) <= 8:
            c.print(corr)
    if result.combinations:  # of the parameters not at a bound
        weakest = result.combinations[-1]
        c.print(
            f"weakest combination: {escape(weakest.describe())} (relative 1σ "
            f"{weakest.relative_sigma:.3g})"
        )
    if result.at_bound:
        c.print(
            "no combination includes "
            + escape(", ".join(result.at_bound))
            + ": at a bound of the search, its 1σ is not valid"
        )
    if result.fixed:
        c.print(f"[yellow]fixed at catalogue values:[/yellow] {escape(', '.join(result.fixed))}")
    if out:
        c.print(f"identified design written to {escape(out)}")


def run(args: argparse.Namespace) -> int:
    check_output_path(args.out, "--out", (".toml",), overwrite=args.overwrite)
    sigma = parse_sigmas(args.sigma)
    free = [n.strip() for n in args.free.split(",") if n.strip()]
    if not free:
        raise InputDataError("--free needs at least one parameter name")
    design = load_design_arg(args)
    from ppm_stiffness.design import save_design
    from ppm_stiffness.fit.identify import identify, measurement_rows
    from ppm_stiffness.statics.measurements import read_measurements

    meas = read_measurements(check_input_path(args.measurements, "--measurements"))
    rows = measurement_rows(design, meas, sigma)
    result = identify(design, rows, free, fix_unidentifiable=args.fix_unidentifiable)
    if args.out:
        with output_files(args.overwrite) as out:
            save_design(result.design, out.temp(args.out, "--out"))
    if args.json:
        print(json_document("identify", _payload(result, args.out), _UNITS))
    else:
        _print(result, args.out)
    return 0
