"""Cold start: ``ppm-stiffness --help`` and every ``COMMAND --help`` import none of the
heavy numerical, plotting, FE or distributed libraries (issue: speed, item 4). Time is
measured by ``benchmarks/bench_cli.py``, not here."""

from __future__ import annotations

import json
import subprocess
import sys

from ppm_stiffness.cli import COMMANDS

HEAVY = ("scipy", "matplotlib", "Pynite", "PyNite", "numba", "dask", "distributed")

_CHILD = """
import contextlib, io, json, sys
from ppm_stiffness.cli import main
for argv in json.loads(sys.argv[1]):
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(argv) == 0, argv
print(json.dumps(sorted(m.split(".")[0] for m in sys.modules)))
"""


def _modules_after(*argvs: list[str]) -> set[str]:
    run = subprocess.run(
        [sys.executable, "-c", _CHILD, json.dumps(list(argvs))],
        capture_output=True,
        text=True,
        check=True,
    )
    return set(json.loads(run.stdout))


def test_top_level_help_imports_no_numerical_library() -> None:
    loaded = _modules_after(["--help"])
    assert not loaded & {*HEAVY, "numpy", "pydantic"}, loaded & {*HEAVY, "numpy", "pydantic"}


def test_command_help_imports_no_heavy_library() -> None:
    # one process for every command: if any of them imported a heavy library, it
    # would still be in sys.modules at the end
    loaded = _modules_after(*([name, "--help"] for name in COMMANDS))
    assert not loaded & set(HEAVY), loaded & set(HEAVY)
    assert "numpy" in loaded  # the check sees what the commands import


#: Commands whose ``--help`` needs constants of library modules that import the design
#: schema (pydantic): deflect (statics.deflection's modes and methods).
SCHEMA_AT_HELP = {"deflect"}


def test_command_help_does_not_load_the_design_schema() -> None:
    # the design schema (pydantic models) is the largest import of the library (about
    # 0.1 s): the other commands' --help must not need it (issue 22, item 5)
    for name in sorted(set(COMMANDS) - SCHEMA_AT_HELP):
        loaded = _modules_after([name, "--help"])
        assert "pydantic" not in loaded, name
