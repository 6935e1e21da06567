"""The facts behind the spatial report's pictures and tables (issue 27, item 9): the
reference wrench scaled to the design, identical panels shown once, the springs'
frame labelled, 3-D labels apart, the modes' shares and distinct names, the design
file embedded as written, the CLI's units, colour bars without an offset text and a
note on a small variation.

One report (the 3-PRS, written by the CLI on a 4 x 4 map grid) serves the page tests;
the pictures' facts are checked on the figures themselves."""

from __future__ import annotations

import html
import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from helpers import ROOT, design_named, example_designs, is_spatial  # noqa: E402
from ppm_stiffness.analysis import analyze_design  # noqa: E402
from ppm_stiffness.cli import main  # noqa: E402
from ppm_stiffness.core.errors import DesignError  # noqa: E402
from ppm_stiffness.design import default_design, load_design  # noqa: E402
from ppm_stiffness.poses import full_pose, home_pose  # noqa: E402
from ppm_stiffness.visuals.report import embedded_json  # noqa: E402
from ppm_stiffness.visuals.report_wrench import (  # noqa: E402
    PAPER_WRENCH,
    REFERENCE_DEFLECTION,
    design_size,
    reference_wrench,
)

SPATIAL = tuple(example_designs(is_spatial))
PRS_FILE = ROOT / "examples" / "3prs.toml"


@pytest.fixture(scope="module")
def page(tmp_path_factory: pytest.TempPathFactory) -> str:
    out = tmp_path_factory.mktemp("report")
    argv = ["report", "--design", str(PRS_FILE), "--grid", "4", "--quiet", "--out", str(out)]
    assert main(argv) == 0
    return (out / "report.html").read_text(encoding="utf-8")


def _stiffness(design: object, pose: np.ndarray) -> np.ndarray:
    """The unloaded K at the tool point, as the report has it."""
    return np.asarray(analyze_design(design, pose).stiffness_matrix)


def _k(name: str) -> tuple[object, np.ndarray, np.ndarray]:
    design = design_named(name)
    pose = home_pose(design)
    return design, pose, _stiffness(design, pose)


# ------------------------------------------------------------------ reference wrench
@pytest.mark.parametrize("name", SPATIAL)
def test_reference_wrench_deflects_by_its_share_of_the_size(name: str) -> None:
    """Before: the paper's 21 N load (0.00127 mm on the hexapod). Now the paper's load
    times s, the tool point moving by 1e-4 of the design's size (s to 2 digits: within
    5 %)."""
    design, pose, k = _k(name)
    ref = reference_wrench(design, pose, k)
    assert ref.source == "scaled"
    np.testing.assert_allclose(ref.wrench, ref.scale * PAPER_WRENCH, rtol=1e-15)
    moved = np.linalg.norm(np.linalg.solve(k, ref.wrench)[3:])
    assert moved / (REFERENCE_DEFLECTION * ref.size) == pytest.approx(1.0, abs=0.05)
    if name == "hexapod_6ups":  # the paper's 21 N moved it by 0.00127 mm
        assert ref.scale > 10
    assert f"× {ref.scale:g}" in ref.text and "mm" in ref.text and "µm" not in ref.text


def test_reference_wrench_scales_with_the_design() -> None:
    """Twice as stiff: twice the load (to the two digits of s); the size is the
    largest distance between two joints (the hexapod's legs' joints are 0.1-0.2 m
    apart: L between the platform's and the base's diameters)."""
    design, pose, k = _k("hexapod_6ups")
    one, two = reference_wrench(design, pose, k), reference_wrench(design, pose, 2 * k)
    assert two.scale / one.scale == pytest.approx(2.0, rel=0.05)
    size = design_size(design, pose)
    base = np.array([leg.base_point for leg in design.legs], dtype=float)
    assert size >= np.max(np.linalg.norm(base[:, None] - base[None], axis=2)) - 1e-12


def test_reference_wrench_from_the_design_file_and_the_paper(tmp_path: Path) -> None:
    text = PRS_FILE.read_text(encoding="utf-8").replace(
        "[workspace]\n",
        "[reference_wrench]\nforce = [0, 0, -800]\nmoment = [1, 0, 0]\n\n[workspace]\n",
        1,
    )
    path = tmp_path / "loaded.toml"
    path.write_text(text, encoding="utf-8")
    design = load_design(path)
    pose = home_pose(design)
    ref = reference_wrench(design, pose, _stiffness(design, pose))
    assert ref.source == "design file"
    np.testing.assert_array_equal(ref.wrench, [1, 0, 0, 0, 0, -800])
    given = np.array([0, 0, 0, 1.0, 2.0, 3.0])
    assert reference_wrench(design, pose, np.eye(6), given).source == "option"
    paper = default_design()
    p0 = home_pose(paper)
    ref0 = reference_wrench(paper, p0, _stiffness(paper, p0))
    assert ref0.source == "paper"
    np.testing.assert_array_equal(ref0.wrench, PAPER_WRENCH)
    bad = text.replace("force = [0, 0, -800]\nmoment = [1, 0, 0]", "force = [0, 0, 0]")
    path.write_text(bad, encoding="utf-8")
    with pytest.raises(DesignError, match="reference_wrench.*both zero"):
        load_design(path)


