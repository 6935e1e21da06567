"""Cold start: ``ppm-stiffness --help`` and every ``COMMAND --help`` import none of the
heavy numerical, plotting, FE or distributed libraries (issue: speed, item 4). Time is
measured by ``benchmarks/bench_cli.py``, not here."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from ppm_stiffness.cli import COMMANDS

HEAVY = ("scipy", "matplotlib", "Pynite", "PyNite", "numba", "dask", "distributed")

_CHILD = """
import contextlib, io, json, sys
from ppm_stiffness.cli import main
for argv in json.loads(sys.argv[1]):
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(argv) == 0, argv
full = len(sys.argv) > 2
print(json.dumps(sorted(m if full else m.split(".")[0] for m in sys.modules)))
"""


def _modules_after(*argvs: list[str]) -> set[str]:
    """Top-level packages imported after running ``argvs`` in one fresh process."""
    return _run_child(list(argvs), [])


def _modules_after_full(*argvs: list[str]) -> set[str]:
    """Full names of the modules imported after running ``argvs`` in a fresh process."""
    return _run_child(list(argvs), ["full"])


def _run_child(argvs: list[list[str]], extra: list[str]) -> set[str]:
    run = subprocess.run(
        [sys.executable, "-c", _CHILD, json.dumps(argvs), *extra],
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
    assert "ppm_stiffness" in loaded  # the check sees what the commands import


#: What building a command's parser must not import: the numerical libraries, the
#: console library and the design schema (0.3-0.5 s of a cold start together; issue 32,
#: item 6: every ``COMMAND --help`` within 0.1 s of ``--help``).
PARSER_HEAVY = {*HEAVY, "numpy", "rich", "pydantic"}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_command_help_imports_no_numpy_rich_or_pydantic(name: str) -> None:
    # a fresh process per command: one command's imports cannot hide another's
    full = _modules_after_full([name, "--help"])
    loaded = {module.split(".")[0] for module in full}
    assert not loaded & PARSER_HEAVY, sorted(loaded & PARSER_HEAVY)
    assert COMMANDS[name][0] in full  # the check sees the command's module


def test_command_help_does_not_load_the_design_schema() -> None:
    # the design schema (pydantic models) is the largest import of the library (about
    # 0.1 s): no command's --help needs it (issue 22, item 5), deflect included (its
    # modes and methods come from statics.modes, not statics.deflection: issue 32, item 6)
    for name in sorted(COMMANDS):
        loaded = _modules_after([name, "--help"])
        assert "pydantic" not in loaded, name


def test_deflect_help_imports_no_deflection_module() -> None:
    # deflect --help lists the modes and methods without importing the computation
    loaded = _modules_after_full(["deflect", "--help"])
    computation = {
        "ppm_stiffness.statics.deflection",
        "ppm_stiffness.statics.measurements",
        "ppm_stiffness.statics.moving_deflection",
        "ppm_stiffness.visuals.deflection",
        "ppm_stiffness.design",
    }
    assert not loaded & computation, sorted(loaded & computation)
    assert "ppm_stiffness.statics.modes" in loaded  # the check sees what deflect imports
