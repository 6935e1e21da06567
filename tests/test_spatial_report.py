"""The report of each spatial example (6-UPS hexapod, 3-PRS, 3-RPS): the sections that
make sense for a spatial design, its embedded analyses equal to ``analyze_design``, its
numbers equal to the library's to their printed digits, a real page in Chromium.

The 3-PRS report is written by the CLI at a tilted pose given in mm and deg (its tool
point is 150 mm below P: K, its springs, the loaded case and the deflection refer to
it); the other two are built at their home poses by :func:`build_report`.
"""

from __future__ import annotations

import base64
import io
import json
import math
import re
from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from helpers import (  # noqa: E402
    ROOT,
    colour_count,
    design_named,
    example_designs,
    half_unit,
    is_spatial,
)
from ppm_stiffness.analysis import ENVELOPE_KEYS, analyze_design, dump_json  # noqa: E402
from ppm_stiffness.cli import main  # noqa: E402
from ppm_stiffness.core.principal import principal_compliance  # noqa: E402
from ppm_stiffness.leading import leading_keys  # noqa: E402
from ppm_stiffness.maps.slices import map_slice  # noqa: E402
from ppm_stiffness.model import (  # noqa: E402
    stiffness_at_pose,
    stiffness_at_tool_point,
    tool_offset,
)
from ppm_stiffness.poses import full_pose, home_pose  # noqa: E402
from ppm_stiffness.statics.deflection import deflection_path  # noqa: E402
from ppm_stiffness.visuals.report import embedded_json  # noqa: E402
from ppm_stiffness.visuals.report_spatial import DEFLECTION_SCALES  # noqa: E402
from ppm_stiffness.visuals.report_wrench import reference_wrench  # noqa: E402
from report_cells import check_cells, parse, screenshot  # noqa: E402

SPATIAL = tuple(example_designs(is_spatial))
PRS_OPTIONS = ["--z", "420", "--rx", "8", "--ry", "-5"]
PRS_TASK = np.array([0.42, math.radians(8.0), math.radians(-5.0)])
SECTIONS = (
    "design",
    "mechanism",
    "stiffness",
    "screw-springs",
    "principal",
    "decoupling",
    "loaded",
    "deflection",
)
FIGURES = (
    "fig-mechanism",
    "fig-springs",  # K under the wrench is the unloaded K (linear actuators): once
    "fig-deflection",
    "fig-modes",  # every spatial example has a mass model (visuals/report_dynamics.py)
    "fig-f1-map",
)


def _pose(name: str) -> np.ndarray:
    design = design_named(name)
    return full_pose(design, PRS_TASK) if name == "3prs" else home_pose(design)


def _reference(name: str) -> np.ndarray:
    """The report's loaded case of an example: the paper's load scaled to it."""
    design, pose = design_named(name), _pose(name)
    k = analyze_design(design, pose).stiffness_matrix
    return reference_wrench(design, pose, k).wrench


class _Pages(dict[str, str]):
    """Each example's report page, built when a test first asks for it (a worker of
    ``pytest -n`` builds only the pages of the tests it runs)."""

    def __init__(self, where: Callable[[], Path], example_report: Callable[[str], str]) -> None:
        super().__init__()
        self.where, self.example_report = where, example_report

    def __missing__(self, name: str) -> str:
        if name == "3prs":
            where = self.where()
            design_file = ROOT / "examples" / "3prs.toml"
            argv = ["report", "--design", str(design_file), *PRS_OPTIONS, "--quiet", "--grid", "6"]
            assert main([*argv, "--out", str(where)]) == 0
            page = (where / "report.html").read_text(encoding="utf-8")
        else:
            page = self.example_report(name)  # build_report, small maps: fast
        self[name] = page
        return page


@pytest.fixture(scope="module")
def pages(
    tmp_path_factory: pytest.TempPathFactory, example_report: Callable[[str], str]
) -> dict[str, str]:
    return _Pages(lambda: tmp_path_factory.mktemp("report"), example_report)


@pytest.mark.parametrize("name", SPATIAL)
def test_sections_figures_and_maps(pages: dict[str, str], name: str) -> None:
    """The spatial sections and figures are there, each image a drawing; the maps of the
    spatial principal stiffnesses over the default slice (the design's first two task
    coordinates, x-y for the hexapod), locked and at the minimum actuator stiffness; none
    of the paper's planar k_phi, k_x, k_y."""
    page = pages[name]
    cells = parse(page)
    axes = "-".join(map_slice(design_named(name)).axes)  # x-y, or the first two
    maps = (f"fig-map-{axes}-max",)  # linear actuator laws: min = max, one map and a note
    for sid in (
        SECTIONS
        + FIGURES
        + maps
        + ("maps", "maps-once", "springs-loaded-same")
        + (
            "analysis-unloaded",
            "analysis-loaded",
        )
    ):
        assert sid in cells.ids, sid
    assert "k<sub>φ</sub>" not in page
    assert len(cells.images) == len(FIGURES) + len(maps)
    for src in cells.images:
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        img = mpimg.imread(io.BytesIO(raw), format="png")
        assert img.shape[0] > 300 and img.shape[1] > (400 if src == cells.images[-1] else 700)
        assert colour_count(img) > 100  # the last image: the f1 map, one panel


