"""Files written by an interrupted ``sweep`` or ``optimize`` say that they are partial:
a first comment line with the count done and the count asked for. Ctrl-C is simulated
as in tests/test_cli_optimize.py: the serial executor raises KeyboardInterrupt at the
n-th task."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

import ppm_stiffness as pps
from ppm_stiffness.cli import main
from ppm_stiffness.optimize.executors import SerialExecutor

ROOT = Path(__file__).parents[1]
SYMMETRIC = str(ROOT / "examples/symmetric_3ppr.toml")
REGION = "--region=-10,10,-10,10,-5.7,5.7,3,3,3"


def _interrupt_after(monkeypatch: pytest.MonkeyPatch, tasks: int) -> None:
    calls = {"n": 0}
    submit = SerialExecutor.submit

    def interrupting(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def]
        calls["n"] += 1
        if calls["n"] > tasks:
            raise KeyboardInterrupt
        return submit(self, fn, *args, **kwargs)

    monkeypatch.setattr(SerialExecutor, "submit", interrupting)


def test_an_interrupted_sweep_csv_says_it_is_partial(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    table = tmp_path / "s.csv"
    argv = ["sweep", "--design", SYMMETRIC, REGION, "--link-modes", "0"]
    argv += ["--quiet", "--csv", str(table), "--vary", "leg*.platform_radius=0.02:0.04:6"]
    _interrupt_after(monkeypatch, 4)
    assert main(argv) == 130
    lines = table.read_text(encoding="utf-8").splitlines()
    assert lines[0] == (
        "# partial: interrupted after 4 of 6 designs; the rows are the designs done, in order"
    )
    rows = list(csv.DictReader(lines[1:]))
    assert [float(r["leg*.platform_radius"]) for r in rows] == pytest.approx(
        [0.02, 0.024, 0.028, 0.032], abs=1e-15
    )
    # a complete sweep has no such line
    monkeypatch.undo()
    whole = tmp_path / "whole.csv"
    assert main([*argv[:-5], "--csv", str(whole), *argv[-2:]]) == 0
    assert whole.read_text(encoding="utf-8").startswith("leg*.platform_radius,")


def test_an_interrupted_optimize_design_says_it_is_partial(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    best = tmp_path / "best.toml"
    argv = ["optimize", "--design", SYMMETRIC, REGION, "--budget", "12", "--quiet"]
    argv += ["--vary", "leg*.platform_radius=0.02:0.06", "--out", str(best)]
    _interrupt_after(monkeypatch, 7)
    assert main(argv) == 130
    first = best.read_text(encoding="utf-8").splitlines()[0]
    assert first == "# partial: interrupted after 7 of 12 evaluations; the best design so far"
    assert pps.load_design(best).architecture == "3-PPR"  # still a design file
    monkeypatch.undo()
    whole = tmp_path / "whole.toml"
    assert main([*argv[:-1], str(whole)]) == 0
    assert "partial" not in whole.read_text(encoding="utf-8")
