"""Pictures of the spatial designs (6-UPS hexapod, 3-PRS, 3-RPS): the 3-D mechanism view
and the screw-spring picture draw the model's geometry, and a planar design's pose
reaches every picture whole.

The drawn data are read back from the artists' gids (``line.get_data_3d()``, mm; see
:mod:`ppm_stiffness.visuals.mechanism3d`) and compared in metres to 1e-12 m with the
legs' joint chains, and with an independent computation of the platform points:
``p + R b`` with R from ``scipy.spatial.transform.Rotation.from_euler("xyz", ...)``.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from helpers import (  # noqa: E402
    ROOT,
    capture_saved_figures,
    check_entries,
    colour_count,
    design_named,
    example_designs,
    is_spatial,
    lines_by_gid,
)
from ppm_stiffness.cli import main  # noqa: E402
from ppm_stiffness.core.eigenscrews import eigenscrews  # noqa: E402
from ppm_stiffness.legs.chain import Joint, Link  # noqa: E402
from ppm_stiffness.legs.joint_kinds import joint_kind  # noqa: E402
from ppm_stiffness.model import stiffness_at_pose, stiffness_at_tool_point  # noqa: E402
from ppm_stiffness.poses import full_pose  # noqa: E402
from ppm_stiffness.visuals.leg_geometry import mechanism_view  # noqa: E402
from ppm_stiffness.visuals.mechanism import plot_mechanism  # noqa: E402
from ppm_stiffness.visuals.mechanism3d import plot_mechanism_3d  # noqa: E402
from ppm_stiffness.visuals.springs import AXIS_GID, plot_screw_springs  # noqa: E402

SPATIAL = tuple(example_designs(is_spatial))
#: An off-home reachable pose of each, as CLI options (mm, deg).
POSE_OPTIONS = {
    "hexapod_6ups": [
        "--x",
        "2",
        "--y",
        "-1.5",
        "--z",
        "205",
        "--rx",
        "2",
        "--ry",
        "-1.5",
        "--rz",
        "3",
    ],
    "3prs": ["--z", "420", "--rx", "8", "--ry", "-5"],
    "3rps": ["--z", "360", "--rx", "5", "--ry", "4"],
    "6rus": ["--x", "3", "--y", "-2", "--z", "215", "--rx", "2", "--ry", "-1.5", "--rz", "3"],
    "6rus_flexure": [
        *("--x", "0.8", "--y", "-0.5", "--z", "213"),
        *("--rx", "0.2", "--ry", "-0.15", "--rz", "0.3"),
    ],
    "flexure_3rrr": ["--x", "0.008", "--y", "-0.005", "--rz", "0.01"],
    "spherical_3rrr": ["--rx", "15", "--ry", "-10", "--rz", "20"],
    "tricept": ["--z", "565", "--rx", "4", "--ry", "-3"],
    "delta": ["--x", "30", "--y", "-20", "--z", "-790"],
}


def test_every_spatial_example_has_a_pose() -> None:
    check_entries(POSE_OPTIONS, SPATIAL, "POSE_OPTIONS")


def _rim(points: list[np.ndarray] | np.ndarray) -> list[int]:
    """Indices of the points (n, 2) not strictly inside the convex hull of the others
    (scipy's Delaunay triangulation; all of them for three points)."""
    from scipy.spatial import Delaunay

    xy = np.asarray(points, dtype=float)
    if len(xy) < 4:
        return list(range(len(xy)))
    inside = [Delaunay(np.delete(xy, i, axis=0)).find_simplex(xy[i]) >= 0 for i in range(len(xy))]
    return [i for i, v in enumerate(inside) if not v]


def _task(name: str) -> np.ndarray:
    """The task coordinates [m, rad] of :data:`POSE_OPTIONS`."""
    opts = POSE_OPTIONS[name]
    values = [float(v) for v in opts[1::2]]
    return np.array(
        [
            math.radians(v) if o.startswith("--r") else v * 1e-3
            for o, v in zip(opts[::2], values, strict=True)
        ]
    )


def _lines(fig) -> dict[str, object]:
    """gid -> the Line3D of the first axes."""
    return {ln.get_gid(): ln for ln in fig.axes[0].get_lines() if ln.get_gid()}


def _data(line) -> np.ndarray:
    """A 3-D line's points (n, 3), mm -> m."""
    return np.array(line.get_data_3d(), dtype=float).T / 1e3


def _rotation(pose: np.ndarray) -> np.ndarray:
    """R = Rz(rz) Ry(ry) Rx(rx), independently of the library (scipy, extrinsic xyz)."""
    return Rotation.from_euler("xyz", pose[3:]).as_matrix()


def _check_chain_drawn(fig, design, pose: np.ndarray, origin: np.ndarray) -> None:
    """Every joint (at its point, its axis bars along its axes, its marker by kind) and
    every link of every leg is drawn where the chain has it, relative to ``origin``
    [m, F_b], to 1e-12 m."""
    lines = _lines(fig)
    p = pose[:3]
    for i, leg in enumerate(design.legs, start=1):
        lp = leg.solve(pose)
        members, member_joints = leg.drawn_members(lp)
        chain = [*leg.chain(lp), *members, *member_joints]
        joints = [e for e in chain if isinstance(e, Joint) and not e.equivalent]
        links = [e for e in chain if isinstance(e, Link)]
        for j, joint in enumerate(joints, start=1):
            at = np.asarray(joint.point) + p - origin
            line = lines[f"joint-{i}-{j}"]
            np.testing.assert_allclose(_data(line)[0], at, rtol=0, atol=1e-12)
            assert line.get_marker() == joint_kind(joint.kind).marker, (i, j, joint.kind)
            axes = {"R": [joint.axis], "P": [joint.axis], "U": [joint.axis, joint.axis2]}
            for k, e in enumerate(axes.get(joint.kind, []), start=1):
                bar = _data(lines[f"joint-axis-{i}-{j}-{k}"])
                np.testing.assert_allclose(bar.mean(axis=0), at, rtol=0, atol=1e-12)
                d = (bar[1] - bar[0]) / np.linalg.norm(bar[1] - bar[0])
                assert np.linalg.norm(np.cross(d, np.asarray(e))) < 1e-12, (i, j, k)
            if joint.kind == "S":
                assert f"joint-axis-{i}-{j}-1" not in lines
        for j, link in enumerate(links, start=1):
            drawn = _data(lines[f"link-{i}-{j}"])
            expected = np.stack([link.start, link.end]) + p - origin
            np.testing.assert_allclose(drawn, expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", SPATIAL)
def test_mechanism_command_draws_the_spatial_model(
    tmp_path: Path, name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``mechanism`` at an off-home pose given in mm and deg: every joint and link at
    the chain's points, the platform polygon through p + R b_i (R from scipy), the
    base polygon through the base points, the rails over the strokes, P, the tool point
    and the platform axes (R's columns); equal scale on the three axes; the title names
    the task and the parasitic coordinates; the PNG is a real drawing."""
    figures = capture_saved_figures(monkeypatch)
    out = tmp_path / "mechanism.png"
    design_file = ROOT / "examples" / f"{name}.toml"
    assert (
        main(["mechanism", "--design", str(design_file), *POSE_OPTIONS[name], "--out", str(out)])
        == 0
    )
    img = mpimg.imread(out)
    assert img.shape[0] > 800 and img.shape[1] > 1000, img.shape
    assert colour_count(img) > 100
    (fig,) = figures
    design = design_named(name)
    pose = full_pose(design, _task(name))
    r = _rotation(pose)
    p = pose[:3]
    _check_chain_drawn(fig, design, pose, np.zeros(3))
    lines = _lines(fig)
    ax = fig.axes[0]

    # the platform: a closed ring through each platform point on its rim once (a point
    # inside the others' hull, a Tricept's central tube at P, is no corner)
    ring = _data(lines["platform"])
    np.testing.assert_allclose(ring[0], ring[-1], rtol=0, atol=0)
    b = np.array([p + r @ leg.attachment() for leg in design.legs])
    match = [int(np.argmin(np.linalg.norm(b - v, axis=1))) for v in ring[:-1]]
    assert sorted(match) == _rim([leg.attachment()[:2] for leg in design.legs])
    np.testing.assert_allclose(ring[:-1], b[match], rtol=0, atol=1e-12)
    # each leg's last link ends there (its last rigid connection for a leg of rigid
    # links, the flexure stage's)
    for i in range(1, len(design.legs) + 1):
        kind = "link" if any(g.startswith(f"link-{i}-") for g in lines) else "rigid"
        last = max(int(g.split("-")[2]) for g in lines if g.startswith(f"{kind}-{i}-"))
        np.testing.assert_allclose(_data(lines[f"{kind}-{i}-{last}"])[-1], b[i - 1], atol=1e-12)
    # the base polygon through the base points
    base = _data(lines["base-polygon"])[:-1]
    a = np.array([leg.base_feature(leg.solve(pose)).point for leg in design.legs], dtype=float)
    assert sorted(int(np.argmin(np.linalg.norm(a - v, axis=1))) for v in base) == _rim(a[:, :2])
    for i, leg in enumerate(design.legs, start=1):
        if leg.type == "PRS":  # the rail through A along u, the band over the stroke
            u = np.asarray(leg.rail_direction)
            for q in _data(lines[f"base-{i}"]):
                assert np.linalg.norm(np.cross(q - a[i - 1], u)) < 1e-12
            expected = a[i - 1] + np.outer(leg.stroke, u)
            np.testing.assert_allclose(_data(lines[f"stroke-{i}"]), expected, rtol=0, atol=1e-12)
        else:
            np.testing.assert_allclose(_data(lines[f"base-{i}"])[0], a[i - 1], atol=1e-12)
    np.testing.assert_allclose(_data(lines["P"])[0], p, rtol=0, atol=1e-15)
    if np.any(np.asarray(design.tool_point) != 0):
        tool = p + r @ np.asarray(design.tool_point)
        np.testing.assert_allclose(_data(lines["tool"])[0], tool, rtol=0, atol=1e-12)
    for k, axis in enumerate("xyz"):
        seg = _data(lines[f"frame-p-{axis}"])
        np.testing.assert_allclose(seg[0], p, rtol=0, atol=1e-15)
        d = (seg[1] - seg[0]) / np.linalg.norm(seg[1] - seg[0])
        np.testing.assert_allclose(d, r[:, k], rtol=0, atol=1e-12)
        seg = _data(lines[f"frame-b-{axis}"])
        np.testing.assert_allclose(seg[0], np.zeros(3), rtol=0, atol=0)
        np.testing.assert_allclose(seg[1] / np.linalg.norm(seg[1]), np.eye(3)[k], atol=1e-15)

    # equal scale: the box's proportions are the limits' spans
    spans = np.array([np.ptp(ax.get_xlim3d()), np.ptp(ax.get_ylim3d()), np.ptp(ax.get_zlim3d())])
    box = np.asarray(ax.get_box_aspect(), dtype=float)
    np.testing.assert_allclose(box / box.max(), spans / spans.max(), rtol=1e-12)
    assert all("[mm]" in lab for lab in (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()))

    title = ax.get_title()
    assert design.name in title and "UNREACHABLE" not in title
    for idx, coord in enumerate(("x", "y", "z", "rx", "ry", "rz")):
        value = math.degrees(pose[idx]) if coord.startswith("r") else pose[idx] * 1e3
        unit = "deg" if coord.startswith("r") else "mm"
        digits = 2 if coord in design.task_coordinates else 4
        assert f"{coord} = {value:.{digits}f} {unit}" in title, (coord, title)
    if len(design.task_coordinates) < 6:
        assert "parasitic" in title
    legend = {t.get_text() for t in ax.get_legend().get_texts()}
    kinds = set()
    for leg in design.legs:
        lp = leg.solve(pose)
        chain = [*leg.chain(lp), *leg.drawn_members(lp)[1]]
        kinds |= {e.kind for e in chain if isinstance(e, Joint) and not e.equivalent}
    assert {joint_kind(k).legend for k in kinds} <= legend
    assert "actuated joint" in legend
    plt.close(fig)


def test_universal_joint_axes_are_normal_to_the_leg() -> None:
    """The two bars of each hexapod U joint: normal to each other and to the leg A->B
    (the U's constrained rotation is about the leg), e1 horizontal (normal to z)."""
    design = design_named("hexapod_6ups")
    pose = full_pose(design, _task("hexapod_6ups"))
    fig = plot_mechanism(design, pose)
    lines = _lines(fig)
    plt.close(fig)
    for i, leg in enumerate(design.legs, start=1):
        a = np.asarray(leg.base_point, dtype=float)
        b = pose[:3] + _rotation(pose) @ np.asarray(leg.platform_point)
        n = (b - a) / np.linalg.norm(b - a)
        e1, e2 = (np.diff(_data(lines[f"joint-axis-{i}-1-{k}"]), axis=0)[0] for k in (1, 2))
        e1, e2 = e1 / np.linalg.norm(e1), e2 / np.linalg.norm(e2)
        for x, y in ((e1, e2), (e1, n), (e2, n)):
            assert abs(x @ y) < 1e-12
        assert abs(e1[2]) < 1e-12


def test_unreachable_spatial_pose_names_each_leg(tmp_path: Path, capsys, monkeypatch) -> None:
    """The hexapod at z = 105 mm, rx = 11.46 deg: refused without --allow-unreachable;
    with it, legs 2, 5, 6 (shorter than their cylinder: |AB| < 140 mm, computed here
    with scipy's R) have no inverse kinematics: named and not drawn (their base is);
    legs 1, 3, 4 are drawn and named with their length outside the stroke, to the
    printed 0.01 mm; the title is red."""
    design_file = str(ROOT / "examples" / "hexapod_6ups.toml")
    opts = ["--z", "105", "--rx", f"{math.degrees(0.2)}"]
    out = tmp_path / "m.png"
    assert main(["mechanism", "--design", design_file, *opts, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "leg length" in err and not out.exists()
    figures = capture_saved_figures(monkeypatch)
    argv = ["mechanism", "--design", design_file, *opts, "--allow-unreachable", "--out", str(out)]
    assert main(argv) == 0
    (fig,) = figures
    ax = fig.axes[0]
    title = ax.get_title().replace("\n", " ")
    lines = _lines(fig)
    design = design_named("hexapod_6ups")
    pose = np.array([0.0, 0.0, 0.105, 0.2, 0.0, 0.0])
    r = _rotation(pose)
    assert matplotlib.colors.same_color(ax.title.get_color(), "tab:red")
    for i, leg in enumerate(design.legs, start=1):
        length = np.linalg.norm(pose[:3] + r @ np.asarray(leg.platform_point) - leg.base_point)
        if length <= leg.cylinder_length:
            assert f"leg {i}: no inverse-kinematics solution (not drawn)" in title
            assert f"link-{i}-1" not in lines and f"joint-{i}-1" not in lines
            assert f"base-{i}" in lines
        else:
            found = re.search(
                rf"leg {i}: leg length \|AB\| (\d+\.\d\d) mm outside \[175\.00, 265\.00\] mm", title
            )
            assert found is not None, (i, title)
            assert abs(float(found.group(1)) - length * 1e3) <= 0.005 + 1e-9
            assert f"link-{i}-1" in lines
    assert sorted(i for i in range(1, 7) if f"link-{i}-1" not in lines) == [2, 5, 6]
    plt.close(fig)


def test_planar_design_both_views_draw_the_same_geometry() -> None:
    """The top view and the 3-D view of the paper's design draw each joint at the same
    point (the shared leg geometry): x, y equal, z = 0, to 1e-15 m."""
    design = design_named("paper")
    pose = np.array([2e-3, -1e-3, math.radians(5.0)])
    top = plot_mechanism(design, pose)
    flat = {
        c.get_gid(): np.asarray(c.get_offsets())[0] for c in top.axes[0].collections if c.get_gid()
    }
    spatial = plot_mechanism_3d(mechanism_view(design, pose))
    lines = _lines(spatial)
    plt.close(top)
    plt.close(spatial)
    joints = [g for g in flat if g.startswith("joint-")]
    assert len(joints) == 9
    for gid in joints:
        q = _data(lines[gid])[0]
        np.testing.assert_allclose(q[:2], flat[gid] / 1e3, rtol=0, atol=1e-15)
        assert q[2] == 0.0


@pytest.mark.parametrize("name", SPATIAL)
def test_springs_command_on_spatial_designs(tmp_path: Path, name: str, monkeypatch) -> None:
    """``springs`` at an off-home pose: the six axes through p_i along e_i of K at P
    (1e-12 m), the mechanism drawn whole relative to P from the legs' chains (1e-12 m),
    the platform first in the legend; the PNG is a real drawing."""
    figures = capture_saved_figures(monkeypatch)
    out = tmp_path / "springs.png"
    design_file = ROOT / "examples" / f"{name}.toml"
    assert (
        main(["springs", "--design", str(design_file), *POSE_OPTIONS[name], "--out", str(out)]) == 0
    )
    img = mpimg.imread(out)
    assert img.shape[0] > 800 and img.shape[1] > 1000 and colour_count(img) > 100
    (fig,) = figures
    design = design_named(name)
    pose = full_pose(design, _task(name))
    springs = eigenscrews(stiffness_at_pose(design, pose))
    axes = lines_by_gid(fig, AXIS_GID)
    for i in range(6):
        a, b = axes[i + 1][0] / 1e3, axes[i + 1][-1] / 1e3
        d = (b - a) / np.linalg.norm(b - a)
        assert np.linalg.norm(np.cross(springs.positions[i] - a, d)) < 1e-12
        assert np.linalg.norm(np.cross(d, springs.axes[i])) < 1e-12
    _check_chain_drawn(fig, design, pose, pose[:3])
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    last = list(design.legs[0].solve(pose).points)[-1]  # the legs' platform point (B, C, ...)
    assert legend[0].startswith(f"platform {last}1-")
    assert "base" in legend
    plt.close(fig)


def test_springs_at_the_tool_point_draw_the_mechanism_relative_to_it() -> None:
    """The 3-PRS's K at its tool point T (150 mm below P): the springs' positions are
    relative to T, and so is the mechanism drawn (P at -R t, every joint at its chain
    point - R t, to 1e-12 m)."""
    design = design_named("3prs")
    pose = full_pose(design, _task("3prs"))
    tool = np.asarray(design.tool_point, dtype=float)
    k_tool = stiffness_at_tool_point(stiffness_at_pose(design, pose), pose, tool)
    springs = eigenscrews(k_tool)
    fig = plot_screw_springs(springs, design, pose, tool_point=tool)
    t_abs = pose[:3] + _rotation(pose) @ tool
    _check_chain_drawn(fig, design, pose, t_abs)
    lines = _lines(fig)
    np.testing.assert_allclose(_data(lines["P"])[0], pose[:3] - t_abs, rtol=0, atol=1e-12)
    np.testing.assert_allclose(_data(lines["tool"])[0], np.zeros(3), rtol=0, atol=0)
    axes = lines_by_gid(fig, AXIS_GID)
    for i in range(6):
        a, b = axes[i + 1][0] / 1e3, axes[i + 1][-1] / 1e3
        d = (b - a) / np.linalg.norm(b - a)
        assert np.linalg.norm(np.cross(springs.positions[i] - a, d)) < 1e-12
    plt.close(fig)
