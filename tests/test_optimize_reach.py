"""The reachable-workspace objective (issue 31, item 4): the share of a candidate region
``[workspace.candidate]`` reached without refusal, against a brute-force count of the
single-pose analysis's refusals pose by pose; the candidate table in design files."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import ppm_stiffness as pps
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError, UnreachablePoseError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.optimize.objectives import OBJECTIVES, check_quantities
from ppm_stiffness.optimize.region import region_from_ranges, region_poses
from ppm_stiffness.optimize.summary import summarize, summarize_candidate
from ppm_stiffness.optimize.variables import apply_values

ROOT = Path(__file__).parents[1]
REACH = OBJECTIVES["reachable-workspace"]


def with_candidate(design: Design, candidate: RequiredRegionModel) -> Design:
    workspace = design.workspace.model_copy(update={"candidate": candidate})
    return design.model_copy(update={"workspace": workspace})


def brute_force(design: Design, candidate: RequiredRegionModel) -> tuple[int, int, int]:
    """(unreachable or beyond limits, singular, poses): every grid pose through the
    single-pose analysis, its refusals counted by their error types."""
    unreachable = singular = 0
    poses = region_poses(candidate).reshape(-1, len(candidate.grid))
    for pose in poses:
        try:
            stiffness_at_pose(design, pose)
        except UnreachablePoseError:
            unreachable += 1
        except SingularConfigurationError:
            singular += 1
    return unreachable, singular, int(poses.shape[0])


def test_share_of_a_planar_candidate_equals_the_single_pose_count() -> None:
    """The 3-RPR over x, y +-40 mm, phi +-60 deg: the grid holds unreachable poses and
    singular ones (phi = -60 deg, where the legs' lines meet), both refused."""
    design = pps.load_design(ROOT / "examples/3rpr.toml")
    candidate = region_from_ranges(
        {"x": (-0.04, 0.04), "y": (-0.04, 0.04), "rz": (-math.pi / 3, math.pi / 3)}, (5, 5, 5)
    )
    design = with_candidate(design, candidate)
    unreachable, singular, n = brute_force(design, candidate)
    assert unreachable > 0 and singular > 0  # both kinds of refusal are counted
    summary = summarize(design, design.workspace.required, frequencies=False, reach=True)
    assert summary.candidate_poses == n == 125
    assert summary.candidate_share == pytest.approx((n - unreachable - singular) / n, rel=1e-15)
    assert REACH.value(summary) == summary.candidate_share
    assert summary.covers  # the required region's figures are unaffected


@pytest.mark.parametrize("platform_radius", [0.10, 0.14])
def test_share_of_the_hexapod_candidate_equals_the_single_pose_count(
    platform_radius: float,
) -> None:
    """The shipped hexapod's candidate ranges on a coarser grid (216 poses), at the
    example's platform radius and a wider one (which reaches less)."""
    design = pps.load_design(ROOT / "examples/hexapod_6ups.toml")
    shipped = design.workspace.candidate
    assert shipped is not None
    candidate = region_from_ranges(shipped.ranges(), (3, 3, 3, 2, 2, 2))
    start = with_candidate(design, candidate)
    values = {"platform_radius": platform_radius}
    summary = summarize_candidate(start, values, start.workspace.required, None, reach=True)
    moved = apply_values(start, values)
    unreachable, singular, n = brute_force(moved, candidate)
    assert 0 < unreachable < n
    assert summary.candidate_poses == n
    assert summary.candidate_share == pytest.approx((n - unreachable - singular) / n, rel=1e-15)


def test_share_is_asked_for_only() -> None:
    """Without ``reach`` the candidate region costs nothing and the share is NaN."""
    design = pps.load_design(ROOT / "examples/hexapod_6ups.toml")
    summary = summarize(design, design.workspace.required, frequencies=False)
    assert math.isnan(summary.candidate_share) and summary.candidate_poses == 0
    assert math.isnan(REACH.value(summary))


def test_objective_needs_a_candidate_region() -> None:
    design = pps.load_design(ROOT / "examples/3rpr.toml")
    with pytest.raises(DesignError, match=r"reachable-workspace: .*\[workspace\.candidate\]"):
        check_quantities(design, [REACH], wrench=False)


def test_candidate_ranges_are_the_task_coordinates(tmp_path: Path) -> None:
    text = (ROOT / "examples/3rpr.toml").read_text(encoding="utf-8")
    path = tmp_path / "tripod_region.toml"
    path.write_text(
        text + "\n[workspace.candidate]\nx = [-0.02, 0.02]\ny = [-0.02, 0.02]\ngrid = [3, 3]\n",
        encoding="utf-8",
    )
    with pytest.raises(DesignError, match=r"workspace\.candidate: its ranges \(x, y\)"):
        pps.load_design(path)


def test_one_objective_search_maximises_the_share() -> None:
    """``optimize`` with reachable-workspace alone: the best design's share is what the
    candidate region gives for its parameters, not below the start's, and the best
    design covers the required region (the one constraint on reach)."""
    from ppm_stiffness.optimize.optimizer import optimize_design
    from ppm_stiffness.optimize.summary import candidate_share
    from ppm_stiffness.optimize.variables import parse_variable

    design = pps.load_design(ROOT / "examples/hexapod_6ups.toml")
    shipped = design.workspace.candidate
    assert shipped is not None
    design = with_candidate(design, region_from_ranges(shipped.ranges(), (3, 3, 3, 2, 2, 2)))
    required = design.workspace.required
    assert required is not None
    small = region_from_ranges(required.ranges(), (2,) * 6)
    variable = parse_variable("base_radius=0.11:0.20", design)
    result = optimize_design(design, [variable], REACH, small, budget=10, seed=1)
    best = apply_values(design, result.best_parameters)
    assert design.workspace.candidate is not None
    share, _ = candidate_share(best, design.workspace.candidate)
    assert result.best_objective == share >= result.initial_objective
    assert result.best_summary.covers


def test_cli_refuses_the_objective_without_a_candidate_region(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("pymoo", reason="pymoo is in the 'pareto' extra")
    from ppm_stiffness.cli import main

    monkeypatch.chdir(tmp_path)
    argv = ["optimize", "--design", str(ROOT / "examples/3rpr.toml"), "--vary", "leg1.psi=5.2:6.2"]
    argv += ["--objective", "worst-k-translational", "--objective", "reachable-workspace"]
    assert main([*argv, "--budget", "16", "--out", "chosen.toml", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "has no candidate region; add a [workspace.candidate] table" in err
    assert len(err.strip().splitlines()) == 1 and list(tmp_path.iterdir()) == []
