"""The hinges' range over the workspace: the ``hinge_range`` map quantity and the
``range>=`` / ``stress<=`` optimisation constraints (issue 29 item 3).

Model: src/ppm_stiffness/statics/hinge_stress.py (``drive_range``, ``stroke_stress``);
docs/flexures.md, "Range over the workspace".
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import Design, load_design
from ppm_stiffness.statics.hinge_stress import hinge_model, hinge_summary, stroke_stress

ROOT = Path(__file__).resolve().parents[1]
STAGE = ROOT / "examples" / "flexure_3rrr.toml"
PLAIN = ROOT / "examples" / "3prr.toml"


@pytest.fixture(scope="module")
def stage() -> Design:
    return load_design(STAGE)


def summary_drive_range(design: Design, pose: np.ndarray) -> float:
    """The smallest of hinge_summary's "drive i" ranges at a pose (as analyze prints)."""
    rows = hinge_summary(design, pose)["directions"]
    return min(r["range"] for r in rows if r["name"].startswith("drive "))


def test_the_map_quantity_is_analyzes_range_at_each_pose(stage: Design) -> None:
    """At every reachable grid pose, hinge_range equals the smallest drive range that
    hinge_summary (analyze's table) gives at that pose."""
    from ppm_stiffness.maps.workspace import stiffness_map

    smap = stiffness_map(stage, axes=("x", "rz"), grid=3, quantities=["hinge_range"])
    q = smap.quantities["hinge_range"]
    assert np.count_nonzero(~np.ma.getmaskarray(q)) >= 3
    for j, i in zip(*np.nonzero(~np.ma.getmaskarray(q)), strict=True):
        pose = np.array([smap.u[i], 0.0, smap.v[j]])  # task (x, y, rz), y fixed at 0
        expected = summary_drive_range(stage, pose)
        assert q[j, i] == pytest.approx(expected, rel=1e-12)
        assert 0.0 < expected < np.inf


def test_the_constraint_figures_are_the_extremes_over_the_region(stage: Design) -> None:
    """range = min over the region's poses of the drive range (brute force with
    hinge_summary); stress = max over the poses of the largest hinge stress with the
    drives anywhere in their strokes (brute force over a 5^3 grid of inputs in the box,
    which holds its corners: the stress is convex in the inputs)."""
    from ppm_stiffness.optimize.objectives import parse_constraint
    from ppm_stiffness.optimize.region import region_poses
    from ppm_stiffness.optimize.summary import summarize

    region = stage.workspace.required.model_copy(update={"grid": [2, 1, 2]})
    poses = region_poses(region).reshape(-1, 3)
    summary = summarize(stage, region, frequencies=False, hinges=True)
    assert summary.covered == poses.shape[0] == 4
    ranges = [summary_drive_range(stage, p) for p in poses]
    rng = parse_constraint("range>=0.01").quantity.value(summary)
    assert rng == pytest.approx(min(ranges), rel=1e-12)
    lo, hi = -0.00075, 0.00075  # the stage's strokes [rad]
    box = np.array(list(itertools.product(np.linspace(lo, hi, 5), repeat=3)))
    brute = max(float(np.max(hinge_model(stage, p).stresses(np.zeros(6), box))) for p in poses)
    stress = parse_constraint("stress<=1e8").quantity.value(summary)
    assert stress == pytest.approx(brute, rel=1e-12)
    assert stroke_stress(stage, poses[0]) <= stress
    # the full stroke of one drive alone stresses the hinges by 0.75e-3 / its range
    yield_strength = 503e6
    assert stress >= yield_strength * 0.00075 / max(ranges) * (1 - 1e-12)
    # the constraint's shortfall is measured against the figure
    c = parse_constraint(f"stress<={stress / 2!r}")
    assert c.shortfall(summary) == pytest.approx(1.0, rel=1e-12)
    assert parse_constraint(f"range>={rng / 2!r}").shortfall(summary) == 0.0


def test_without_hinges_the_figures_are_refused(stage: Design, tmp_path: Path) -> None:
    """A design without notch hinges, or whose hinges have no yield strength: the map
    quantity and the constraints are refused naming what is missing."""
    from ppm_stiffness.maps.map_chunks import quantity_names
    from ppm_stiffness.optimize.objectives import check_quantities, parse_constraint

    plain = load_design(PLAIN)
    with pytest.raises(DesignError, match="has no notch hinge"):
        quantity_names(plain, ["hinge_range"])
    for text in ("range>=0.01", "stress<=1e8"):
        with pytest.raises(DesignError, match=r"(range|stress): .* has no notch hinge"):
            check_quantities(plain, [parse_constraint(text).quantity], wrench=False)
    path = tmp_path / "no_yield.toml"
    path.write_text(
        STAGE.read_text(encoding="utf-8").replace(", yield_strength = 5.03e+08", ""),
        encoding="utf-8",
    )
    no_yield = load_design(path)
    with pytest.raises(DesignError, match="no yield_strength"):
        quantity_names(no_yield, ["hinge_range"])
    with pytest.raises(DesignError, match="range: .*no yield_strength"):
        check_quantities(no_yield, [parse_constraint("range>=0.01").quantity], wrench=False)


