"""Workspace, stiffness maps (Figures 6-7), their files and the ``map`` command."""

from __future__ import annotations

import re
import struct
from pathlib import Path

import numpy as np
import pytest

from helpers import colour_count, half_unit
from ppm_stiffness.cli import main
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import (
    InputDataError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.design import default_design
from ppm_stiffness.maps import workspace
from ppm_stiffness.maps.workspace import StiffnessMap, load_npz, stiffness_map
from ppm_stiffness.model import solve_legs, stiffness_at_pose
from ppm_stiffness.statics.actuator import stiffness_from_force
from ppm_stiffness.statics.loading import loaded_state

DESIGN = default_design()
PHI30 = np.radians(30.0)
#: The paper's loaded case in library order (m_x, m_y, m_z, f_x, f_y, f_z).
PAPER_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])


@pytest.fixture(scope="module")
def maps() -> dict[tuple[float, str], StiffnessMap]:
    return {
        (phi, acts): stiffness_map(DESIGN, phi=phi, actuators=acts, grid=(31, 41))
        for phi in (0.0, PHI30)
        for acts in ("max", "min")
    }


def principal_single(pose: np.ndarray, k_act: np.ndarray | None = None) -> np.ndarray:
    dec = decouple(stiffness_at_pose(DESIGN, pose, k_act), "paper")
    return np.array([dec.rotational_values[2], *dec.translational_values[:2]])


# ------------------------------------------------------------------------- workspace
@pytest.mark.parametrize("phi", [0.0, PHI30])
def test_workspace_bounds_follow_the_joint_limits(phi: float) -> None:
    """Legs 1-2 rails run along y, rods along +-x; leg 3 the other way round. So the
    workspace is a rectangle: x from the rod limits of legs 1-2 and the stroke of leg 3,
    y from the strokes of legs 1-2 and the rod limits of leg 3 (each affine, slope +-1)."""
    geo = [leg.solve(np.array([0.0, 0.0, phi])) for leg in DESIGN.legs]
    legs = DESIGN.legs
    rho = [float(g.coordinates["rho"]) for g in geo]
    rod = [float(g.coordinates["rod"]) for g in geo]
    # rod_1 = rod_1(0) + x, rod_2 = rod_2(0) - x, rho_3 = rho_3(0) + x
    x_lo = max(
        legs[0].rod_length_range[0] - rod[0],
        rod[1] - legs[1].rod_length_range[1],
        legs[2].stroke[0] - rho[2],
    )
    x_hi = min(
        legs[0].rod_length_range[1] - rod[0],
        rod[1] - legs[1].rod_length_range[0],
        legs[2].stroke[1] - rho[2],
    )
    # rho_1 = rho_1(0) + y, rho_2 = rho_2(0) + y, rod_3 = rod_3(0) - y
    y_lo = max(
        legs[0].stroke[0] - rho[0], legs[1].stroke[0] - rho[1], rod[2] - legs[2].rod_length_range[1]
    )
    y_hi = min(
        legs[0].stroke[1] - rho[0], legs[1].stroke[1] - rho[1], rod[2] - legs[2].rod_length_range[0]
    )
    box = workspace.workspace_bounds(DESIGN, phi)
    np.testing.assert_allclose(box, [x_lo, x_hi, y_lo, y_hi], atol=1e-12)
    # just inside every corner is reachable, just outside each side is not
    eps = 1e-7
    for x in (box[0] + eps, box[1] - eps):
        for y in (box[2] + eps, box[3] - eps):
            solve_legs(DESIGN, [x, y, phi])
    centre = [(box[0] + box[1]) / 2, (box[2] + box[3]) / 2]
    for x, y in (
        (box[0] - eps, centre[1]),
        (box[1] + eps, centre[1]),
        (centre[0], box[2] - eps),
        (centre[0], box[3] + eps),
    ):
        with pytest.raises(UnreachablePoseError, match=r"leg \d: .* mm outside \["):
            solve_legs(DESIGN, [x, y, phi])


def test_reconstructed_limits_of_the_built_in_design() -> None:
    """docs/maps.md: 50 mm strokes centred on the centre pose, rods 3-120 mm; at phi = 0
    x spans [3 mm - rod_1(0), rod_2(0) - 3 mm] ~ [-14.97, 8.67] mm and y +-25 mm."""
    box = workspace.workspace_bounds(DESIGN, 0.0) * 1e3
    np.testing.assert_allclose(box, [-14.969, 8.669, -25.0, 25.0], atol=2e-3)
    with pytest.raises(UnreachablePoseError, match="no reachable position at phi = 90.00 deg"):
        workspace.workspace_bounds(DESIGN, np.radians(90.0))


