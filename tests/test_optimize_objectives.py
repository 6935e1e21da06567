"""The actuator effort and balanced condition number objectives, the cheap checks
before the maps, and the budget (issue 31, items 3 and 4).

- actuator effort against ``analyze --wrench``'s library call
  (:func:`ppm_stiffness.analysis.analyze_design`) at the worst pose found by brute
  force over the region's grid, a linear-drive design (N) and a rotary one (N·m);
- the condition number against ``numpy.linalg.cond`` of K at the tool point scaled by
  hand, and its invariance under a rotation of the base frame (the 3-RPR turned about
  z by turning every base and platform point);
- the cheap check: a problem where some candidates cannot reach the region's corners
  (leg 1's base point too far or too near for its stroke); the maps are not computed
  for them (a spy on :func:`ppm_stiffness.optimize.summary.summarize`) and the front
  and the single-objective result equal those of the same seeded run that computes
  every design's maps;
- the budget: evaluations never exceed it, in both modes, and the CLI reports both.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import ppm_stiffness as pps
from ppm_stiffness.analysis import analyze_design
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import rotation_z
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.maps.batch import stiffness_matrix
from ppm_stiffness.optimize import summary as summary_module
from ppm_stiffness.optimize.objectives import (
    OBJECTIVES,
    check_quantities,
    parse_constraint,
    quantity,
)
from ppm_stiffness.optimize.optimizer import optimize_design
from ppm_stiffness.optimize.precheck import check_poses, refused_check_poses
from ppm_stiffness.optimize.region import make_region, region_poses
from ppm_stiffness.optimize.summary import summarize, summarize_candidate
from ppm_stiffness.optimize.variables import apply_values, parse_variable

ROOT = Path(__file__).parents[1]
#: 3 x 3 x 3 poses: x, y in +-10 mm, phi in +-0.1 rad.
REGION = make_region((-0.01, 0.01), (-0.01, 0.01), (-0.1, 0.1), (3, 3, 3))
#: (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the tool point: every component non-zero.
WRENCH = np.array([0.5, -0.3, 2.0, 10.0, -20.0, 5.0])
#: A tool point off P [m, platform frame], so that the wrench's moment changes with phi.
TOOL = (0.02, -0.01, 0.0)


def _design(name: str, tool: tuple[float, float, float] = TOOL, mass: bool = True) -> pps.Design:
    """The example with ``tool`` as its tool point; without its mass model when
    ``mass`` is False (analyze's first mode, which the brute-force checks do not use,
    costs 3 s a pose with it; such a copy takes no parameter values)."""
    design = pps.load_design(ROOT / f"examples/{name}.toml")
    update: dict[str, Any] = {"tool_point": tool}
    if not mass:
        update["platform"] = None
    return design.model_copy(update=update)


@pytest.mark.parametrize(("name", "objective"), [("3rpr", "N"), ("3rrr", "N·m")])
def test_effort_equals_analyze_at_the_worst_grid_pose(name: str, objective: str) -> None:
    design = _design(name, mass=False)
    summary = summarize(design, REGION, WRENCH, frequencies=False)
    assert summary.covers
    brute = [
        np.max(np.abs(analyze_design(design, p, WRENCH).actuator_forces))
        for p in region_poses(REGION).reshape(-1, 3)
    ]
    worst = max(brute)
    effort = quantity("effort")
    assert effort is OBJECTIVES["actuator-effort"]
    # measured residual 4e-16 (the same equilibrium, batched against one pose)
    assert effort.value(summary) == pytest.approx(worst, rel=1e-12)
    per_kind = "actuator-force" if objective == "N" else "actuator-torque"
    other = "actuator-torque" if objective == "N" else "actuator-force"
    assert OBJECTIVES[per_kind].value(summary) == effort.value(summary)
    assert np.isnan(OBJECTIVES[other].value(summary))
    # the worst pose is a corner of the region here, not the home pose: the max is
    # taken over the grid, not at one pose
    assert worst > 1.05 * min(brute)
    with pytest.raises(DesignError, match=f"{other}: design .* has no"):
        check_quantities(design, [OBJECTIVES[other]], wrench=True)


def test_effort_needs_a_wrench_and_constrains() -> None:
    design = _design("3rpr")
    with pytest.raises(InputDataError, match="actuator-effort needs --wrench"):
        check_quantities(design, [quantity("effort")], wrench=False)
    summary = summarize(design, REGION, WRENCH, frequencies=False)
    limit = parse_constraint("effort<=20")
    assert str(limit) == "actuator-effort<=20"
    # 22.46 N against 20 N: 12.3 % over the bound
    assert limit.shortfall(summary) == pytest.approx((summary.actuator_force_max - 20) / 20)
    assert parse_constraint("effort<=25").shortfall(summary) == 0.0


def test_condition_number_is_that_of_the_hand_balanced_k_at_the_tool_point() -> None:
    design = _design("3rpr", mass=False)
    summary = summarize(design, REGION, frequencies=False, condition=True)
    scale = np.diag([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])  # 1 / L, L = 0.1 m
    by_hand = max(
        np.linalg.cond(scale @ analyze_design(design, p).stiffness_matrix @ scale)
        for p in region_poses(REGION).reshape(-1, 3)
    )
    value = OBJECTIVES["condition-number"].value(summary)
    assert value == pytest.approx(by_hand, rel=1e-13)  # measured 2e-15
    # the balancing matters: K in SI units has a condition number far from it
    unbalanced = np.linalg.cond(analyze_design(design, (0.0, 0.0, 0.0)).stiffness_matrix)
    assert abs(np.log10(unbalanced / value)) > 1
    # without condition=True the figure is not computed (NaN, never a number)
    assert np.isnan(summarize(design, REGION, frequencies=False).condition_max)


def _turned(design: pps.Design, angle: float) -> pps.Design:
    """``design`` turned about the base z axis by ``angle`` [rad]: every base point's
    angle and every platform point's angle psi (the revolute axes are along z)."""
    values = {}
    for i in (1, 2, 3):
        for name in (f"leg{i}.psi", f"leg{i}.base_point.angle"):
            start = parse_variable(f"{name}=-3:3", design, False).start(design)
            assert start is not None
            values[name] = (start + angle + np.pi) % (2 * np.pi) - np.pi
    return apply_values(design, values)


