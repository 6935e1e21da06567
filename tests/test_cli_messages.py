"""Messages and readers (issue 27, item 7): a spatial design's pose printed in full, a
home pose in mm or degrees refused with the likely value, and every CSV reader (and
the tolerance file) reads a file that starts with a UTF-8 byte-order mark, as
spreadsheet programs write, as it reads the same file without one."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from ppm_stiffness.cli import main
from ppm_stiffness.cli.common import read_matrix_csv
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import default_design, design_from_dict, load_design
from ppm_stiffness.design.io import design_to_dict
from ppm_stiffness.fit.tolerances import read_tolerances
from ppm_stiffness.model import pose_label
from ppm_stiffness.statics.actuator_fit import read_force_displacement
from ppm_stiffness.statics.measurements import read_measurements

ROOT = Path(__file__).parents[1]
DATA = ROOT / "src/ppm_stiffness/data"
HEXAPOD = ROOT / "examples/hexapod_6ups.toml"
BOM = "\ufeff"


def _with_bom(source: Path, folder: Path, drop_comments: bool = False) -> Path:
    text = source.read_text(encoding="utf-8")
    if drop_comments:  # the header is then the first line, right after the mark
        text = "".join(line for line in text.splitlines(True) if not line.startswith("#"))
    out = folder / f"bom_{source.name}"
    out.write_bytes((BOM + text).encode("utf-8"))
    assert out.read_bytes()[:3] == b"\xef\xbb\xbf"
    return out


# -- a spatial design's pose in full -------------------------------------------------


def test_a_spatial_pose_in_the_plane_is_printed_in_full() -> None:
    """A hexapod pose with z = rx = ry = 0 was printed as the planar triple
    ``(10.00 mm, 0.00 mm, 5.73 deg)``: z, rx, ry were lost."""
    pose = np.array([0.01, 0.0, 0.0, 0.0, 0.0, 0.1])
    text = pose_label(pose, load_design(HEXAPOD))
    assert text == (
        " at pose (x = 10.00 mm, y = 0.00 mm, z = 0.00 mm, rx = 0.00 deg, ry = 0.00 deg, "
        "rz = 5.73 deg)"
    )
    # a planar design's pose stays the paper's triple
    assert pose_label(pose, default_design()) == " at pose (10.00 mm, 0.00 mm, 5.73 deg)"


# -- [workspace] in mm or degrees ------------------------------------------------------


@pytest.mark.parametrize(
    ("key", "value", "hint"),
    [
        ("rx", 40.0, "did you mean 0.698132?"),
        ("ry", -5.0, "did you mean -0.0872665?"),
        ("phi", 12.566, "did you mean 0.219318?"),
        ("centre_z", 200.0, "did you mean 0.2?"),
        ("centre_x", -15.0, "did you mean -0.015?"),
    ],
)
def test_a_home_pose_in_mm_or_degrees_is_refused_with_the_likely_value(
    key: str, value: float, hint: str
) -> None:
    """Before, [workspace] rx = 40 was taken as 40 rad (2292 deg) and the pose options'
    errors then read "rx in [..] deg" around it; a centre of 200 (mm) was 200 m."""
    data = design_to_dict(load_design(HEXAPOD))
    data["workspace"][key] = value
    unit = "radians" if key in ("rx", "ry", "phi") else "metres"
    with pytest.raises(DesignError, match=rf"workspace.*{key} = {value:g}: .*{unit}.*{hint}"):
        design_from_dict(data)


def test_a_home_pose_in_mm_is_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = design_to_dict(load_design(HEXAPOD))
    data["workspace"]["rx"] = 40.0
    path = tmp_path / "d.toml"
    path.write_text(tomli_w.dumps(data), encoding="utf-8")
    assert main(["analyze", "--design", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "rx = 40: angles in design files are in radians" in err
    assert "did you mean 0.698132?" in err


# -- CSV with a byte-order mark ------------------------------------------------------


def test_matrix_csv_with_a_byte_order_mark(tmp_path: Path) -> None:
    """analyze --matrix and calibrate --target (read_matrix_csv): before, the mark
    started the first comment line, which was then read as a row and refused."""
    plain = read_matrix_csv(DATA / "paper_eq22.csv")
    for drop in (False, True):
        bom = _with_bom(DATA / "paper_eq22.csv", tmp_path, drop)
        for option in ("--matrix", "--target"):
            np.testing.assert_array_equal(read_matrix_csv(bom, option), plain)


def test_analyze_matrix_with_a_byte_order_mark(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = []
    for path in (DATA / "paper_eq22.csv", _with_bom(DATA / "paper_eq22.csv", tmp_path)):
        assert main(["analyze", "--matrix", str(path), "--json"]) == 0
        results.append(json.loads(capsys.readouterr().out)["stiffness_matrix"])
    assert results[0] == results[1]


@pytest.mark.parametrize(
    ("name", "drop"),
    [
        ("src/ppm_stiffness/data/measurements_synthetic_planar.csv", False),
        ("examples/identification/measurements.csv", False),
        ("examples/identification/measurements.csv", True),
        ("examples/identification/3rps_measurements.csv", True),
    ],
)
def test_measurements_with_a_byte_order_mark(tmp_path: Path, name: str, drop: bool) -> None:
    """deflect --measurements and identify --measurements (read_measurements), with the
    mark before a comment or before the header."""
    source = ROOT / name
    plain = read_measurements(source)
    bom = read_measurements(_with_bom(source, tmp_path, drop))
    assert bom.components == plain.components and bom.pose_columns == plain.pose_columns
    np.testing.assert_array_equal(bom.twists, plain.twists)
    for field in ("loads", "poses", "wrenches", "sigmas"):
        a, b = getattr(plain, field), getattr(bom, field)
        assert (a is None) == (b is None)
        if a is not None:
            np.testing.assert_array_equal(b, a)


def test_force_displacement_with_a_byte_order_mark(tmp_path: Path) -> None:
    """fit-actuator DATA.csv (read_force_displacement)."""
    source = DATA / "actuator_synthetic.csv"
    plain = read_force_displacement(source)
    for drop in (False, True):
        bom = read_force_displacement(_with_bom(source, tmp_path, drop))
        np.testing.assert_array_equal(bom.displacement_m, plain.displacement_m)
        np.testing.assert_array_equal(bom.force_n, plain.force_n)
        assert bom.displacement_unit == plain.displacement_unit


def test_tolerance_file_with_a_byte_order_mark(tmp_path: Path) -> None:
    """--tolerances FILE.toml (read_tolerances), as the design file already was."""
    source = ROOT / "examples/identification/tolerances.toml"
    assert read_tolerances(_with_bom(source, tmp_path)) == read_tolerances(source)


def test_a_file_that_is_not_utf8_is_still_refused(tmp_path: Path) -> None:
    path = tmp_path / "latin1.csv"
    path.write_bytes("# caf\xe9\n1,2\n".encode("latin-1"))
    with pytest.raises(InputDataError, match="cannot read"):
        read_matrix_csv(path)


# -- help text of the spatial era (item 13) ---------------------------------------------


def test_top_level_help_is_not_planar_only(capsys: pytest.CaptureFixture[str]) -> None:
    """It said "Stiffness of compliant planar parallel manipulators"."""
    assert main(["--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "compliant planar parallel manipulators" not in text
    assert "planar (3-PPR, 3-RPR, ...) and spatial (hexapods" in text


def test_map_help_names_the_spatial_quantities(capsys: pytest.CaptureFixture[str]) -> None:
    """`map`'s help named only k_phi, k_x, k_y; every quantity a map of any design may
    show (maps.result.QUANTITIES) is now named in `map --help`."""
    from ppm_stiffness.maps.result import QUANTITIES

    assert main(["map", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    for name in QUANTITIES:
        assert name.replace("_", "-") in text or name in text, name
    assert main(["--help"]) == 0
    top = " ".join(capsys.readouterr().out.split())
    assert "spatial principal stiffnesses (rotational_min/mid/max" in top


def test_equilibrium_docstring_documents_the_poses_it_takes() -> None:
    """`equilibrium` takes task coordinates or a full 6-D pose and returns a 6-D pose;
    its docstring said ``pose : array_like (3,) [m, m, rad]``."""
    from ppm_stiffness.statics import equilibrium as module

    for doc in (module.__doc__, module.equilibrium.__doc__, module.Equilibrium.__doc__):
        assert doc is not None and "(3,)" not in doc
    assert "pose : array_like (n_task,) or (6,) [m, rad]" in (module.equilibrium.__doc__ or "")
    hexapod = load_design(HEXAPOD)
    pose = np.array([0.002, -0.001, 0.2, 0.01, -0.02, 0.03])
    state = module.equilibrium(hexapod, [0, 0, 0, 0, 0, -10.0], pose)
    np.testing.assert_array_equal(state.pose, pose)
