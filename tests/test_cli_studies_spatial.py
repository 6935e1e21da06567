"""``compare``, ``sweep`` and ``optimize`` on spatial designs: their JSON against the
schemas, the region option over any task coordinates, f1 and the load margin in the
outputs, the errors, and the comparison picture's labels."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main

jsonschema = pytest.importorskip("jsonschema", reason="jsonschema is in the 'test' extra")

ROOT = Path(__file__).parents[1]
SCHEMAS = ROOT / "docs" / "schemas"
PRS, RPS = str(ROOT / "examples/3prs.toml"), str(ROOT / "examples/3rps.toml")
HEXAPOD = str(ROOT / "examples/hexapod_6ups.toml")
#: z [mm], rx, ry [deg] ranges and counts: inside both tripods' regions.
TRIPOD_REGION = "--region=340,360,-5,5,-5,5,2,2,2"
WRENCH = ["--wrench", "10,0,-200,0,0,0"]  # f [N], then m [N·m]


def _json(capsys: pytest.CaptureFixture[str], argv: list[str], schema: str) -> dict:
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    spec = json.loads((SCHEMAS / f"{schema}.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(doc, spec)
    return doc


def test_compare_two_tripods_with_f1_and_the_load_margin(
    capsys: pytest.CaptureFixture[str],
) -> None:
    argv = ["compare", "--json", "--quiet", "--design", PRS, "--design", RPS, TRIPOD_REGION]
    argv += ["--link-modes", "2"]  # the loaded f1 with each leg's first pair (cheap)
    doc = _json(capsys, [*argv, *WRENCH, "--load-margin"], "compare")
    assert doc["region"]["task_coordinates"] == ["z", "rx", "ry"]
    assert doc["region"]["z"] == pytest.approx([0.34, 0.36], rel=1e-15)
    assert doc["region"]["rx"] == pytest.approx([-math.radians(5), math.radians(5)])
    for design in doc["designs"]:
        f = design["figures"]
        assert design["covers"] and design["mass_model"] and design["load_margin_poses"] == 8
        assert f["k_x_min"] is None and f["k_translational_min"] > 0
        assert f["f1_min"] > 0 and f["load_margin"] > 0 and f["max_displacement"] > 0


def test_compare_refuses_designs_of_other_task_coordinates(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["compare", "--quiet", "--design", PRS, "--design", HEXAPOD]) == 2
    err = capsys.readouterr().err
    assert "must share their task coordinates" in err and "(z, rx, ry)" in err


def test_the_region_option_speaks_a_tripods_coordinates(
    capsys: pytest.CaptureFixture[str],
) -> None:
    bad = "--region=340,360,5,-5,-5,5,2,2,2"
    assert main(["compare", "--quiet", "--design", PRS, bad]) == 2
    assert "--region RX0,RX1 = 5,-5 deg: inverted range (RX0 > RX1)" in capsys.readouterr().err
    assert main(["compare", "--quiet", "--design", PRS, "--region=-5,5,-5,5,0,0,3,3"]) == 2
    err = capsys.readouterr().err
    assert "Z0,Z1,RX0,RX1,RY0,RY1,NZ,NRX,NRY" in err


def test_sweep_a_spatial_design_writes_f1(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    table = tmp_path / "sweep.csv"
    argv = ["sweep", "--json", "--quiet", "--design", RPS, TRIPOD_REGION]
    argv += ["--vary", "leg*.cylinder_length=0.2:0.25:2", "--quantity", "f1", "--csv", str(table)]
    argv += ["--link-modes", "0"]
    doc = _json(capsys, argv, "sweep")
    rows = doc["rows"]
    assert [r["leg*.cylinder_length"] for r in rows] == [0.2, 0.25]
    assert rows[1]["f1_min"] > rows[0]["f1_min"] > 0  # a longer cylinder: stiffer legs
    with table.open(encoding="utf-8") as fh:
        header = next(csv.reader(fh))
    assert "k_translational_min" in header and "f1_min" in header and "k_x_min" not in header


def test_optimize_a_hexapod_by_its_first_frequency(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "best.toml"
    region = "--region=0,0,0,0,195,205,0,0,0,0,-2,2,1,1,2,1,1,2"
    argv = ["optimize", "--json", "--quiet", "--design", HEXAPOD, region, "--out", str(out)]
    argv += ["--objective", "first-frequency", "--budget", "10", "--seed", "2"]
    argv += ["--link-modes", "2"]  # each leg's first pair: cheap (2 elements per link)
    argv += ["--vary", "leg*.actuator.locked_stiffness=2e7:2e8"]
    doc = _json(capsys, argv, "optimize")
    assert doc["objective"] == "first-frequency" and doc["objective_unit"] == "Hz"
    assert doc["best_objective"] >= doc["initial_objective"] > 0
    assert doc["best_figures"]["f1_min"] == doc["best_objective"]
    assert doc["region"]["task_coordinates"] == ["x", "y", "z", "rx", "ry", "rz"]
    assert out.exists()


def test_f1_asked_of_a_design_without_a_mass_model_names_the_table(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    text = (ROOT / "examples/3rrr.toml").read_text(encoding="utf-8")
    start = text.index("[platform]")
    end = text.find("\n[", start + 1)
    bare = tmp_path / "bare.toml"
    stripped = text[:start] + (text[end + 1 :] if end >= 0 else "")
    stripped = "\n".join(
        line
        for line in stripped.splitlines()
        if not line.strip().startswith(("mass", "carriage_mass", "inertia_transverse"))
    )
    bare.write_text(stripped, encoding="utf-8")
    argv = ["optimize", "--quiet", "--design", str(bare), "--objective", "first-frequency"]
    argv += ["--vary", "leg*.platform_radius=0.05:0.07", "--out", str(tmp_path / "x.toml")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "has no mass model; add a [platform] table" in err
    assert not (tmp_path / "x.toml").exists()


def test_the_comparison_picture_labels_a_tripods_axes_and_quantities() -> None:
    from ppm_stiffness.cli.study_options import region_box, region_from_text, region_maps
    from ppm_stiffness.design import load_design
    from ppm_stiffness.visuals.comparison import plot_maps_side_by_side

    designs = [load_design(PRS), load_design(RPS)]
    region = region_from_text("340,360,-5,5,-5,5,2,2,2", ("z", "rx", "ry"))
    maps = region_maps(designs, region, grid=6)
    fig = plot_maps_side_by_side(maps, ["prs", "rps"], region_box(region))
    axes = fig.axes
    labels = {(a.get_xlabel(), a.get_ylabel()) for a in axes if a.get_xlabel()}
    assert labels == {("z [mm]", "rx [deg]")}
    titles = [a.get_title() for a in axes if a.get_title()]
    assert any("k_{r,\\min}" in t for t in titles) and any("k_{t,\\min}" in t for t in titles)
    assert not any("k_x" in t or "k_\\phi" in t for t in titles)
    assert "ry = 0°" in fig.get_suptitle()
    patch = axes[0].patches[0]  # the region's box in the panel's units
    assert patch.get_x() == pytest.approx(340.0) and patch.get_width() == pytest.approx(20.0)
    assert patch.get_y() == pytest.approx(-5.0) and np.isclose(patch.get_height(), 10.0)
