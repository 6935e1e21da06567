"""CLI options that issue 27's attack found silently accepted: unit slips (an angle
beyond a turn, a length far beyond the design's size, metres mixed with mm) and options
ignored in the combination given. Each is refused: exit 2, one stderr line naming the
option, the value and what is valid or likely meant, nothing written. Before the fix
every one of these ran (exit 0), e.g. ``map --bounds=-500,500,-500,500`` on the 3-RPS
reported "4.0% in the workspace" and ``analyze --rz 5730`` printed phi = 5730 deg."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.cli.common import design_size_mm
from ppm_stiffness.design import default_design
from ppm_stiffness.statics.measurements import Measurements

ROOT = Path(__file__).resolve().parents[1]
RPS = str(ROOT / "examples" / "3rps.toml")


def _refused(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (out, err)
    lines = [line for line in err.splitlines() if line]
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("ppm-stiffness: error: ")
    return lines[0]


def test_the_design_size_bounds_every_joint_distance() -> None:
    """The size the length refusals compare with (442 mm for the built-in 3-PPR, as the
    messages below print) is the largest distance between two joints at home: every
    leg's base and platform joints lie within it of each other."""
    import numpy as np

    from ppm_stiffness.poses import home_pose
    from ppm_stiffness.visuals.leg_geometry import mechanism_view

    design = default_design()
    view = mechanism_view(design, home_pose(design))
    points = np.vstack([np.array(list(v.points.values())).reshape(-1, 3) for v in view.legs])
    far = max(float(np.linalg.norm(a - b)) for a in points for b in points)
    assert far <= 1e-3 * design_size_mm(design) * (1 + 1e-12)
    assert 1e3 * far == pytest.approx(442.2, abs=0.05)  # the figure the messages print


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        # angles beyond +-360 deg: the mrad reading offered (5730 mrad = 328.3 deg)
        (
            ["analyze", "--rz", "5730"],
            "--rz 5730 deg: beyond +-360 deg; the option takes "
            "degrees (if these are mrad, write 328.3)",
        ),
        (["analyze", "--phi", "-400"], "--phi -400 deg: beyond +-360 deg"),
        (["validate", "--angle", "400", "--poses", "1"], "--angle 400 deg: beyond +-360 deg"),
        (
            [
                "map",
                "--design",
                RPS,
                "--axes",
                "rx,ry",
                "--grid",
                "5",
                "--bounds=-500,500,-500,500",
            ],
            "--bounds rx -500 deg: beyond +-360 deg; the option takes degrees (if these "
            "are mrad, write -28.65)",
        ),
        # lengths: um typed as mm (10 m, 22 times the 3-PPR's 442 mm), m mixed with mm
        (
            ["map", "--grid", "5", "--bounds=-10000,10000,-10000,10000"],
            "--bounds x -10000 mm: beyond 10 times the design's size (442 mm",
        ),
        (
            ["map", "--grid", "5", "--bounds=-0.5,0.5,-0.5,0.5e3"],
            "--bounds: x within +-0.5 mm but y up to 500 mm: both are in mm (if x's ends "
            "are metres, write -500,500)",
        ),
        (
            ["deflect", "--threshold", "6000"],
            "--threshold 6000 mm: beyond the design's size (442 mm",
        ),
    ],
)
def test_unit_slips_are_refused_with_the_likely_value(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str], expected: str
) -> None:
    written = ["--data", str(tmp_path / "m.csv")] if argv[0] == "map" else []
    line = _refused(capsys, argv + written)
    assert expected in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["analyze", "--samples", "8"], "--samples 8: it counts the QMC samples"),
        (["analyze", "--tolerance-method", "qmc"], "--tolerance-method qmc: it sets how"),
        (
            ["analyze", "--tolerances", "t.toml", "--samples", "8"],
            "--samples 8: it counts the QMC samples, unused with --tolerance-method "
            "first-order; add --tolerance-method qmc",
        ),
        (
            ["deflect", "--mode", "moment", "--alpha", "30"],
            "--alpha 30: it sets the direction of the planar force, unused with --mode moment",
        ),
        (["deflect", "--max", "1", "--step", "5"], "--step 5 is larger than --max 1"),
        (
            ["map", "--grid", "5", "--reference-force", "5"],
            "--reference-force 5: it sets the actuator load that defines --actuators min, "
            "unused with --actuators max",
        ),
    ],
)
def test_ignored_options_are_refused(
    capsys: pytest.CaptureFixture[str], argv: list[str], expected: str
) -> None:
    assert expected in _refused(capsys, argv)


