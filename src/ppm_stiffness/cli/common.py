"""Helpers shared by the CLI commands: options, units at the edges, output.

Every command module imports this one, also for its ``--help``: the library's design,
model and analysis modules (pydantic, the dynamics, ...), numpy and rich are imported
inside the helpers that use them (the consoles are made on first use), so that
``ppm-stiffness COMMAND --help`` stays light (``benchmarks/bench_cli.py``,
``tests/test_cold_start.py``).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from ppm_stiffness.core.errors import InputDataError, UnreachablePoseError
from ppm_stiffness.core.names import POSE_INDEX

if TYPE_CHECKING:
    import numpy as np
    from rich.console import Console

    from ppm_stiffness.design import Design

__all__ = ["json_document"]  # for the commands (JSON_SCHEMA_VERSION too, lazily)


def json_document(command: str, payload: dict[str, Any], units: dict[str, str]) -> str:
    """:func:`ppm_stiffness.analysis.json_document` (imported when a document is made)."""
    from ppm_stiffness.analysis import json_document as document

    return document(command, payload, units)


def actuator_stiffness_text(value: float | None, spec: str = ".6g", unit: str = "") -> str:
    """An actuator stiffness for the text output (``5e+07 N/m``), or "none (passive
    leg)" for a passive constraining leg's (``inf`` inside, ``null`` in JSON)."""
    if value is None or not math.isfinite(value):
        return "none (passive leg)"
    return f"{value:{spec}}" + (f" {unit}" if unit else "")


def solve_legs(design: Design, pose: np.ndarray) -> None:
    """:func:`ppm_stiffness.model.solve_legs` (imported when called), for its refusal of
    a pose out of reach."""
    from ppm_stiffness.model import solve_legs as solve

    solve(design, pose)


def __getattr__(name: str) -> Any:
    if name == "JSON_SCHEMA_VERSION":  # defined once, in ppm_stiffness.analysis
        from ppm_stiffness.analysis import JSON_SCHEMA_VERSION

        return JSON_SCHEMA_VERSION
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _LazyConsole:
    """A rich ``Console`` made on first use: importing rich costs about 0.1 s of a cold
    start, which ``COMMAND --help`` does not need (issue 32, item 6).

    Parameters
    ----------
    stderr : bool
        The console writes to stderr (else stdout, 80 columns wide when piped).
    """

    def __init__(self, stderr: bool = False) -> None:
        self._stderr = stderr
        self._console: Console | None = None

    def __getattr__(self, name: str) -> Any:
        if self._console is None:
            from rich.console import Console

            if self._stderr:
                self._console = Console(stderr=True)
            else:
                self._console = Console(width=None if sys.stdout.isatty() else 80)
        return getattr(self._console, name)


#: Tables go to stdout; piped output is 80 columns wide, the width every table fits.
console = cast("Console", _LazyConsole())
err_console = cast("Console", _LazyConsole(stderr=True))


#: Image formats every figure option accepts (matplotlib writes them from the suffix).
FIGURE_FORMATS = (".png", ".svg", ".pdf")


def check_output_path(
    path: str | None,
    option: str,
    suffixes: tuple[str, ...] | None = None,
    *,
    overwrite: bool = False,
) -> str | None:
    """Validate an output path before any computation; None passes through.

    Refuses an empty path, an unknown suffix, a directory, a missing parent
    directory (nothing is created on the user's behalf), an existing file unless
    ``overwrite`` (the command's ``--overwrite``), and a path inside the installed
    package (its data is read-only to every command).
    """
    if path is None:
        return None
    if not path.strip():
        raise InputDataError(f"{option}: empty path")
    p = Path(path)
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise InputDataError(
            f"{option} {path}: unknown format {p.suffix or '(no suffix)'}; "
            f"use one of {', '.join(suffixes)}"
        )
    if p.is_dir():
        raise InputDataError(f"{option} {path}: is a directory")
    parent = p.parent
    if parent.exists() and not parent.is_dir():
        raise InputDataError(f"{option} {path}: {parent} is not a directory")
    if not parent.is_dir():
        raise InputDataError(f"{option} {path}: directory {parent} does not exist")
    if _inside_package(p):
        raise InputDataError(
            f"{option} {path}: inside the installed ppm_stiffness package, whose files "
            "are read-only to every command; write to another folder"
        )
    if p.exists() and not overwrite:
        raise InputDataError(f"{option} {path}: file exists; pass --overwrite to replace it")
    return path


