"""``ppm-stiffness validate``: the virtual-joint K against an independent FE frame model.

Needs the optional extra ``validate`` (PyNite). Compares at the workspace centre and
at ``--poses`` seeded reachable poses; prints the largest relative difference of the
planar (phi_z, x, y) and out-of-plane (phi_x, phi_y, z) blocks per pose and the time
each model takes. Exit code 0 when every block is within the tolerances (planar 2%,
out-of-plane 5%), 1 otherwise.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np
from rich.markup import escape
from rich.table import Table

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_overwrite_argument,
    add_seed_argument,
    check_output_path,
    console,
    eng,
    json_document,
    load_design_arg,
    progress,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.validation.compare import (
    BLOCKS,
    TOLERANCES,
    PoseComparison,
    compare_at_pose,
    csv_rows,
    validation_poses,
)
from ppm_stiffness.validation.fe_model import require_pynite

#: Upper bound of --poses: about 3 to 4 minutes of FE solves on the reference machine.
MAX_POSES = 1000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_overwrite_argument(parser)
    add_design_argument(parser)
    parser.add_argument(
        "--poses",
        type=int,
        default=5,
        metavar="N",
        help="seeded reachable poses besides the workspace centre (default 5)",
    )
    add_seed_argument(parser, "the poses")
    parser.add_argument(
        "--radius",
        type=float,
        default=10.0,
        metavar="MM",
        help="poses drawn within +-MM of the centre in x and y (default 10)",
    )
    parser.add_argument(
        "--angle",
        type=float,
        default=5.0,
        metavar="DEG",
        help="poses drawn within +-DEG of the centre orientation (default 5)",
    )
    parser.add_argument(
        "--csv",
        metavar="FILE",
        help="write pose_x_mm, pose_y_mm, phi_deg, block, max_rel_diff (one row per "
        "pose and block)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument(
        "--json", action="store_true", help="print the comparison as one JSON object (SI)"
    )


def _check_args(args: argparse.Namespace) -> None:
    if not 0 <= args.poses <= MAX_POSES:
        raise InputDataError(
            f"--poses must be between 0 and {MAX_POSES} (about 0.2 s of FE solve each), "
            f"got {args.poses}"
        )
    for name in ("radius", "angle"):
        value = getattr(args, name)
        if not math.isfinite(value) or value < 0:
            raise InputDataError(f"--{name} must be finite and >= 0, got {value}")


def _run_poses(design: Design, poses: np.ndarray, args: argparse.Namespace) -> list[PoseComparison]:
    out: list[PoseComparison] = []
    with progress("FE model", len(poses), enabled=not (args.quiet or args.json)) as advance:
        for pose in poses:
            out.append(compare_at_pose(design, pose))
            advance(1)
    return out


def _table(results: list[PoseComparison]) -> Table:
    table = Table(
        title="virtual-joint (VJ) K vs FE frame model (PyNite): largest relative "
        "difference of the planar and out-of-plane (out-pl.) blocks; time per pose",
        title_justify="left",
    )
    for col in (
        "pose",
        "x [mm]",
        "y [mm]",
        "phi [deg]",
        "planar",
        "out-pl.",
        "FE [s]",
        "VJ [s]",
    ):
        table.add_column(escape(col), justify="right")
    for i, r in enumerate(results):
        table.add_row(
            "centre" if i == 0 else str(i),
            f"{r.pose[0] * 1e3:.2f}",
            f"{r.pose[1] * 1e3:.2f}",
            f"{np.degrees(r.pose[2]):.2f}",
            eng(r.differences["planar"], 3),
            eng(r.differences["out_of_plane"], 3),
            eng(r.time_fe, 3),
            eng(r.time_virtual_joint, 3),
        )
    return table


def _write_csv(path: Path, name: str, results: list[PoseComparison]) -> None:
    """Write the rows to ``path`` (a temporary file for ``--csv name``)."""
    rows = csv_rows(results)
    try:
        with path.open("w", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    except OSError as exc:
        raise InputDataError(f"cannot write {name}: {exc.strerror}") from None


def run(args: argparse.Namespace) -> int:
    _check_args(args)
    check_output_path(args.csv, "--csv", (".csv",), overwrite=args.overwrite)
    require_pynite()
    design = load_design_arg(args)
    poses = validation_poses(
        design, args.poses, args.seed, args.radius * 1e-3, math.radians(args.angle)
    )
    results = _run_poses(design, poses, args)
    worst = {name: max(r.differences[name] for r in results) for name in BLOCKS}
    ok = all(worst[name] <= TOLERANCES[name] for name in BLOCKS)
    if args.csv:
        with output_files(args.overwrite) as out:
            _write_csv(out.temp(args.csv, "--csv"), args.csv, results)
    if args.json:
        payload = {
            "design": design.name,
            "architecture": design.architecture,
            "poses": [
                {
                    "pose": {"x": r.pose[0], "y": r.pose[1], "phi": r.pose[2]},
                    "differences": r.differences,
                    "stiffness_virtual_joint": r.k_virtual_joint,
                    "stiffness_fe": r.k_fe,
                    "time_fe": r.time_fe,
                    "time_virtual_joint": r.time_virtual_joint,
                }
                for r in results
            ],
            "worst": worst,
            "tolerances": {name: TOLERANCES[name] for name in BLOCKS},
            "passed": ok,
            "csv": args.csv,
        }
        print(json_document("validate", payload, _JSON_UNITS))
        return 0 if ok else 1
    console.print(_table(results))
    for name in BLOCKS:
        console.print(
            f"{name}: max {worst[name]:.2e} (tolerance {TOLERANCES[name]:.0%}) "
            f"{'ok' if worst[name] <= TOLERANCES[name] else 'FAILED'}"
        )
    t_fe = float(np.mean([r.time_fe for r in results]))
    t_vj = float(np.mean([r.time_virtual_joint for r in results]))
    console.print(
        f"time per pose: FE {t_fe * 1e3:.1f} ms, virtual joints {t_vj * 1e3:.2f} ms "
        f"(FE / VJ = {t_fe / t_vj:.0f})"
    )
    return 0 if ok else 1


_BLOCKS = "K_rr N·m/rad, K_rt N, K_tt N/m (order phi_x, phi_y, phi_z, x, y, z)"
_JSON_UNITS = {
    "poses.pose": "x, y [m], phi [rad]",
    "poses.differences": "1 (largest relative difference of the block)",
    "poses.stiffness_virtual_joint": _BLOCKS,
    "poses.stiffness_fe": _BLOCKS,
    "poses.time_fe": "s",
    "poses.time_virtual_joint": "s",
    "worst": "1",
    "tolerances": "1",
}
