"""The required region and its summary figures, against the single-pose API.

References: the summary's minimum, mean and 5th percentile of k_x, k_y, k_phi are
recomputed from :func:`ppm_stiffness.analyze` pose by pose (an independent path: the
single-pose solver and the general decoupling, not the batched closed forms); the
covered fraction from which poses :func:`ppm_stiffness.stiffness_at_pose` refuses; the
worst deflection from :func:`ppm_stiffness.loaded_state` pose by pose.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import ppm_stiffness as pps
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import design_from_dict
from ppm_stiffness.design.io import design_to_dict
from ppm_stiffness.optimize.region import make_region, region_of, region_poses
from ppm_stiffness.optimize.summary import summarize, summarize_candidate

ROOT = Path(__file__).parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))


def _reference(design: pps.Design, poses: np.ndarray, tool: np.ndarray | None = None) -> dict:
    """Figures from the single-pose API: analyze() at each pose that it accepts."""
    ks, covered = [], 0
    for pose in poses:
        try:
            result = pps.analyze(design, pose, tool_point=tool).to_dict()
        except (pps.UnreachablePoseError, pps.SingularConfigurationError):
            continue
        covered += 1
        pr = result["principal"]
        ks.append(
            (
                pr["translational"]["values"][0],
                pr["translational"]["values"][1],
                pr["rotational"]["values"][2],
            )
        )
    k = np.array(ks)
    out = {"covered_fraction": covered / len(poses)}
    for col, name in enumerate(("k_x", "k_y", "k_phi")):
        out[f"{name}_min"] = float(np.min(k[:, col]))
        out[f"{name}_mean"] = float(np.mean(k[:, col]))
        out[f"{name}_p5"] = float(np.percentile(k[:, col], 5))
    return out


@pytest.mark.parametrize(
    "path", [ROOT / "examples/3rrr.toml", ROOT / "examples/symmetric_3ppr.toml"]
)
def test_summary_matches_the_single_pose_api(path: Path) -> None:
    design = pps.load_design(path)
    region = make_region((-0.01, 0.01), (-0.008, 0.012), (-0.1, 0.1), (3, 3, 2))
    summary = summarize(design, region, frequencies=False)
    reference = _reference(design, region_poses(region).reshape(-1, 3))
    assert summary.covers and summary.poses == 18
    for name, value in reference.items():
        # batched closed forms vs single-pose solver: round-off (measured at most
        # 3.8e-14 relative on these designs and the tool-point case below)
        assert summary[name] == pytest.approx(value, rel=1e-12), name


def test_summary_at_a_tool_point_matches_analyze() -> None:
    design = pps.load_design(ROOT / "examples/3prr.toml")
    tool = np.array([0.02, -0.01, 0.0])
    design = design.model_copy(update={"tool_point": tuple(tool)})
    region = make_region((-0.005, 0.005), (-0.005, 0.005), (-0.1, 0.1), (2, 2, 2))
    summary = summarize(design, region, frequencies=False)
    reference = _reference(design, region_poses(region).reshape(-1, 3), tool)
    for name, value in reference.items():
        assert summary[name] == pytest.approx(value, rel=1e-12), name  # measured 2.2e-16


def test_covered_fraction_counts_the_poses_the_model_refuses() -> None:
    design = pps.default_design()  # the paper's 3-PPR reaches x in [-15, 8.7] mm at phi = 0
    region = make_region((0.0, 0.012), (-0.01, 0.01), (0.0, 0.0), (7, 3, 1))
    summary = summarize(design, region, frequencies=False)
    reference = _reference(design, region_poses(region).reshape(-1, 3))
    assert 0 < summary.covered_fraction < 1 and not summary.covers
    assert summary.covered_fraction == reference["covered_fraction"]
    assert summary["k_x_min"] == pytest.approx(reference["k_x_min"], rel=1e-12)


def test_worst_deflection_matches_the_loaded_state_pose_by_pose() -> None:
    design = pps.load_design(ROOT / "examples/redundant_4ppr.toml")  # Newton path
    region = make_region((-0.01, 0.01), (0.0, 0.0), (-0.05, 0.05), (3, 1, 2))
    wrench = np.array([0.02, -0.01, 0.3, 6.0, -4.0, 5.0])
    summary = summarize(design, region, wrench, frequencies=False)
    twists = [
        pps.loaded_state(design, wrench, p).twist for p in region_poses(region).reshape(-1, 3)
    ]
    t = np.array(twists)
    # the summary uses the batched equilibrium (maps.loaded.loaded_poses), equal to
    # loaded_state to 4e-14 measured (tests/test_loaded_batch.py); 1e-11 as there
    assert summary["max_displacement"] == pytest.approx(
        np.max(np.hypot(t[:, 3], t[:, 4])), rel=1e-11
    )
    assert summary["max_rotation"] == pytest.approx(np.max(np.abs(t[:, 2])), rel=1e-11)
    assert summary.loaded_failures == 0


def test_a_load_beyond_the_model_makes_the_worst_case_unbounded() -> None:
    design = pps.load_design(ROOT / "examples/symmetric_3ppr.toml")
    region = make_region((0.0, 0.0), (0.0, 0.0), (0.0, 0.0), (1, 1, 1))
    summary = summarize(design, region, [0.0, 0.0, 50.0, 0.0, 0.0, 0.0], frequencies=False)
    assert summary.loaded_failures == 1
    assert summary["max_rotation"] == np.inf and summary.figures()["k_x_min"] is not None


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_every_example_has_a_region_it_covers(path: Path) -> None:
    design = pps.load_design(path)
    assert summarize(design, region_of(design), frequencies=False).covers


def test_refused_parameter_values_are_a_failed_record_not_an_error() -> None:
    design = pps.load_design(ROOT / "examples/symmetric_3ppr.toml")
    region = make_region((0.0, 0.0), (0.0, 0.0), (0.0, 0.0), (1, 1, 1))
    summary = summarize_candidate(design, {"leg*.platform_radius": -0.01}, region)
    assert summary.error is not None and not summary.covers
    assert summary.figures()["k_x_min"] is None


@pytest.mark.parametrize(
    ("required", "key", "hint"),
    [
        ({"x": [-10, 10]}, "workspace.required.x", "did you mean [-0.01, 0.01]?"),  # mm
        ({"phi": [-5, 5]}, "workspace.required.phi", "did you mean [-0.0872665, 0.0872665]?"),
        ({"y": [0.01, -0.01]}, "workspace.required.y", "inverted range"),
        ({"grid": [3, 3, 2], "phi": [0, 0]}, "workspace.required.phi", "grid value 1"),
        ({"grid": [3, 0, 1]}, "workspace.required.grid.1", "greater than or equal to 1"),
        ({"z": [0, 1]}, "workspace.required.z", "z is not a task coordinate of this design"),
    ],
)
def test_region_errors_name_the_key_and_the_unit_mistake(
    required: dict, key: str, hint: str
) -> None:
    data = design_to_dict(pps.default_design())
    data["workspace"]["required"] = {
        "x": [-0.01, 0.01],
        "y": [-0.01, 0.01],
        "phi": [0.0, 0.0],
        "grid": [3, 3, 1],
        **required,
    }
    with pytest.raises(DesignError) as err:
        design_from_dict(data)
    assert f"key '{key}'" in str(err.value) and hint in str(err.value)


def test_the_region_is_a_table_not_a_varied_parameter() -> None:
    design = pps.load_design(ROOT / "examples/3rpr.toml")
    assert design.workspace.required is not None
    assert not any("required" in n for n in design.scalar_parameter_names())
    copy = design.with_parameters({"leg1.platform_radius": 0.05})
    assert copy.workspace.required == design.workspace.required


@pytest.mark.parametrize(
    ("example", "old", "new", "refused"),
    [
        (
            "hexapod_6ups.toml",
            "rz = [-0.05, 0.05]",
            "rz = [-3.0, 3.0]",
            r"key 'workspace\.required\.rz': rz = \[-3, 3\]: neither end is reachable .*"
            r"in radians: did you mean \[-0\.0523599, 0\.0523599\]\?$",
        ),
        (
            "../src/ppm_stiffness/data/paper_3ppr.toml",
            "phi = [-0.1, 0.1]",
            "phi = [-2.0, 2.0]",
            r"key 'workspace\.required\.phi': phi = \[-2, 2\]: .*did you mean "
            r"\[-0\.0349066, 0\.0349066\]\?$",
        ),
    ],
)
def test_a_required_angle_range_in_degrees_within_pi_is_refused(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    example: str,
    old: str,
    new: str,
    refused: str,
) -> None:
    """rz = [-3, 3] (degrees meant) passes the |angle| <= pi check of the schema: compare
    accepted it (a third of the region covered, rz +-171.9 deg printed). Neither end is
    reachable while both read as degrees are: refused by compare, sweep and the library
    (region_of); the shipped region (both ends reachable) is not. (The 3-RPR reaches
    phi = +-2 rad: a wide range that is reachable is no slip.)"""
    from ppm_stiffness.cli import main

    text = (ROOT / "examples" / example).read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / Path(example).name
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    design = pps.load_design(path)
    with pytest.raises(DesignError, match=refused):
        region_of(design)
    for argv in (["compare"], ["sweep", "--vary", "platform.mass=0.5:1:2"]):
        assert main([*argv, "--design", str(path), "--quiet"]) == 2
        out, err = capsys.readouterr()
        assert out == "" and len(err.strip().splitlines()) == 1, err
        assert re.search(refused, err.strip()), err
    assert region_of(pps.load_design(ROOT / "examples" / example)) is not None


def test_a_wide_required_angle_range_that_is_reachable_is_kept(tmp_path: Path) -> None:
    """The 3-RPR reaches phi = +-2 rad (+-114.6 deg) at its home position: such a range
    is a design's, not a slip, and region_of keeps it."""
    text = (ROOT / "examples" / "3rpr.toml").read_text(encoding="utf-8")
    path = tmp_path / "3rpr.toml"
    path.write_text(text.replace("phi = [-0.1, 0.1]", "phi = [-2.0, 2.0]", 1), encoding="utf-8")
    region = region_of(pps.load_design(path))
    assert region.range("rz") == (-2.0, 2.0)