def _inside_package(path: Path) -> bool:
    """True if ``path`` lies inside the ppm_stiffness package folder."""
    package = Path(__file__).resolve().parents[1]
    try:
        path.resolve().relative_to(package)
    except ValueError:
        return False
    return True


def add_overwrite_argument(parser: argparse.ArgumentParser) -> None:
    """``--overwrite``: every command that writes files refuses existing ones without it."""
    parser.add_argument(
        "--overwrite", action="store_true", help="replace output files that already exist"
    )


def add_figure_output(parser: argparse.ArgumentParser) -> None:
    """A required ``--out FIG`` option (and ``--overwrite``) for commands whose product
    is a figure."""
    parser.add_argument(
        "--out",
        metavar="FIG",
        required=True,
        help="output image; format from the suffix: " + ", ".join(FIGURE_FORMATS),
    )
    add_overwrite_argument(parser)


def check_figure_path(path: str, overwrite: bool = False) -> str:
    """The --out figure path, checked before any computation."""
    checked = check_output_path(path, "--out", FIGURE_FORMATS, overwrite=overwrite)
    assert checked is not None
    return checked


def check_input_path(path: str, option: str) -> Path:
    """An existing regular file, or an InputDataError naming the option."""
    if not path.strip():
        raise InputDataError(f"{option}: empty path")
    p = Path(path)
    if p.is_dir():
        raise InputDataError(f"{option} {path}: is a directory")
    if not p.is_file():
        raise InputDataError(f"{option}: file not found: {path}")
    return p