# ------------------------------------------------------------------- map = single pose
def test_map_equals_single_pose_path_and_masks_exactly_the_rejected_poses() -> None:
    bounds = np.array([-0.02, 0.012, -0.03, 0.03])  # wider than the workspace
    for phi in (0.0, 0.3):
        smap = stiffness_map(DESIGN, phi=phi, grid=(9, 8), bounds=bounds)
        assert 0 < smap.reachable.sum() < smap.reachable.size
        for j, y in enumerate(smap.y):
            for i, x in enumerate(smap.x):
                pose = np.array([x, y, phi])
                try:
                    ref = principal_single(pose)
                except (UnreachablePoseError, SingularConfigurationError):
                    assert not smap.reachable[j, i]
                    assert smap.k_phi.mask[j, i] and smap.k_x.mask[j, i]
                    continue
                assert smap.reachable[j, i]
                got = [smap.k_phi[j, i], smap.k_x[j, i], smap.k_y[j, i]]
                np.testing.assert_allclose(got, ref, rtol=1e-10)
        np.testing.assert_array_equal(smap.mask, ~smap.reachable)


def test_wrench_map_is_the_loaded_state_at_each_pose() -> None:
    smap = stiffness_map(DESIGN, phi=0.2, actuators="wrench", wrench=PAPER_WRENCH, grid=5)
    assert smap.reachable.all()
    for j in (0, 2, 4):
        for i in (0, 3):
            pose = np.array([smap.x[i], smap.y[j], 0.2])
            state = loaded_state(DESIGN, PAPER_WRENCH, pose)
            dec = decouple(state.stiffness_matrix, "paper")
            ref = [dec.rotational_values[2], *dec.translational_values[:2]]
            np.testing.assert_allclose(
                [smap.k_phi[j, i], smap.k_x[j, i], smap.k_y[j, i]], ref, rtol=1e-9
            )
            np.testing.assert_allclose(
                smap.actuator_stiffness[0], state.actuator_stiffness, rtol=1e-9
            )


def test_wrench_map_actuator_stiffness_at_phi_0_is_the_centre_one() -> None:
    """At phi = 0 the in-plane statics of the 3-PPR do not depend on (x, y): the
    smallest and largest K_act over the map are the loaded state's at the centre (which
    test_model_paper.py compares with the paper's). Measured 4.8e-15 relative."""
    smap = stiffness_map(DESIGN, actuators="wrench", wrench=PAPER_WRENCH, grid=4)
    centre = loaded_state(DESIGN, PAPER_WRENCH).actuator_stiffness
    np.testing.assert_allclose(smap.actuator_stiffness, [centre] * 2, rtol=2e-14)


def test_min_state_is_eq21_under_the_reference_force(maps: dict) -> None:
    k_min = float(stiffness_from_force(DESIGN.actuator, 10.0))
    assert 1700 < k_min < 1800  # q k_a delta^(q-1), delta = (10 / 44.75)^(1/0.225) m
    np.testing.assert_allclose(maps[(0.0, "min")].actuator_stiffness, k_min, rtol=1e-14)
    np.testing.assert_allclose(maps[(0.0, "max")].actuator_stiffness, 1.1108e5, rtol=1e-14)
    assert maps[(0.0, "min")].reference_force == 10.0


# ----------------------------------------------------------------- the paper's trends
@pytest.mark.parametrize("phi", [0.0, PHI30])
@pytest.mark.parametrize("acts", ["max", "min"])
def test_k_x_depends_on_y_only_and_k_y_on_x_only(maps: dict, phi: float, acts: str) -> None:
    """Paper: "k_x is constant for a given y ... stiffer with increasing y, while k_y
    keeps constant for a given x". Exact in this model at any phi: the rod of leg 3
    (the only leg pushing along x) shortens as y grows, the rods of legs 1-2 (pushing
    along y) change with x only, and K_tt[0, 1] = 0."""
    m = maps[(phi, acts)]
    assert m.reachable.all()
    kx, ky = m.k_x.filled(np.nan), m.k_y.filled(np.nan)
    row_spread = np.ptp(kx, axis=1) / kx.mean(axis=1)
    col_spread = np.ptp(ky, axis=0) / ky.mean(axis=0)
    assert row_spread.max() < 1e-12
    assert col_spread.max() < 1e-12
    assert np.all(np.diff(kx[:, 0]) > 0)  # stiffer with increasing y
    assert np.ptp(ky[0]) > 1e-4 * ky.mean()  # k_y does vary with x


