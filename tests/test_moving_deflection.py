"""``deflect --geometry moving``: the moving-geometry curve beside the frozen one.

Each point of the moving curve is the single-pose moving equilibrium under that load; the
two curves agree to first order as the load tends to 0 (their difference is of second
order in the load); a curve whose load path passes the load margin stops before it and
names the load at which stability is lost (the load margin's); the CLI's tables, JSON
(validated against docs/schemas/deflect.schema.json) and CSV carry both curves.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from tests.helpers import design_named
from tests.paper import PAPER_WRENCH

from ppm_stiffness.cli import main
from ppm_stiffness.statics.margin import load_margin
from ppm_stiffness.statics.moving import moving_equilibrium
from ppm_stiffness.statics.moving_deflection import MOVING_METHOD, moving_deflection

jsonschema = pytest.importorskip("jsonschema", reason="jsonschema is in the 'test' extra")

ROOT = Path(__file__).parents[1]
SCHEMA = ROOT / "docs" / "schemas" / "deflect.schema.json"
PAPER_LOAD = "5,5,20,0,0,0.1"  # FX,FY,FZ,MX,MY,MZ: PAPER_WRENCH


def test_each_point_is_the_single_pose_moving_equilibrium_spatial_with_tool_point() -> None:
    design = design_named("3rps")
    unit = np.array([2.0, 2.0, 5.0, 200.0, 200.0, -500.0])
    tool = np.array([0.01, -0.005, 0.02])
    loads = np.linspace(0.0, 1.0, 5)
    both = moving_deflection(design, unit, loads, method="closed-form", tool_point=tool)
    assert both.moving_stop is None and both.frozen_stop is None
    assert both.moving.method == MOVING_METHOD
    for load, twist, pose in zip(
        both.moving.loads, both.moving.twists, both.displaced_poses, strict=True
    ):
        state = moving_equilibrium(design, load * unit, tool_point=tool)
        # the same solver row by row: equal to its convergence tolerance
        np.testing.assert_allclose(twist, state.twist, rtol=0, atol=1e-12)
        np.testing.assert_allclose(pose, state.displaced_pose, rtol=0, atol=1e-12)


def test_the_curves_part_at_second_order_in_the_load() -> None:
    # moving - frozen = O(L^2): halving a small load quarters the difference
    design = design_named("3rpr")
    unit = np.array([2.0, 2.0, 5.0, 200.0, 200.0, -500.0])
    loads = np.array([0.0, 0.05, 0.1])
    both = moving_deflection(design, unit, loads, method="closed-form")
    gap = np.linalg.norm(both.moving.twists - both.frozen.twists, axis=1)
    assert gap[0] == 0.0
    assert gap[2] / gap[1] == pytest.approx(4.0, rel=0.05)  # measured 4.00-4.02
    assert gap[2] < 0.05 * np.linalg.norm(both.frozen.twists[2])


def test_the_moving_curve_stops_before_the_load_margin() -> None:
    # the paper's machine under multiples of the paper's load: the moving path ends at
    # a limit point at 3.26 times it (docs/statics.md); the frozen model leaves its
    # small-rotation range (5.7 deg) first
    design = design_named("paper")
    loads = np.linspace(0.0, 4.0, 9)
    both = moving_deflection(design, PAPER_WRENCH, loads, method="closed-form")
    margin = load_margin(design, PAPER_WRENCH)
    assert margin.factor is not None
    stop = both.moving_stop
    assert stop is not None and stop.instability_load is not None
    assert stop.load == 3.5 and both.moving.loads[-1] == 3.0
    assert stop.instability_load == pytest.approx(margin.factor, rel=1e-6)
    assert both.moving.loads[-1] < stop.instability_load < stop.load
    assert both.frozen_stop is not None and "rotation" in both.frozen_stop.reason
    assert both.frozen.loads[-1] < both.frozen_stop.load
    lines = both.stops()
    assert len(lines) == 2 and "loses stability at 3.26" in lines[1]


def test_cli_json_csv_and_text(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    csv = tmp_path / "c.csv"
    argv = ["deflect", "--mode", "wrench", "--wrench", PAPER_LOAD, "--max", "4", "--step", "0.5"]
    assert main([*argv, "--geometry", "moving", "--json", "--csv", str(csv)]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    doc = json.loads(out)
    jsonschema.validate(
        doc, json.loads(SCHEMA.read_text(encoding="utf-8")), cls=jsonschema.Draft202012Validator
    )
    assert doc["geometry"] == "moving"
    mg = doc["moving_geometry"]
    assert mg["stopped"]["load"] == 3.5
    assert mg["stopped"]["instability_load"] == pytest.approx(3.2618, abs=5e-5)
    assert mg["stopped"]["mode_direction"] == "rotation about z"
    assert doc["loads"][-1] == 1.5 and mg["frozen_stopped"]["load"] == 2.0
    state = moving_equilibrium(design_named("paper"), 3.0 * PAPER_WRENCH)
    np.testing.assert_allclose(mg["twists"][-1], state.twist, rtol=0, atol=1e-12)
    rows = [r for r in csv.read_text(encoding="utf-8").splitlines() if not r.startswith("#")]
    assert rows[0].startswith("load,phi_x_deg") and rows[0].endswith("moving_z_mm,K_F_vs_K")
    assert len(rows) == 1 + 7  # loads 0 .. 3: the moving curve's
    assert rows[-1].split(",")[1] == ""  # the frozen curve stopped before 3
    assert main([*argv, "--geometry", "moving"]) == 0
    text = capsys.readouterr().out
    assert "geometry moving (the frozen curve first" in " ".join(text.split())
    assert "frozen geometry: platform deflection" in text and "moving geometry:" in text
    assert "loses stability at 3.26181" in " ".join(text.split())
    assert main([*argv[:5], "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["geometry"] == "frozen"


def test_cli_refuses_moving_with_tolerances(capsys: pytest.CaptureFixture[str]) -> None:
    tol = ROOT / "examples" / "identification" / "tolerances.toml"
    code = main(["deflect", "--geometry", "moving", "--tolerances", str(tol)])
    assert code == 2
    err = capsys.readouterr().err
    assert "frozen geometry only" in err and len(err.strip().splitlines()) == 1
