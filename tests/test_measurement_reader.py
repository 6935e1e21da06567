"""The one measurement reader shared by ``deflect --measurements`` and ``identify``:
columns with units in their names, optional sigma columns, comments, clear errors."""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.statics.measurements import read_measurements


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "m.csv"
    p.write_text(text, encoding="utf-8")
    return p


def test_wrench_file_with_poses_and_sigmas_in_si(tmp_path: Path) -> None:
    p = _write(
        tmp_path,
        "# rig: bench 2\n# free text comment\n"
        "pose_x_mm,pose_y_mm,pose_phi_deg,fx_N,mz_Nm,phi_z_deg,x_mm,sigma_x_mm\n"
        "10,-5,2,4,0.1,0.5,0.02,0.001\n"
        "0,0,0,-3,0,0.1,-0.01,0.002\n",
    )
    m = read_measurements(p)
    assert m.loads is None and m.n == 2
    assert m.metadata == {"rig": "bench 2"}
    assert m.components == (2, 3)
    # 6-D poses (x, y, z, rx, ry, rz); a coordinate the file does not give is NaN
    np.testing.assert_allclose(m.poses[0, [0, 1, 5]], [0.01, -0.005, math.radians(2)], rtol=1e-15)
    assert np.isnan(m.poses[:, 2:5]).all()
    assert m.pose_columns == ("pose_x_mm", "pose_y_mm", "pose_phi_deg")
    # library order (m_x, m_y, m_z, f_x, f_y, f_z); absent components are zero
    np.testing.assert_allclose(m.wrenches[0], [0, 0, 0.1, 4, 0, 0], rtol=1e-15)
    np.testing.assert_allclose(m.twists[1, 2:4], [math.radians(0.1), -1e-5], rtol=1e-15)
    assert np.isnan(m.twists[:, [0, 1, 4, 5]]).all()
    np.testing.assert_allclose(m.sigmas[:, 3], [1e-6, 2e-6], rtol=1e-15)
    assert np.isnan(m.sigmas[:, 2]).all()
    with pytest.raises(InputDataError, match="load column"):
        m.load_values()


@pytest.mark.parametrize("name", ["planar", "moment", "vertical"])
def test_shipped_deflect_files_still_load(name: str) -> None:
    path = resources.files("ppm_stiffness").joinpath(f"data/measurements_synthetic_{name}.csv")
    m = read_measurements(Path(str(path)))
    assert m.loads is not None and m.loads.size == 10 and m.wrenches is None
    assert m.poses is None and np.isnan(m.sigmas).all()


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("fx_N,x_m\n1,0.2\n", "unknown column 'x_m'.*did you mean 'x_mm'"),
        ("fx_N,x_mm,speed\n1,0.2,3\n", "unknown column 'speed'"),
        ("x_mm,y_mm\n0.1,0.2\n", "displacements with no wrench"),
        ("fx_N,mz_Nm\n1,0.2\n", "no displacement column"),
        ("load,fx_N,x_mm\n1,1,0.2\n", "either a load column or wrench"),
        (
            "fx_N,pose_phi_deg,pose_rz_deg,x_mm\n1,0,0,0.2\n",
            "'pose_phi_deg' and 'pose_rz_deg' are the same coordinate",
        ),
        ("fx_N,pose_z_m,x_mm\n1,0,0.2\n", "unknown column 'pose_z_m'.*did you mean 'pose_z_mm'"),
        ("fx_N,x_mm\n1,nan\n", "column 'x_mm': nan"),
        ("fx_N,x_mm\n1,\n", "column 'x_mm': empty"),
        ("fx_N,x_mm\n1,abc\n", "column 'x_mm': 'abc' is not numeric"),
        ("fx_N,x_mm,sigma_y_mm\n1,0.2,0.1\n", "'sigma_y_mm' without the component"),
        ("fx_N,x_mm,sigma_x_mm\n1,0.2,0\n", "sigma must be > 0"),
        ("fx_N,x_mm\n", "at least one data row"),
        ("fx_N,x_mm,x_mm\n1,0.2,0.2\n", "more than once"),
        ("fx_N,x_mm\n1,0.2,3\n", "3 fields"),
    ],
)
def test_malformed_files_name_the_problem(tmp_path: Path, text: str, match: str) -> None:
    with pytest.raises(InputDataError, match=match):
        read_measurements(_write(tmp_path, text))
