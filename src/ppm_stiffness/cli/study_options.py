"""Options shared by ``compare``, ``sweep`` and ``optimize``: the required region, the
wrench, where the designs are evaluated, and the stiffness maps they draw.

Not a command (it is not in :data:`ppm_stiffness.cli.COMMANDS`). Light at import: the
optimisation package, scipy, matplotlib and dask load inside the functions.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ppm_stiffness.cli.common import (
    add_link_modes_argument,
    f1_link_modes,
    link_modes_from_args,
    parse_floats,
)
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.core.names import ANGLE_COORDINATES, POSE_COORDINATES

if TYPE_CHECKING:
    from ppm_stiffness.design import Design
    from ppm_stiffness.design.schema import RequiredRegionModel

#: Grid points per axis of the pictures' stiffness maps (default).
MAP_GRID = 60


def add_region_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--region",
        metavar="X0,X1,Y0,Y1,PHI0,PHI1,NX,NY,NPHI",
        help="required region over the design's task coordinates [mm, deg] and its grid, "
        "instead of its [workspace.required] (which is in SI: m, rad): LO,HI of each task "
        "coordinate in order, then the grid counts (planar: X0,X1,Y0,Y1,PHI0,PHI1,NX,NY,"
        "NPHI; a tripod: Z0,Z1,RX0,RX1,RY0,RY1,NZ,NRX,NRY; a hexapod: 12 ends, 6 counts)",
    )


def add_load_margin_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--load-margin",
        action="store_true",
        help="also the load margin of --wrench (the smallest factor of the load at which "
        "the machine becomes unstable), on the region's corner poses only (about 0.1 s "
        "per pose; docs/optimization.md)",
    )


def add_f1_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--no-f1",
        action="store_true",
        help="leave out the first natural frequency (the f1 figures): by default a design "
        "with a mass model gets them, at several times the cost of the stiffness figures",
    )
    add_link_modes_argument(parser, "the f1 figures")


def study_link_modes(args: argparse.Namespace, frequencies: bool) -> int:
    """--link-modes of compare and sweep: the count per leg (the default when not
    given); 0 without the f1 figures. Refused with --no-f1."""
    n = link_modes_from_args(args, not args.no_f1, "the f1 figures (--no-f1 given)")
    return f1_link_modes(n, frequencies) or 0


def margin_note(poses: int) -> str:
    """The line saying where the load margin was evaluated."""
    return (
        f"load margin: the minimum over the region's {poses} corner poses (a coarse "
        "sub-grid; a lower margin between them is not seen); 1000 = no instability up "
        "to 1000 times the load"
    )


def add_execution_arguments(parser: argparse.ArgumentParser) -> None:
    where = parser.add_mutually_exclusive_group()
    where.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="evaluate the designs in N local processes (default: serially, here)",
    )
    where.add_argument(
        "--scheduler",
        metavar="tcp://HOST:PORT",
        help="evaluate the designs on this Dask distributed scheduler (extra 'dask')",
    )
    parser.add_argument(
        "--quiet", action="store_true", help="no progress bar (compare: nor timing line)"
    )


#: Smallest nonzero extent of --region along x or y [mm]: below it, metres are likely.
MIN_REGION_SPAN_MM = 0.1
#: Largest |x|, |y| of --region within which every value hints at metres [mm].
METRE_LIKE_MM = 1.0


def region_names(task: Sequence[str]) -> list[str]:
    """The option's names of the task coordinates: X, Y, Z, RX, RY, and PHI for rz of a
    planar design (RZ of any other)."""
    planar = tuple(task) == PLANAR_TASK
    return ["PHI" if n == "rz" and planar else n.upper() for n in task]


def _check_region_ranges(
    values: list[float], counts: list[int], task: Sequence[str] = ("x", "y", "rz")
) -> None:
    """The --region ranges in the option's units (mm, deg), each error naming them so:
    out of range, inverted, inconsistent with its grid count, or so small that the
    numbers are likely metres (an error below :data:`MIN_REGION_SPAN_MM` across, a
    warning when every length lies within +-:data:`METRE_LIKE_MM`)."""
    import warnings

    from ppm_stiffness.design.schema import (
        MAX_REGION_ANGLE,
        MAX_REGION_AXIS,
        MAX_REGION_LENGTH,
    )

    names = region_names(task)
    if not all(1 <= c <= MAX_REGION_AXIS for c in counts):
        raise InputDataError(
            f"--region: {', '.join('N' + n for n in names)} must be between 1 and "
            f"{MAX_REGION_AXIS}, got {counts}"
        )
    angle = [n in ANGLE_COORDINATES for n in task]
    axes = [
        (
            f"{n}0,{n}1",
            f"N{n}",
            "deg" if a else "mm",
            math.degrees(MAX_REGION_ANGLE) if a else 1e3 * MAX_REGION_LENGTH,
        )
        for n, a in zip(names, angle, strict=True)
    ]
    for k, (pair, count, unit, limit) in enumerate(axes):
        lo, hi = values[2 * k], values[2 * k + 1]
        text = f"--region {pair} = {lo:g},{hi:g} {unit}"
        if max(abs(lo), abs(hi)) > limit:
            raise InputDataError(f"{text}: beyond +-{limit:g} {unit}, the option's limit")
        if lo > hi:
            first, second = pair.split(",")
            raise InputDataError(f"{text}: inverted range ({first} > {second})")
        if (counts[k] == 1) != (lo == hi):
            raise InputDataError(
                f"{text} with {count} = {counts[k]}: one grid value goes with equal ends, "
                "and equal ends with one grid value"
            )
        if unit == "mm" and 0 < hi - lo < MIN_REGION_SPAN_MM:
            raise InputDataError(
                f"{text}: {hi - lo:.3g} mm across, less than {MIN_REGION_SPAN_MM:g} mm; "
                f"the option takes mm: were these metres ({1e3 * lo:g},{1e3 * hi:g} mm)?"
            )
    length_values = [v for k, a in enumerate(angle) if not a for v in values[2 * k : 2 * k + 2]]
    lengths = [abs(v) for v in length_values]
    if any(lengths) and max(lengths) <= METRE_LIKE_MM:
        which = " and ".join(n.lower() for n, a in zip(names, angle, strict=True) if not a)
        warnings.warn(
            f"--region: {which} within +-{METRE_LIKE_MM:g} mm; the option takes mm (if "
            f"these are metres, write {','.join(f'{1e3 * v:g}' for v in length_values)})",
            UserWarning,
            stacklevel=2,
        )


#: The task coordinates of a planar design.
PLANAR_TASK = ("x", "y", "rz")


def region_from_text(text: str, task: Sequence[str] = PLANAR_TASK) -> RequiredRegionModel:
    """``LO,HI`` of each task coordinate then their grid counts [mm or deg, counts] as a
    region (SI); a planar design's ``X0,X1,Y0,Y1,PHI0,PHI1,NX,NY,NPHI``.

    Raises
    ------
    InputDataError
        A malformed list, or a range refused in the option's units (mm, deg; see
        :func:`_check_region_ranges`).
    """
    from ppm_stiffness.optimize.region import region_from_ranges

    names = region_names(task)
    n = len(names)
    spec = ",".join([f"{a}0,{a}1" for a in names] + [f"N{a}" for a in names])
    v = parse_floats(text, 3 * n, "--region", f"{spec} [mm, deg]")
    if any(c != int(c) for c in v[2 * n :]):
        raise InputDataError(
            f"--region: {', '.join('N' + a for a in names)} must be integers, got {v[2 * n :]}"
        )
    counts = [int(c) for c in v[2 * n :]]
    _check_region_ranges(v[: 2 * n], counts, task)
    ranges = {
        name: (
            (math.radians(v[2 * k]), math.radians(v[2 * k + 1]))
            if name in ANGLE_COORDINATES
            else (v[2 * k] * 1e-3, v[2 * k + 1] * 1e-3)
        )
        for k, name in enumerate(task)
    }
    try:
        return region_from_ranges(ranges, counts)
    except DesignError as exc:  # from the region model (the grid's size): name the option
        message = str(exc).removeprefix("region: ")
        raise InputDataError(f"--region: {message}") from None


def region_from_args(args: argparse.Namespace, designs: Sequence[Design]) -> RequiredRegionModel:
    """--region, else the designs' one ``[workspace.required]`` (all equal)."""
    from ppm_stiffness.optimize.region import region_of

    tasks = {tuple(d.task_coordinates) for d in designs}
    if len(tasks) > 1:
        raise InputDataError(
            "the designs compared must share their task coordinates; these have "
            + " and ".join(f"({', '.join(t)})" for t in sorted(tasks))
        )
    if args.region is not None:
        return region_from_text(args.region, designs[0].task_coordinates)
    regions = [region_of(d) for d in designs]
    for d, r in zip(designs[1:], regions[1:], strict=True):
        if r != regions[0]:
            raise InputDataError(
                f"designs {designs[0].name!r} and {d.name!r} have different "
                "[workspace.required] regions; pass --region to compare them on one"
            )
    return regions[0]


