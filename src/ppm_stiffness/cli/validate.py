"""``ppm-stiffness validate``: the virtual-joint K against an independent FE frame model.

Needs the optional extra ``validate`` (PyNite). Compares at the home pose and at
``--poses`` seeded reachable poses, drawn over the design's task coordinates (within
``--radius`` of the home pose in every length coordinate and ``--angle`` in every
angle coordinate, or over the required region with ``--region``), completed; prints
per pose the largest relative differences (planar designs: the planar (phi_z, x, y)
and out-of-plane (phi_x, phi_y, z) blocks; other designs: the whole matrix; all: every
twist direction) and the time the FE model takes. Exit code 0 when every figure is
within its tolerance (planar 2 %, out-of-plane 5 %, whole matrix 2 %, directions 5 %),
1 otherwise.

``--modes``: also the natural frequencies at each pose: the whole FE frame's six lowest
(its consistent beam masses, link bodies, the platform's inertia) against the model's
with the legs' own modes (the default number per leg) and condensed
(:func:`ppm_stiffness.validation.modal.modal_comparison`); within 0.5 % in f1..f6. A
design whose mass model lumps a parallelogram's bars (the Delta) gets a note: the
frame's continuous bars differ from that rule by physics (docs/dynamics.md).

``--hinge FILE``: instead, each distinct notch hinge of a design (or one hinge) by a 2-D
finite-element model, plane stress and plane strain (scikit-fem,
:mod:`ppm_stiffness.validation.hinge_continuum`), beside the beam integrals.
"""

from __future__ import annotations

import argparse
import csv
import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from ppm_stiffness.cli.common import (
    add_design_argument,
    add_overwrite_argument,
    add_seed_argument,
    check_option_angle,
    check_output_path,
    console,
    eng,
    json_document,
    load_design_arg,
    progress,
)
from ppm_stiffness.cli.output_files import output_files
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.names import (
    ANGLE_COORDINATES,
    POSE_COORDINATES,
    POSE_CSV_COLUMNS,
    POSE_INDEX,
)

if TYPE_CHECKING:  # the design schema and the FE model load when run, not for --help
    import numpy as np
    from rich.table import Table

    from ppm_stiffness.design import Design
    from ppm_stiffness.validation.compare import PoseComparison
    from ppm_stiffness.validation.modal import ModalComparison

#: Upper bound of --poses: 2 to 10 minutes of FE solves on the reference machine.
MAX_POSES = 1000
#: --modes: the largest relative difference of f1..f6 accepted between the whole FE
#: frame and the model with link modes (the issue's 0.5 %; the shipped examples
#: measure 1.9e-4 at most, the flexure stage's notch hinges aside: 3.6e-3).
FREQUENCY_TOLERANCE = 5e-3


_Result = TypeVar("_Result")


def add_arguments(parser: argparse.ArgumentParser) -> None:

    add_overwrite_argument(parser)
    add_design_argument(parser)
    parser.add_argument(
        "--poses",
        type=int,
        default=5,
        metavar="N",
        help="seeded reachable poses besides the home pose (default 5)",
    )
    add_seed_argument(parser, "the poses")
    parser.add_argument(
        "--radius",
        type=float,
        metavar="MM",
        help="poses drawn within +-MM of the home pose in each length task coordinate "
        "(x, y, z) (default 10)",
    )
    parser.add_argument(
        "--angle",
        type=float,
        metavar="DEG",
        help="poses drawn within +-DEG of the home pose in each angle task coordinate "
        "(rx, ry, rz) (default 5)",
    )
    parser.add_argument(
        "--region",
        action="store_true",
        help="draw the poses over the design's required region ([workspace.required]) "
        "instead of --radius / --angle",
    )
    parser.add_argument(
        "--csv",
        metavar="FILE",
        help="write "
        + ", ".join(POSE_CSV_COLUMNS)
        + ", phi_deg (= pose_rz_deg), block, max_rel_diff "
        "(one row per pose and figure)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument(
        "--hinge",
        metavar="FILE",
        help="instead of the frame model: each notch hinge of a design FILE (or one hinge "
        "FILE: profile, width, material) by 2-D plane-stress and plane-strain FE models "
        "(scikit-fem): "
        "its K_phiz and axial K beside the beam integrals' (docs/flexures.md)",
    )
    parser.add_argument(
        "--json", action="store_true", help="print the comparison as one JSON object (SI)"
    )
    parser.add_argument(
        "--modes",
        action="store_true",
        help="also the natural frequencies f1..f6: the whole FE frame's (consistent beam "
        "masses, link bodies) against the model's with link modes (default per leg) at "
        f"each pose, within {FREQUENCY_TOLERANCE * 100:g} %% (needs a mass model)",
    )
    parser.add_argument(
        "--hinge-segments",
        type=int,
        default=DEFAULT_HINGE_SEGMENTS,
        metavar="N",
        help="a design with notch hinges: the convergence check at home builds each hinge "
        "as N/4, N/2 and N beam members (N a multiple of 4, at most "
        f"{MAX_HINGE_SEGMENTS}; default {DEFAULT_HINGE_SEGMENTS}: about 1.5 min on the "
        "3-RRR flexure stage; 0 skips it)",
    )


