"""Measurement files with 6-D poses: the pose columns give a design's task coordinates
(and may give the dependent ones, which must be those the legs impose); old planar
files load as before; a load along a direction reads back with its '# direction:'."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from helpers import design_named
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.poses import full_poses, home_pose
from ppm_stiffness.statics.deflection import direction_wrench, mode_wrench
from ppm_stiffness.statics.measurements import (
    check_mode,
    measured_poses,
    read_measurements,
)

ROOT = Path(__file__).parents[1]
RPS = design_named("3rps")
#: Two poses of the 3-RPS by its task coordinates (z [mm], rx, ry [deg]).
TASKS = ((350.0, 0.0, 0.0), (330.0, 5.0, -2.0))


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "m.csv"
    p.write_text(text, encoding="utf-8")
    return p


def _completed() -> np.ndarray:
    """The full poses (2, 6) the 3-RPS's legs complete at TASKS."""
    tasks = np.array([[z * 1e-3, math.radians(a), math.radians(b)] for z, a, b in TASKS])
    poses, ok = full_poses(RPS, tasks)
    assert ok.all()
    return poses


def _rps_file(tmp_path: Path, dependent: str = "", values: list[str] | None = None) -> Path:
    """Two rows at TASKS, with the dependent columns ``dependent`` (e.g. ",pose_y_mm")
    and their values per row."""
    rows = [
        f"{z:g},{a:g},{b:g}" + (f",{values[k]}" if values else "") + ",10,0.01,0.02"
        for k, (z, a, b) in enumerate(TASKS)
    ]
    header = f"pose_z_mm,pose_rx_deg,pose_ry_deg{dependent},fx_N,x_mm,sigma_x_mm"
    return _write(tmp_path, "# two rows\n" + header + "\n" + "\n".join(rows) + "\n")


def test_task_coordinates_of_a_tripod_are_completed_by_its_legs(tmp_path: Path) -> None:
    """A 3-RPS file gives z, rx, ry; x, y, rz follow from the legs (the completion)."""
    m = read_measurements(_rps_file(tmp_path))
    assert m.pose_columns == ("pose_z_mm", "pose_rx_deg", "pose_ry_deg")
    assert np.isnan(m.poses[:, [0, 1, 5]]).all()
    poses = measured_poses(RPS, m)
    np.testing.assert_array_equal(poses, _completed())
    assert abs(poses[1, 1]) > 1e-4  # a tilt about x moves P along y by 0.29 mm


def test_dependent_coordinates_given_must_be_the_imposed_ones(tmp_path: Path) -> None:
    """The imposed y written to 7 significant digits (in mm) is accepted; 0.01 mm off it
    is refused, naming the file, the line, the value, the imposed one and the task
    coordinates."""
    y = _completed()[:, 1] * 1e3
    good = _rps_file(tmp_path, ",pose_y_mm", [f"{v:.7g}" for v in y])
    np.testing.assert_array_equal(measured_poses(RPS, read_measurements(good)), _completed())
    bad = _rps_file(tmp_path, ",pose_y_mm", [f"{y[0]:.7g}", f"{y[1] + 0.01:.7g}"])
    message = (
        f"{bad}, line 4: pose_y_mm = {y[1] + 0.01:.7g} disagrees with the legs, which impose "
        f"y = {y[1]:.10g} mm there: the task coordinates of this design are z, rx, ry"
    )
    with pytest.raises(InputDataError, match="^" + re.escape(message)):
        measured_poses(RPS, read_measurements(bad))


def test_every_task_coordinate_has_its_column(tmp_path: Path) -> None:
    path = _write(tmp_path, "pose_z_mm,pose_rx_deg,fx_N,x_mm\n350,0,1,0.01\n")
    with pytest.raises(InputDataError, match="missing column 'pose_ry_deg': the pose columns "):
        measured_poses(RPS, read_measurements(path))
    # a planar design's rz column is called pose_phi_deg, as in its files
    path = _write(tmp_path, "fx_N,pose_x_mm,pose_y_mm,x_mm\n1,0,0,0.2\n")
    with pytest.raises(InputDataError, match="missing column 'pose_phi_deg'.*x, y, rz"):
        measured_poses(design_named("paper"), read_measurements(path))
    hexapod = design_named("hexapod_6ups")
    with pytest.raises(InputDataError, match="missing column 'pose_x_mm'"):
        measured_poses(hexapod, read_measurements(_rps_file(tmp_path)))


