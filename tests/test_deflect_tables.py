"""``deflect``'s text tables on spatial designs: round-off is printed as 0 (the values
the design's symmetry makes zero), every other cell is the raw value's, the JSON keeps
the raw numbers, the header names the geometry asked for and the load column's header
is never cut at 80 columns."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.cli.common import console, eng
from ppm_stiffness.cli.deflect import _twist_table
from ppm_stiffness.core.conventions import BALANCE

ROOT = Path(__file__).parents[1]
#: Table units of the six twist components (deg, mm) per SI unit (rad, m).
SCALE = np.array([180 / math.pi] * 3 + [1e3] * 3)
#: The components are round-off: at most this fraction of the largest (length-balanced).
#: Measured: 3.5e-17 (hexapod), 1e-13 (3-PRS, moving geometry); the tables' rule is
#: 1e-9 (core.decoupling.DECOUPLED_TOLERANCE).
ROUND_OFF = 1e-12

#: (design, --direction, extra options, twist components the symmetry makes zero,
#: legs whose actuator force is zero). Hexapod, force along x at home: the mirror
#: y -> -y keeps the load and reverses phi_x, phi_z and y; the 3-fold symmetry about z
#: leaves no linear coupling of f_x to z. 3-RPS, force along y at home: the legs'
#: constraint forces (through the spherical joints, along the revolute axes) carry all
#: of f_y, so the actuators carry nothing; the mirror x -> -x reverses phi_y, phi_z, x
#: and z. 3-PRS, force along -z at its tool point below P: the 3-fold symmetry leaves
#: z alone.
CASES = [
    ("hexapod_6ups", "1,0,0,0,0,0", [], (0, 2, 4, 5), ()),
    ("3rps", "0,1,0,0,0,0", [], (1, 2, 3, 5), (0, 1, 2)),
    ("3prs", "0,0,-1,0,0,0", [], (0, 1, 2, 3, 4), ()),
    ("3prs", "0,0,-1,0,0,0", ["--geometry", "moving", "--step", "2.5"], (0, 1, 2, 3, 4), ()),
]


def _tables(out: str) -> list[tuple[list[str], list[list[str]]]]:
    """Each rich table of ``out``: its column names (the header's last line) and rows of
    cells (split at blanks; no cell has one)."""
    lines = out.splitlines()
    tables = []
    for k, line in enumerate(lines):
        if line.strip() and set(line.strip()) == {"─"}:
            rows = []
            for row in lines[k + 1 :]:
                if not row.strip():
                    break
                rows.append(row.split())
            tables.append((lines[k - 1].split(), rows))
    return tables


def _run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert err == ""
    return out


@pytest.mark.parametrize(("name", "direction", "extra", "zero", "idle_legs"), CASES)
def test_round_off_is_printed_as_zero_and_the_rest_unchanged(
    name: str,
    direction: str,
    extra: list[str],
    zero: tuple[int, ...],
    idle_legs: tuple[int, ...],
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(console, "width", 80)
    argv = ["deflect", "--design", str(ROOT / f"examples/{name}.toml"), "--direction", direction]
    doc = json.loads(_run(capsys, [*argv, *extra, "--json"]))
    out = _run(capsys, [*argv, *extra])
    assert "…" not in out and max(len(line) for line in out.splitlines()) <= 80
    curves = [doc] + ([doc["moving_geometry"]] if "--geometry" in extra else [])
    twist_tables = [
        t for t in _tables(out) if t[0][-6:] == ["phi_x", "phi_y", "phi_z", "x", "y", "z"]
    ]
    assert len(twist_tables) == len(curves)
    for curve, (_, rows) in zip(curves, twist_tables, strict=True):
        twists = np.asarray(curve["twists"])
        assert len(rows) == len(curve["loads"])
        balanced = np.abs(twists / BALANCE)
        # the symmetry's zeros are round-off in the raw (JSON) values, which stay raw
        assert np.max(balanced[:, zero]) <= ROUND_OFF * np.max(balanced)
        for row, twist in zip(rows, twists * SCALE, strict=True):
            for j, value in enumerate(twist):
                assert row[1 + j] == ("0" if j in zero else eng(value)), (row, j)
    forces = np.asarray(doc["actuator_forces"])
    if idle_legs:  # the raw forces are round-off against the load
        assert np.max(np.abs(forces[:, idle_legs])) <= ROUND_OFF * max(doc["loads"])
    expected = {
        "G": [["0" if i in idle_legs else eng(v) for i, v in enumerate(g)] for g in forces],
        "K": [[eng(v) for v in k] for k in doc["actuator_stiffness"]],
    }
    actuator_tables = [t for t in _tables(out) if "G1" in t[0] or "K1" in t[0]]
    assert actuator_tables
    for header, rows in actuator_tables:
        kinds = [kind for kind in "GK" if f"{kind}1" in header]
        assert [row[1:] for row in rows] == [
            [cell for kind in kinds for cell in expected[kind][k]] for k in range(len(rows))
        ]


def test_the_header_names_the_geometry_asked_for(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["deflect", "--design", str(ROOT / "examples/3prs.toml"), "--direction", "0,0,-1,0,0,0"]
    first = _run(capsys, [*argv, "--step", "5", "--geometry", "moving"]).splitlines()[0]
    assert "geometry moving" in first and "frozen" in first and "geometry frozen" not in first
    assert "geometry frozen" in _run(capsys, [*argv, "--step", "5"]).splitlines()[0]


def test_the_load_header_fits_beside_six_ten_character_columns(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The widest cells eng() prints (a sign, four digits, a two-digit exponent) in all
    six columns and a load of six characters: the table still fits 80 columns with
    its load header whole."""
    monkeypatch.setattr(console, "width", 80)
    loads = np.array([0.0, 0.0125, 0.025])
    twists = np.outer(loads, -1.234e-13 / SCALE / 0.0125)
    console.print(_twist_table("title", "N·m", loads, twists))
    out = capsys.readouterr().out
    assert "-123.4e-15" in out and "0.0125" in out
    assert "…" not in out and max(len(line) for line in out.splitlines()) <= 80
    lines = out.splitlines()
    rule = next(k for k, line in enumerate(lines) if set(line.strip()) == {"─"})
    header = " ".join(lines[rule - 2 : rule]).split()
    assert "load" in header and "[N·m]" in header, header