def test_the_same_options_where_they_count_still_work(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Legitimate neighbours of the refusals: an angle within a turn is taken as given
    (phi printed as 30 deg), --alpha with the planar force, --step equal to --max."""
    assert main(["analyze", "--rz", "30"]) == 0
    assert "phi = 30.000 deg" in capsys.readouterr().out
    assert main(["deflect", "--alpha", "30", "--max", "1", "--step", "1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["alpha_deg"] == pytest.approx(30.0, rel=1e-12)


def test_compare_quiet_prints_nothing_on_stderr(capsys: pytest.CaptureFixture[str]) -> None:
    """Before, ``compare --quiet`` still printed "1 designs in 1.07 s (serial)"."""
    argv = ["compare", "--design", str(ROOT / "examples" / "symmetric_3ppr.toml")]
    argv += ["--region=-5,5,-5,5,-2,2,2,2,2", "--quiet", "--link-modes", "0"]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert err == "" and "symmetric" in out.lower()


PLANAR = ROOT / "src" / "ppm_stiffness" / "data" / "measurements_synthetic_planar.csv"


def _scaled_positions(tmp_path: Path, factor: float) -> Path:
    """The shipped planar measurements with x_mm and y_mm multiplied by ``factor``."""
    lines = []
    for line in PLANAR.read_text(encoding="utf-8").splitlines():
        if line and not line.startswith(("#", "load")):
            f = line.split(",")  # load, phi_z_deg, x_mm, y_mm
            f[2:4] = [f"{float(v) * factor:.6g}" for v in f[2:4]]
            line = ",".join(f)
        lines.append(line)
    path = tmp_path / f"m{factor:g}.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_column_named_twice_is_refused_by_every_header_reader(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """``fit-actuator`` took the first of two ``force_N`` columns silently (issue 27's
    attack); the measurements reader had its own check, now shared (csvio)."""
    path = tmp_path / "f.csv"
    path.write_text("displacement_mm,force_N,force_N\n0.1,1,9\n0.2,2,9\n0.3,3,9\n")
    out = tmp_path / "fit.png"
    line = _refused(capsys, ["fit-actuator", str(path), "--plot", str(out)])
    assert "column 'force_N' appears more than once (columns 2 and 3)" in line
    assert not out.exists()
    meas = tmp_path / "m.csv"
    meas.write_text("# mode: planar-force\nload,x_mm,y_mm,x_mm\n1,0.1,0.1,0.1\n")
    line = _refused(capsys, ["deflect", "--measurements", str(meas)])
    assert "column 'x_mm' appears more than once (columns 2 and 4)" in line


def test_measured_deflections_beyond_the_design_are_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """The shipped planar data (up to 0.7918 mm) in um under the x_mm header: 791.8 mm,
    beyond the 3-PPR's 442 mm; before, deflect compared them with the model silently."""
    line = _refused(capsys, ["deflect", "--measurements", str(_scaled_positions(tmp_path, 1e3))])
    assert "line 19: x_mm = 791.8 mm, beyond the design's size (442 mm" in line
    assert "if these are um, divide by 1000" in line


def test_large_measured_deflections_are_warned_of() -> None:
    """Between a tenth of the design's size and the size: a warning naming the row and
    the value (71.3 mm = 90 x 0.7918 mm, beyond 44.2 mm), not a refusal."""
    from ppm_stiffness.statics.actuator_fit import ImplausibleDataWarning
    from ppm_stiffness.statics.measurements import check_displacement_scale, read_measurements

    size = 1e-3 * design_size_mm(default_design())
    meas = read_measurements(PLANAR)
    check_displacement_scale(meas, size)  # the shipped data: nothing to say
    big = Measurements(meas.loads, meas.twists * 90, meas.components, source="m.csv")
    with pytest.warns(ImplausibleDataWarning, match=r"x_mm = 71\.26\d* mm, more than 10%"):
        check_displacement_scale(big, size)


def test_a_threshold_beyond_the_stroke_is_named_in_the_options_unit(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``deflect --threshold 60`` (mm) on the built-in design, whose strokes are 50 mm:
    one line in mm, the design check's reason given once (it read
    "actuator.threshold_displacement = 0.06: actuator.threshold_displacement = 0.06: ...;
    did you mean 6e-05 (mm)?", a hint in the design key's metres)."""
    assert main(["deflect", "--mode", "planar-force", "--threshold", "60"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert "--threshold 60 mm: beyond the actuator's stroke (0.05 m)" in err
    assert "threshold_displacement" not in err and "did you mean" not in err


def test_check_value_names_the_parameter_once() -> None:
    """A leg-level check's message starts with its own key; check_value gives the full
    name once."""
    from ppm_stiffness.core.errors import DesignError
    from ppm_stiffness.design import default_design

    with pytest.raises(DesignError, match=r"^actuator\.threshold_displacement = 6: beyond") as e:
        default_design().check_value("actuator.threshold_displacement", 6.0)
    assert str(e.value).count("threshold_displacement") == 1