def region_text(region: RequiredRegionModel) -> str:
    """One line describing the region in mm and deg."""
    from ppm_stiffness.maps.slices import cli_scale

    planar = tuple(region.ranges()) == PLANAR_TASK
    parts = []
    for name, (lo, hi) in region.ranges().items():
        scale, unit = cli_scale(name)
        label = "φ" if planar and name == "rz" else name
        if unit == "deg":
            parts.append(f"{label} [{lo * scale:.4g}, {hi * scale:.4g}]°")
        else:
            parts.append(f"{label} [{lo * scale:g}, {hi * scale:g}] mm")
    grid = " x ".join(str(n) for n in region.grid)
    return f"{', '.join(parts)}; grid {grid} = {math.prod(region.grid)} poses"


def region_json(region: RequiredRegionModel) -> dict[str, Any]:
    """The region [m, rad] by design-file key (x, y, z, rx, ry, phi), the grid counts and
    the task coordinates it ranges over."""
    from ppm_stiffness.design.schema import REGION_KEYS

    out: dict[str, Any] = {
        REGION_KEYS[POSE_COORDINATES.index(name)]: list(pair)
        for name, pair in region.ranges().items()
    }
    out["grid"] = list(region.grid)
    out["task_coordinates"] = list(region.ranges())
    return out