@pytest.mark.parametrize("name", SPATIAL)
def test_embedded_analyses_are_analyze_design(pages: dict[str, str], name: str) -> None:
    """Both blocks are analyze_design's output at the pose, unloaded and under the
    design's reference wrench (at the tool point; the paper's load scaled to it)."""
    design = design_named(name)
    pose = _pose(name)
    reference = _reference(name)
    for block, wrench in (("analysis-unloaded", None), ("analysis-loaded", reference)):
        # as `analyze --json` prints it: the least-squares shift first, the keys added
        expected = json.loads(dump_json(analyze_design(design, pose, wrench, "least-squares")))
        expected |= leading_keys(False, None)
        embedded = embedded_json(pages[name], block)
        assert {k: v for k, v in embedded.items() if k not in ENVELOPE_KEYS} == expected


@pytest.mark.parametrize("name", SPATIAL)
def test_every_number_is_the_analysis(pages: dict[str, str], name: str) -> None:
    """Every traced number equals its JSON value to its printed digits; the pose table,
    K, all springs, the spatial principal stiffnesses and the loaded twist are among
    them."""
    page = pages[name]
    blocks = {
        "unloaded": embedded_json(page, "analysis-unloaded"),
        "loaded": embedded_json(page, "analysis-loaded"),
        "modes": embedded_json(page, "analysis-modes"),
    }
    if 'id="analysis-hinges"' in page:  # a design with notch hinges
        blocks["hinges"] = embedded_json(page, "analysis-hinges")
    cells = parse(page).cells
    paths = {c[0] for c in cells}
    for key in ("unloaded", "loaded"):
        assert all(f"{key}/stiffness_matrix/{i}/{j}" in paths for i in range(6) for j in range(6))
        assert all(f"{key}/eigenscrews/{i}/spring_constant" in paths for i in range(6))
        assert f"{key}/principal_compliance/worst_translational" in paths
    assert all(f"unloaded/pose/{c}" in paths for c in ("x", "y", "z", "rx", "ry", "rz"))
    assert all(f"unloaded/principal_compliance/rotational/values/{j}" in paths for j in range(3))
    assert all(f"loaded/twist/{j}" in paths for j in range(6))
    check_cells(cells, blocks)


def _printed(page: str, path: str) -> tuple[float, str]:
    found = re.search(rf'data-path="{re.escape(path)}" data-scale="([^"]+)">([^<]+)<', page)
    assert found is not None, path
    return float(found.group(1)), found.group(2)


@pytest.mark.parametrize("name", SPATIAL)
def test_principal_stiffnesses_are_the_library_s(pages: dict[str, str], name: str) -> None:
    """The printed spatial principal stiffnesses equal core.principal's of K at the tool
    point (computed here from the model, not from the page's JSON), to their digits."""
    design = design_named(name)
    pose = _pose(name)
    k = stiffness_at_tool_point(stiffness_at_pose(design, pose), pose, design.tool_point)
    pc = principal_compliance(k)
    base = "unloaded/principal_compliance"
    expected = {
        f"{base}/worst_rotational": pc.worst_rotational,
        f"{base}/worst_translational": pc.worst_translational,
        **{f"{base}/rotational/values/{j}": pc.rotational_values[j] for j in range(3)},
        **{f"{base}/translational/values/{j}": pc.translational_values[j] for j in range(3)},
    }
    for path, value in expected.items():
        scale, text = _printed(pages[name], path)
        assert abs(float(text) - value * scale) <= half_unit(text) * (1 + 1e-9), (path, text)