def test_page_states_and_uses_the_reference_wrench(page: str) -> None:
    design = design_named("3prs")
    pose = home_pose(design)
    ref = reference_wrench(design, pose, _stiffness(design, pose))
    np.testing.assert_allclose(embedded_json(page, "analysis-loaded")["wrench"], ref.wrench)
    stated = re.search(r'id="reference-wrench">(.*?)</p>', page)
    assert stated is not None and "scaled to the design" in stated.group(1)
    assert "0.01 % of the design" in stated.group(1)


# ------------------------------------------------------------------ identical panels
def test_identical_panels_are_shown_once(page: str) -> None:
    """Linear actuators (q = 1): min = max actuator stiffness, and K under the wrench
    is the unloaded K; before, both pairs of pictures were drawn, identical."""
    from ppm_stiffness.visuals.report import actuators_differ, same_stiffness

    unloaded = embedded_json(page, "analysis-unloaded")
    loaded = embedded_json(page, "analysis-loaded")
    k0 = np.asarray(unloaded["stiffness_matrix"])
    assert np.max(np.abs(np.asarray(loaded["stiffness_matrix"]) - k0)) <= 1e-12 * np.max(abs(k0))
    assert same_stiffness(unloaded, loaded)
    assert not actuators_differ(design_named("3prs"))
    assert actuators_differ(default_design())  # the paper's law: two states
    assert 'id="fig-map-z-rx-max"' in page and 'id="fig-map-z-rx-min"' not in page
    assert 'id="maps-once"' in page and 'id="springs-loaded-same"' in page
    assert 'id="fig-springs-loaded"' not in page


# ------------------------------------------------------------------ design file, units
def test_design_file_is_embedded_as_written(page: str) -> None:
    """Before: a re-serialisation (comments, task_coordinates and [workspace] rx, ry
    gone)."""
    block = re.search(r'<pre id="design-file">(.*?)</pre>', page, re.S)
    assert block is not None
    assert html.unescape(block.group(1)) == PRS_FILE.read_bytes().decode("utf-8")
    assert f"Design file {PRS_FILE} as written" in page


def test_units_are_the_cli_units(page: str) -> None:
    """deg and mm as the CLI prints them; no "SI" unit; powers as superscripts (in
    what the page shows: the embedded JSON keeps its SI unit strings)."""
    page = re.sub(r"<script.*?</script>", "", page, flags=re.S)
    page = re.sub(r'src="data:[^"]*"', "", page)  # the pictures' base64
    for wrong in ("µrad", "[µm]", "<td>SI</td>", "[SI]", "kg·m^2", "m^2", "m^4", "N/mq"):
        assert wrong not in page, wrong
    assert "φ<sub>x</sub> [deg]" in page and "x [mm]" in page
    assert "displacement δ [mm]" in page
    assert "<td>N/m^q</td>" in page  # k_a's unit: a power that is not 2, 3 or 4


# ------------------------------------------------------------------ pictures
def test_springs_picture_names_its_frame() -> None:
    """Drawn relative to the point of K (T here), its axes those of F_b: the labels
    say so (before: "x [mm]", read as F_b's x)."""
    from ppm_stiffness.core.eigenscrews import eigenscrews
    from ppm_stiffness.visuals.springs import plot_screw_springs

    design, pose, k = _k("3prs")
    fig = plot_screw_springs(eigenscrews(k), design, pose, tool_point=design.tool_point)
    ax = fig.axes[0]
    for name, label in zip("xyz", (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()), strict=True):
        assert label == f"{name} − {name}$_T$ [mm]"
    assert "drawn relative to T (tool point) with the axes of F_b" in ax.get_title()


@pytest.mark.parametrize("name", SPATIAL)
def test_mechanism_labels_do_not_overlap(name: str) -> None:
    """No two labels' boxes on screen overlap, nor a label another point's marker
    (before: hexapod "leg 1"/"A1", "leg 3"/"A3"; 3-PRS "B1"/"y_p"); "P" is the
    platform point only (the prismatic joint's legend names its type letter)."""
    from ppm_stiffness.visuals.leg_geometry import mechanism_view
    from ppm_stiffness.visuals.mechanism3d import (
        POINT_LEGEND,
        _anchor,
        label_boxes,
        marker_boxes,
        plot_mechanism_3d,
    )

    design = design_named(name)
    fig = plot_mechanism_3d(mechanism_view(design, home_pose(design)))
    ax = fig.axes[0]
    boxes = label_boxes(ax)
    marks = marker_boxes(ax)
    assert len(boxes) > 15 and len(marks) > 10
    for i, (a, ba) in enumerate(boxes):
        for b, bb in boxes[i + 1 :]:
            assert not ba.overlaps(bb), (a.get_text(), b.get_text())
        own = _anchor(a, ax)
        for mb in marks:
            assert mb.contains(*own) or not ba.overlaps(mb), a.get_text()
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert POINT_LEGEND in legend
    assert not any(t.startswith("prismatic joint P") for t in legend)