def seed_value(text: str) -> int:
    """The argparse type of every ``--seed``: an integer >= 0 (numpy's
    ``SeedSequence``, behind every seeded random choice, refuses negative seeds), or
    an ``argparse.ArgumentTypeError`` (one line, exit 2) naming the valid range."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"a seed is an integer >= 0, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"a seed is an integer >= 0, got {value}")
    return value


def add_seed_argument(parser: argparse.ArgumentParser, what: str) -> None:
    """``--seed N`` (default 0), an integer >= 0; ``what`` says what it seeds."""
    parser.add_argument(
        "--seed",
        type=seed_value,
        default=0,
        metavar="N",
        help=f"seed of {what}, an integer >= 0 (default 0)",
    )


def add_design_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--design", metavar="FILE", help="TOML design file (default: the built-in 3-PPR)"
    )


#: The pose options: option name -> (pose coordinate, factor to SI, unit).
POSE_OPTIONS = {
    "x": ("x", 1e-3, "mm"),
    "y": ("y", 1e-3, "mm"),
    "z": ("z", 1e-3, "mm"),
    "rx": ("rx", math.pi / 180, "deg"),
    "ry": ("ry", math.pi / 180, "deg"),
    "rz": ("rz", math.pi / 180, "deg"),
    "phi": ("rz", math.pi / 180, "deg"),
}


#: Largest |angle| an option in degrees takes [deg] (a full turn): beyond it, a unit
#: slip (mrad, or a value in some other unit) is likely.
MAX_OPTION_ANGLE_DEG = 360.0
#: A length option [mm] beyond this many times the design's size
#: (:func:`design_size_mm`) is refused as a likely unit slip (um, or a value in m
#: mixed with mm).
DESIGN_SIZE_FACTOR = 10.0


def check_option_angle(text: str, value: float) -> None:
    """Refuse an angle [deg] beyond +-:data:`MAX_OPTION_ANGLE_DEG` as a likely unit slip.

    Parameters
    ----------
    text : str
        The option and what it names, which starts the message (``"--rz"``,
        ``"--bounds rx"``).
    value : float
        The angle as given [deg].

    Raises
    ------
    InputDataError
        ``"--rz 5730 deg: beyond +-360 deg; the option takes degrees (if these are
        mrad, write 328.3)"``.
    """
    if abs(value) > MAX_OPTION_ANGLE_DEG:
        raise InputDataError(
            f"{text} {value:g} deg: beyond +-{MAX_OPTION_ANGLE_DEG:g} deg; the option "
            f"takes degrees (if these are mrad, write {math.degrees(value * 1e-3):.4g})"
        )


def design_size_mm(design: Design) -> float:
    """The design's size [mm]: the largest distance between two of its joints at the
    home pose (:func:`ppm_stiffness.visuals.report_wrench.design_size`, no plotting)."""
    from ppm_stiffness.poses import home_pose
    from ppm_stiffness.visuals.report_wrench import design_size

    return 1e3 * design_size(design, home_pose(design))


def check_option_length(
    text: str, value: float, size_mm: float, factor: float = DESIGN_SIZE_FACTOR
) -> None:
    """Refuse a length [mm] beyond ``factor`` times the design's size ``size_mm``
    (:func:`design_size_mm`; default :data:`DESIGN_SIZE_FACTOR`) as a likely unit slip.

    Raises
    ------
    InputDataError
        ``"--bounds x 10000 mm: beyond 10 times the design's size (442 mm, ...); the
        option takes mm (if these are um, write 10)"``.
    """
    if abs(value) > factor * size_mm:
        times = "" if factor == 1 else f"{factor:g} times "
        raise InputDataError(
            f"{text} {value:g} mm: beyond {times}the design's size ({size_mm:.3g} mm, the "
            f"largest distance between two joints); the option takes mm (if these are "
            f"um, write {value * 1e-3:.4g})"
        )


def add_pose_arguments(parser: argparse.ArgumentParser) -> None:
    """``--x --y --z`` [mm], ``--rx --ry --rz`` [deg] (R = Rz Ry Rx), ``--phi`` = --rz:
    the design's task coordinates; the others follow from the legs."""
    parser.add_argument("--x", type=float, metavar="MM", help="x of P in F_b [mm]")
    parser.add_argument("--y", type=float, metavar="MM", help="y of P in F_b [mm]")
    parser.add_argument("--z", type=float, metavar="MM", help="z of P in F_b [mm]")
    parser.add_argument(
        "--rx", type=float, metavar="DEG", help="roll about the x axis of F_b [deg]"
    )
    parser.add_argument(
        "--ry", type=float, metavar="DEG", help="pitch about the y axis of F_b [deg]"
    )
    parser.add_argument(
        "--rz", type=float, metavar="DEG", help="yaw about the z axis of F_b [deg] (R = Rz Ry Rx)"
    )
    parser.add_argument("--phi", type=float, metavar="DEG", help="orientation [deg]: --rz")


#: What uses --link-modes in optimize (its refusal names them).
F1_QUANTITIES = "a first-frequency objective or an f1 constraint"


def add_safety_factor_argument(parser: argparse.ArgumentParser, where: str) -> None:
    """``--safety-factor SF`` of a design with notch hinges: the allowed stress is the
    yield strength / SF in ``where`` (the command's hinge figures)."""
    parser.add_argument(
        "--safety-factor",
        type=float,
        default=None,
        metavar="SF",
        help=f"a design with notch hinges: allowed stress = yield strength / SF in {where}",
    )


def add_link_modes_argument(parser: argparse.ArgumentParser, what: str) -> None:
    """``--link-modes N``: f1 (``what``) with each leg's own modes, as ``analyze``."""
    parser.add_argument(
        "--link-modes",
        type=int,
        metavar="N",
        help=f"{what} with each leg's N lowest own modes with the platform held "
        "(Craig-Bampton, a degenerate pair kept whole), as 'analyze' and 'modes'; 0: the "
        "legs follow statically (condensed; faster) (default: 8)",
    )


def link_modes_from_args(
    args: argparse.Namespace, used: bool = True, without: str = ""
) -> int | None:
    """--link-modes, None when not given; a negative count, or one given where f1 is
    not computed (``used`` False; ``without``: what is missing), an InputDataError."""
    n: int | None = args.link_modes
    if n is not None and n < 0:
        raise InputDataError(f"--link-modes {n}: a number of modes per leg, 0 or more")
    if n is not None and not used:
        raise InputDataError(
            f"--link-modes {n}: it sets the legs' own modes of f1, unused without {without}"
        )
    return n