def test_pose_table_names_task_and_parasitic_coordinates(pages: dict[str, str]) -> None:
    """The 3-PRS at z = 420 mm, rx = 8, ry = -5 deg: z, rx, ry are task coordinates
    printed as given; x, y, rz are parasitic and printed as the completed pose's."""
    page = pages["3prs"]
    table = re.search(r"<caption>The pose of P.*?</table>", page, re.S)
    assert table is not None
    rows = re.findall(
        r"<tr><td>(\w+)</td>(<td[^>]*>[^<]*</td>)<td>(\w+)</td><td>([^<]*)</td>", table.group(0)
    )
    kinds = {name: kind for name, _, _, kind in rows}
    assert kinds == {
        "x": "parasitic (imposed by the legs)",
        "y": "parasitic (imposed by the legs)",
        "z": "task",
        "rx": "task",
        "ry": "task",
        "rz": "parasitic (imposed by the legs)",
    }
    pose = _pose("3prs")
    for i, name in enumerate(("x", "y", "z", "rx", "ry", "rz")):
        scale, text = _printed(page, f"unloaded/pose/{name}")
        assert scale == (180 / math.pi if name.startswith("r") else 1e3)
        assert abs(float(text) - pose[i] * scale) <= half_unit(text) * (1 + 1e-9)
    assert abs(float(_printed(page, "unloaded/pose/z")[1]) - 420.0) < 1e-9
    assert abs(float(_printed(page, "unloaded/pose/x")[1])) > 0.1  # parasitic x is ~0.9 mm


def test_mechanism_captions_name_what_each_design_has(pages: dict[str, str]) -> None:
    """The 3-D view's caption names the joints, rails and tool point a design has and
    nothing else: U for the hexapod, rails and a tool point for the 3-PRS."""
    captions = {
        name: re.search(r'id="fig-mechanism".*?<figcaption>(.*?)</figcaption>', pages[name], re.S)
        for name in ("hexapod_6ups", "3prs", "3rps")
    }
    text = {name: m.group(1) for name, m in captions.items() if m is not None}
    assert "universal joints U: a cross" in text["hexapod_6ups"]
    assert "rail" not in text["hexapod_6ups"]
    assert "tool point" not in text["hexapod_6ups"]
    assert "rail over the actuator stroke" in text["3prs"] and "tool point T" in text["3prs"]
    assert "revolute joints R: a circle" in text["3rps"]
    assert "universal" not in text["3rps"]
    assert "its point P" in text["3rps"] and "prismatic joints (type letter P)" in text["3rps"]


def test_repeated_springs_are_named(pages: dict[str, str]) -> None:
    """The hexapod at its 3-fold symmetric home pose has repeated eigenvalues: the note
    names the groups of analyze's eigenscrews_repeated."""
    page = pages["hexapod_6ups"]
    groups = embedded_json(page, "analysis-unloaded")["eigenscrews_repeated"]
    assert groups
    names = "; ".join(", ".join(f"s{i + 1}" for i in g) for g in groups)
    assert f"Repeated eigenvalues ({names})" in page


def test_deflection_follows_the_loaded_wrench() -> None:
    """The spatial deflection curve is the load path along the loaded case's wrench: at
    its full scale (1) it reaches the loaded analysis's tool-point twist (the
    equilibrium, an independent solution) to 1e-6 of its size."""
    design = design_named("3prs")
    pose = _pose("3prs")
    wrench = _reference("3prs")
    curve = deflection_path(design, wrench, DEFLECTION_SCALES, pose, method="integrate")
    twist = np.asarray(analyze_design(design, pose, wrench).to_dict()["twist"])
    assert DEFLECTION_SCALES[0] == 0.0 and DEFLECTION_SCALES[-1] == 1.0
    np.testing.assert_allclose(curve.twists[-1], twist, rtol=0, atol=1e-6 * np.max(np.abs(twist)))


def test_tolerance_bands_of_a_spatial_design(tmp_path: Path) -> None:
    """``report --tolerances`` on a spatial design: the section's nominal principal
    stiffnesses are the spatial ones of the pose (k_rot_1..3, k_trans_1..3 ascending, as
    principal_compliance gives them, to the 5 printed digits), each band contains its
    nominal, and the tolerance of a leg's actuator stiffness widens the axial (largest)
    translational stiffness."""
    from ppm_stiffness.fit.tolerances import parse_tolerances, tolerance_variables
    from ppm_stiffness.visuals.html import format_number
    from ppm_stiffness.visuals.uncertainty_report import uncertainty_section

    design = design_named("3rps")
    pose = _pose("3rps")
    entries = parse_tolerances('["leg*.actuator.locked_stiffness"]\npm = "10%"\n')
    variables = tolerance_variables(design, entries)
    _, _, page = uncertainty_section(design, variables, pose, grid=4)
    pc = principal_compliance(stiffness_at_pose(design, pose))
    nominal = [*sorted(pc.rotational_values), *sorted(pc.translational_values)]
    rows = re.findall(r"<tr><td>(k_(?:rot|trans)_\d)</td>(.*?)</tr>", page)
    assert [name for name, _ in rows] == [
        *(f"k_rot_{j}" for j in (1, 2, 3)),
        *(f"k_trans_{j}" for j in (1, 2, 3)),
    ]
    for (_, cells), value in zip(rows, nominal, strict=True):
        nom, low, up = (float(c) for c in re.findall(r"<td>([^<]+)</td>", cells)[:3])
        assert nom == float(format_number(value))
        assert low <= nom <= up
    low, up = (float(c) for c in re.findall(r"<td>([^<]+)</td>", rows[5][1])[1:3])
    assert up - low > 0.01 * nominal[5]


