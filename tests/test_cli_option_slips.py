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


def test_the_design_size_is_the_largest_joint_distance() -> None:
    """The built-in 3-PPR's size: 442 mm (the largest distance between two joints at
    home, printed in the refusals below): a bound for the slips, not a result."""
    assert design_size_mm(default_design()) == pytest.approx(442.2, abs=0.05)


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
    argv += ["--region=-5,5,-5,5,-2,2,2,2,2", "--quiet"]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert err == "" and "symmetric" in out.lower()
