"""Command-line interface: ``ppm-stiffness COMMAND ...``.

A thin layer: each command lives in its own module of this package, exposing
``add_arguments(parser)`` and ``run(args) -> int`` (its one-line help is in
:data:`COMMANDS`); it parses, calls the library and prints. A command module imports
its libraries (numpy, rich, scipy, matplotlib, PyNite, the design schema, ...) inside
the functions that run it only, so that ``COMMAND --help`` stays within 0.1 s of
``--help`` (``tests/test_cold_start.py``, ``benchmarks/bench_cli.py``). Errors of the
library (:class:`PPMStiffnessError`) become one line on stderr and exit code 2, never a
traceback. Before a command runs,
glibc's malloc thresholds are raised in this process
(:func:`ppm_stiffness._allocator.tune_allocator`; ``PPM_STIFFNESS_NO_MALLOPT=1`` opts
out): batch temporaries then stay on the heap instead of page-faulting on every use.
SIGTERM (``timeout``, ``kill``, a job scheduler) and SIGHUP (the terminal closed, an
ssh session lost) take the path of Ctrl-C while :func:`main` runs (:class:`Terminated`,
a KeyboardInterrupt): temporary output files are removed, an interrupted sweep or
optimisation writes what it has done, and the exit code is 128 + the signal's number
(143 for SIGTERM, 129 for SIGHUP, as a shell reports a terminated process) instead of
Ctrl-C's 130.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import warnings
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from types import FrameType
from typing import Any, NoReturn, TextIO

from ppm_stiffness.core.errors import PPMStiffnessError

#: command name -> (module, one-line help). The help lives here so that
#: ``ppm-stiffness --help`` imports no command module; a command module is imported
#: only when it runs or its own ``--help`` is asked for.
COMMANDS: dict[str, tuple[str, str]] = {
    "analyze": (
        "ppm_stiffness.cli.analyze",
        "stiffness matrix, screw springs, decoupling and principal stiffnesses at a pose",
    ),
    "calibrate": (
        "ppm_stiffness.cli.calibrate",
        "identify design parameters from a target 6x6 stiffness matrix (bounded least squares)",
    ),
    "fit-actuator": (
        "ppm_stiffness.cli.fit_actuator",
        "fit the actuator law G = k_a delta^q (eq. 20) to force-displacement data",
    ),
    "deflect": (
        "ppm_stiffness.cli.deflect",
        "deflection of the platform under a load growing from zero (actuator law in the loop)",
    ),
    "map": (
        "ppm_stiffness.cli.map_cmd",
        "contour maps over a 2-D slice of the workspace (Figs. 6-7), any architecture: "
        "k_phi, k_x, k_y of a planar design; the spatial principal stiffnesses "
        "(rotational_min/mid/max, translational_min/mid/max) of any design; f1, load margin",
    ),
    "springs": (
        "ppm_stiffness.cli.springs",
        "3D picture of the six screw springs of K, platform and legs in place (Fig. 5)",
    ),
    "mechanism": (
        "ppm_stiffness.cli.mechanism",
        "the manipulator at a pose (top view of a planar design, 3-D of a spatial one)",
    ),
    "report": (
        "ppm_stiffness.cli.report",
        "self-contained HTML report: parameters, K, screw springs, decoupling, loaded case, "
        "deflection curves and stiffness maps",
    ),
    "validate": (
        "ppm_stiffness.cli.validate",
        "compare the virtual-joint stiffness with an independent FE frame model (PyNite)",
    ),
    "compare": (
        "ppm_stiffness.cli.compare",
        "summary figures of several designs over one required region",
    ),
    "sweep": (
        "ppm_stiffness.cli.sweep",
        "summary figures over the required region for a grid or sample of parameters",
    ),
    "optimize": (
        "ppm_stiffness.cli.optimize",
        "optimise design parameters over the required region (differential evolution)",
    ),
    "modes": (
        "ppm_stiffness.cli.modes",
        "natural frequencies and mode shapes at a pose, from K and the design's mass model",
    ),
    "identify": (
        "ppm_stiffness.cli.identify",
        "identify element stiffnesses from measured platform deflections under known loads",
    ),
}


class OneLineErrorParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line on stderr, like every other
    error of the CLI (no usage block): ``ppm-stiffness: error: MESSAGE; see
    `ppm-stiffness COMMAND --help```, exit code 2. Subparsers are of the same class.

    Attributes
    ----------
    help_hint : str or None
        The program whose ``--help`` the hint names (default: this parser's ``prog``);
        :func:`main` sets the command's on the top-level parser, which reports the
        command's unrecognised arguments.
    """

    help_hint: str | None = None

    def error(self, message: str) -> NoReturn:
        hint = self.help_hint or self.prog
        print(f"ppm-stiffness: error: {message}; see `{hint} --help`", file=sys.stderr)
        sys.exit(2)