def f1_link_modes(link_modes: int | None, used: bool) -> int | None:
    """The modes per leg f1 is computed with (the JSON documents' ``link_modes``): the
    given count or the default; None where no f1 is computed."""
    if not used:
        return None
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    return resolve_link_modes(link_modes)


def add_tool_point_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--tool-point",
        metavar="X,Y,Z",
        help="report at this point of the platform [mm, platform frame] instead of the "
        "design's tool_point (default: P)",
    )


def tool_point_from_args(args: argparse.Namespace, design: Design) -> np.ndarray:
    """The tool point [m, platform frame]: --tool-point [mm] or the design's.

    Each component of --tool-point is within the plausible length of a design
    (:data:`ppm_stiffness.legs.base.MAX_LENGTH`, 10 m = 10000 mm), as the design
    file's ``tool_point``; beyond it the error speaks the option's unit (mm).
    """
    import numpy as np

    from ppm_stiffness.legs.base import MAX_LENGTH

    text = getattr(args, "tool_point", None)
    if text is None:
        return np.asarray(design.tool_point, dtype=float)
    values = parse_floats(text, 3, "--tool-point", "X,Y,Z")
    limit_mm = MAX_LENGTH * 1e3
    far = [v for v in values if abs(v) > limit_mm]
    if far:
        raise InputDataError(
            f"--tool-point {text}: {far[0]:g} mm is beyond the {limit_mm:g} mm "
            f"({MAX_LENGTH:g} m) any length of a design may have; X,Y,Z are in mm"
        )
    return np.array(values) * 1e-3


def add_wrench_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--wrench",
        metavar="FX,FY,FZ,MX,MY,MZ",
        help="external wrench on the platform [N, N·m], axes of F_b, acting at the tool "
        "point (P unless the design or --tool-point sets one)",
    )


def load_design_arg(args: argparse.Namespace) -> Design:
    from ppm_stiffness.design import default_design, load_design

    path = getattr(args, "design", None)
    if path is None:
        return default_design()
    return load_design(check_input_path(path, "--design"))


def pose_options_given(
    args: argparse.Namespace, design: Design, axes: tuple[str, ...] = ()
) -> dict[str, float]:
    """The pose options given [mm, deg] as task coordinates [m, rad] by name.

    Raises
    ------
    InputDataError
        A value that is not finite, a coordinate that is not a task coordinate of
        ``design`` (naming those the user may give: the task coordinates that are not in
        ``axes``), one of ``axes`` (the axes of a map vary), --phi and --rz together,
        or an angle beyond +-360 deg (:func:`check_option_angle`).
    """
    task = design.task_coordinates
    given: dict[str, float] = {}
    for option, (name, factor, unit) in POSE_OPTIONS.items():
        value = getattr(args, option, None)
        if value is None:
            continue
        if not math.isfinite(value):
            raise InputDataError(f"--{option} must be finite")
        if name not in task:
            raise InputDataError(
                f"--{option}: {name} is not a task coordinate of this design; give "
                + ", ".join(f"--{n}" for n in task if n not in axes)
                + " (the other coordinates follow from the legs)"
            )
        if name in axes:
            raise InputDataError(
                f"--{option}: {name} is an axis of the map (--axes {','.join(axes)}); fix "
                "only the other task coordinates"
            )
        if name in given:
            raise InputDataError("--phi and --rz are the same coordinate: give one")
        if unit == "deg":
            check_option_angle(f"--{option}", value)
        given[name] = value * factor
    return given


