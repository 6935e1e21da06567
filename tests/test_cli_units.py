"""Units at the CLI edge (docs/conventions.md): deflections in deg and mm in every
table, an actuator's reference load in its own kind's unit."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from ppm_stiffness.cli import main

ROOT = Path(__file__).parents[1]
WRENCH = "--wrench=5,5,20,0,0,0.1"  # the paper's loaded case [N, N·m]


def test_analyze_prints_the_deflection_in_deg_and_mm_as_deflect_does(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The printed numbers are the JSON twist [rad, m] in deg and mm, to the 4
    significant digits printed (analyze printed mrad and µm)."""
    assert main(["analyze", WRENCH, "--json"]) == 0
    twist = json.loads(capsys.readouterr().out)["twist"]
    assert main(["analyze", WRENCH]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "mrad" not in text and "µm" not in text
    found = re.search(r"deflection: rotation \(([^)]*)\) deg, displacement \(([^)]*)\) mm", text)
    assert found is not None
    printed = [float(v) for group in found.groups() for v in group.split(",")]
    expected = [math.degrees(v) for v in twist[:3]] + [1e3 * v for v in twist[3:]]
    for p, e in zip(printed, expected, strict=True):
        assert p == pytest.approx(e, rel=5e-4, abs=1e-12)  # 4 significant digits


@pytest.mark.parametrize(
    ("design", "unit"), [(None, "N"), (str(ROOT / "examples/3rrr.toml"), "N·m")]
)
def test_map_names_the_reference_loads_unit(
    design: str | None, unit: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """A linear actuator's reference load is a force [N], a rotary one's a moment
    [N·m] (``leg.actuator_units()``); map printed a bare 'reference load 10'."""
    argv = ["map", "--actuators", "min", "--grid", "4", "--quiet"]
    assert main(argv + ([] if design is None else ["--design", design])) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.endswith(f"actuators: min (reference load 10 {unit})")