def executor_label(args: argparse.Namespace) -> str:
    if args.scheduler is not None:
        return f"dask {args.scheduler}"
    if args.workers is not None and args.workers > 1:
        return f"{args.workers} local processes"
    return "serial"


def check_workers(args: argparse.Namespace) -> None:
    if args.workers is not None and args.workers < 1:
        raise InputDataError(f"--workers must be at least 1, got {args.workers}")


#: The map quantities of the pictures of a design that is not planar (the worst-direction
#: principal stiffnesses); a planar design's are the paper's k_phi, k_x, k_y.
SPATIAL_MAP_QUANTITIES = ("rotational_min", "translational_min")


def region_map_axes(region: RequiredRegionModel) -> tuple[str, str]:
    """The two coordinates of the pictures' maps: x, y for a planar region, else the
    first two that vary over the region (the first two when fewer vary)."""
    names = list(region.ranges())
    if tuple(names) == PLANAR_TASK:
        return ("x", "y")
    varying = [n for n, count in zip(names, region.grid, strict=True) if count > 1]
    chosen = (varying + [n for n in names if n not in varying])[:2]
    return (chosen[0], chosen[1])


def region_maps(
    designs: Sequence[Design], region: RequiredRegionModel, grid: int = MAP_GRID
) -> list[Any]:
    """Locked-actuator stiffness maps of each design over the region's two map axes
    (:func:`region_map_axes`), the other coordinates at the middle of their ranges, over
    the region's box widened by a quarter of its size on each side."""
    from ppm_stiffness.maps.workspace import stiffness_map

    ranges = region.ranges()
    axes = region_map_axes(region)
    bounds = []
    for name in axes:
        lo, hi = ranges[name]
        w = max(hi - lo, 1e-3)
        bounds += [lo - w / 4, hi + w / 4]
    if tuple(ranges) == PLANAR_TASK:
        phi = 0.5 * (ranges["rz"][0] + ranges["rz"][1])
        return [stiffness_map(d, phi=phi, grid=grid, bounds=bounds) for d in designs]
    fixed = {n: 0.5 * (lo + hi) for n, (lo, hi) in ranges.items() if n not in axes}
    return [
        stiffness_map(
            d,
            grid=grid,
            axes=axes,
            fixed=fixed,
            bounds=bounds,
            quantities=SPATIAL_MAP_QUANTITIES,
        )
        for d in designs
    ]


def region_box(region: RequiredRegionModel) -> tuple[float, float, float, float]:
    """The region's ranges of the two map axes (u0, u1, v0, v1) [m or rad]."""
    a, b = region_map_axes(region)
    return (*region.range(a), *region.range(b))


def figure_cell(value: float | None) -> str:
    """A figure for a table: engineering notation, 'n/a' for none, 'inf' for unbounded."""
    from ppm_stiffness.cli.common import eng

    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    return eng(value)
