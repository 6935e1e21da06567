"""``ppm-stiffness mechanism``: the manipulator at a pose (top view of a planar design, 3-D
view of a spatial one)."""

from __future__ import annotations

import argparse

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_figure_output,
    add_pose_arguments,
    check_figure_path,
    console,
    load_design_arg,
    pose_from_args,
)
from ppm_stiffness.cli.output_files import output_files


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_figure_output(parser)
    parser.add_argument(
        "--allow-unreachable",
        action="store_true",
        help="draw a pose outside the legs' limits (each violated limit named in the title; "
        "legs without an inverse-kinematics solution left out) instead of refusing it",
    )


def run(args: argparse.Namespace) -> int:
    out = check_figure_path(args.out, args.overwrite)
    design = load_design_arg(args)
    # an unreachable pose is an error, as in every command, unless asked for
    pose = pose_from_args(args, design, check_reach=not args.allow_unreachable)

    from ppm_stiffness.visuals import save_figure, use_headless_backend

    use_headless_backend()
    from ppm_stiffness.visuals.mechanism import plot_mechanism

    fig = plot_mechanism(design, pose)
    with output_files(args.overwrite) as files:
        save_figure(fig, files.temp(out, "--out"))
    console.print(f"wrote {out}")
    return 0