def test_mode_names_give_shares_and_are_distinct() -> None:
    """At the 3-PRS's tilted pose two modes have the same dominant component (the
    library's directions); the picture's names carry each named component's share
    of the length-balanced norm squared and are distinct."""
    from ppm_stiffness.dynamics.analysis import modal_analysis
    from ppm_stiffness.visuals.modes import COMPONENT_NAMES, mode_names, mode_shares

    np.testing.assert_allclose(mode_shares([0, 0, 0, 3.0, 4.0, 0]), [0, 0, 0, 0.36, 0.64, 0])
    np.testing.assert_allclose(mode_shares([0.01, 0, 0, 0, 0.001, 0]), [0.5, 0, 0, 0, 0.5, 0])
    design = design_named("3prs")
    pose = full_pose(design, np.array([0.42, math.radians(8.0), math.radians(-5.0)]))
    result = modal_analysis(design, pose, tool_point=np.zeros(3))
    shapes = np.array([m["shape"] for m in result.to_dict()["modes"]])
    names = mode_names(shapes)
    assert len(set(names)) == 6
    for v, name in zip(shapes, names, strict=True):
        share = mode_shares(v)
        top = int(np.argmax(share))
        assert name.startswith(f"{COMPONENT_NAMES[top]} {100 * share[top]:.0f} %")


def test_mode_names_number_a_repeated_pair() -> None:
    from ppm_stiffness.visuals.modes import mode_names

    shapes = np.eye(6)[[3, 3, 4, 5, 0, 1]]
    names = mode_names(shapes)
    assert names[:2] == ["x translation 100 %, mode 1", "x translation 100 %, mode 2"]
    assert len(set(names)) == 6


def test_colour_bars_have_no_offset_and_small_variation_is_stated() -> None:
    """The hexapod's x-y map: k_r,max varies by about 3 %, k_t,max by about 3 % (before:
    "1e5"/"1e7" offset texts over ticks 2.8054 ... and no word on the variation)."""
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.visuals.maps import plot_stiffness_maps
    from ppm_stiffness.visuals.ticks import SMALL_VARIATION, variation

    design = design_named("hexapod_6ups")
    smap = stiffness_map(
        design, axes=("x", "y"), fixed={"z": 0.2, "rx": 0.0, "ry": 0.0, "rz": 0.0}, grid=5
    )
    fig = plot_stiffness_maps(smap)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    panels = [ax for ax in fig.axes if ax.get_xlabel() == "x [mm]"]
    bars = [ax for ax in fig.axes if ax not in panels and ax.get_ylabel()]
    assert len(panels) == len(bars) == len(smap.quantities) == 6
    small = 0
    for ax, cax, (key, values) in zip(panels, bars, smap.quantities.items(), strict=True):
        assert cax.yaxis.get_offset_text().get_text() == ""
        label = cax.get_ylabel()
        prefix = re.search(r"\[(k|M|G)?(N/m|N·m/rad)\]", label)
        assert prefix is not None, label
        factor = {None: 1.0, "k": 1e3, "M": 1e6, "G": 1e9}[prefix.group(1)]
        ticks = [t for t in cax.yaxis.get_ticklabels() if t.get_text()]
        for t in ticks:  # the value in the unit, to the label's last printed decimal
            text = t.get_text()
            half_digit = 0.5 * 10.0 ** -len(text.partition(".")[2])
            assert abs(float(text) - t.get_position()[1] / factor) <= half_digit * (1 + 1e-9)
        var = (np.ma.max(values) - np.ma.min(values)) / np.ma.max(np.abs(values))
        assert variation(values) == pytest.approx(float(var), rel=1e-12)
        noted = "variation" in ax.get_title()
        assert noted == (var < SMALL_VARIATION), (key, var)
        small += noted
        if noted:
            assert f"variation {100 * var:.2g} % over the slice" in ax.get_title()
    assert small >= 1


def test_one_panel_map_keeps_its_title_whole() -> None:
    """A one-panel map of a tall slice (the report's f1 map of the 3-PPR) was 3.4 in wide
    and its title "First natural frequency f1, locked actuators" ran past both edges;
    now the figure is at least MIN_WIDTH wide and the title's box lies inside it."""
    import dataclasses

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.visuals.maps import MIN_WIDTH, plot_stiffness_maps

    smap = stiffness_map(default_design(), phi=0.0, grid=4)
    one = dataclasses.replace(smap, quantities={"k_x": smap.quantities["k_x"]})
    fig = plot_stiffness_maps(one, title="First natural frequency f1, locked actuators")
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    assert fig.get_size_inches()[0] >= MIN_WIDTH
    box = fig._suptitle.get_window_extent(canvas.get_renderer())
    assert box.x0 >= 0 and box.x1 <= fig.bbox.width