def test_condition_number_is_invariant_under_a_rotation_of_the_base_frame() -> None:
    # leg 1's base point moved out: K_tt is not isotropic (the example's is, at home)
    design = apply_values(_design("3rpr", (0.0, 0.0, 0.0)), {"leg1.base_point.radius": 0.28})
    turned = _turned(design, 0.7)
    # the region x = y = 0 maps onto itself under a turn about z through the origin
    region = make_region((0.0, 0.0), (0.0, 0.0), (-0.1, 0.1), (1, 1, 3))
    k0 = stiffness_matrix(design, (0.0, 0.0, 0.05))
    k1 = stiffness_matrix(turned, (0.0, 0.0, 0.05))
    t = np.zeros((6, 6))
    t[:3, :3] = t[3:, 3:] = rotation_z(0.7)
    # the turned design's K is the turned K (measured 1.4e-14 of the largest entry)
    assert np.max(np.abs(t @ k0 @ t.T - k1)) < 1e-12 * np.max(np.abs(k0))
    c0 = summarize(design, region, frequencies=False, condition=True).condition_max
    c1 = summarize(turned, region, frequencies=False, condition=True).condition_max
    assert c1 == pytest.approx(c0, rel=1e-12)  # measured 2e-15
    # a per-component balancing that is not a multiple of diag(1, 1, 1) per block would
    # not be invariant: scale x alone and the two differ
    s = np.diag([10.0, 10.0, 10.0, 2.0, 1.0, 1.0])
    assert abs(np.linalg.cond(s @ k0 @ s) / np.linalg.cond(s @ k1 @ s) - 1) > 1e-3


# --- the cheap check -------------------------------------------------------------------

#: Leg 1's base point radius: below 0.19 m or above 0.31 m a corner of REGION needs a
#: pivot distance outside the stroke [0.15, 0.3] m (measured: 0.18 refuses 2 of the 9
#: check poses, 0.32 refuses 3, 0.36 all).
REACH = "leg1.base_point.radius=0.17:0.40"
PSI = "leg2.psi=1.1:2.1"


