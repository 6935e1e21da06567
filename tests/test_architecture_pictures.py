"""Pictures and the report for every shipped architecture (3-PPR, 4-PPR, 3-RPR, 3-PRR,
3-RRR): the plotted joints, links and platform are the legs' inverse kinematics and
joint chains; the figure files decode; the report of a 3-RRR shows rotary units.

Read back from the artists' gids (see :mod:`ppm_stiffness.visuals.mechanism`), in mm;
compared in metres to 1e-12 m.
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
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from helpers import (  # noqa: E402
    capture_saved_figures,
    colour_count,
    example_designs,
    half_unit,
    is_planar,
    lines_by_gid,
)
from ppm_stiffness.analysis import ENVELOPE_KEYS, analyze_design, dump_json  # noqa: E402
from ppm_stiffness.cli import main  # noqa: E402
from ppm_stiffness.core.eigenscrews import eigenscrews  # noqa: E402
from ppm_stiffness.design import Design, default_design, load_design  # noqa: E402
from ppm_stiffness.leading import leading_keys  # noqa: E402
from ppm_stiffness.legs.chain import Joint, Link  # noqa: E402
from ppm_stiffness.model import stiffness_at_pose, workspace_centre  # noqa: E402
from ppm_stiffness.statics.loading import loaded_state  # noqa: E402
from ppm_stiffness.visuals.mechanism import (  # noqa: E402
    mechanism_legs,
    plot_mechanism,
)
from ppm_stiffness.visuals.report import DEFAULT_WRENCH, embedded_json  # noqa: E402
from ppm_stiffness.visuals.springs import AXIS_GID, plot_screw_springs  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = tuple(example_designs(is_planar))
DESIGNS = ("paper_3ppr",) + EXAMPLES


def _design(name: str) -> Design:
    return (
        default_design()
        if name == "paper_3ppr"
        else load_design(ROOT / "examples" / f"{name}.toml")
    )


def _design_path(name: str) -> Path:
    if name == "paper_3ppr":
        return ROOT / "src" / "ppm_stiffness" / "data" / "paper_3ppr.toml"
    return ROOT / "examples" / f"{name}.toml"


def _artists(fig) -> dict[str, np.ndarray]:
    """gid -> plotted data [mm]: lines (n, 2), scatter offsets (n, 2), polygon (n, 2)."""
    ax = fig.axes[0]
    out: dict[str, np.ndarray] = {}
    for line in ax.get_lines():
        if line.get_gid():
            out[line.get_gid()] = np.asarray(line.get_xydata(), dtype=float)
    for coll in ax.collections:
        if coll.get_gid():
            out[coll.get_gid()] = np.asarray(coll.get_offsets(), dtype=float)
    for patch in ax.patches:
        if patch.get_gid():
            out[patch.get_gid()] = np.asarray(patch.get_xy(), dtype=float)
    return out


def _pose(design: Design, name: str) -> np.ndarray:
    """An off-centre reachable pose (small step from the centre), for a real test."""
    centre = workspace_centre(design)
    return centre + (
        np.array([1e-3, -1.5e-3, np.radians(2.0)])
        if name != "paper_3ppr"
        else np.array([2e-3, -1e-3, np.radians(1.0)])
    )


@pytest.mark.parametrize("name", DESIGNS)
def test_mechanism_draws_the_chain(name: str) -> None:
    """Every joint at its chain point, every link from start to end, the base feature
    through its point, the platform = the D points: all to 1e-12 m."""
    design = _design(name)
    pose = _pose(design, name)
    views = mechanism_legs(design, pose)
    fig = plot_mechanism(design, pose)
    art = _artists(fig)
    title = fig.axes[0].get_title()
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    plt.close(fig)
    assert "UNREACHABLE" not in title
    p_abs = np.array([pose[0], pose[1], 0.0])
    d_expected = []
    for i, leg in enumerate(design.legs, start=1):
        lp = leg.solve(pose)
        chain = leg.chain(lp)
        joints = [e for e in chain if isinstance(e, Joint)]
        links = [e for e in chain if isinstance(e, Link)]
        assert joints and links
        for j, joint in enumerate(joints, start=1):
            drawn = art[f"joint-{i}-{j}"] / 1e3
            np.testing.assert_allclose(drawn[0], (joint.point + p_abs)[:2], rtol=0, atol=1e-12)
        # the last link ends at the platform point D
        np.testing.assert_allclose(links[-1].end[:2], lp.points["D"][:2], rtol=0, atol=1e-12)
        for j, link in enumerate(links, start=1):
            drawn = art[f"link-{i}-{j}"] / 1e3
            expected = np.stack([link.start, link.end])[:, :2] + pose[:2]
            np.testing.assert_allclose(drawn, expected, rtol=0, atol=1e-12)
        # every named point of the IK is drawn: a joint, a link end or a rigid segment end
        drawn_pts = np.vstack(
            [art[g] for g in art if g.startswith((f"joint-{i}-", f"link-{i}-", f"rigid-{i}-"))]
        )
        for key, pt in lp.points.items():
            gap = np.min(np.linalg.norm(drawn_pts / 1e3 - (pt + p_abs)[:2], axis=1))
            assert gap < 1e-12, (i, key)
        base = leg.base_feature(lp)
        drawn = art[f"base-{i}"] / 1e3
        if base.kind == "pivot":
            np.testing.assert_allclose(drawn[0], base.point[:2], rtol=0, atol=1e-12)
        else:  # the rail line passes through the rail origin along the rail
            u = base.axis[:2]
            for pt in drawn:
                rel = pt - base.point[:2]
                assert abs(rel[0] * u[1] - rel[1] * u[0]) < 1e-12
        assert views[i - 1].solvable and not views[i - 1].violations
        d_expected.append((lp.points["D"] + p_abs)[:2])
    verts = art["platform"][: len(design.legs)] / 1e3
    d_expected_arr = np.array(d_expected)
    # each drawn vertex is one D_i, every D_i is drawn once
    match = [int(np.argmin(np.linalg.norm(d_expected_arr - v, axis=1))) for v in verts]
    assert sorted(match) == list(range(len(design.legs)))
    np.testing.assert_allclose(verts, d_expected_arr[match], rtol=0, atol=1e-12)
    platform = [t for t in legend if t.startswith("platform")]
    assert platform == ["platform " + "-".join(f"D{k + 1}" for k in match)]
    np.testing.assert_allclose(art["P"][0] / 1e3, pose[:2], rtol=0, atol=1e-15)


def test_four_leg_legend_and_title() -> None:
    """A 4-leg design: the platform is D1-D2-D3-D4 and every leg is labelled."""
    design = _design("redundant_4ppr")
    fig = plot_mechanism(design)
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    texts = [t.get_text() for t in ax.texts]
    title = ax.get_title()
    plt.close(fig)
    assert "platform D1-D2-D3-D4" in legend
    assert not any(t == "platform D1-D2-D3" for t in legend)
    assert [t for t in texts if t.startswith("leg ")] == ["leg 1", "leg 2", "leg 3", "leg 4"]
    assert all(f"D{i}" in texts for i in range(1, 5))
    # the joint coordinates of all four legs, in mm
    assert "rho [mm] = (34.5, 34.5, 34.5, 34.5)" in title


def test_rotary_legs_legend_and_stroke_arc() -> None:
    """3-RRR: base pivots, the actuated base revolute ringed, the stroke arc at a
    constant distance from the pivot spanning the stroke, theta in degrees."""
    design = _design("3rrr")
    fig = plot_mechanism(design)
    art = _artists(fig)
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    title = ax.get_title()
    plt.close(fig)
    assert {
        "base pivot",
        "actuated joint",
        "revolute joint R",
        "proximal link",
        "distal link",
    } <= set(legend)
    assert "prismatic joint P" not in legend and "rail over the actuator stroke" not in legend
    for i, leg in enumerate(design.legs, start=1):
        arc = art[f"stroke-{i}"] / 1e3 - np.asarray(leg.base_point)
        r = np.linalg.norm(arc, axis=1)
        assert np.ptp(r) < 1e-12
        ang = np.unwrap(np.arctan2(arc[:, 1], arc[:, 0]))
        assert abs((ang[-1] - ang[0]) - (leg.stroke[1] - leg.stroke[0])) < 1e-9
    theta = [
        np.degrees(float(leg.solve(workspace_centre(design)).coordinates["theta"]))
        for leg in design.legs
    ]
    assert "theta [deg] = (" + ", ".join(f"{t:.1f}" for t in theta) + ")" in title


def test_unreachable_pose_names_limits_and_unsolvable_legs() -> None:
    """3-RRR at y = 200 mm: legs 2 and 3 cannot reach (no IK: not drawn, named), leg 1
    can but past its stroke (the coordinate and its range named); the paper's design
    at x = 30 mm: leg 2's rod runs out."""
    design = _design("3rrr")
    far = np.array([0.0, 0.2, 0.0])  # |D - A| = 0.39 m > 0.3 m for legs 2 and 3
    views = mechanism_legs(design, far)
    unsolvable = [v.index for v in views if not v.solvable]
    assert unsolvable == [2, 3]
    lo, hi = (np.degrees(x) for x in design.legs[0].stroke)
    assert len(views[0].violations) == 1
    assert re.fullmatch(
        rf"actuator angle -?\d+\.\d\d deg outside \[{lo:.2f}, {hi:.2f}\] deg",
        views[0].violations[0],
    )
    fig = plot_mechanism(design, far)
    art = _artists(fig)
    title = fig.axes[0].get_title().replace("\n", " ")
    plt.close(fig)
    for i in unsolvable:
        assert f"leg {i}: no inverse-kinematics solution (not drawn)" in title
        assert f"joint-{i}-1" not in art and f"link-{i}-1" not in art
        assert f"base-{i}" in art  # the base pivot is fixed: drawn
    assert title.count("UNREACHABLE") == 1

    # the paper's design at x = 30 mm: leg 2's rod runs out (a limit, not the IK)
    paper = default_design()
    fig = plot_mechanism(paper, [0.03, 0.0, 0.0])
    title = fig.axes[0].get_title().replace("\n", " ")
    plt.close(fig)
    lo, hi = (x * 1e3 for x in paper.legs[1].rod_length_range)
    assert re.search(
        rf"leg 2: rod free length -?\d+\.\d\d mm outside \[{lo:.2f}, {hi:.2f}\] mm", title
    ), title