@pytest.mark.parametrize("phi", [0.0, PHI30])
def test_k_phi_rises_from_lower_left_to_right_boundary_with_locked_actuators(
    maps: dict, phi: float
) -> None:
    """Paper: "k_phi becomes higher from the left lower region to the right boundary".
    The model (locked actuators): k_phi grows monotonically with x and with y, lowest at
    the lower-left corner and highest at the upper-right one (on the right boundary).
    With the actuators at their minimum the trend reverses (docs/maps.md)."""
    kp = maps[(phi, "max")].k_phi.filled(np.nan)
    assert np.all(np.diff(kp, axis=1) > 0) and np.all(np.diff(kp, axis=0) > 0)
    assert np.unravel_index(np.argmin(kp), kp.shape) == (0, 0)
    assert np.unravel_index(np.argmax(kp), kp.shape) == (kp.shape[0] - 1, kp.shape[1] - 1)
    kp_min = maps[(phi, "min")].k_phi.filled(np.nan)
    assert np.all(np.diff(kp_min, axis=0) < 0)
    assert kp_min[0, 0] > kp_min[-1, -1]


@pytest.mark.parametrize("phi", [0.0, PHI30])
def test_maximum_over_minimum_stiffness(maps: dict, phi: float) -> None:
    """Paper: "the maximum values are at least 10 times higher than the minimum ones".
    In the model this holds between the two actuator states (pointwise, >= 13x with the
    10 N reference force), not within one map (each map varies by less than 2.5x)."""
    hi, lo = maps[(phi, "max")], maps[(phi, "min")]
    for name in ("k_phi", "k_x", "k_y"):
        a, b = hi.fields()[name], lo.fields()[name]
        assert float((a / b).min()) >= 10.0
        assert 1.0 < float(a.max() / a.min()) < 2.5
        assert 1.0 < float(b.max() / b.min()) < 1.2


# ---------------------------------------------------------------------- files and API
def test_npz_and_csv_round_trip(tmp_path: Path) -> None:
    smap = stiffness_map(DESIGN, grid=(6, 5), bounds=[-0.02, 0.005, -0.01, 0.01])
    assert not smap.reachable.all()
    back = load_npz(smap.to_npz(tmp_path / "m.npz"))
    for name in ("k_phi", "k_x", "k_y"):
        np.testing.assert_array_equal(back.fields()[name].mask, smap.fields()[name].mask)
        np.testing.assert_array_equal(
            back.fields()[name].compressed(), smap.fields()[name].compressed()
        )
    assert back.actuators == "max" and back.wrench is None
    np.testing.assert_array_equal(back.x, smap.x)
    path = smap.to_csv(tmp_path / "m.csv")
    lines = [ln.rstrip("\n") for ln in path.open(encoding="utf-8") if not ln.startswith("#")]
    assert lines[0].split(",")[:3] == ["x_m", "y_m", "reachable"]
    body = [ln.split(",") for ln in lines[1:]]
    assert len(body) == 30
    for n, cells in enumerate(body):
        j, i = divmod(n, 6)
        assert float(cells[0]) == pytest.approx(smap.x[i], rel=1e-11)
        assert float(cells[1]) == pytest.approx(smap.y[j], rel=1e-11)
        if smap.reachable[j, i]:
            assert cells[2] == "1"
            assert float(cells[4]) == pytest.approx(float(smap.k_x[j, i]), rel=1e-11)
        else:
            assert cells[2:] == ["0", "", "", ""]


def test_progress_reports_every_chunk_up_to_the_total() -> None:
    calls: list[tuple[int, int]] = []
    stiffness_map(DESIGN, grid=(20, 30), progress=lambda d, t: calls.append((d, t)), chunk_size=100)
    assert len(calls) == 6  # 5 rows of 20 per chunk
    assert calls[-1] == (600, 600)
    assert all(b[0] > a[0] for a, b in zip(calls, calls[1:], strict=False))


