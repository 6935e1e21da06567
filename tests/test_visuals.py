"""Pictures: screw springs (Fig. 5), the mechanism's top view, the figure commands.

The figures are checked on their plotted data (read back from the artists), not on
pixels: the drawn spring axes must be the computed screw axes, the helices must wind
with the sign of the pitch, and the mechanism must show the modelled geometry.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from helpers import capture_saved_figures, colour_count, design_named, lines_by_gid  # noqa: E402
from ppm_stiffness.cli import main  # noqa: E402
from ppm_stiffness.core.eigenscrews import eigenscrews  # noqa: E402
from ppm_stiffness.design import default_design  # noqa: E402
from ppm_stiffness.legs.chain import Joint  # noqa: E402
from ppm_stiffness.model import stiffness_at_pose  # noqa: E402
from ppm_stiffness.statics.loading import loaded_state  # noqa: E402
from ppm_stiffness.visuals.mechanism import mechanism_legs, plot_mechanism  # noqa: E402
from ppm_stiffness.visuals.springs import (  # noqa: E402
    AXIS_GID,
    HELIX_GID,
    plot_screw_springs,
)

PAPER_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])  # f = [5, 5, 20] N, m_z = 0.1 N·m


def _cross2(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


@pytest.mark.parametrize("loaded", [False, True], ids=["unloaded", "paper-wrench"])
def test_spring_axes_pass_through_positions(loaded: bool) -> None:
    """Each drawn axis is the line through p_i along e_i (eq. 9-10), within 1e-12 m."""
    design = default_design()
    k = loaded_state(design, PAPER_WRENCH).stiffness_matrix if loaded else stiffness_at_pose(design)
    springs = eigenscrews(k)
    fig = plot_screw_springs(springs, design)
    axes = lines_by_gid(fig, AXIS_GID)
    plt.close(fig)
    assert sorted(axes) == [1, 2, 3, 4, 5, 6]
    for i in range(6):
        a, b = axes[i + 1][0] / 1e3, axes[i + 1][-1] / 1e3  # mm -> m
        direction = (b - a) / np.linalg.norm(b - a)
        p, e = springs.positions[i], springs.axes[i]
        dist = np.linalg.norm(np.cross(p - a, direction))
        assert dist < 1e-12
        assert np.linalg.norm(np.cross(direction, e)) < 1e-12
        assert np.linalg.norm(b - a) > 0.01  # a visible segment (>= 10 mm)


def test_helix_handedness_follows_pitch_sign() -> None:
    """The helix around s_i winds positively about e_i iff the pitch is positive.

    For the paper's design the pitches come in +- pairs (Table 4), so both hands
    occur: three right-handed and three left-handed helices.
    """
    design = default_design()
    springs = eigenscrews(stiffness_at_pose(design))
    fig = plot_screw_springs(springs, design)
    helices = lines_by_gid(fig, HELIX_GID)
    plt.close(fig)
    hands = []
    for i in range(6):
        pts = helices[i + 1] / 1e3
        e, p = springs.axes[i], springs.positions[i]
        rel = pts - p
        radial = rel - np.outer(rel @ e, e)
        # angular momentum of the sweep about e, plus the advance along e
        turn = np.einsum("ij,ij->i", np.cross(radial[:-1], np.diff(radial, axis=0)), e[None, :])
        advance = np.diff(rel @ e)
        assert np.all(advance > 0)
        hands.append(np.sign(turn.sum()))
        # the helix stays at a constant distance from the axis
        r = np.linalg.norm(radial, axis=1)
        assert np.ptp(r) < 1e-9 * r.mean()
    assert hands == list(np.sign(springs.pitches))
    assert sorted(hands) == [-1, -1, -1, 1, 1, 1]


def test_mechanism_drawing_is_the_modelled_geometry() -> None:
    """Top view of the paper's design at seeded random poses: the platform is
    D1-D2-D3 at radius r from P, each rod (the link ending at D) runs along its
    bearing's axis (the rod slides in the bearing), each rail passes through the base
    point along the actuated joint's axis, and the proximal link joins B to C."""
    design = default_design()
    rng = np.random.default_rng(7)
    for _ in range(3):
        pose = np.array([*rng.uniform(-0.02, 0.02, 2), rng.uniform(-0.5, 0.5)])
        views = mechanism_legs(design, pose)
        fig = plot_mechanism(design, pose)
        ax = fig.axes[0]
        lines = {
            ln.get_gid(): np.array(ln.get_xydata()) / 1e3 for ln in ax.get_lines() if ln.get_gid()
        }
        poly = [p for p in ax.patches if p.get_gid() == "platform"][0]
        verts = np.array(poly.get_xy())[:3] / 1e3
        plt.close(fig)
        d = np.array([v.points["D"][:2] for v in views])
        np.testing.assert_allclose(verts, d, atol=1e-12)  # D1-D2-D3 counter-clockwise
        radii = np.linalg.norm(verts - pose[:2], axis=1)
        np.testing.assert_allclose(radii, [leg.platform_radius for leg in design.legs], rtol=1e-12)
        for i, (leg, view) in enumerate(zip(design.legs, views, strict=True), start=1):
            assert view.chain is not None
            guide, bearing = (e for e in view.chain if isinstance(e, Joint) and e.kind != "R")
            u, w = guide.axis[:2], bearing.axis[:2]
            rod = lines[f"link-{i}-2"]
            assert abs(_cross2(rod[1] - rod[0], w)) < 1e-12
            np.testing.assert_allclose(rod[1], view.points["D"][:2], atol=1e-12)
            rail = lines[f"base-{i}"]
            a = np.array(leg.base_point)
            assert abs(_cross2(rail[0] - a, u)) < 1e-12
            assert abs(_cross2(rail[1] - rail[0], u)) < 1e-12
            link = lines[f"link-{i}-1"]
            np.testing.assert_allclose(
                link, np.stack([view.points["B"], view.points["C"]])[:, :2], atol=1e-12
            )
            # bearing C sits bearing_offset along w from the rail point under D
            assert abs((view.points["C"][:2] - a) @ w - leg.bearing_offset) < 1e-12