@pytest.mark.parametrize("name", DESIGNS)
def test_mechanism_and_springs_commands_on_every_design(
    tmp_path: Path, name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Both figure commands on the design file draw the model at the workspace centre:
    the mechanism's joints at the legs' chain points, the six spring axes through the
    screw springs' positions along their axes (eq. 9-10), all to 1e-12 m; the PNGs
    decode at a sensible size with a drawing in them."""
    figures = capture_saved_figures(monkeypatch)
    for command in ("mechanism", "springs"):
        out = tmp_path / f"{command}.png"
        assert main([command, "--design", str(_design_path(name)), "--out", str(out)]) == 0
        img = mpimg.imread(out)
        assert img.shape[0] > 600 and img.shape[1] > 900, (command, img.shape)
        assert colour_count(img) > 20
    mechanism, springs_fig = figures
    design = _design(name)
    pose = workspace_centre(design)
    art = _artists(mechanism)
    p_abs = np.array([pose[0], pose[1], 0.0])
    for i, leg in enumerate(design.legs, start=1):
        joints = [e for e in leg.chain(leg.solve(pose)) if isinstance(e, Joint)]
        for j, joint in enumerate(joints, start=1):
            drawn = art[f"joint-{i}-{j}"][0] / 1e3
            np.testing.assert_allclose(drawn, (joint.point + p_abs)[:2], rtol=0, atol=1e-12)
    springs = eigenscrews(stiffness_at_pose(design, pose))
    axes = lines_by_gid(springs_fig, AXIS_GID)
    assert sorted(axes) == [1, 2, 3, 4, 5, 6]
    for i in range(6):
        a, b = axes[i + 1][0] / 1e3, axes[i + 1][-1] / 1e3  # mm -> m
        direction = (b - a) / np.linalg.norm(b - a)
        assert np.linalg.norm(np.cross(springs.positions[i] - a, direction)) < 1e-12
        assert np.linalg.norm(np.cross(direction, springs.axes[i])) < 1e-12


@pytest.mark.parametrize("name", EXAMPLES)
def test_springs_plane_draws_every_link(name: str) -> None:
    """The 3-D picture draws each leg's links (clipped to the box) in the plane z = 0."""
    design = _design(name)
    pose = workspace_centre(design)
    fig = plot_screw_springs(eigenscrews(stiffness_at_pose(design, pose)), design, pose)
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(fig)
    n = len(design.legs)
    expected_platform = "platform " + "-".join(f"D{k}" for k in range(1, n + 1))
    assert labels[0] == expected_platform
    names = {
        e.name for leg in design.legs for e in leg.chain(leg.solve(pose)) if isinstance(e, Link)
    }
    assert {f"{nm} link" for nm in names} <= set(labels)


@pytest.fixture(scope="module")
def rrr_report(example_report: Callable[[str], str]) -> str:
    return example_report("3rrr")  # build_report(_design("3rrr"), grid=6), conftest


def test_report_of_a_3rrr_has_sections_and_rotary_units(rrr_report: str) -> None:
    for sid in (
        "design",
        "mechanism",
        "stiffness",
        "screw-springs",
        "decoupling",
        "loaded",
        "deflection",
        "maps",
        "fig-mechanism",
        "fig-springs",
        "fig-deflection",
    ):
        assert f'id="{sid}"' in rrr_report, sid
    assert "3-RRR" in rrr_report
    # the actuator table in the rotary units, none of the linear ones
    head = re.search(r"<caption>Actuators under the wrench.*?</thead>", rrr_report).group(0)
    assert "force G [N·m]" in head and "displacement δ [deg]" in head  # the CLI's unit
    assert "K<sub>act</sub> unloaded [N·m/rad]" in head and "[N/m]" not in head
    # displacement cells are in deg: SI rad x 180/pi
    loaded = embedded_json(rrr_report, "analysis-loaded")
    for i, delta in enumerate(loaded["actuator_displacements"]):
        cell = re.search(
            rf'data-path="loaded/actuator_displacements/{i}" data-scale="([^"]+)">'
            r"([^<]+)<",
            rrr_report,
        )
        assert cell is not None and float(cell.group(1)) == 180 / math.pi
        shown = delta * 180 / math.pi
        assert abs(float(cell.group(2)) - shown) <= 5e-4 * max(abs(shown), 1e-300)
    # nothing of the P-P-R legs' parts in the mechanism caption
    caption = re.search(r'id="fig-mechanism".*?</figcaption>', rrr_report, re.S).group(0)
    for word in ("guide block", "bearing", "rod"):
        assert word not in caption


def test_report_of_a_3rrr_images_decode(rrr_report: str) -> None:
    srcs = re.findall(r'<img[^>]*src="([^"]+)"', rrr_report)
    assert len(srcs) >= 4  # mechanism, two spring pictures, deflection (+ maps if any)
    for src in srcs:
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        img = mpimg.imread(io.BytesIO(raw), format="png")
        assert img.shape[0] > 200 and img.shape[1] > 300
        assert np.ptp(img[..., :3]) > 0.5


@pytest.mark.parametrize("name", ["redundant_4ppr", "3prr", "3rpr"])
def test_report_of_the_other_examples_shows_their_analysis(tmp_path: Path, name: str) -> None:
    """The report of each other example at its centre: the embedded analyses are
    analyze_design's, unloaded and under the default wrench, the actuator-force cells
    print the loaded state's forces to their printed digits, and every architecture
    has its stiffness maps."""
    code = main(
        [
            "report",
            "--design",
            str(_design_path(name)),
            "--grid",
            "5",
            "--quiet",
            "--out",
            str(tmp_path),
        ]
    )
    assert code == 0
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    design = _design(name)
    for block, wrench in (("analysis-unloaded", None), ("analysis-loaded", DEFAULT_WRENCH)):
        expected = json.loads(dump_json(analyze_design(design, None, wrench)))
        expected |= leading_keys(True, None)  # as `analyze --json` adds them
        embedded = embedded_json(page, block)
        assert {k: v for k, v in embedded.items() if k not in ENVELOPE_KEYS} == expected
    forces = loaded_state(design, DEFAULT_WRENCH).actuator_forces
    for i, g in enumerate(forces):
        cell = re.search(
            rf'data-path="loaded/actuator_forces/{i}" data-scale="([^"]+)">([^<]+)<', page
        )
        assert cell is not None, i
        shown = float(cell.group(2)) / float(cell.group(1))
        assert abs(shown - g) <= half_unit(cell.group(2)) / float(cell.group(1)), (i, g)
    assert "no map" not in page  # every architecture has its stiffness maps


def test_architecture_figures_script(tmp_path: Path) -> None:
    """scripts/architecture_figures.py writes the five docs pictures as decodable PNGs."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "architecture_figures", ROOT / "scripts" / "architecture_figures.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    paths = module.write_figures(tmp_path)
    assert sorted(p.name for p in paths) == [
        "arch_3ppr.png",
        "arch_3prr.png",
        "arch_3rpr.png",
        "arch_3rrr.png",
        "arch_4ppr.png",
    ]
    for path in paths:
        img = mpimg.imread(path)
        assert 700 < img.shape[0] < 1200 and 900 < img.shape[1] < 1500, (path.name, img.shape)
        assert (ROOT / "docs" / "figures" / path.name).is_file()
