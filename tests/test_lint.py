"""ruff and mypy are part of the test suite, so CI (the README's test command) checks them."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _run(module: str, *args: str) -> subprocess.CompletedProcess[str]:
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"{module} is not installed (extra 'test')")
    return subprocess.run(
        [sys.executable, "-m", module, *args], cwd=ROOT, capture_output=True, text=True, check=False
    )


def test_ruff_clean() -> None:
    run = _run("ruff", "check", "src", "tests", "benchmarks", "scripts")
    assert run.returncode == 0, run.stdout + run.stderr


def test_ruff_format_clean() -> None:
    run = _run("ruff", "format", "--check", "src", "tests", "benchmarks", "scripts")
    assert run.returncode == 0, run.stdout + run.stderr


def test_mypy_clean() -> None:
    run = _run("mypy", "src")
    assert run.returncode == 0, run.stdout + run.stderr
