"""Design studies on spatial designs: the region summary, f1 and the load margin.

References: the summary's stiffness figures against :func:`ppm_stiffness.analyze` pose
by pose (the single-pose solver and :func:`~ppm_stiffness.core.principal.principal_compliance`,
not the batched closed forms); f1 against :func:`ppm_stiffness.dynamics.analysis.modal_analysis`
(what ``modes`` prints) pose by pose; the scaling laws of K v = omega^2 M v (every
stiffness doubled: f1 x sqrt(2); every mass doubled: f1 / sqrt(2)); the load margin of
the returned design against :func:`ppm_stiffness.statics.margin.load_margin` pose by pose.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import ppm_stiffness as pps
from helpers import check_entries, example_designs, is_spatial
from ppm_stiffness.analysis import analyze_matrix
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design, design_from_dict
from ppm_stiffness.design.io import design_to_dict
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.model import (
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
    validate_pose,
)
from ppm_stiffness.optimize.margin import margin_poses
from ppm_stiffness.optimize.objectives import OBJECTIVES, check_quantities, parse_constraint
from ppm_stiffness.optimize.optimizer import optimize_design
from ppm_stiffness.optimize.region import region_from_ranges, region_poses
from ppm_stiffness.optimize.summary import summarize
from ppm_stiffness.optimize.variables import parse_variable

ROOT = Path(__file__).parents[1]
SPATIAL = example_designs(is_spatial)
#: Small regions over each spatial example's task coordinates (inside its own region).
REGIONS = {
    "hexapod_6ups": (
        {
            "x": (-0.01, 0.01),
            "y": (0.0, 0.0),
            "z": (0.19, 0.21),
            "rx": (0.0, 0.05),
            "ry": (0.0, 0.0),
            "rz": (-0.05, 0.05),
        },
        (2, 1, 2, 2, 1, 2),
    ),
    "3prs": ({"z": (0.36, 0.44), "rx": (-0.3, 0.3), "ry": (-0.2, 0.1)}, (2, 3, 2)),
    "3rps": ({"z": (0.33, 0.37), "rx": (-0.1, 0.15), "ry": (-0.15, 0.1)}, (2, 2, 3)),
    "6rus": (
        {
            "x": (-0.01, 0.01),
            "y": (0.0, 0.0),
            "z": (0.205, 0.22),
            "rx": (0.0, 0.05),
            "ry": (0.0, 0.0),
            "rz": (-0.05, 0.05),
        },
        (2, 1, 2, 2, 1, 2),
    ),
    "6rus_flexure": (
        {
            "x": (-0.001, 0.001),
            "y": (0.0, 0.0),
            "z": (0.2115, 0.2135),
            "rx": (0.0, 0.005),
            "ry": (0.0, 0.0),
            "rz": (-0.005, 0.005),
        },
        (2, 1, 2, 2, 1, 2),
    ),
    "flexure_3rrr": ({"x": (-1e-5, 1e-5), "y": (0.0, 1e-5), "rz": (-2e-4, 2e-4)}, (2, 2, 2)),
    "spherical_3rrr": ({"rx": (-0.3, 0.3), "ry": (-0.2, 0.1), "rz": (-0.1, 0.2)}, (2, 3, 2)),
    "tricept": ({"z": (0.53, 0.57), "rx": (-0.05, 0.08), "ry": (-0.06, 0.05)}, (2, 3, 2)),
    "delta": ({"x": (-0.05, 0.05), "y": (0.0, 0.03), "z": (-0.83, -0.78)}, (2, 2, 2)),
}


def test_every_spatial_example_has_a_region() -> None:
    check_entries(REGIONS, SPATIAL, "REGIONS")


#: (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the tool point.
WRENCH = np.array([2.0, -1.0, 0.5, 30.0, -20.0, -200.0])


def _design(name: str) -> Design:
    return pps.load_design(ROOT / "examples" / f"{name}.toml")


def _region(name: str):  # type: ignore[no-untyped-def]
    ranges, grid = REGIONS[name]
    return region_from_ranges(ranges, grid)


def _scaled(design: Design, units: set[str], factor: float) -> Design:
    """Every scalar parameter of a unit in ``units`` times ``factor``."""
    values = {
        n: factor * float(design.parameter(n))
        for n in design.scalar_parameter_names()
        if design.parameter_unit(n) in units
    }
    return design.with_parameters(values)


def _without_masses(design: Design) -> Design:
    """The design without its mass model (no [platform] table, no part masses)."""
    data = design_to_dict(design)
    data.pop("platform")

    def strip(node: object) -> None:
        if isinstance(node, dict):
            for key in [k for k in node if "mass" in k or k == "inertia_transverse"]:
                node.pop(key)
            for value in node.values():
                strip(value)
        elif isinstance(node, list):
            for value in node:
                strip(value)

    strip(data.get("legs"))
    strip(data.get("parts"))
    return design_from_dict(data)


STIFFNESS_UNITS = {"N/m", "N·m/rad", "Pa", "N/m^q"}
MASS_UNITS = {"kg", "kg·m^2"}


@pytest.mark.parametrize("name", SPATIAL)
def test_spatial_summary_equals_the_single_pose_analysis(name: str) -> None:
    design, region = _design(name), _region(name)
    summary = summarize(design, region, frequencies=False)  # f1: the test below
    poses = region_poses(region).reshape(-1, len(design.task_coordinates))
    tool = np.asarray(design.tool_point)
    trans, rot = [], []
    for pose in poses:
        # analyze's single-pose path (without its f1, which this test does not read)
        p = validate_pose(design, pose)
        k_tool = stiffness_at_tool_point(stiffness_at_pose(design, p), p, tool)
        pc = analyze_matrix(k_tool).to_dict()["principal_compliance"]
        trans.append(min(pc["translational"]["values"]))
        rot.append(min(pc["rotational"]["values"]))
    assert summary.covers and not summary.planar
    for key, ref in (("k_translational", np.array(trans)), ("k_rotational", np.array(rot))):
        # batched engine and closed-form eigenvalues vs the single-pose solver and
        # numpy's eigh: round-off, measured at most 1.0e-13 relative
        assert summary[f"{key}_min"] == pytest.approx(ref.min(), rel=1e-12)
        assert summary[f"{key}_mean"] == pytest.approx(ref.mean(), rel=1e-12)
        assert summary[f"{key}_p5"] == pytest.approx(np.percentile(ref, 5), rel=1e-12)
    assert math.isnan(summary["k_x_min"]) and math.isnan(summary["k_phi_min"])
    objective = OBJECTIVES["worst-k-translational"].value(summary)
    assert objective == summary["k_translational_min"]
    assert OBJECTIVES["worst-k-rotational"].value(summary) == summary["k_rotational_min"]


F1_CASES = [
    pytest.param(name, loaded, id=f"{name}-{'loaded' if loaded else 'locked'}")
    for name in SPATIAL
    for loaded in (False, True)
]


@pytest.mark.parametrize(("name", "loaded"), F1_CASES)
def test_f1_objective_is_the_minimum_of_the_modes_f1(name: str, loaded: bool) -> None:
    design, region = _design(name), _region(name)
    wrench = WRENCH if loaded else None
    summary = summarize(design, region, wrench, link_modes=0)
    poses = region_poses(region).reshape(-1, len(design.task_coordinates))
    # the condensed f1 on both sides (with link modes: tests/test_link_modes_maps.py)
    f1 = np.array([modal_analysis(design, p, wrench, link_modes=0).frequencies[0] for p in poses])
    value = OBJECTIVES["first-frequency"].value(summary)
    # K, M at P (batched) vs at the tool point (single pose): the congruence leaves the
    # frequencies unchanged up to round-off, measured at most 4.5e-14 relative
    assert value == pytest.approx(f1.min(), rel=1e-12)
    assert summary["f1_mean"] == pytest.approx(f1.mean(), rel=1e-12)


@pytest.mark.parametrize("name", ["3rps", "hexapod_6ups", "3rrr"])
def test_f1_scales_as_the_square_root_of_stiffness_over_mass(name: str) -> None:
    design = _design(name)
    region = _region(name) if name in REGIONS else None
    if region is None:
        assert design.workspace.required is not None
        region = design.workspace.required
    f1 = summarize(design, region, link_modes=0)["f1_min"]
    stiffer = summarize(_scaled(design, STIFFNESS_UNITS, 2.0), region, link_modes=0)["f1_min"]
    heavier = summarize(_scaled(design, MASS_UNITS, 2.0), region, link_modes=0)["f1_min"]
    # condensed: K doubles and M (the legs follow the spring ratios) does not: omega^2 doubles;
    # measured at most 8.6e-14 relative
    assert stiffer / f1 == pytest.approx(math.sqrt(2.0), rel=1e-12)
    assert f1 / heavier == pytest.approx(math.sqrt(2.0), rel=1e-12)


def test_loaded_figures_are_3d_norms_of_the_tool_point_motion() -> None:
    design, region = _design("3prs"), _region("3prs")  # tool point 150 mm below P
    summary = summarize(design, region, WRENCH, frequencies=False)
    poses = region_poses(region).reshape(-1, 3)
    disp, rot = [], []
    for pose in poses:
        p = validate_pose(design, pose)
        offset = tool_offset(p, design.tool_point)
        w_p = np.concatenate([WRENCH[:3] + np.cross(offset, WRENCH[3:]), WRENCH[3:]])
        t = pps.loaded_state(design, w_p, p).twist
        disp.append(np.linalg.norm(t[3:] + np.cross(t[:3], offset)))
        rot.append(np.linalg.norm(t[:3]))
    assert summary.loaded_failures == 0
    # batched equilibrium vs loaded_state: measured equal (0 difference); 1e-11 as in
    # tests/test_loaded_batch.py
    assert summary["max_displacement"] == pytest.approx(max(disp), rel=1e-11)
    assert summary["max_rotation"] == pytest.approx(max(rot), rel=1e-11)


def test_optimize_improves_a_spatial_design() -> None:
    design, region = _design("3rps"), _region("3rps")
    variables = [parse_variable("leg*.cylinder_length=0.15:0.29", design, count=False)]
    start = float(design.parameter("leg*.cylinder_length"))
    assert variables[0].lo < start < variables[0].hi
    result = optimize_design(
        design,
        variables,
        OBJECTIVES["first-frequency"],
        region,
        budget=20,
        seed=3,
        link_modes=0,  # the optimiser under test, on the cheaper condensed f1
    )
    check = summarize(result.best_design, region, link_modes=0)
    assert result.best_objective == check["f1_min"]  # the same model, same poses
    # measured: 15.085 Hz at the start (0.25 m) -> 18.17 Hz (0.29 m, the range's end)
    assert result.best_objective > 1.15 * result.initial_objective
    assert check.covers


def test_a_load_margin_constraint_is_met_by_the_returned_design() -> None:
    from ppm_stiffness.statics.margin import load_margin

    design = _design("3rps")
    # two margin poses (the corners in z at rx = 0.15 rad, the least margins of the
    # region's four corners): each candidate's margins are one batch of two searches
    region = region_from_ranges(
        {"z": (0.33, 0.37), "rx": (0.15, 0.15), "ry": (0.0, 0.0)}, (2, 1, 1)
    )
    wrench = np.array([0.0, 0.0, 0.0, 400.0, 0.0, -4000.0])
    # the start design's margin is 5.04 (a limit point): infeasible; measured 6.17 at a
    # cylinder length of 0.27 m, 7.71 at 0.29 m
    bound = 6.0
    variables = [parse_variable("leg*.cylinder_length=0.24:0.29", design, count=False)]
    result = optimize_design(
        design,
        variables,
        OBJECTIVES["max-displacement"],
        region,
        budget=10,
        seed=1,
        wrench=wrench,
        constraints=[parse_constraint(f"load-margin>={bound}")],
    )
    best = result.best_design
    assert result.best_summary.margin_poses == 2
    margins = []
    for pose in margin_poses(region):
        m = load_margin(best, wrench, pose, tool_point=best.tool_point)
        margins.append(m.factor if m.factor is not None else m.searched_up_to)
    assert min(margins) >= bound
    assert result.best_summary["load_margin"] == pytest.approx(min(margins), rel=1e-12)


def test_f1_of_a_design_without_a_mass_model_names_the_platform_table() -> None:
    bare = _without_masses(_design("3prs"))
    with pytest.raises(DesignError, match=r"no mass model; add a \[platform\] table"):
        check_quantities(bare, [OBJECTIVES["first-frequency"]], wrench=False)
    with pytest.raises(DesignError, match=r"\[platform\]"):
        check_quantities(bare, [parse_constraint("f1>=10").quantity], wrench=False)
    assert math.isnan(summarize(bare, _region("3prs"))["f1_min"])


def test_stiffness_figures_of_the_other_family_are_refused() -> None:
    from ppm_stiffness.optimize.objectives import quantity

    with pytest.raises(InputDataError, match="k_translational, k_rotational"):
        check_quantities(_design("3prs"), [quantity("k_phi_p5")], wrench=False)
    with pytest.raises(InputDataError, match="k_x, k_y, k_phi"):
        check_quantities(pps.default_design(), [quantity("k_rotational_min")], wrench=False)


def test_a_variable_that_does_not_apply_names_the_ones_that_do() -> None:
    with pytest.raises(DesignError, match=r"this design's are .*leg\*\.link_length"):
        parse_variable("leg*.platform_radius=0.1:0.2", _design("3prs"), count=False)


def test_the_margin_subgrid_is_the_region_corners() -> None:
    region = _region("hexapod_6ups")
    corners = margin_poses(region)
    assert corners.shape == (2**4, 6)  # four coordinates vary
    grid = region_poses(region).reshape(-1, 6)
    assert all(any(np.array_equal(c, g) for g in grid) for c in corners)


def test_platform_radius_scales_every_legs_point_radially() -> None:
    from ppm_stiffness.optimize.variables import apply_values, geometry_radius

    design = _design("hexapod_6ups")
    assert geometry_radius(design, "platform_radius") == pytest.approx(0.1, rel=1e-12)
    moved = apply_values(design, {"platform_radius": 0.12, "base_radius": 0.18})
    for before, after in zip(design.legs, moved.legs, strict=True):
        for key, radius in (("platform_point", 0.12), ("base_point", 0.18)):
            p, q = np.asarray(getattr(before, key)), np.asarray(getattr(after, key))
            assert np.hypot(q[0], q[1]) == pytest.approx(radius, rel=1e-14)
            assert math.atan2(q[1], q[0]) == pytest.approx(math.atan2(p[1], p[0]), abs=1e-14)
            assert q[2] == p[2]


def test_optimize_a_hexapods_platform_radius() -> None:
    design, region = _design("hexapod_6ups"), _region("hexapod_6ups")
    variables = [parse_variable("platform_radius=0.08:0.14", design, count=False)]
    assert variables[0].start(design) == pytest.approx(0.1, rel=1e-12)
    result = optimize_design(
        design, variables, OBJECTIVES["worst-k-rotational"], region, budget=10, seed=0
    )
    check = summarize(result.best_design, region, frequencies=False)
    assert result.best_objective == check["k_rotational_min"]
    # a wider platform circle: longer lever arms; measured 1.9x at 0.14 m
    assert result.best_objective > 1.3 * result.initial_objective
    assert math.isnan(result.best_summary["f1_min"])  # f1 is computed only when used


def test_a_geometric_variable_that_does_not_apply_is_refused() -> None:
    with pytest.raises(
        DesignError, match=r"platform_radius does not apply.*leg\*\.platform_radius"
    ):
        parse_variable("platform_radius=0.05:0.07", _design("3rpr"), count=False)