def test_old_planar_files_and_the_rz_name(tmp_path: Path) -> None:
    """pose_x_mm, pose_y_mm, pose_phi_deg of a planar design: (x, y, 0, 0, 0, phi) as
    before; pose_rz_deg is the same column; a planar design's z given as 0 agrees, as 1
    mm it does not."""
    paper = design_named("paper")
    old = _write(tmp_path, "pose_x_mm,pose_y_mm,pose_phi_deg,fx_N,x_mm\n2,-1,3,1,0.01\n")
    expected = [[0.002, -0.001, 0.0, 0.0, 0.0, math.radians(3)]]
    np.testing.assert_allclose(measured_poses(paper, read_measurements(old)), expected, rtol=1e-15)
    new = tmp_path / "rz.csv"
    new.write_text("pose_x_mm,pose_y_mm,pose_rz_deg,pose_z_mm,fx_N,x_mm\n2,-1,3,0,1,0.01\n")
    np.testing.assert_allclose(measured_poses(paper, read_measurements(new)), expected, rtol=1e-15)
    new.write_text("pose_x_mm,pose_y_mm,pose_rz_deg,pose_z_mm,fx_N,x_mm\n2,-1,3,1,1,0.01\n")
    with pytest.raises(InputDataError, match="line 2: pose_z_mm = 1 disagrees with the legs"):
        measured_poses(paper, read_measurements(new))
    shipped = read_measurements(ROOT / "examples/identification/measurements.csv")
    poses = measured_poses(paper, shipped)
    np.testing.assert_allclose(poses[:, [0, 1, 5]], shipped.poses[:, [0, 1, 5]], rtol=1e-15)
    assert not poses[:, 2:5].any()


def test_without_pose_columns_every_row_is_at_home(tmp_path: Path) -> None:
    m = read_measurements(_write(tmp_path, "fz_N,z_mm\n100,0.01\n200,0.02\n"))
    np.testing.assert_array_equal(measured_poses(RPS, m), np.tile(home_pose(RPS), (2, 1)))


# ------------------------------------------------------------------ a direction
def test_a_direction_file_states_its_load_per_unit(tmp_path: Path) -> None:
    path = _write(tmp_path, "# mode: direction\n# direction: 3,4,0,0,0,1\nload,x_mm\n2,0.1\n")
    m = read_measurements(path)
    np.testing.assert_allclose(m.unit_wrench(), direction_wrench([0, 0, 1, 3, 4, 0]))
    np.testing.assert_allclose(m.unit_wrench(), [0, 0, 0.2, 0.6, 0.8, 0], rtol=1e-15)
    check_mode(m, "direction", math.nan, direction_wrench([0, 0, 2, 6, 8, 0]))  # same line
    with pytest.raises(InputDataError, match="the measurements are for the load per unit"):
        check_mode(m, "direction", math.nan, direction_wrench([0, 0, 0, 1, 0, 0]))
    wrench = _write(tmp_path, "# mode: wrench\n# direction: 3,4,0,0,0,1\nload,x_mm\n2,0.1\n")
    np.testing.assert_allclose(read_measurements(wrench).unit_wrench(), [0, 0, 1, 3, 4, 0])
    planar = _write(tmp_path, "# mode: planar-force\n# alpha_deg: 30\nload,x_mm\n2,0.1\n")
    np.testing.assert_allclose(
        read_measurements(planar).unit_wrench(), mode_wrench("planar-force", math.radians(30))
    )


@pytest.mark.parametrize(
    ("comment", "message"),
    [
        ("# mode: direction", "line 1: '# mode: direction' needs a '# direction: FX,FY,FZ"),
        ("# mode: direction\n# direction: 1,2", "line 2: '# direction: 1,2' is not six finite"),
        ("# mode: wrench\n# direction: 0,0,0,0,0,0", "line 2: '# direction: 0,0,0,0,0,0' is not"),
    ],
)
def test_malformed_direction_lines(tmp_path: Path, comment: str, message: str) -> None:
    path = _write(tmp_path, f"{comment}\nload,x_mm\n1,0.1\n")
    with pytest.raises(InputDataError, match="^" + re.escape(f"{path}, {message}")):
        read_measurements(path)
