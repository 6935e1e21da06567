"""Command-line interface: ``ppm-stiffness COMMAND ...``.

A thin layer: each command lives in its own module of this package, exposing
``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int``; it parses,
calls the library and prints. Errors of the library (:class:`PPMStiffnessError`)
become one line on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import sys
import warnings
from collections.abc import Sequence
from typing import TextIO

from ppm_stiffness.core.errors import PPMStiffnessError

#: command name -> module (imported only when the command runs)
COMMANDS: dict[str, str] = {
    "analyze": "ppm_stiffness.cli.analyze",
    "calibrate": "ppm_stiffness.cli.calibrate",
    "fit-actuator": "ppm_stiffness.cli.fit_actuator",
    "deflect": "ppm_stiffness.cli.deflect",
    "map": "ppm_stiffness.cli.map_cmd",
    "springs": "ppm_stiffness.cli.springs",
    "mechanism": "ppm_stiffness.cli.mechanism",
    "report": "ppm_stiffness.cli.report",
    "validate": "ppm_stiffness.cli.validate",
    "identify": "ppm_stiffness.cli.identify",
}


def _available() -> dict[str, str]:
    return {name: mod for name, mod in COMMANDS.items() if importlib.util.find_spec(mod)}


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every available command."""
    parser = argparse.ArgumentParser(
        prog="ppm-stiffness",
        description="Stiffness of compliant planar parallel manipulators "
        "(virtual-spring model, eigenscrews, decoupling, actuation compliance).",
    )
    from ppm_stiffness import __version__

    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, modname in _available().items():
        module = importlib.import_module(modname)
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """Warnings as one line on stderr, like errors (no source line, no file name)."""
    print(f"ppm-stiffness: warning: {message}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit code (0 ok, 2 bad input)."""
    warnings.showwarning = _one_line_warning
    parser = build_parser()
    from ppm_stiffness.cli.common import join_negative_values

    raw = sys.argv[1:] if argv is None else list(argv)
    try:
        args = parser.parse_args(join_negative_values(raw))
    except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
        return int(exc.code or 0)
    try:
        return int(args._run(args))
    except PPMStiffnessError as exc:
        print(f"ppm-stiffness: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # a file that cannot be read or written
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"ppm-stiffness: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("ppm-stiffness: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