def test_bad_map_requests_raise() -> None:
    needed = 'a wrench is needed for actuators="wrench" and only for it'
    with pytest.raises(InputDataError, match=needed):
        stiffness_map(DESIGN, actuators="wrench")  # no wrench
    with pytest.raises(InputDataError, match=needed):
        stiffness_map(DESIGN, actuators="max", wrench=PAPER_WRENCH)
    with pytest.raises(InputDataError, match="actuators must be one of .* got 'medium'"):
        stiffness_map(DESIGN, actuators="medium")
    with pytest.raises(InputDataError, match="a map grid needs at least 2 x 2 points, got 1 x 1"):
        stiffness_map(DESIGN, grid=1)
    with pytest.raises(UnreachablePoseError, match="no reachable position at phi = 90.00 deg"):
        stiffness_map(DESIGN, phi=np.radians(90.0))


# ------------------------------------------------------------------------ the CLI
def png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", data[16:24])
    return width, height


def expected_pixels(smap: StiffnessMap) -> tuple[int, int]:
    from ppm_stiffness.visuals.maps import DPI, plot_stiffness_maps

    w, h = plot_stiffness_maps(smap).get_size_inches()
    return round(w * DPI), round(h * DPI)


def test_cli_writes_figure_and_data(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    import matplotlib.image

    fig, data = tmp_path / "maps.png", tmp_path / "maps.npz"
    rc = main(
        ["map", "--grid", "30", "--phi", "30", "--out", str(fig), "--data", str(data), "--quiet"]
    )
    assert rc == 0
    out = capsys.readouterr().out
    assert "k_phi" in out and "figure written" in out
    smap = load_npz(data)
    assert smap.k_phi.shape == (30, 30) and smap.phi == pytest.approx(PHI30)
    assert png_size(fig) == expected_pixels(smap)
    img = matplotlib.image.imread(fig)
    assert img.std() > 0.1  # not a blank page
    assert colour_count(img) > 50  # contours drawn


@pytest.mark.parametrize("suffix", [".svg", ".pdf"])
def test_cli_writes_vector_figures_of_the_right_size(tmp_path: Path, suffix: str) -> None:
    fig, data = tmp_path / f"maps{suffix}", tmp_path / "maps.csv"
    rc = main(
        [
            "map",
            "--grid",
            "12",
            "--actuators",
            "min",
            "--out",
            str(fig),
            "--data",
            str(data),
            "--quiet",
        ]
    )
    assert rc == 0
    assert data.stat().st_size > 12 * 12 * 30
    from ppm_stiffness.visuals.maps import plot_stiffness_maps

    smap = stiffness_map(DESIGN, actuators="min", grid=12)
    w, h = plot_stiffness_maps(smap).get_size_inches() * 72  # points
    text = fig.read_bytes()
    if suffix == ".svg":
        assert f'width="{w:g}pt"'.encode() in text or f'width="{w:.6g}pt"'.encode() in text
        assert text.count(b"<path") > 20
    else:
        assert text.startswith(b"%PDF")
        assert f"/MediaBox [ 0 0 {w:g} {h:g} ]".encode() in text
        assert len(text) > 5000


def test_cli_wrench_map(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    rc = main(["map", "--grid", "6", "--actuators", "5,5,20,0,0,0.1", "--quiet"])
    assert rc == 0
    out = capsys.readouterr().out
    header = next(line for line in out.splitlines() if "actuator stiffness" in line)
    shown = re.findall(r"([0-9.]+(?:e[+-]?\d+)?) N/m", header)
    assert "wrench" in header and len(shown) == 3
    # the loaded state's K_act at the centre (uniform at phi = 0), to the printed digits
    centre = loaded_state(DESIGN, PAPER_WRENCH).actuator_stiffness
    for text, value in zip(shown, centre, strict=True):
        assert abs(float(text) - value) <= half_unit(text), (text, value)


@pytest.mark.parametrize(
    "argv",
    [
        ["map", "--actuators", "soft"],
        ["map", "--actuators", "1,2,3"],
        ["map", "--out", "maps.txt"],
        ["map", "--data", "maps.json"],
        ["map", "--phi", "90"],
        ["map", "--grid", "1"],
        ["map", "--bounds", "1,2,3"],
    ],
)
def test_cli_bad_input_is_one_line_and_exit_2(
    argv: list[str], capsys: pytest.CaptureFixture
) -> None:
    assert main([*argv, "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("ppm-stiffness: error:")
