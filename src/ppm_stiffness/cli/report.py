"""``ppm-stiffness report``: one self-contained HTML page with every table and figure."""

from __future__ import annotations

import argparse
import time
from contextlib import suppress
from pathlib import Path

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_overwrite_argument,
    add_pose_arguments,
    add_wrench_argument,
    check_output_path,
    console,
    err_console,
    load_design_arg,
    parse_wrench,
    pose_from_args,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.cli.tolerances import (
    add_tolerance_arguments,
    read_tolerance_args,
    report_sections,
)
from ppm_stiffness.core.errors import InputDataError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_wrench_argument(parser)
    add_tolerance_arguments(parser)
    parser.epilog = (
        "Loaded case (--wrench overrides it): the design file's [reference_wrench], else "
        "the paper's f = [5, 5, 20] N, m_z = 0.1 N·m for a planar design and that load "
        "scaled to a spatial one (its tool point moves by 0.01 % of the design's size; "
        "docs/report.md)."
    )
    parser.add_argument(
        "--grid",
        type=int,
        default=60,
        metavar="N",
        help="points per axis of the stiffness maps (default 60)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument(
        "--out", metavar="DIR", required=True, help="output directory (gets report.html)"
    )


def design_text(args: argparse.Namespace) -> str | None:
    """The design file as written (None for the built-in design): its text, a
    byte-order mark dropped (not content, as the reader does)."""
    if args.design is None:
        return None
    return Path(args.design).read_bytes().decode("utf-8-sig")


def run(args: argparse.Namespace) -> int:
    if not 2 <= args.grid <= 2000:
        raise InputDataError(f"--grid must be between 2 and 2000, got {args.grid}")
    out_dir = Path(args.out)
    if not args.out.strip():
        raise InputDataError("--out: empty path")
    if out_dir.exists() and not out_dir.is_dir():
        raise InputDataError(f"--out {out_dir}: exists and is not a directory")
    if not out_dir.parent.is_dir():
        raise InputDataError(f"--out {out_dir}: directory {out_dir.parent} does not exist")
    if out_dir.is_dir():  # a new one is created (its parent must exist)
        check_output_path(str(out_dir / "report.html"), "--out", overwrite=args.overwrite)
    design = load_design_arg(args)
    pose = pose_from_args(args, design)  # refuses an unreachable pose
    wrench = parse_wrench(args.wrench)
    variables = read_tolerance_args(args, design)

    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from ppm_stiffness.visuals import use_headless_backend

    use_headless_backend()
    from ppm_stiffness.visuals.report import build_report

    start = time.perf_counter()
    show = not args.quiet and err_console.is_terminal
    with Progress(
        TextColumn("[bold]report[/bold] {task.description:<34}"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeElapsedColumn(),
        console=err_console,
        disable=not show,
        transient=True,
    ) as bar:
        task = bar.add_task("starting", total=1.0)

        def progress(description: str, fraction: float) -> None:
            bar.update(task, description=description, completed=fraction)

        extra = report_sections(args, design, variables, pose, progress)
        page = build_report(
            design, pose, wrench, args.grid, progress, args.design, extra, design_text(args)
        )
    created = not out_dir.is_dir()
    path = out_dir / "report.html"
    try:
        out_dir.mkdir(exist_ok=True)
        with output_files(args.overwrite) as out:
            out.temp(path, "--out").write_text(page, encoding="utf-8")
    except BaseException:  # refused or interrupted: no empty folder of ours left
        if created:
            with suppress(OSError):
                out_dir.rmdir()
        raise
    console.print(
        f"wrote {path} ({path.stat().st_size / 1e6:.1f} MB, {time.perf_counter() - start:.1f} s)"
    )
    return 0