#: Default and largest --hinge-segments (the finest mesh of the hinge convergence check;
#: beyond it the solve's round-off, rising as N^3, passes the discretisation error).
DEFAULT_HINGE_SEGMENTS = 256
MAX_HINGE_SEGMENTS = 256

#: Defaults of --radius [mm] and --angle [deg].
DEFAULT_RADIUS_MM = 10.0
DEFAULT_ANGLE_DEG = 5.0


def _check_args(args: argparse.Namespace) -> None:
    """Check the options; fill in the defaults of --radius and --angle."""
    n = args.hinge_segments
    if n != 0 and not (4 <= n <= MAX_HINGE_SEGMENTS and n % 4 == 0):
        raise InputDataError(
            f"--hinge-segments must be 0 or a multiple of 4 from 4 to {MAX_HINGE_SEGMENTS}, got {n}"
        )
    if not 0 <= args.poses <= MAX_POSES:
        raise InputDataError(
            f"--poses must be between 0 and {MAX_POSES} (0.1 to 0.6 s of FE solve each), "
            f"got {args.poses}"
        )
    if args.region and (args.radius is not None or args.angle is not None):
        raise InputDataError(
            "--region draws the poses over the design's required region: give it "
            "without --radius and --angle"
        )
    for name, default in (("radius", DEFAULT_RADIUS_MM), ("angle", DEFAULT_ANGLE_DEG)):
        value = getattr(args, name)
        if value is None:
            setattr(args, name, default)
        elif not math.isfinite(value) or value < 0:
            raise InputDataError(f"--{name} must be finite and >= 0, got {value}")
    check_option_angle("--angle", args.angle)


def _run_modes(
    design: Design, poses: np.ndarray, args: argparse.Namespace
) -> list[ModalComparison]:
    from ppm_stiffness.validation.modal import modal_comparison

    return _at_each_pose("FE modes", design, poses, args, modal_comparison)


def _frequency_difference(c: ModalComparison) -> float:
    """The largest relative difference of f1..f6, the model with link modes against
    the whole FE frame."""
    return float(
        max(abs(a / b - 1.0) for a, b in zip(c.linked_frequencies, c.full_frequencies, strict=True))
    )