def test_spatial_report_renders_in_headless_chromium(pages: dict[str, str], tmp_path: Path) -> None:
    """The hexapod's page in headless Chromium: the requested size, many colours, a
    sensible share of non-background pixels."""
    page = tmp_path / "report.html"
    page.write_text(pages["hexapod_6ups"], encoding="utf-8")
    img = mpimg.imread(screenshot(page, tmp_path, height=2400))
    assert img.shape[:2] == (2400, 1280)
    rgb = np.round(img[..., :3] * 255).astype(np.uint8).reshape(-1, 3)
    assert colour_count(rgb) > 50
    background = np.all(rgb >= 240, axis=1)
    assert 0.02 < 1.0 - background.mean() < 0.9


def _leg_row(page: str, key: str) -> tuple[list[str], str]:
    """The per-leg texts and the unit of one row of the leg-parameter table."""
    row = re.search(
        rf"<tr><td>{re.escape(key)}</td>((?:<td class=\"num\">[^<]*</td>)+)<td>([^<]*)</td></tr>",
        page,
    )
    assert row is not None, key
    return re.findall(r'<td class="num">([^<]*)</td>', row.group(1)), row.group(2)


def test_design_parameters_in_display_units(pages: dict[str, str]) -> None:
    """The hexapod's leg fields and joint parts, one column per leg, in display units:
    points in mm (each component of the design's, to its 6 printed digits), joint
    angle limits in deg, spring constants in N/m and N·m/rad, directions unitless; the
    required region over the six task coordinates in mm and deg."""
    page = pages["hexapod_6ups"]
    design = design_named("hexapod_6ups")
    texts, unit = _leg_row(page, "base_point")
    assert unit == "mm" and len(texts) == 6
    for text, leg in zip(texts, design.legs, strict=True):
        shown = [float(v) for v in text.strip("()").split(",")]
        for v, si in zip(shown, leg.base_point, strict=True):
            assert abs(v - si * 1e3) <= 5e-6 * max(abs(si * 1e3), 1e-300) or v == si == 0
    texts, unit = _leg_row(page, "base_joint.max_angle")
    assert unit == "deg" and all(abs(float(t) - 30.0) < 5e-5 for t in texts)
    assert _leg_row(page, "base_joint.torsion")[1] == "N·m/rad"
    assert _leg_row(page, "platform_joint.radial")[1] == "N/m"
    assert _leg_row(page, "platform_joint_axis")[1] == "–"
    for coord, unit in (("x", "mm"), ("z", "mm"), ("rx", "deg"), ("rz", "deg")):
        cells = rf'<td class="num">\([^<]+\)</td><td>{unit}</td>'
        assert re.search(rf"<td>workspace\.required\.{coord}</td>{cells}", page), coord


@pytest.mark.parametrize("name", SPATIAL)
def test_a_stage_with_hinges_reports_their_stress_and_range(
    pages: dict[str, str], name: str
) -> None:
    """A design with notch hinges (the 3-RRR stage) has the "Notch hinges" section:
    its embedded figures are hinge_summary's under the loaded case's wrench (at P, SF 1),
    every range and stress printed from them; a design without hinges has none."""
    from ppm_stiffness.statics.hinge_stress import has_hinges, hinge_summary

    page, design = pages[name], design_named(name)
    if not has_hinges(design):
        assert 'id="analysis-hinges"' not in page and 'id="hinges"' not in page
        return
    embedded = embedded_json(page, "analysis-hinges")
    pose = _pose(name)
    ref = _reference(name)
    offset = tool_offset(pose, np.asarray(design.tool_point, dtype=float))
    at_p = np.concatenate([ref[:3] + np.cross(offset, ref[3:]), ref[3:]])
    expected = json.loads(dump_json(hinge_summary(design, pose, at_p, 1.0)))
    assert embedded == expected
    paths = {c[0] for c in parse(page).cells}
    n = len(expected["hinges"])
    assert all(f"hinges/hinges/{j}/stress" in paths for j in range(n))
    assert all(f"hinges/directions/{j}/range" in paths for j in range(len(expected["directions"])))