def pose_from_args(
    args: argparse.Namespace, design: Design, check_reach: bool = True
) -> np.ndarray:
    """The full pose (6,) [m, rad] from the pose options (mm, deg): the home pose with the
    task coordinates given replaced, completed (:mod:`ppm_stiffness.poses`). An option
    for a coordinate that is not a task coordinate is refused, naming the task
    coordinates; unless ``check_reach`` is False, a pose out of reach is refused with
    what is reachable near it."""
    from ppm_stiffness.poses import full_pose, home_pose, task_indices

    values = home_pose(design)
    given = pose_options_given(args, design)
    for name, value in given.items():
        values[POSE_INDEX[name]] = value
    pose = values[list(task_indices(design))]
    try:
        full = full_pose(design, pose)
        if check_reach:
            solve_legs(design, full)
    except UnreachablePoseError as exc:
        from ppm_stiffness.maps.reach import reach_hint

        if not check_reach:
            raise
        raise UnreachablePoseError(f"{exc}; {reach_hint(design, values)}") from None
    return full


def parse_floats(text: str, count: int, option: str, spec: str) -> list[float]:
    """``count`` comma-separated finite numbers, or an InputDataError that says
    ``option must be <count> numbers <spec>``."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise InputDataError(f"{option} must be {count} numbers {spec}, got {text!r}") from None
    if len(values) != count:
        raise InputDataError(f"{option} must be {count} numbers {spec}, got {len(values)}")
    if not all(math.isfinite(v) for v in values):
        raise InputDataError(f"{option} components must be finite")
    return values


def parse_wrench(text: str | None) -> np.ndarray | None:
    """The CLI's wrench ``FX,FY,FZ,MX,MY,MZ`` [N, N·m] as the library's
    ``(m_x, m_y, m_z, f_x, f_y, f_z)``."""
    import numpy as np

    if text is None:
        return None
    values = parse_floats(text, 6, "--wrench", "FX,FY,FZ,MX,MY,MZ")
    f, m = values[:3], values[3:]
    return np.array(m + f)


def read_matrix_csv(path: str | Path, option: str = "--matrix") -> np.ndarray:
    """A 6x6 matrix from CSV (``#`` comments allowed, read by
    :func:`ppm_stiffness.csvio.read_numbered_csv`); raises InputDataError."""
    import numpy as np

    from ppm_stiffness.csvio import read_numbered_csv

    p = check_input_path(str(path), option)
    rows: list[list[float]] = []
    try:
        for line in read_numbered_csv(p).rows:
            if not line or all(not c.strip() for c in line):
                continue
            rows.append([float(c) for c in line])
    except ValueError as exc:
        raise InputDataError(f"{p}: not a numeric CSV ({exc})") from None
    if len(rows) != 6 or any(len(r) != 6 for r in rows):
        shape = f"{len(rows)} rows of {sorted({len(r) for r in rows})} columns"
        raise InputDataError(f"{p}: a stiffness matrix must be 6x6, got {shape}")
    return np.array(rows)


@contextmanager
def progress(
    description: str, total: float, enabled: bool = True
) -> Iterator[Callable[[float], None]]:
    """A rich progress bar on stderr, shown only when stderr is a terminal.

    Yields ``advance(amount)``; nothing is drawn when stderr is not a terminal (so
    ``--json`` on stdout stays parseable and logs stay clean) or ``enabled`` is False.
    """
    if not (enabled and err_console.is_terminal):
        yield lambda amount: None
        return
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeRemainingColumn(),
        console=err_console,
        transient=True,
    ) as bar:
        task = bar.add_task(description, total=total)
        yield lambda amount: bar.advance(task, amount)


def eng(value: float, digits: int = 4) -> str:
    """A number in engineering notation for tables: ``12.35e3``, ``-4.1e-6``, ``0``.

    ``digits`` significant digits; exponents are multiples of 3 and omitted for
    magnitudes in [1, 1000); no ``-0``; NaN as ``nan``.
    """
    v = float(value)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if v == 0:
        return "0"
    exp3 = int(math.floor(math.log10(abs(v)) / 3) * 3)
    mant = v / 10.0**exp3
    text = f"{mant:.{digits}g}"
    if abs(float(text)) >= 1000:  # rounding carried into the next group
        exp3 += 3
        text = f"{v / 10.0**exp3:.{digits}g}"
    if float(text) == 0:
        return "0"
    return text if exp3 == 0 else f"{text}e{exp3}"