MAGIC = {".png": b"\x89PNG\r\n\x1a\n", ".pdf": b"%PDF", ".svg": b"<svg"}


@pytest.mark.parametrize("command", ["springs", "mechanism"])
@pytest.mark.parametrize("suffix", [".png", ".svg", ".pdf"])
def test_figure_commands_write_requested_format(tmp_path: Path, command: str, suffix: str) -> None:
    out = tmp_path / f"fig{suffix}"
    assert main([command, "--out", str(out)]) == 0
    data = out.read_bytes()
    assert len(data) > 5000
    if suffix == ".svg":
        assert MAGIC[suffix] in data[:2000]
    else:
        assert data.startswith(MAGIC[suffix])
    if suffix == ".png":
        img = mpimg.imread(out)
        assert img.shape[0] > 400 and img.shape[1] > 400
        assert colour_count(img) > 10


def test_springs_command_with_wrench_and_pose(tmp_path: Path, capsys) -> None:
    out = tmp_path / "s.png"
    code = main(
        [
            "springs",
            "--x",
            "2",
            "--y",
            "-3",
            "--phi",
            "1",
            "--wrench",
            "5,5,20,0,0,0.1",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    assert out.stat().st_size > 5000
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["springs", "--out", "x.jpg"], "unknown format"),
        (["mechanism", "--out", "x"], "unknown format"),
        (["mechanism", "--x", "30", "--out", "x.png"], "rod free length"),
        (["springs", "--wrench", "1,2,3", "--out", "x.png"], "6 numbers"),
    ],
)
def test_figure_commands_reject_bad_input(tmp_path: Path, capsys, argv, message) -> None:
    argv = [a if not a.startswith("x") else str(tmp_path / a) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_mechanism_draws_unreachable_pose_on_request(tmp_path: Path) -> None:
    """x = 30 mm is beyond leg 2's rod (11.7 mm free at the centre): flagged, drawn."""
    out = tmp_path / "m.png"
    assert main(["mechanism", "--x", "30", "--allow-unreachable", "--out", str(out)]) == 0
    fig = plot_mechanism(default_design(), [0.03, 0.0, 0.0])
    title = fig.axes[0].get_title()
    plt.close(fig)
    assert "UNREACHABLE" in title and "leg 2" in title


def test_analyze_does_not_import_matplotlib() -> None:
    """Pictures cost nothing to the commands that draw none (issue 5, point 4)."""
    code = (
        "import sys, io, contextlib\n"
        "from ppm_stiffness.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    rc = main(['analyze', '--json'])\n"
        "assert rc == 0, rc\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib')\n"
        "print('MPL', len(bad))\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert "MPL 0" in res.stdout


def test_planar_pose_reaches_every_picture(tmp_path: Path, monkeypatch) -> None:
    """A planar design's pose from the CLI is a full pose (x, y, z, rx, ry, rz): the
    pictures' titles give phi = rz (on main they printed z, 0, as phi), the top view's
    platform polygon is turned by phi."""
    figures = capture_saved_figures(monkeypatch)
    opts = ["--x", "2", "--y", "-1", "--phi", "10"]
    for command in ("mechanism", "springs"):
        assert main([command, *opts, "--out", str(tmp_path / f"{command}.png")]) == 0
    mechanism, springs = figures
    assert "phi = 10.00 deg" in mechanism.axes[0].get_title()
    assert "phi = 10.00 deg" in springs.axes[0].get_title()
    design = design_named("paper")
    poly = next(p for p in mechanism.axes[0].patches if p.get_gid() == "platform")
    verts = np.asarray(poly.get_xy())[: len(design.legs)] / 1e3
    for v in verts:  # D_i - P = -r (cos(psi + phi), sin(psi + phi)) for some leg
        rel = v - [2e-3, -1e-3]
        angles = [math.atan2(-rel[1], -rel[0]) - leg.psi for leg in design.legs]
        assert min(abs(math.remainder(a - math.radians(10), 2 * math.pi)) for a in angles) < 1e-12
    plt.close(mechanism)
    plt.close(springs)
