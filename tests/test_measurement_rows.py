"""Measurement files: an error about a row names the file and the row's line (1-based,
as a text editor counts, comments and header included), and a file's stated loading
mode is checked before a deflection curve is computed."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import ppm_stiffness.statics.deflection as deflection
from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import default_design
from ppm_stiffness.fit.identify import measurement_rows
from ppm_stiffness.statics.measurements import read_measurements

ROOT = Path(__file__).parents[1]
PLANAR = ROOT / "src/ppm_stiffness/data/measurements_synthetic_planar.csv"
IDENTIFICATION = ROOT / "examples/identification/measurements.csv"


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and err.startswith("ppm-stiffness: error: ")
    return err


def test_a_mode_mismatch_is_named_before_any_load_is_computed(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The planar-force file's loads (1-10 N) read as moments [N·m] gave "load too
    large"; now the mode its '# mode:' line states is compared first."""

    def no_curve(*args: object, **kwargs: object) -> None:
        raise AssertionError("the curve must not be computed")

    monkeypatch.setattr(deflection, "deflection_curve", no_curve)  # imported when run
    assert main(["deflect", "--mode", "moment", "--measurements", str(PLANAR)]) == 2
    err = _one_line(capsys)
    assert (
        f"{PLANAR}: the measurements are for mode 'planar-force' (its '# mode:' line), the "
        "model curve for 'moment'" in err
    )
    assert main(["deflect", "--alpha", "30", "--measurements", str(PLANAR)]) == 2
    assert "the measurements are for alpha = 45 deg" in _one_line(capsys)


@pytest.mark.parametrize(
    ("comment", "message"),
    [
        ("# mode: planar", "line 2: '# mode: planar' names no loading mode; expected one of"),
        ("# alpha_deg: abc", "line 2: '# alpha_deg: abc' is not a finite number"),
    ],
)
def test_malformed_metadata_names_its_line(tmp_path: Path, comment: str, message: str) -> None:
    path = tmp_path / "m.csv"
    path.write_text(f"# a note\n{comment}\nload,x_mm\n1,0.1\n", encoding="utf-8")
    with pytest.raises(InputDataError, match="^" + re.escape(f"{path}, {message}")):
        read_measurements(path)


@pytest.mark.parametrize(
    ("row", "message"),
    [
        ("2,abc", "line 6, column 'x_mm': 'abc' is not numeric"),
        ("2,0.1,3", "line 6: 3 fields, the header has 2"),
        ("-2,0.1", "line 6: load -2: loads must be >= 0"),
    ],
)
def test_a_malformed_row_names_its_line(tmp_path: Path, row: str, message: str) -> None:
    """Two comment lines, the header, one good row and a blank line come first: the
    bad row is line 6 (it was 'data row 2')."""
    path = tmp_path / "m.csv"
    text = f"# mode: moment\n# measured today\nload,x_mm\n1,0.05\n\n{row}\n"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputDataError, match="^" + re.escape(f"{path}, {message}")):
        read_measurements(path)


def _identification_file(tmp_path: Path, edit: str) -> Path:
    """The shipped identification data with line 13 (its third data row) changed:
    ``pose`` moves it out of the workspace, ``load`` makes its force 80 kN, ``zero``
    removes its load."""
    lines = IDENTIFICATION.read_text(encoding="utf-8").splitlines()
    fields = lines[12].split(",")
    if edit == "pose":
        fields[0] = "500"  # pose_x_mm
    elif edit == "load":
        fields[3:9] = ["80000", "0", "0", "0", "0", "0"]
    else:
        fields[3:9] = ["0"] * 6
    lines[12] = ",".join(fields)
    path = tmp_path / f"{edit}.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        ("pose", "line 13: leg 1: rod free length"),
        ("load", "line 13: load too large: actuator"),
        ("zero", "line 13: a zero wrench"),
    ],
)
def test_identify_names_the_file_and_line_of_a_bad_row(
    tmp_path: Path, edit: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _identification_file(tmp_path, edit)
    argv = ["identify", "--measurements", str(path), "--free", "leg1.guide.yaw"]
    assert main(argv) == 2
    assert f"error: {path}, {message}" in _one_line(capsys)


def test_measurement_rows_carry_their_lines() -> None:
    rows = measurement_rows(default_design(), read_measurements(IDENTIFICATION))
    assert rows.labels[0] == f"{IDENTIFICATION}, line 11" and len(rows.labels) == rows.n_rows
    assert rows.repeated(2).labels == rows.labels * 2


def test_an_actuator_data_row_names_its_line(tmp_path: Path) -> None:
    """fit-actuator's reader counted rows from the header, not lines: with two comment
    lines the bad row (line 6) was called 'data row 4'."""
    from ppm_stiffness.statics.actuator_fit import read_force_displacement

    path = tmp_path / "a.csv"
    path.write_text(
        "# load cell\n# 2024\ndisplacement_mm,force_N\n0.01,3.5\n0.02,4.0\n0.03,x\n",
        encoding="utf-8",
    )
    with pytest.raises(InputDataError, match="^" + re.escape(f"{path}, line 6: not numeric")):
        read_force_displacement(path)
