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

from ppm_stiffness.cli.common import parse_floats
from ppm_stiffness.core.errors import DesignError, InputDataError

if TYPE_CHECKING:
    from ppm_stiffness.design import Design
    from ppm_stiffness.design.schema import RequiredRegionModel

#: Grid points per axis of the pictures' stiffness maps (default).
MAP_GRID = 60


def add_region_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--region",
        metavar="X0,X1,Y0,Y1,PHI0,PHI1,NX,NY,NPHI",
        help="required region [mm, mm, deg] and its grid, instead of the design's "
        "[workspace.required] (which is in SI: m, rad)",
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
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


#: Smallest nonzero extent of --region along x or y [mm]: below it, metres are likely.
MIN_REGION_SPAN_MM = 0.1
#: Largest |x|, |y| of --region within which every value hints at metres [mm].
METRE_LIKE_MM = 1.0


def _check_region_ranges(values: list[float], counts: list[int]) -> None:
    """The --region ranges in the option's units (mm, deg), each error naming them so:
    out of range, inverted, inconsistent with its grid count, or so small that the
    numbers are likely metres (an error below :data:`MIN_REGION_SPAN_MM` across, a
    warning when every x and y lies within +-:data:`METRE_LIKE_MM`)."""
    import warnings

    from ppm_stiffness.design.schema import (
        MAX_REGION_ANGLE,
        MAX_REGION_AXIS,
        MAX_REGION_LENGTH,
    )

    if not all(1 <= c <= MAX_REGION_AXIS for c in counts):
        raise InputDataError(
            f"--region: NX, NY, NPHI must be between 1 and {MAX_REGION_AXIS}, got {counts}"
        )
    axes = (
        ("X0,X1", "NX", "mm", 1e3 * MAX_REGION_LENGTH),
        ("Y0,Y1", "NY", "mm", 1e3 * MAX_REGION_LENGTH),
        ("PHI0,PHI1", "NPHI", "deg", math.degrees(MAX_REGION_ANGLE)),
    )
    for k, (names, count, unit, limit) in enumerate(axes):
        lo, hi = values[2 * k], values[2 * k + 1]
        text = f"--region {names} = {lo:g},{hi:g} {unit}"
        if max(abs(lo), abs(hi)) > limit:
            raise InputDataError(f"{text}: beyond +-{limit:g} {unit}, the option's limit")
        if lo > hi:
            first, second = names.split(",")
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
    lengths = [abs(v) for v in values[:4]]
    if any(lengths) and max(lengths) <= METRE_LIKE_MM:
        warnings.warn(
            f"--region: x and y within +-{METRE_LIKE_MM:g} mm; the option takes mm (if "
            f"these are metres, write {','.join(f'{1e3 * v:g}' for v in values[:4])})",
            UserWarning,
            stacklevel=2,
        )


def region_from_text(text: str) -> RequiredRegionModel:
    """``X0,X1,Y0,Y1,PHI0,PHI1,NX,NY,NPHI`` [mm, mm, deg, counts] as a region (SI).

    Raises
    ------
    InputDataError
        A malformed list, or a range refused in the option's units (mm, deg; see
        :func:`_check_region_ranges`).
    """
    from ppm_stiffness.optimize.region import make_region

    v = parse_floats(text, 9, "--region", "X0,X1,Y0,Y1,PHI0,PHI1,NX,NY,NPHI [mm, deg]")
    if any(c != int(c) for c in v[6:]):
        raise InputDataError(f"--region: NX, NY, NPHI must be integers, got {v[6:]}")
    counts = [int(c) for c in v[6:]]
    _check_region_ranges(v[:6], counts)
    try:
        return make_region(
            (v[0] * 1e-3, v[1] * 1e-3),
            (v[2] * 1e-3, v[3] * 1e-3),
            (math.radians(v[4]), math.radians(v[5])),
            (counts[0], counts[1], counts[2]),
        )
    except DesignError as exc:  # from the region model (the grid's size): name the option
        message = str(exc).removeprefix("region: ")
        raise InputDataError(f"--region: {message}") from None


def region_from_args(args: argparse.Namespace, designs: Sequence[Design]) -> RequiredRegionModel:
    """--region, else the designs' one ``[workspace.required]`` (all equal)."""
    from ppm_stiffness.optimize.region import region_of

    if args.region is not None:
        return region_from_text(args.region)
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
    nx, ny, nphi = region.grid
    phi = region.range("phi")
    return (
        f"x [{region.range('x')[0] * 1e3:g}, {region.range('x')[1] * 1e3:g}] mm, "
        f"y [{region.range('y')[0] * 1e3:g}, {region.range('y')[1] * 1e3:g}] mm, "
        f"φ [{math.degrees(phi[0]):.4g}, {math.degrees(phi[1]):.4g}]°; "
        f"grid {nx} x {ny} x {nphi} = {nx * ny * nphi} poses"
    )


def region_json(region: RequiredRegionModel) -> dict[str, Any]:
    return {
        "x": list(region.range("x")),
        "y": list(region.range("y")),
        "phi": list(region.range("phi")),
        "grid": list(region.grid),
    }


def executor_label(args: argparse.Namespace) -> str:
    if args.scheduler is not None:
        return f"dask {args.scheduler}"
    if args.workers is not None and args.workers > 1:
        return f"{args.workers} local processes"
    return "serial"


def check_workers(args: argparse.Namespace) -> None:
    if args.workers is not None and args.workers < 1:
        raise InputDataError(f"--workers must be at least 1, got {args.workers}")


def region_maps(
    designs: Sequence[Design], region: RequiredRegionModel, grid: int = MAP_GRID
) -> list[Any]:
    """Locked-actuator stiffness maps of each design at the region's middle orientation,
    over the region's box widened by a quarter of its size on each side."""
    from ppm_stiffness.maps.workspace import stiffness_map

    phi = 0.5 * (region.range("phi")[0] + region.range("phi")[1])
    wx = max(region.range("x")[1] - region.range("x")[0], 1e-3)
    wy = max(region.range("y")[1] - region.range("y")[0], 1e-3)
    bounds = (
        region.range("x")[0] - wx / 4,
        region.range("x")[1] + wx / 4,
        region.range("y")[0] - wy / 4,
        region.range("y")[1] + wy / 4,
    )
    return [stiffness_map(d, phi=phi, grid=grid, bounds=bounds) for d in designs]


def region_box(region: RequiredRegionModel) -> tuple[float, float, float, float]:
    return (region.range("x")[0], region.range("x")[1], region.range("y")[0], region.range("y")[1])


def figure_cell(value: float | None) -> str:
    """A figure for a table: engineering notation, 'n/a' for none, 'inf' for unbounded."""
    from ppm_stiffness.cli.common import eng

    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    return eng(value)
