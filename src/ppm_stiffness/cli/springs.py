"""``ppm-stiffness springs``: picture of the six screw springs (the paper's Fig. 5)."""

from __future__ import annotations

import argparse

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_figure_output,
    add_pose_arguments,
    add_wrench_argument,
    check_figure_path,
    console,
    load_design_arg,
    parse_wrench,
    pose_from_args,
)
from ppm_stiffness.cli.output_files import output_files


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_wrench_argument(parser)
    add_figure_output(parser)


def run(args: argparse.Namespace) -> int:
    out = check_figure_path(args.out, args.overwrite)
    design = load_design_arg(args)
    pose = pose_from_args(args, design)
    wrench = parse_wrench(args.wrench)
    from ppm_stiffness.core.eigenscrews import eigenscrews
    from ppm_stiffness.model import stiffness_at_pose
    from ppm_stiffness.statics.loading import loaded_state

    if wrench is None:
        k = stiffness_at_pose(design, pose)
        state = "unloaded"
    else:
        k = loaded_state(design, wrench, pose).stiffness_matrix
        f, m = wrench[3:], wrench[:3]
        state = "f = ({:g}, {:g}, {:g}) N, m = ({:g}, {:g}, {:g}) N·m".format(*f, *m)
    springs = eigenscrews(k)

    from ppm_stiffness.visuals import save_figure, use_headless_backend

    use_headless_backend()
    from ppm_stiffness.visuals.leg_geometry import pose_text
    from ppm_stiffness.visuals.springs import plot_screw_springs

    title = f"Screw springs of K at P ({state})\n{pose_text(design, pose)}"
    fig = plot_screw_springs(springs, design, pose, title=title)
    with output_files(args.overwrite) as files:
        save_figure(fig, files.temp(out, "--out"))
    console.print(f"wrote {out}")
    return 0