def build_parser(commands: Iterable[str] | None = None) -> OneLineErrorParser:
    """The argument parser.

    Parameters
    ----------
    commands : iterable of str, optional
        The commands whose options are added (their modules are imported); every
        command is listed with its help either way. None: all of them.
    """
    parser = OneLineErrorParser(
        prog="ppm-stiffness",
        description="Stiffness of compliant parallel manipulators, planar (3-PPR, "
        "3-RPR, ...) and spatial (hexapods, 3-PRS and 3-RPS tripods): virtual-spring "
        "model, eigenscrews, decoupling, actuation compliance, natural frequencies.",
    )
    from ppm_stiffness import __version__

    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    wanted = set(COMMANDS) if commands is None else set(commands)
    for name, (modname, text) in COMMANDS.items():
        p = sub.add_parser(name, help=text, description=text)
        if name in wanted:
            module = importlib.import_module(modname)
            module.add_arguments(p)
            p.set_defaults(_run=module.run)
    return parser


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``--wrench -5,0,...`` -> ``--wrench=-5,0,...``: argparse reads a value that starts
    with ``-`` as an option, so a value that starts with ``-`` and a digit or a point
    (a negative number, alone or in a comma list) is attached to the option before it."""
    out: list[str] = []
    for arg in argv:
        prev = out[-1] if out else ""
        if (
            prev.startswith("--")
            and "=" not in prev
            and len(arg) > 1
            and arg[0] == "-"
            and (arg[1].isdigit() or arg[1] == ".")
        ):
            out[-1] = f"{prev}={arg}"
        else:
            out.append(arg)
    return out


def _command_in(argv: Sequence[str]) -> str | None:
    """The command named in ``argv`` (the first argument that is one), or None."""
    return next((a for a in argv if a in COMMANDS), None)


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """Warnings as one line on stderr, like errors (no source line, no file name). A
    numerical library's RuntimeWarning (``divide by zero encountered in ...``) is named
    as such, with the file and line it came from: expected ones are silenced where they
    arise (``np.errstate``), so one reaching the user is worth reporting."""
    if issubclass(category, RuntimeWarning):
        where = f"{filename.replace(chr(92), '/').rsplit('/', 1)[-1]}:{lineno}"
        print(
            f"ppm-stiffness: warning: a numerical routine reported '{message}' (at "
            f"{where}); treat the numbers printed with care",
            file=sys.stderr,
        )
        return
    print(f"ppm-stiffness: warning: {message}", file=sys.stderr)


#: Exit code of Ctrl-C (SIGINT) and of SIGTERM: 128 + the signal's number.
INTERRUPTED_EXIT = 128 + signal.SIGINT
TERMINATED_EXIT = 128 + signal.SIGTERM

#: The signals that take Ctrl-C's path while :func:`main` runs: SIGTERM and, where the
#: platform has it, SIGHUP (whose default action would kill the process on the spot,
#: leaving its temporary files behind).
TERMINATING_SIGNALS: tuple[signal.Signals, ...] = (signal.SIGTERM,) + tuple(
    getattr(signal, name) for name in ("SIGHUP",) if hasattr(signal, name)
)


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP received by the CLI process: raised where the signal arrives, so
    that it takes Ctrl-C's path (temporary files removed, partial results written).

    Parameters
    ----------
    signum : int
        The signal received (default SIGTERM).
    """

    def __init__(self, signum: int = signal.SIGTERM) -> None:
        super().__init__(signum)
        self.signum = int(signum)

    @property
    def name(self) -> str:
        """The signal's name, e.g. ``"SIGTERM"``."""
        return signal.Signals(self.signum).name


@contextmanager
def _sigterm_as_interrupt() -> Iterator[list[int]]:
    """While the block runs, SIGTERM or SIGHUP in this process raises
    :class:`Terminated` (once; a second signal during the clean-up is ignored). Yields
    the list of signals received. A process forked meanwhile (a local worker) that
    inherits the handler gets the default action instead: it is not the CLI. Outside the
    main thread (where no handler can be installed) nothing changes."""
    received: list[int] = []
    pid = os.getpid()

    def handler(signum: int, frame: FrameType | None) -> None:
        if os.getpid() != pid:
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        if not received:
            received.append(signum)
            raise Terminated(signum)

    previous: dict[signal.Signals, Any] = {}
    try:
        for sig in TERMINATING_SIGNALS:
            previous[sig] = signal.signal(sig, handler)
    except ValueError:  # not the main thread
        yield received
        return
    try:
        yield received
    finally:
        for sig, action in previous.items():
            signal.signal(sig, action)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit code (0 ok, 2 bad input)."""
    warnings.showwarning = _one_line_warning
    raw = join_negative_values(sys.argv[1:] if argv is None else argv)
    command = _command_in(raw)
    parser = build_parser([] if command is None else [command])
    if command is not None:
        parser.help_hint = f"{parser.prog} {command}"
    try:
        args = parser.parse_args(raw)
    except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
        return int(exc.code or 0)
    from ppm_stiffness._allocator import tune_allocator

    tune_allocator()
    with _sigterm_as_interrupt() as received:
        code = _run_command(args)
    if received and code == INTERRUPTED_EXIT:
        return 128 + received[0]
    return code


def _run_command(args: argparse.Namespace) -> int:
    """Run the parsed command; the library's errors as one line and exit code 2."""
    try:
        return int(args._run(args))
    except PPMStiffnessError as exc:
        print(f"ppm-stiffness: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # a file that cannot be read or written
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"ppm-stiffness: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except Terminated as exc:
        print(f"ppm-stiffness: terminated ({exc.name})", file=sys.stderr)
        return INTERRUPTED_EXIT  # main: 128 + the signal's number
    except KeyboardInterrupt:
        print("ppm-stiffness: interrupted", file=sys.stderr)
        return INTERRUPTED_EXIT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