def test_check_poses_are_the_corners_and_home() -> None:
    design = _design("3rpr")
    poses = check_poses(design, REGION)
    assert poses.shape == (9, 3)
    assert {tuple(p) for p in poses[:8]} == {
        (x, y, phi) for x in (-0.01, 0.01) for y in (-0.01, 0.01) for phi in (-0.1, 0.1)
    }
    assert tuple(poses[8]) == (0.0, 0.0, 0.0)
    far = apply_values(design, {"leg1.base_point.radius": 0.36})
    assert refused_check_poses(far, REGION) == (9, 9)
    assert refused_check_poses(design, REGION) == (9, 0)


class _Spy:
    """Counts the calls of the region's maps (:func:`summarize`)."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.calls = 0
        original = summary_module.summarize

        def counted(*args: Any, **kwargs: Any) -> Any:
            self.calls += 1
            return original(*args, **kwargs)

        monkeypatch.setattr(summary_module, "summarize", counted)


def test_refused_candidate_is_returned_without_maps(monkeypatch: pytest.MonkeyPatch) -> None:
    spy = _Spy(monkeypatch)
    design = _design("3rpr")
    far = {"leg1.base_point.radius": 0.36}
    skipped = summarize_candidate(design, far, REGION, check="skip")
    assert spy.calls == 0
    assert (skipped.maps, skipped.covers, skipped.check_refused) == (False, False, 9)
    recorded = summarize_candidate(design, far, REGION, check="record")
    assert spy.calls == 1 and recorded.maps and recorded.covered == 0
    # the moving mass is the design's, with or without maps (it was NaN when skipped)
    assert skipped.moving_mass == recorded.moving_mass > 0
    near = summarize_candidate(design, {"leg1.base_point.radius": 0.25}, REGION, check="skip")
    assert spy.calls == 2 and near.covers and near.check_refused == 0


def _front_run(cheap: bool) -> Any:
    pytest.importorskip("pymoo", reason="pymoo is in the 'pareto' extra")
    from ppm_stiffness.optimize.pareto import optimize_front

    design = _design("3rpr", (0.0, 0.0, 0.0))
    variables = [parse_variable(v, design, False) for v in (REACH, PSI)]
    objectives = [quantity("k_x_min"), quantity("k_y_min")]
    return optimize_front(
        design, variables, objectives, REGION, budget=48, seed=3, cheap_checks=cheap
    )


def test_front_skips_the_maps_of_refused_designs_and_is_unchanged(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    spy = _Spy(monkeypatch)
    fast = _front_run(True)
    calls_fast = spy.calls
    spy.calls = 0
    full = _front_run(False)
    assert fast.refused_by_check > 0
    assert full.refused_by_check == fast.refused_by_check
    # one map per design the check passes (the start design's included), none for the
    # refused ones; every design's map without the cheap check
    assert calls_fast == fast.evaluations - fast.refused_by_check
    assert spy.calls == full.evaluations
    assert fast.evaluations == full.evaluations <= 48
    assert [d.parameters for d in fast.front] == [d.parameters for d in full.front]
    assert [d.objectives for d in fast.front] == [d.objectives for d in full.front]
    assert len(fast.front) >= 3


def _single_run(cheap: bool) -> Any:
    design = _design("3rpr", (0.0, 0.0, 0.0))
    variables = [parse_variable(v, design, False) for v in (REACH, PSI)]
    return optimize_design(
        design,
        variables,
        OBJECTIVES["worst-k-translational"],
        REGION,
        budget=40,
        seed=2,
        cheap_checks=cheap,
    )


def test_single_objective_skips_the_maps_and_is_unchanged(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    spy = _Spy(monkeypatch)
    fast = _single_run(True)
    calls_fast = spy.calls
    spy.calls = 0
    full = _single_run(False)
    assert fast.refused_by_check > 0
    assert calls_fast == fast.evaluations - fast.refused_by_check
    assert spy.calls == full.evaluations
    assert fast.evaluations == full.evaluations <= 40
    assert fast.best_parameters == full.best_parameters
    assert fast.best_objective == full.best_objective
    assert fast.history == full.history
    assert fast.best_summary.covers


# --- the budget ------------------------------------------------------------------------


def _json(capsys: pytest.CaptureFixture[str], argv: list[str], schema: str = "") -> Any:
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    if schema:
        jsonschema = pytest.importorskip("jsonschema", reason="jsonschema is in the 'test' extra")
        path = ROOT / "docs" / "schemas" / f"{schema}.schema.json"
        jsonschema.validate(doc, json.loads(path.read_text(encoding="utf-8")))
    return doc


@pytest.mark.parametrize("budget", [10, 23, 37])
def test_budget_bounds_single_objective_evaluations(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, budget: int
) -> None:
    argv = ["optimize", "--design", str(ROOT / "examples/3rpr.toml"), "--quiet", "--json"]
    argv += ["--vary", REACH, "--vary", PSI, "--region=-10,10,-10,10,-5.7,5.7,3,3,3"]
    argv += ["--budget", str(budget), "--seed", "1", "--out", str(tmp_path / "b.toml")]
    doc = _json(capsys, argv, "optimize")
    assert doc["budget"] == budget
    assert doc["evaluations"] <= budget
    # the plan spends the budget down to less than one population
    assert doc["evaluations"] > budget - doc["population"]
    assert 0 < doc["refused_by_check"] < doc["evaluations"]
    assert doc["history"][-1]["evaluations"] == doc["evaluations"]


@pytest.mark.parametrize("budget", [16, 41])
def test_budget_bounds_front_evaluations(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, budget: int
) -> None:
    pytest.importorskip("pymoo", reason="pymoo is in the 'pareto' extra")
    argv = ["optimize", "--design", str(ROOT / "examples/3rpr.toml"), "--quiet", "--json"]
    argv += ["--vary", REACH, "--vary", PSI, "--region=-10,10,-10,10,-5.7,5.7,3,3,3"]
    argv += ["--objective", "worst-k-translational", "--objective", "condition-number"]
    argv += ["--budget", str(budget), "--seed", "1", "--out", str(tmp_path / "b.toml")]
    doc = _json(capsys, argv, "optimize-front")
    assert doc["budget"] == budget
    assert doc["evaluations"] <= budget
    assert doc["refused_by_check"] <= doc["evaluations"]
    assert doc["history"][-1]["evaluations"] == doc["evaluations"]
    # the chosen design against the start: each objective's row is the front's value (the
    # condition number was NaN there when the comparison did not ask for it)
    chosen = doc["front"][doc["chosen"]]["objectives"]
    rows = {r["name"]: r for r in doc["comparison"]}
    for objective, value in zip(doc["objectives"], chosen, strict=True):
        name = objective["name"]
        assert rows[name]["chosen"] == pytest.approx(value, rel=1e-12), name


def test_text_output_reports_the_budget_and_the_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    argv = ["optimize", "--design", str(ROOT / "examples/3rpr.toml"), "--quiet"]
    argv += ["--vary", REACH, "--region=-10,10,-10,10,-5.7,5.7,3,3,3", "--budget", "10"]
    argv += ["--seed", "1", "--out", str(tmp_path / "b.toml"), "--objective", "actuator-effort"]
    assert main(argv) == 2
    assert "actuator-effort needs --wrench" in capsys.readouterr().err
    argv += ["--wrench", "10,-20,5,0.5,-0.3,2"]
    assert main(argv) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "evaluations of --budget 10 (population 5, 1 generation;" in out
    assert "refused by the cheap check, without maps)" in out


def test_effort_unit_is_stated_for_the_design(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    argv = ["optimize", "--design", str(ROOT / "examples/3rrr.toml"), "--quiet", "--json"]
    argv += ["--vary", "leg*.platform_radius=0.05:0.07", "--objective", "actuator-effort"]
    argv += ["--region=-5,5,-5,5,0,0,3,3,1", "--wrench", "10,-20,0,0,0,0.5", "--budget", "10"]
    argv += ["--seed", "1", "--out", str(tmp_path / "b.toml"), "--constraint", "effort<=100"]
    doc = _json(capsys, argv, "optimize")
    assert doc["objective"] == "actuator-effort"
    assert doc["objective_unit"] == "N·m"  # the 3-RRR's drives are rotary
    assert doc["units"]["best_objective"] == "N·m"
    assert 0 < doc["best_objective"] <= doc["initial_objective"]


def test_sweep_computes_the_condition_number() -> None:
    from ppm_stiffness.optimize.sweep import sweep_designs

    design = _design("3rpr", mass=True)
    variable = parse_variable("leg2.psi=1.3:1.8:2", design, True)
    result = sweep_designs(design, [variable], REGION, frequencies=False, condition=True)
    direct = summarize(
        apply_values(design, {"leg2.psi": 1.3}), REGION, frequencies=False, condition=True
    )
    assert result.summaries[0].condition_max == pytest.approx(direct.condition_max, rel=1e-12)


def test_a_passive_leg_is_no_drive() -> None:
    """The Tricept's central leg has no actuator: its column of the loaded states'
    forces is not a linear drive's (it was counted as one, in N)."""
    from ppm_stiffness.optimize.summary import actuator_efforts, drive_units

    design = pps.load_design(ROOT / "examples/tricept.toml")
    assert drive_units(design) == ["N", "N", "N", None]
    force, torque = actuator_efforts(design, np.array([[1.0, -2.0, 3.0, 100.0]]))
    assert force == 3.0 and np.isnan(torque)