@pytest.mark.parametrize(
    "argv",
    [
        ["map", "--design", str(PLAIN), "--quantities", "hinge_range", "--out", "m.png"],
        ["optimize", "--design", str(PLAIN), "--vary", "platform.mass=0.5:1"]
        + ["--constraint", "range>=0.01", "--out", "best.toml"],
    ],
)
def test_the_cli_refuses_hinge_figures_without_hinges(
    argv: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from ppm_stiffness.cli import main

    out = tmp_path / argv[-1]
    assert main([*argv[:-1], str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "has no notch hinge" in err
    assert len(err.splitlines()) == 1
    assert not out.exists()


def test_the_map_command_writes_hinge_range(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`map --quantities hinge_range --json` on the stage: a document its schema
    accepts, the quantity's unit and its extremes those of the library's map."""
    import json

    jsonschema = pytest.importorskip("jsonschema")
    from ppm_stiffness.cli import main
    from ppm_stiffness.maps.workspace import stiffness_map

    argv = ["map", "--design", str(STAGE), "--quantities", "hinge_range", "--grid", "3"]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    schema = json.loads((ROOT / "docs" / "schemas" / "map.schema.json").read_text("utf-8"))
    jsonschema.validate(doc, schema)
    assert doc["quantities"] == {"hinge_range": "rad"}  # the stage's drives are rotary
    smap = stiffness_map(
        load_design(STAGE), grid=3, quantities=["hinge_range"], phi=0.0, axes=("x", "y")
    )
    q = smap.quantities["hinge_range"]
    assert doc["summary"]["hinge_range"]["min"] == pytest.approx(float(q.min()), rel=1e-12)
    assert doc["summary"]["hinge_range"]["max"] == pytest.approx(float(q.max()), rel=1e-12)


def test_the_hinge_range_maps_unit_and_subtitle(tmp_path: Path) -> None:
    """The stage's hinge_range map carries its drives' unit (rad: revolute drives; the
    colour bar in mrad, the CSV column hinge_range_rad) and says what it shows: each
    drive alone until a hinge yields, not "actuators locked"; a linear drive's is m."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ppm_stiffness.maps.result import load_npz
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.visuals.maps import HINGE_RANGE_TEXT, plot_stiffness_maps

    smap = stiffness_map(
        load_design(STAGE), grid=3, quantities=["hinge_range"], phi=0.0, axes=("x", "y")
    )
    assert smap.unit("hinge_range") == "rad"
    fig = plot_stiffness_maps(smap)
    labels = [a.get_ylabel() for a in fig.axes]
    assert any("[mrad]" in label for label in labels), labels
    texts = [t.get_text() for f in (fig, *fig.subfigs) for t in f.texts]
    assert any(HINGE_RANGE_TEXT in t for t in texts) and not any("locked" in t for t in texts)
    plt.close(fig)
    smap.to_csv(tmp_path / "m.csv")
    assert "hinge_range_rad" in (tmp_path / "m.csv").read_text(encoding="utf-8")
    smap.to_npz(tmp_path / "m.npz")
    assert load_npz(tmp_path / "m.npz").unit("hinge_range") == "rad"
    from dataclasses import replace

    assert replace(smap, drive_unit="m").unit("hinge_range") == "m"


def test_compare_gives_the_stages_hinge_figures(capsys: pytest.CaptureFixture[str]) -> None:
    """`compare --json` of the stage carries its hinge range and stress (numbers, not
    null): the smallest drive range and the largest stroke stress over its required
    region's poses (pose by pose, the library's), the range in rad (its drives')."""
    import json

    from ppm_stiffness.cli import main
    from ppm_stiffness.optimize.region import region_poses
    from ppm_stiffness.statics.hinge_stress import drive_range, stroke_stress

    assert main(["compare", "--design", str(STAGE), "--json", "--quiet", "--no-f1"]) == 0
    doc = json.loads(capsys.readouterr().out)
    figures = doc["designs"][0]["figures"]
    design = load_design(STAGE)
    region = design.workspace.required
    assert region is not None
    poses = region_poses(region).reshape(-1, 3)
    ranges = [drive_range(design, p) for p in poses]
    stresses = [stroke_stress(design, p) for p in poses]
    assert figures["hinge_range_min"] == pytest.approx(min(ranges), rel=1e-12)
    assert figures["hinge_stress_max"] == pytest.approx(max(stresses), rel=1e-12)
    assert doc["units"]["figures.hinge_range_min"] == "rad"
