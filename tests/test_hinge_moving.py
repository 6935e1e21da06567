"""Notch hinges' stress along the moving-geometry curve of ``deflect`` (issue 29 item 3):
src/ppm_stiffness/statics/hinge_stress.py (``moving_hinge_loads``,
``moving_curve_stresses``); docs/flexures.md, "Stress and range of motion"."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.design import load_design
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.hinge_stress import (
    curve_stresses,
    moving_curve_stresses,
    moving_hinge_loads,
)
from ppm_stiffness.statics.moving_deflection import moving_deflection
from ppm_stiffness.statics.moving_path import platform_chains

ROOT = Path(__file__).resolve().parents[1]
STAGE = ROOT / "examples" / "flexure_3rrr.toml"
#: The stage's test load (tests/test_flexure_loaded.py): f = (30, -20, 0) N, m_z = 0.5 N·m.
WRENCH = np.array([0.0, 0.0, 0.5, 30.0, -20.0, 0.0])


@pytest.fixture(scope="module")
def curves() -> tuple[object, object]:
    """The stage's frozen and moving curves at 1e-3 and 2e-3 times the test load and at
    the test load."""
    design = load_design(STAGE)
    size = float(np.linalg.norm(WRENCH))
    loads = np.array([1e-3 * size, 2e-3 * size, size])
    return design, moving_deflection(design, WRENCH / size, loads, home_pose(design))


def test_at_small_loads_the_moving_stress_is_the_frozen_one_to_first_order(
    curves: tuple[object, object],
) -> None:
    """The largest hinge stress of the moving curve over the frozen curve's, minus 1:
    measured 1.387e-7 and 2.774e-7 at 1e-3 and 2e-3 times the test load (slope 1.39e-4
    per test load, ratio 2.000: the difference is of first order in the load, so the
    stresses agree to first order), 1.389e-4 at the test load; the same hinge."""
    design, mv = curves
    frozen = curve_stresses(design, mv.frozen)  # type: ignore[attr-defined]
    moving = moving_curve_stresses(design, mv)
    rel = np.asarray(moving["stress"]) / np.asarray(frozen["stress"]) - 1.0
    print("relative differences", rel)
    assert abs(rel[0]) < 1e-6
    assert rel[1] / rel[0] == pytest.approx(2.0, abs=0.02)
    assert abs(rel[2] - 1e3 * rel[0]) < 0.02 * abs(rel[2])
    assert moving["hinge"] == frozen["hinge"]


def test_at_the_test_load_each_elastic_hinge_carries_k_times_its_rotation(
    curves: tuple[object, object],
) -> None:
    """An elastic R hinge's moment about its axis, from the leg's wrench in the moving
    equilibrium moved to its displaced centre, equals k_h times its rotation, the chain
    coordinate the equilibrium solved (measured 4.5e-13 relative at most over the six
    passive hinges and the three loads): the displaced centres and axes are right. A
    transport leaving the hinges at their unloaded centres and axes is 0.67 off."""
    design, mv = curves
    model, loads = moving_hinge_loads(design, mv)
    pose = np.asarray(mv.moving.pose).reshape(1, 6)  # type: ignore[attr-defined]
    chains = platform_chains(design, pose, np.zeros((1, 3))).chains
    worst = 0.0
    for leg, chain in enumerate(chains):
        assert chain.elastic is not None
        columns = np.flatnonzero(chain.elastic)
        passive = [j for j, h in enumerate(model.hinges) if h.leg == leg and h.parallel == 0.0]
        assert len(columns) == len(passive) == 2
        for column, j in zip(columns, passive, strict=True):
            k_theta = chain.elastic[column] * mv.coordinates[leg][:, column]  # type: ignore[attr-defined]
            worst = max(worst, float(np.max(np.abs(loads[:, j, 2] / k_theta - 1.0))))
    print("worst relative difference", worst)
    assert worst < 1e-10


def test_deflect_moving_gives_the_moving_hinge_stress(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``deflect --geometry moving``: the moving curve's hinge table, JSON
    (``moving_geometry.hinge_stress``, valid against the schema) and CSV columns
    (``moving_hinge_stress_max_MPa``, ``moving_hinge_utilisation``), equal to the library's
    (at 60 N: 175.99 MPa against the frozen 175.95, utilisation 0.6997 at SF 2)."""
    from ppm_stiffness.cli import main

    design = load_design(STAGE)
    argv = ["deflect", "--design", str(STAGE), "--direction", "30,-20,0,0,0,0.5"]
    argv += ["--max", "60", "--step", "15", "--safety-factor", "2", "--geometry", "moving"]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema = pytest.importorskip("jsonschema")
    schema = (ROOT / "docs" / "schemas" / "deflect.schema.json").read_text(encoding="utf-8")
    jsonschema.validate(doc, json.loads(schema))
    got = doc["moving_geometry"]["hinge_stress"]
    unit = np.asarray(doc["load_direction"])
    mv = moving_deflection(design, unit, np.asarray(doc["moving_geometry"]["loads"]))
    ref = moving_curve_stresses(design, mv, 2.0)
    np.testing.assert_allclose(got["stress"], ref["stress"], rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(got["utilisation"], ref["utilisation"], rtol=1e-12)
    assert got["hinge"][-1] == "leg3.base_hinge"
    csv = tmp_path / "curve.csv"
    assert main([*argv, "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "along the moving curve" in out
    lines = [r for r in csv.read_text(encoding="utf-8").splitlines() if not r.startswith("#")]
    header, last = lines[0].split(","), lines[-1].split(",")
    at = header.index("moving_hinge_stress_max_MPa")
    assert float(last[at]) == pytest.approx(ref["stress"][-1] / 1e6, rel=1e-8)
    assert float(last[at + 1]) == pytest.approx(ref["utilisation"][-1], rel=1e-8)
