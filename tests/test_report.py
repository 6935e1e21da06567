"""The HTML report: sections, embedded images, numbers equal to ``analyze --json``,
and a headless-Chromium screenshot that shows a real page.

One report is built per module (small map grid) for a design file and an
off-centre pose, so that the design and pose options are exercised as well.
"""

from __future__ import annotations

import base64
import io
import json
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from helpers import colour_count  # noqa: E402
from ppm_stiffness.analysis import (
    ENVELOPE_KEYS,  # noqa: E402
    analyze_design,  # noqa: E402
    dump_json,  # noqa: E402
)
from ppm_stiffness.cli import main  # noqa: E402
from ppm_stiffness.design import default_design, save_design  # noqa: E402
from ppm_stiffness.leading import leading_keys  # noqa: E402
from ppm_stiffness.visuals.report import DEFAULT_WRENCH, embedded_json  # noqa: E402
from report_cells import check_cells, parse, screenshot  # noqa: E402

POSE_ARGS = ["--x", "3", "--y", "-4", "--phi", "5"]  # mm, mm, deg
POSE = np.array([3e-3, -4e-3, np.radians(5.0)])
SECTIONS = (
    "design",
    "mechanism",
    "stiffness",
    "screw-springs",
    "decoupling",
    "loaded",
    "deflection",
    "maps",
    "dynamics",  # the built-in design has a mass model (visuals/report_dynamics.py)
)
FIGURES = (
    "fig-mechanism",
    "fig-springs",
    "fig-springs-loaded",
    "fig-deflection",
    "fig-map-0-max",
    "fig-map-0-min",
    "fig-map-30-max",
    "fig-map-30-min",
    "fig-modes",
    "fig-f1-map",
)


@pytest.fixture(scope="module")
def design_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The built-in design with a stiffer guide yaw, as a design file."""
    design = default_design().with_parameters({"guide.yaw": 2000.0})
    design = design.model_copy(update={"name": "report test <design> & co"})
    path = tmp_path_factory.mktemp("design") / "design.toml"
    save_design(design, path)
    return path


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory, design_file: Path) -> str:
    out = tmp_path_factory.mktemp("report")
    code = main(
        [
            "report",
            "--design",
            str(design_file),
            *POSE_ARGS,
            "--grid",
            "12",
            "--quiet",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    path = out / "report.html"
    assert path.is_file()
    return path.read_text(encoding="utf-8")


_parse = parse


def test_report_has_every_section_and_figure(report: str) -> None:
    ids = _parse(report).ids
    for sid in SECTIONS + FIGURES + ("analysis-unloaded", "analysis-loaded"):
        assert sid in ids, sid
    # the pose as given (phi is rz of the full pose; main printed z there)
    assert "pose x = 3.000 mm, y = -4.000 mm, φ = 5.000°" in report
    # the design name is escaped, not injected
    assert "report test &lt;design&gt; &amp; co" in report
    assert "<design>" not in report


def test_report_is_self_contained(report: str) -> None:
    """No network access needed: no external script, style, font or image."""
    for pattern in (r'src="(?!data:)', r"<link\b", r"@import", r"url\(", r'href="http'):
        assert re.search(pattern, report) is None, pattern
    assert "<style>" in report


def test_report_images_decode(report: str) -> None:
    images = _parse(report).images
    assert len(images) == len(FIGURES)
    for src in images:
        assert src.startswith("data:image/png;base64,")
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        img = mpimg.imread(io.BytesIO(raw), format="png")
        assert img.shape[0] > 200 and img.shape[1] > 300
        assert np.ptp(img[..., :3]) > 0.5  # a drawing, not a blank canvas


def test_embedded_json_equals_analyze_design(report: str, design_file: Path) -> None:
    """The blocks are analyze_design's output for the same design, pose and wrench."""
    from ppm_stiffness.design import load_design

    design = load_design(design_file)
    for block, wrench in (("analysis-unloaded", None), ("analysis-loaded", DEFAULT_WRENCH)):
        expected = json.loads(dump_json(analyze_design(design, POSE, wrench)))
        expected |= leading_keys(True, None)  # as `analyze --json` adds them
        embedded = embedded_json(report, block)
        assert embedded["command"] == "analyze"
        assert {k: v for k, v in embedded.items() if k not in ENVELOPE_KEYS} == expected


def test_embedded_json_equals_analyze_cli(report: str, design_file: Path, capsys) -> None:
    """... and what ``ppm-stiffness analyze --json`` prints with the same options."""
    for block, extra in (
        ("analysis-unloaded", []),
        ("analysis-loaded", ["--wrench", "5,5,20,0,0,0.1"]),
    ):
        capsys.readouterr()
        assert main(["analyze", "--design", str(design_file), *POSE_ARGS, *extra, "--json"]) == 0
        printed = json.loads(capsys.readouterr().out)
        assert embedded_json(report, block) == printed


def test_table_numbers_match_the_embedded_analysis(report: str) -> None:
    """Every traced number of the page equals its JSON value to its printed precision."""
    blocks = {
        "unloaded": embedded_json(report, "analysis-unloaded"),
        "loaded": embedded_json(report, "analysis-loaded"),
        "modes": embedded_json(report, "analysis-modes"),
    }
    cells = _parse(report).cells
    paths = {c[0] for c in cells}
    # both K matrices in full, all six springs of both, the principal stiffnesses
    for key in ("unloaded", "loaded"):
        assert all(f"{key}/stiffness_matrix/{i}/{j}" in paths for i in range(6) for j in range(6))
        assert all(f"{key}/eigenscrews/{i}/spring_constant" in paths for i in range(6))
        assert f"{key}/principal/rotational/values/2" in paths
    assert all(f"loaded/actuator_forces/{i}" in paths for i in range(3))
    assert len(cells) > 300
    check_cells(cells, blocks)


def test_report_rejects_bad_grid(tmp_path: Path, capsys) -> None:
    assert main(["report", "--grid", "1", "--out", str(tmp_path)]) == 2
    assert "--grid" in capsys.readouterr().err


def test_report_renders_in_headless_chromium(report: str, tmp_path: Path) -> None:
    """Render the page in headless Chromium (Debian's ``chromium``) and check the
    screenshot: the requested size, and a page with content (many colours, not
    mostly blank)."""
    page = tmp_path / "report.html"
    page.write_text(report, encoding="utf-8")
    shot = screenshot(page, tmp_path, height=2000)
    img = mpimg.imread(shot)
    assert img.shape[:2] == (2000, 1280)
    rgb = np.round(img[..., :3] * 255).astype(np.uint8).reshape(-1, 3)
    assert colour_count(rgb) > 50
    # text, tables and the first figure: a good share of pixels is not background
    background = np.all(rgb >= 240, axis=1)
    assert 0.02 < 1.0 - background.mean() < 0.9


def test_report_deflection_loads_match_deflect_defaults() -> None:
    """The report's curves reach the loads ``ppm-stiffness deflect`` uses by default."""
    from ppm_stiffness.cli.deflect import DEFAULT_MAX
    from ppm_stiffness.visuals.report import DEFLECTION_LOADS

    for mode, loads in DEFLECTION_LOADS.items():
        assert loads[0] == 0.0 and loads[-1] == DEFAULT_MAX[mode]