def _modes_table(design: Design, modal: list[ModalComparison]) -> Table:
    from rich import box
    from rich.table import Table

    link_modes = modal[0].link_modes if modal else 0
    table = Table(
        title="natural frequencies [Hz]: the model condensed and with "
        f"{link_modes} link modes per leg vs the whole FE frame (PyNite, consistent beam "
        "masses); f_link,1: the frame's with P held",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    for name in ("pose", "f1 cond.", "f1 links", "f1 FE", "f1..f6 diff", "f_link,1"):
        table.add_column(name, justify="right")
    for i, c in enumerate(modal):
        table.add_row(
            "home" if i == 0 else str(i),
            f"{c.model_frequencies[0]:.4g}",
            f"{c.linked_frequencies[0]:.4g}",
            f"{c.full_frequencies[0]:.4g}",
            eng(_frequency_difference(c), 3),
            f"{c.link_frequency:.4g}",
        )
    return table


def _print_bar_rule(design: Design) -> None:
    """A note where the mass model lumps a parallelogram's bars (module doc)."""
    from ppm_stiffness.validation.modal import lumps_bar_masses

    if lumps_bar_masses(design):
        console.print(
            "note: the mass model lumps each parallelogram bar's halves at its crossbars "
            "and has no bending of the bars, the FE frame has continuous bars: the "
            "difference is that rule (docs/dynamics.md: the Delta's f1, f2 3.6 % low, "
            "its bars' bending modes near 104 Hz absent)"
        )


def _modes_json(modal: list[ModalComparison], worst: float) -> dict[str, object]:
    """``--modes`` in the JSON document (module doc)."""
    return {
        "link_modes": modal[0].link_modes if modal else 0,
        "poses": [
            {
                "frequencies_condensed": c.model_frequencies.tolist(),
                "frequencies_link_modes": c.linked_frequencies.tolist(),
                "frequencies_fe": c.full_frequencies.tolist(),
                # None: no mass moves with P held (a leg without mass)
                "link_frequency_fe": (
                    float(c.link_frequency) if math.isfinite(c.link_frequency) else None
                ),
                "difference": _frequency_difference(c),
            }
            for c in modal
        ],
        "worst": worst,
        "tolerance": FREQUENCY_TOLERANCE,
    }


def _run_poses(design: Design, poses: np.ndarray, args: argparse.Namespace) -> list[PoseComparison]:
    from ppm_stiffness.validation.compare import compare_at_pose

    return _at_each_pose("FE model", design, poses, args, compare_at_pose)


def _at_each_pose(
    what: str,
    design: Design,
    poses: np.ndarray,
    args: argparse.Namespace,
    compare: Callable[[Design, np.ndarray], _Result],
) -> list[_Result]:
    """``compare(design, pose)`` at each pose, with a progress bar named ``what``
    (none with --quiet or --json)."""
    out: list[_Result] = []
    with progress(what, len(poses), enabled=not (args.quiet or args.json)) as advance:
        for pose in poses:
            out.append(compare(design, pose))
            advance(1)
    return out


#: Short table headers of the figures, and what they compare.
_HEADERS = {"planar": "planar", "out_of_plane": "out-pl.", "full": "full", "directions": "dirs"}
_DESCRIPTIONS = {
    "planar": "block phi_z, x, y",
    "out_of_plane": "block phi_x, phi_y, z",
    "full": "whole 6x6",
    "directions": "any twist direction",
}


def _shown_coordinates(design: Design) -> tuple[str, ...]:
    """The pose columns of the table: a planar design's task coordinates (the others
    are zero), all six for any other design (the dependent ones completed)."""

    return design.task_coordinates if design.planar else POSE_COORDINATES


def _coordinate(name: str, value: float, planar: bool) -> str:
    """A pose coordinate in mm or deg, at most 6 characters for a spatial design's
    table up to |angle| < 1000 deg and |length| < 100 m."""

    if name in ANGLE_COORDINATES:
        deg = math.degrees(value)
        return f"{deg:.{2 if planar or abs(deg) < 99.995 else 1}f}"
    mm = value * 1e3
    return f"{mm:.{2 if planar or abs(mm) < 99.995 else 1 if abs(mm) < 999.95 else 0}f}"


def _table(design: Design, results: list[PoseComparison]) -> Table:
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.validation.compare import figure_names

    names = figure_names(design)
    shown = _shown_coordinates(design)
    table = Table(
        title="virtual-joint K vs FE frame model (PyNite): largest relative "
        "differences (" + ", ".join(f"{_HEADERS[n]}: {_DESCRIPTIONS[n]}" for n in names) + "); "
        "pose in mm and deg",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    table.add_column("pose", justify="right")
    for name in shown:
        table.add_column(escape("phi" if design.planar and name == "rz" else name), justify="right")
    for name in names:
        table.add_column(_HEADERS[name], justify="right")
    for i, r in enumerate(results):
        table.add_row(
            "home" if i == 0 else str(i),
            *(_coordinate(n, float(r.pose[POSE_INDEX[n]]), design.planar) for n in shown),
            *(eng(r.differences[n], 3) for n in names),
        )
    return table


def _write_csv(path: Path, name: str, results: list[PoseComparison]) -> None:
    """Write the rows to ``path`` (a temporary file for ``--csv name``)."""
    from ppm_stiffness.validation.compare import csv_rows

    rows = csv_rows(results)
    try:
        with path.open("w", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    except OSError as exc:
        raise InputDataError(f"cannot write {name}: {exc.strerror}") from None


def _pose_json(pose: np.ndarray) -> dict[str, float]:
    """The full pose [m, rad] by coordinate name, and phi (= rz)."""

    out = {name: float(v) for name, v in zip(POSE_COORDINATES, pose, strict=True)}
    out["phi"] = float(pose[5])
    return out


#: The frame-model options that --hinge does not take (the defaults they must keep).
_FRAME_OPTIONS = {
    "design": None,
    "csv": None,
    "json": False,
    "region": False,
    "poses": 5,
    "radius": None,
    "angle": None,
    "seed": 0,
    "modes": False,
    "hinge_segments": DEFAULT_HINGE_SEGMENTS,
}


def _run_hinge(args: argparse.Namespace) -> int:
    """``--hinge FILE``: the continuum check of each distinct hinge (table on stdout)."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.cli.common import check_input_path
    from ppm_stiffness.validation.hinge_continuum import (
        continuum_stiffness,
        hinges_in_file,
        require_skfem,
    )

    given = [f"--{k.replace('_', '-')}" for k, v in _FRAME_OPTIONS.items() if getattr(args, k) != v]
    if given:
        raise InputDataError(f"--hinge checks hinges alone: give it without {', '.join(given)}")
    require_skfem()
    hinges = hinges_in_file(check_input_path(args.hinge, "--hinge"))
    table = Table(
        title="notch hinges: Euler-Bernoulli integrals (EB) vs 2-D FE, plane stress and "
        "plane strain (scikit-fem, quadratic triangles, Richardson limit over 3 meshes; p: "
        "observed order); a hinge much wider than thick lies between the two",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    for name in ("hinge", "stiffness", "EB", "FE", "EB/FE-1", "p"):
        table.add_column(name, justify="left" if name in ("hinge", "stiffness") else "right")
    with progress("FE hinge", len(hinges), enabled=not args.quiet) as advance:
        for name, hinge in hinges:
            stress = continuum_stiffness(hinge)
            strain = continuum_stiffness(hinge, state="strain")
            rows = [
                (f"K_{what}, plane {state}", r)
                for what in ("phiz", "x")
                for state, r in (("stress", stress), ("strain", strain))
            ]
            for k, (what, r) in enumerate(rows):
                eb, fe, order = (
                    (r.rotational_eb, r.rotational, r.order_rotational)
                    if "phiz" in what
                    else (r.axial_eb, r.axial, r.order_axial)
                )
                table.add_row(
                    escape(name) if k == 0 else "",
                    what,
                    eng(eb, 4),
                    eng(fe, 4),
                    f"{eb / fe - 1:+.4f}",
                    "-" if order is None else f"{order:.2f}",
                )
            advance(1)
    console.print(table)
    console.print("units: K_phiz N·m/rad, K_x N/m (hinge axes: docs/conventions.md)")
    return 0


def _print_hinge_convergence(design: Design, finest: int) -> None:
    """A design with notch hinges: the FE frame's hinge chains of ``finest`` / 4, / 2 and
    ``finest`` members against the model at home (docs/flexures.md, "FE frame")."""
    from ppm_stiffness.validation.compare import has_notch_hinges, hinge_convergence

    if finest == 0 or not has_notch_hinges(design):
        return
    r = hinge_convergence(design, segments=(finest // 4, finest // 2, finest))
    console.print(
        "notch hinges in the FE frame as chains of "
        + "/".join(str(n) for n in r.segments)
        + " beam members (harmonic-mean sections), at home: max|dK_ij|/sqrt(K_ii K_jj) "
        + ", ".join(f"{d:.2e}" for d in r.differences)
        + (f", observed order {r.order:.2f}" if r.order is not None else "")
        + f"; Richardson limit {r.extrapolated:.2e}; reciprocity of the FE compliance "
        + f"{max(r.asymmetry):.1e}"
    )


def run(args: argparse.Namespace) -> int:
    import numpy as np

    if args.hinge is not None:
        return _run_hinge(args)
    from ppm_stiffness.validation.compare import (
        TOLERANCES,
        describe_box,
        figure_names,
        sampling_box,
        validation_poses,
    )
    from ppm_stiffness.validation.fe_model import require_pynite

    _check_args(args)
    check_output_path(args.csv, "--csv", (".csv",), overwrite=args.overwrite)
    require_pynite()
    design = load_design_arg(args)
    radius, angle = args.radius * 1e-3, math.radians(args.angle)
    centre, half = sampling_box(design, radius, angle, args.region)
    poses = validation_poses(design, args.poses, args.seed, radius, angle, args.region)
    if args.modes:
        from ppm_stiffness.dynamics.mass import require_mass_model

        require_mass_model(design)
    results = _run_poses(design, poses, args)
    modal = _run_modes(design, poses, args) if args.modes else []
    names = figure_names(design)
    worst = {name: max(r.differences[name] for r in results) for name in names}
    ok = all(worst[name] <= TOLERANCES[name] for name in names)
    worst_modes = max((_frequency_difference(c) for c in modal), default=0.0)
    ok = ok and worst_modes <= FREQUENCY_TOLERANCE
    if args.csv:
        with output_files(args.overwrite) as out:
            _write_csv(out.temp(args.csv, "--csv"), args.csv, results)
    if args.json:
        payload = {
            "design": design.name,
            "architecture": design.architecture,
            "task_coordinates": list(design.task_coordinates),
            "sampling": {
                "region": bool(args.region),
                "low": dict(zip(design.task_coordinates, (centre - half).tolist(), strict=True)),
                "high": dict(zip(design.task_coordinates, (centre + half).tolist(), strict=True)),
            },
            "poses": [
                {
                    "pose": _pose_json(r.pose),
                    "differences": r.differences,
                    "stiffness_virtual_joint": r.k_virtual_joint,
                    "stiffness_fe": r.k_fe,
                    "time_fe": r.time_fe,
                    "time_virtual_joint": r.time_virtual_joint,
                }
                for r in results
            ],
            "worst": worst,
            "tolerances": {name: TOLERANCES[name] for name in names},
            "passed": ok,
            "csv": args.csv,
        }
        if args.modes:
            payload["modes"] = _modes_json(modal, worst_modes)
        units = {**_JSON_UNITS, **(_MODES_UNITS if args.modes else {})}
        print(json_document("validate", payload, units))
        return 0 if ok else 1
    console.print(
        f"poses: the home pose and {args.poses} drawn with {describe_box(design, centre, half)}"
        f"{' (the required region)' if args.region else ''}, seed {args.seed}"
    )
    console.print(_table(design, results))
    for name in names:
        console.print(
            f"{name}: max {worst[name]:.2e} (tolerance {TOLERANCES[name]:.0%}) "
            f"{'ok' if worst[name] <= TOLERANCES[name] else 'FAILED'}"
        )
    if args.modes:
        console.print(_modes_table(design, modal))
        console.print(
            f"frequencies (f1..f6, with link modes vs FE): max {worst_modes:.2e} "
            f"(tolerance {FREQUENCY_TOLERANCE:.1%}) "
            f"{'ok' if worst_modes <= FREQUENCY_TOLERANCE else 'FAILED'}"
        )
        _print_bar_rule(design)
    _print_hinge_convergence(design, args.hinge_segments)
    t_fe = float(np.mean([r.time_fe for r in results]))
    t_vj = float(np.mean([r.time_virtual_joint for r in results]))
    console.print(
        f"time per pose: FE {t_fe * 1e3:.1f} ms, virtual joints {t_vj * 1e3:.2f} ms "
        f"(FE / VJ = {t_fe / t_vj:.0f})"
    )
    return 0 if ok else 1


_BLOCKS = "K_rr N·m/rad, K_rt N, K_tt N/m (order phi_x, phi_y, phi_z, x, y, z)"
_JSON_UNITS = {
    "sampling": "x, y, z [m], rx, ry, rz [rad] (the task coordinates' ranges drawn from)",
    "poses.pose": "x, y, z [m], rx, ry, rz [rad] (R = Rz Ry Rx); phi = rz",
    "poses.differences": "1 (largest relative difference of each figure)",
    "poses.stiffness_virtual_joint": _BLOCKS,
    "poses.stiffness_fe": _BLOCKS,
    "poses.time_fe": "s",
    "poses.time_virtual_joint": "s",
    "worst": "1",
    "tolerances": "1",
}
#: The units of ``--modes`` in the JSON document.
_MODES_UNITS = {
    "modes.poses": "Hz (frequencies_*, link_frequency_fe); 1 (difference)",
    "modes.worst": "1",
    "modes.tolerance": "1",
}