def test_sweep_ranks_by_reachable_workspace(capsys: pytest.CaptureFixture[str]) -> None:
    """``sweep --quantity reachable-workspace`` prints each design's candidate share, as
    summarize gives it over the same region (the sweep passed no reach: an empty
    table, exit 0)."""
    from ppm_stiffness.optimize.region import region_from_ranges
    from ppm_stiffness.optimize.summary import summarize
    from ppm_stiffness.optimize.variables import apply_values

    argv = ["sweep", "--design", str(ROOT / "examples/hexapod_6ups.toml"), "--quiet"]
    argv += ["--vary", "platform_radius=0.10:0.14:2", "--quantity", "reachable-workspace"]
    argv += ["--no-f1", "--region=-10,10,-10,10,190,210,-2,2,-2,2,-2,2,2,2,2,2,2,2"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    rows = [line.split("│")[1:3] for line in lines if line.count("│") >= 3]
    printed = [float(b) for a, b in rows if a.strip()[:1].isdigit()]
    doc = _json(capsys, [*argv, "--json"], "sweep")
    box = doc["region"]
    names = ("x", "y", "z", "rx", "ry", "phi")
    region = region_from_ranges({n: tuple(box[n]) for n in names}, box["grid"])
    design = pps.load_design(ROOT / "examples/hexapod_6ups.toml")
    expected = [
        summarize(
            apply_values(design, {"platform_radius": r}), region, frequencies=False, reach=True
        ).candidate_share
        for r in (0.10, 0.14)
    ]
    assert len(printed) == 2
    np.testing.assert_allclose(printed, expected, rtol=5e-4)  # printed to 4 digits
    # the JSON rows carry the quantity swept (they had the table figures alone)
    assert doc["quantity"] == {"name": "reachable-workspace", "unit": "1"}
    assert [row["reachable-workspace"] for row in doc["rows"]] == expected


def test_the_hinge_range_is_stated_in_its_drives_unit() -> None:
    """On the stage (three rotary drives) the ``range`` objective and constraint are in
    rad (they said "rad or m", which the optimize table printed); a design whose drives
    are of both kinds would keep "rad or m" (none is shipped)."""
    from ppm_stiffness.optimize.objectives import for_design

    stage = pps.load_design(ROOT / "examples/flexure_3rrr.toml")
    assert OBJECTIVES["range"].unit == "rad or m"
    assert for_design(OBJECTIVES["range"], stage).unit == "rad"
    assert parse_constraint("range>=0.02", stage).quantity.unit == "rad"
    assert for_design(OBJECTIVES["stress"], stage).unit == "Pa"
