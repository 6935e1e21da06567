"""``--tolerances TOL.toml`` shared by ``analyze``, ``map``, ``deflect`` and ``report``:
the options, and the glue between a command's result and its uncertainty bands.

The library does the work (:mod:`ppm_stiffness.fit.tolerances`,
:mod:`ppm_stiffness.fit.uncertainty`, :mod:`ppm_stiffness.fit.band_outputs`); this
module reads the options, calls it and turns the bands into JSON-ready dicts and
tables. Heavy libraries are imported inside the functions.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from ppm_stiffness.cli.common import check_input_path, console, eng, progress
from ppm_stiffness.core.errors import InputDataError

#: The principal stiffnesses of a planar design ranked by the sensitivity tables, and
#: their units (a spatial design's: ``fit.band_outputs.principal_quantities``).
RANKED = (("k_phi", "N·m/rad"), ("k_x", "N/m"), ("k_y", "N/m"))
#: Variables listed per ranking.
TOP = 5


def add_tolerance_arguments(parser: argparse.ArgumentParser) -> None:
    """``--tolerances``, ``--tolerance-method`` and ``--samples``."""
    parser.add_argument(
        "--tolerances",
        metavar="TOL.toml",
        help="parameter tolerances (pm or sigma, absolute or %%; docs/identification.md): "
        "adds uncertainty bands and a sensitivity ranking",
    )
    parser.add_argument(
        "--tolerance-method",
        choices=("first-order", "qmc"),
        help="with --tolerances: first-order propagation (bands ±2σ) or quasi-Monte Carlo "
        "(Sobol; bands 5th-95th percentile, right near singularities) (default "
        f"{DEFAULT_TOLERANCE_METHOD})",
    )
    parser.add_argument(
        "--samples",
        type=int,
        metavar="N",
        help=f"with --tolerance-method qmc: QMC samples (default {DEFAULT_SAMPLES}; a power "
        "of 2 keeps Sobol's balance)",
    )


#: Defaults of --tolerance-method and --samples.
DEFAULT_TOLERANCE_METHOD = "first-order"
DEFAULT_SAMPLES = 64


def check_tolerance_options(args: argparse.Namespace) -> None:
    """Refuse --tolerance-method without --tolerances and --samples without
    --tolerance-method qmc (each would be ignored); fill in their defaults."""
    method, samples = args.tolerance_method, args.samples
    if getattr(args, "tolerances", None) is None:
        if method is not None:
            raise InputDataError(
                f"--tolerance-method {method}: it sets how the tolerances of --tolerances "
                "propagate, unused without it; give --tolerances TOL.toml too"
            )
        if samples is not None:
            raise InputDataError(
                f"--samples {samples}: it counts the QMC samples of --tolerances with "
                "--tolerance-method qmc, unused without them; give both"
            )
    elif samples is not None and method != "qmc":
        raise InputDataError(
            f"--samples {samples}: it counts the QMC samples, unused with --tolerance-method "
            f"{method or DEFAULT_TOLERANCE_METHOD}; add --tolerance-method qmc"
        )
    args.tolerance_method = method or DEFAULT_TOLERANCE_METHOD
    args.samples = DEFAULT_SAMPLES if samples is None else samples


def read_tolerance_args(args: argparse.Namespace, design: Any) -> list[Any] | None:
    """The tolerance variables of ``--tolerances`` (None without it), checked before
    any computation (with --tolerance-method and --samples: :func:`check_tolerance_options`)."""
    check_tolerance_options(args)
    path = getattr(args, "tolerances", None)
    if path is None:
        return None
    if not 2 <= args.samples <= 100_000:
        raise InputDataError(f"--samples must be between 2 and 100000, got {args.samples}")
    from ppm_stiffness.fit.tolerances import read_tolerances, tolerance_variables

    return tolerance_variables(design, read_tolerances(check_input_path(path, "--tolerances")))


def compute_bands(
    args: argparse.Namespace,
    design: Any,
    variables: list[Any],
    output: Any,
    failed_value: Any = None,
) -> Any:
    """Bands of ``output`` with the command's method and samples (a progress bar);
    ``failed_value`` as :func:`~ppm_stiffness.fit.uncertainty.propagate`'s, and also
    the outputs' lower limit (a stiffness: 0), below which a first-order band is
    warned about."""
    from ppm_stiffness.fit.uncertainty import propagate

    n = 2 * len(variables) + (args.samples if args.tolerance_method == "qmc" else 0)
    with progress("tolerances", n) as advance:
        return propagate(
            design,
            variables,
            output,
            args.tolerance_method,
            args.samples,
            0,
            advance,
            failed_value=failed_value,
            lower_limit=failed_value,
        )


def _head(bands: Any) -> dict[str, Any]:
    return {
        "method": bands.method,
        "band": bands.label,
        "samples": bands.samples,
        "failed_samples": bands.failed,
        "redrawn": bands.redrawn,
        "variables": bands.labels,
    }


def _ranking(bands: Any, index: Any) -> list[dict[str, Any]]:
    return [{"parameter": n, "share": s} for n, s in bands.ranking(index)[:TOP]]


def pose_uncertainty(
    args: argparse.Namespace,
    design: Any,
    variables: list[Any],
    pose: Any,
    tool_point: Any,
    wrench: Any | None,
) -> dict[str, Any]:
    """Bands of the principal stiffnesses (k_phi, k_x, k_y of a planar design; the
    spatial ones, ``k_rot_1..3`` and ``k_trans_1..3`` at the tool point in ascending
    order, of a spatial design), K (and the twist under a wrench) at one pose, as the
    ``uncertainty`` entry of ``analyze --json``."""
    from ppm_stiffness.fit.band_outputs import (
        pose_failed_value,
        pose_output,
        principal_quantities,
    )

    ranked = principal_quantities(design)
    n = len(ranked)
    output = pose_output(pose, tool_point, wrench)
    failed = pose_failed_value(design, wrench is not None)
    if design.has_mass_model:  # and the first natural frequency, last
        output, failed = _with_f1(output, failed, pose, tool_point, wrench)
        ranked = (*ranked, ("f1", "Hz"))
    bands = compute_bands(args, design, variables, output, failed)
    out = _head(bands)
    quantities = {}
    for i, (name, unit) in enumerate(ranked):
        j = -1 if name == "f1" else i  # f1 is the output's last value
        quantities[name] = {
            "unit": unit,
            "nominal": bands.nominal[j],
            "lower": bands.lower[j],
            "upper": bands.upper[j],
            "std": bands.std[j],
        }
    out["quantities"] = quantities
    out["stiffness_matrix_lower"] = bands.lower[n : n + 36].reshape(6, 6)
    out["stiffness_matrix_upper"] = bands.upper[n : n + 36].reshape(6, 6)
    if wrench is not None:
        out["twist_lower"] = bands.lower[n + 36 : n + 42]
        out["twist_upper"] = bands.upper[n + 36 : n + 42]
    out["sensitivity"] = {
        name: _ranking(bands, -1 if name == "f1" else i) for i, (name, _) in enumerate(ranked)
    }
    return _json_safe(out)


def quantity_bands(bands: Any, names: list[str], unit: str) -> dict[str, Any]:
    """The JSON entry of bands whose values are the quantities ``names`` in order, all
    in ``unit`` (``modes``' frequencies): the head, ``quantities`` and ``sensitivity``."""
    out = _head(bands)
    out["quantities"] = {
        name: {
            "unit": unit,
            "nominal": bands.nominal[j],
            "lower": bands.lower[j],
            "upper": bands.upper[j],
            "std": bands.std[j],
        }
        for j, name in enumerate(names)
    }
    out["sensitivity"] = {name: _ranking(bands, j) for j, name in enumerate(names)}
    return dict(_json_safe(out))


def _with_f1(output: Any, failed: Any, pose: Any, tool_point: Any, wrench: Any) -> Any:
    """``output`` with the first natural frequency [Hz] appended
    (:func:`~ppm_stiffness.fit.band_outputs.modes_output`), and its failed value."""
    import numpy as np

    from ppm_stiffness.fit.band_outputs import MODES_FAILED_VALUE, modes_output

    frequencies = modes_output(pose, tool_point, wrench)

    def both(design: Any) -> Any:
        return np.concatenate([output(design), frequencies(design)[:1]])

    return both, np.concatenate([failed, [MODES_FAILED_VALUE]])


def _json_safe(obj: Any) -> Any:
    """NaN (no value: every sample failed there) as None for JSON."""
    import numpy as np

    if isinstance(obj, dict):
        return {k: _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _json_safe(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        return None if not math.isfinite(float(obj)) else float(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def print_head(unc: dict[str, Any]) -> None:
    """One line: the method, the band's meaning, samples failed and redrawn."""
    text = f"[bold]uncertainty[/bold]: {unc['band']}; {len(unc['variables'])} tolerance variables"
    if unc["method"] == "qmc":
        text += (
            f"; {unc['failed_samples']} of {unc['samples']} samples unreachable or singular"
            f"; {unc['redrawn']} values redrawn (a stiffness <= 0)"
        )
    console.print(text)


def print_sensitivity(sensitivity: dict[str, list[dict[str, Any]]], what: str = "") -> None:
    """Which tolerance matters most for each ranked output (share of the first-order
    variance), one line per output."""
    from rich.markup import escape

    console.print(f"sensitivity, share of the first-order variance{what}:")
    for name, ranking in sensitivity.items():
        items = ", ".join(f"{r['parameter']} {100 * r['share']:.0f}%" for r in ranking)
        console.print(f"  {name}: {escape(items)}")


def print_pose_uncertainty(unc: dict[str, Any]) -> None:
    """Tables of ``analyze``'s bands."""
    from rich import box
    from rich.table import Table

    print_head(unc)
    t = Table(box=box.SIMPLE)
    for col in ("", "nominal", "lower", "upper", "unit"):
        t.add_column(col, justify="left" if col in ("", "unit") else "right")
    for name, q in unc["quantities"].items():
        t.add_row(
            name,
            eng(q["nominal"]),
            "-" if q["lower"] is None else eng(q["lower"]),
            "-" if q["upper"] is None else eng(q["upper"]),
            q["unit"],
        )
    console.print(t)
    if any(name.startswith("k_rot_") for name in unc["quantities"]):
        console.print(
            "k_rot_1..3 and k_trans_1..3: the principal stiffnesses in ascending order "
            "(1 the worst direction), not in the order of the principal table"
        )
    print_sensitivity(unc["sensitivity"])


def curve_uncertainty(
    args: argparse.Namespace, design: Any, variables: list[Any] | None, curve: Any
) -> tuple[Any, dict[str, Any] | None]:
    """Bands of a deflection curve's twists (n_loads, 6) and the JSON entry ((None,
    None) without tolerances)."""
    import numpy as np

    if variables is None:
        return None, None
    from ppm_stiffness.fit.band_outputs import deflection_output

    output = deflection_output(curve.unit_wrench, curve.loads, curve.pose, curve.tool_point)
    bands = compute_bands(args, design, variables, output)
    out = _head(bands)
    out["twists_lower"] = bands.lower
    out["twists_upper"] = bands.upper
    big = np.max(np.abs(curve.twists[-1]))
    comps = [i for i in range(6) if abs(curve.twists[-1, i]) > 1e-6 * big]
    from ppm_stiffness.core.conventions import TWIST_COMPONENTS

    out["sensitivity"] = {
        TWIST_COMPONENTS[i]: _ranking(bands, (len(curve.loads) - 1, i)) for i in comps
    }
    return bands, _json_safe(out)


def print_curve_uncertainty(curve: Any, unc: dict[str, Any]) -> None:
    """Tables of the bands at each load for the curve's main components (those the
    sensitivity ranks: the ones that are not round-off), three a table."""
    import numpy as np
    from rich import box
    from rich.table import Table

    from ppm_stiffness.core.conventions import TWIST_COMPONENTS

    print_head(unc)
    main = list(unc["sensitivity"])
    lo, hi = np.asarray(unc["twists_lower"], float), np.asarray(unc["twists_upper"], float)
    for start in range(0, max(len(main), 1), 3):
        names = main[start : start + 3]
        t = Table(box=box.SIMPLE)
        t.add_column(f"load \\[{curve.load_unit}]", justify="right")
        for name in names:
            unit = "deg" if name.startswith("phi") else "mm"
            t.add_column(f"{name} lo..hi \\[{unit}]", justify="right")
        for k, load in enumerate(curve.loads):
            cells = []
            for name in names:
                i = TWIST_COMPONENTS.index(name)
                f = 180 / math.pi if i < 3 else 1e3
                cells.append(f"{eng(lo[k, i] * f, 3)}..{eng(hi[k, i] * f, 3)}")
            t.add_row(eng(load, 3), *cells)
        console.print(t)
    print_sensitivity(unc["sensitivity"], " (at the largest load)")


def map_uncertainty(
    args: argparse.Namespace,
    design: Any,
    variables: list[Any] | None,
    smap: Any,
    wrench: Any | None,
) -> tuple[Any, dict[str, Any] | None]:
    """Bands of the map's quantities over its grid (n_quantities, nv, nu) and a JSON
    summary ((None, None) without tolerances)."""
    import numpy as np

    if variables is None:
        return None, None
    from ppm_stiffness.fit.band_outputs import MAP_FAILED_VALUE, map_output
    from ppm_stiffness.maps.result import QUANTITIES

    output = map_output(**smap.grid_arguments())
    bands = compute_bands(args, design, variables, output, MAP_FAILED_VALUE)
    out = _head(bands)
    summary = {}
    names = list(smap.quantities)
    for i, name in enumerate(names):
        nominal = bands.nominal[i]
        ok = np.isfinite(nominal) & np.isfinite(bands.lower[i])
        spread = (bands.upper[i] - bands.lower[i])[ok] / nominal[ok]
        summary[name] = {
            "unit": QUANTITIES[name][0],
            "min_nominal": float(np.nanmin(nominal)) if np.any(ok) else None,
            "min_lower": float(np.min(bands.lower[i][ok])) if np.any(ok) else None,
            "median_relative_spread": float(np.median(spread)) if spread.size else None,
            "max_relative_spread": float(np.max(spread)) if spread.size else None,
        }
    out["summary"] = summary
    out["sensitivity"] = {name: _ranking(bands, i) for i, name in enumerate(names)}
    return bands, _json_safe(out)


def print_map_uncertainty(unc: dict[str, Any]) -> None:
    from rich import box
    from rich.table import Table

    print_head(unc)
    t = Table(box=box.SIMPLE)
    for col in ("", "min nominal", "min lower", "median spread", "max spread", "unit"):
        t.add_column(col, justify="left" if col in ("", "unit") else "right")
    for name, s in unc["summary"].items():
        t.add_row(
            name,
            "-" if s["min_nominal"] is None else eng(s["min_nominal"]),
            "-" if s["min_lower"] is None else eng(s["min_lower"]),
            "-"
            if s["median_relative_spread"] is None
            else f"{100 * s['median_relative_spread']:.3g}%",
            "-" if s["max_relative_spread"] is None else f"{100 * s['max_relative_spread']:.3g}%",
            s["unit"],
        )
    console.print(t)
    console.print("(spread: (upper - lower) / nominal over the grid)")
    print_sensitivity(unc["sensitivity"], " (mean over the grid)")


def report_sections(
    args: argparse.Namespace,
    design: Any,
    variables: list[Any] | None,
    pose: Any,
    report_progress: Any,
) -> list[tuple[str, str, str]] | None:
    """The report's uncertainty section (None without tolerances)."""
    if variables is None:
        return None
    from ppm_stiffness.visuals.uncertainty_report import uncertainty_section

    report_progress("uncertainty bands", 0.0)
    return [
        uncertainty_section(design, variables, pose, args.grid, args.tolerance_method, args.samples)
    ]


__all__ = [
    "add_tolerance_arguments",
    "check_tolerance_options",
    "compute_bands",
    "curve_uncertainty",
    "map_uncertainty",
    "pose_uncertainty",
    "print_curve_uncertainty",
    "print_map_uncertainty",
    "print_pose_uncertainty",
    "read_tolerance_args",
    "report_sections",
]
