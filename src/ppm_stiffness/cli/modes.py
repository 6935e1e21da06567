"""``ppm-stiffness modes``: natural frequencies and mode shapes at a pose."""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING, Any

from ppm_stiffness.cli.common import (
    FIGURE_FORMATS,
    actuator_stiffness_text,
    add_design_argument,
    add_overwrite_argument,
    add_pose_arguments,
    add_tool_point_argument,
    add_wrench_argument,
    check_output_path,
    console,
    err_console,
    json_document,
    load_design_arg,
    parse_wrench,
    pose_from_args,
    tool_point_from_args,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.tolerances import add_tolerance_arguments, read_tolerance_args

if TYPE_CHECKING:
    import numpy as np


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_wrench_argument(parser)
    add_tool_point_argument(parser)
    add_tolerance_arguments(parser)
    parser.add_argument(
        "--link-modes",
        type=int,
        metavar="N",
        help="each leg's own lowest modes with the platform held (Craig-Bampton), N per "
        "leg (a degenerate pair kept whole); 0: the legs follow statically (default: 8)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    parser.add_argument(
        "--out",
        metavar="FIG",
        help="also draw the platform displaced along each mode; format from the suffix: "
        + ", ".join(FIGURE_FORMATS),
    )
    add_overwrite_argument(parser)


def run(args: argparse.Namespace) -> int:
    from rich.markup import escape

    out = check_output_path(args.out, "--out", FIGURE_FORMATS, overwrite=args.overwrite)
    design = load_design_arg(args)
    pose = pose_from_args(args, design)
    wrench = parse_wrench(args.wrench)
    tool = tool_point_from_args(args, design)
    variables = read_tolerance_args(args, design)
    if args.link_modes is not None and args.link_modes < 0:
        err_console.print(f"--link-modes {args.link_modes}: a number of modes per leg, 0 or more")
        return 2
    from ppm_stiffness.dynamics.analysis import MODES_UNITS, modal_analysis

    result = modal_analysis(design, pose, wrench, tool, args.link_modes).to_dict()
    if args.link_modes == 0:
        from ppm_stiffness.dynamics.legmodes import warn_slow_legs
        from ppm_stiffness.poses import full_pose

        f1 = result["frequencies"][0]
        warn_slow_legs(design, full_pose(design, pose), result["actuator_stiffness"], f1)
    if variables is not None:
        result["uncertainty"] = modes_uncertainty(args, design, variables, pose, tool, wrench)
    if out is not None:
        _figure(design, pose, tool, result, out, args.overwrite)
    if args.json:
        units = MODES_UNITS | ({"uncertainty.quantities": "Hz"} if variables else {})
        print(json_document("modes", result, units))
    else:
        k_units = [leg.actuator_units()[2] for leg in design.legs]
        print_tables(result, design.name, k_units)
        if variables is not None:
            from ppm_stiffness.cli.tolerances import print_pose_uncertainty

            print_pose_uncertainty(result["uncertainty"])
    if out is not None:
        (err_console if args.json else console).print(f"figure written to {escape(out)}")
    return 0


def modes_uncertainty(
    args: argparse.Namespace,
    design: Any,
    variables: list[Any],
    pose: np.ndarray,
    tool: np.ndarray,
    wrench: np.ndarray | None,
) -> dict[str, Any]:
    """Bands of the six natural frequencies f1..f6 [Hz] (``modes --json``'s
    ``uncertainty``: as ``analyze``'s, its quantities the frequencies)."""
    from ppm_stiffness.cli.tolerances import compute_bands, quantity_bands
    from ppm_stiffness.fit.band_outputs import MODES_FAILED_VALUE, modes_output

    output = modes_output(pose, tool, wrench, args.link_modes)  # the f1 the table shows
    bands = compute_bands(args, design, variables, output, MODES_FAILED_VALUE)
    return quantity_bands(bands, [f"f{j + 1}" for j in range(6)], "Hz")


def _figure(
    design: Any, pose: np.ndarray, tool: np.ndarray, result: dict[str, Any], out: str, over: bool
) -> None:
    """The mode-shape picture (shapes moved from the tool point to P)."""
    import numpy as np

    from ppm_stiffness.core.conventions import twist_b_from_twist_a
    from ppm_stiffness.model import tool_offset
    from ppm_stiffness.visuals import save_figure, use_headless_backend

    use_headless_backend()
    from ppm_stiffness.visuals.modes import plot_modes

    to_p = twist_b_from_twist_a(np.eye(3), tool_offset(pose, tool))
    shapes = np.array([to_p @ np.asarray(m["shape"]) for m in result["modes"]])
    state = "locked actuators" if result["state"] == "locked" else "under the wrench"
    fig = plot_modes(
        design,
        pose,
        result["frequencies"],
        shapes,
        [m["direction"] for m in result["modes"]],
        title=f"{design.name}: vibration modes ({state})",
    )
    with output_files(over) as files:
        save_figure(fig, files.temp(out, "--out"))


def print_tables(result: dict[str, Any], title: str, units: list[str]) -> None:
    """Readable tables of a modal analysis (:mod:`ppm_stiffness.dynamics.analysis`);
    ``units``: each leg's actuator stiffness unit."""
    import numpy as np
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.core.conventions import LENGTH_SCALE, TWIST_BALANCE, TWIST_COMPONENTS
    from ppm_stiffness.poses import format_pose

    c = console
    c.print(f"[bold]{escape(title)}[/bold]")
    p = result["pose"]
    full = [p[n] for n in ("x", "y", "z", "rx", "ry", "rz")]
    task = [("x", "y", "z", "rx", "ry", "rz").index(n) for n in result["task_coordinates"]]
    c.print(f"pose: {format_pose(full, task)} (P in F_b)")
    values = result["actuator_stiffness"]
    if len(set(units)) == 1 and all(v is not None and math.isfinite(v) for v in values):
        k_act = ", ".join(f"{v:.4g}" for v in values) + f" {units[0]}"
    else:
        k_act = ", ".join(
            actuator_stiffness_text(v, ".4g", u) for v, u in zip(values, units, strict=True)
        )
    if result["state"] == "locked":
        c.print(f"actuators locked (stiffness {k_act})")
    else:
        w = result["wrench"]
        loads = ", ".join(f"{v:.4g}" for v in w[3:]), ", ".join(f"{v:.4g}" for v in w[:3])
        c.print(
            f"under the wrench f = ({loads[0]}) N, m = ({loads[1]}) N·m: the loaded tangent "
            f"K, actuator stiffness {k_act}"
        )
    m = result["masses"]
    c.print(
        f"masses: platform {m['platform']:.4g} kg, links {m['links']:.4g} kg, "
        f"carriages {m['carriages']:.4g} kg (total {m['total']:.4g} kg)"
    )
    at = "T" if any(result["tool_point"]) else "P"
    t = Table(title=f"Natural frequencies, K v = omega^2 M v (at {at})", title_justify="left")
    shared = "platform_share" in result["modes"][0]
    for col in ("mode", "f [Hz]", "dominant direction", "share"):
        t.add_column(col, justify="right")
    if shared:
        t.add_column("platform's kinetic energy", justify="right")
    for j, mode in enumerate(result["modes"], start=1):
        cells = [str(j), f"{mode['frequency']:.5g}", mode["direction"]]
        cells.append(f"{mode['share'] * 100:.0f} %")
        if shared:
            cells.append(f"{mode['platform_share'] * 100:.3g} %")
        t.add_row(*cells)
    c.print(t)
    if "link_modes" in result:
        c.print(
            f"with each leg's {result['link_modes']} lowest own modes (platform held; "
            "Craig-Bampton); --link-modes 0: the legs follow statically"
        )
    s = Table(
        title=f"Mode shapes: twists at {at} (rotations x {LENGTH_SCALE:g} m), unit norm",
        title_justify="left",
    )
    s.add_column("mode", justify="right")
    for name in TWIST_COMPONENTS:
        s.add_column(name, justify="right")
    scale = TWIST_BALANCE
    for j, mode in enumerate(result["modes"], start=1):
        b = np.asarray(mode["shape"]) * scale
        s.add_row(str(j), *(f"{x + 0.0:+.3f}" for x in np.where(np.abs(b) < 5e-4, 0.0, b)))
    c.print(s)
    groups = result.get("modes_repeated") or []
    if groups:
        names = "; ".join(", ".join(str(i + 1) for i in g) for g in groups)
        c.print(
            f"note: repeated frequencies (modes {names}): their shapes are not unique; "
            "shown: those closest to the coordinate axes"
        )
