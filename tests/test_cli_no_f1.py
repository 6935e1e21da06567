"""``sweep`` and ``compare --no-f1`` (issue 32, item 3): the stiffness figures without
the first natural frequency, equal to those of a run with it; f1 asked for with
``--no-f1`` is refused."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from ppm_stiffness.cli import main

ROOT = Path(__file__).resolve().parents[1]
DESIGN = str(ROOT / "examples" / "3rrr.toml")  # a mass model: f1 by default
VARY = ["--vary", "leg*.distal.area=1e-4:2e-4:2"]


def _rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(row for row in f if not row.startswith("#")))


def test_sweep_without_f1_keeps_the_stiffness_figures(tmp_path: Path) -> None:
    with_f1, without = tmp_path / "a.csv", tmp_path / "b.csv"
    argv = ["sweep", "--design", DESIGN, *VARY, "--csv", str(with_f1), "--quiet"]
    assert main([*argv, "--link-modes", "0"]) == 0
    argv = ["sweep", "--design", DESIGN, *VARY, "--csv", str(without), "--quiet", "--no-f1"]
    assert main(argv) == 0
    a, b = _rows(with_f1), _rows(without)
    assert "f1_min" in a[0] and not any(k.startswith("f1") for k in b[0])
    for ra, rb in zip(a, b, strict=True):
        assert {k: ra[k] for k in rb} == rb  # the same numbers, as written


def test_compare_without_f1(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["compare", "--design", DESIGN, "--design", DESIGN, "--json", "--no-f1"]) == 0
    doc = json.loads(capsys.readouterr().out)
    text = json.dumps(doc)
    assert "f1_min" not in text and "k_x_min" in text


def test_f1_with_no_f1_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["sweep", "--design", DESIGN, *VARY, "--quantity", "first-frequency", "--no-f1"]
    assert main(argv) == 2
    assert "drop --no-f1" in capsys.readouterr().err
