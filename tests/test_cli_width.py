"""Every command's output fits 80 columns at its defaults: rendered at width 80, no line
is longer and no cell is cut short with an ellipsis."""

from __future__ import annotations

from pathlib import Path

import pytest

from ppm_stiffness.cli import COMMANDS, main
from ppm_stiffness.cli.common import console

ROOT = Path(__file__).parents[1]
DATA = ROOT / "src" / "ppm_stiffness" / "data"

#: Command lines at their defaults (plus what each requires); ``{tmp}`` is a scratch dir.
LINES = [
    ["analyze"],
    ["analyze", "--wrench", "5,5,20,0,0,0.1"],
    [
        "analyze",
        "--design",
        str(ROOT / "examples/redundant_4ppr.toml"),
        "--wrench",
        "5,5,20,0,0,0.1",
    ],
    ["analyze", "--design", str(ROOT / "examples/3rrr.toml")],
    ["calibrate", "--list-parameters"],
    [
        "calibrate",
        "--target",
        str(DATA / "paper_eq22.csv"),
        "--free",
        "leg*.actuator.threshold_displacement,leg1.psi",
    ],
    ["fit-actuator", str(DATA / "actuator_synthetic.csv")],
    ["deflect"],
    ["deflect", "--design", str(ROOT / "examples/3rrr.toml"), "--mode", "moment"],
    ["map"],
    ["map", "--design", str(ROOT / "examples/hexapod_6ups.toml"), "--grid", "20"],
    ["map", "--design", str(ROOT / "examples/3prs.toml"), "--axes", "rx,ry", "--grid", "20"],
    [
        "map",
        "--design",
        str(ROOT / "examples/3rps.toml"),
        "--grid",
        "20",
        "--actuators=0,0,0,0,0,-100",
    ],
    ["springs", "--out", "{tmp}/springs.png"],
    ["mechanism", "--out", "{tmp}/mechanism.png"],
    ["report", "--out", "{tmp}/report", "--grid", "10"],
    ["validate", "--poses", "1"],  # the table's width does not depend on its rows
    [
        "compare",
        *(
            f"--design={ROOT / 'examples' / n}.toml"
            for n in ("3prr", "3rpr", "3rrr", "redundant_4ppr")
        ),
        "--design",
        str(ROOT / "examples/symmetric_3ppr.toml"),
        "--region=-10,10,-10,10,-5,5,3,3,2",
        "--wrench",
        "5,5,0,0,0,0.1",
        "--link-modes",
        "0",
    ],
    [
        "sweep",
        "--design",
        str(ROOT / "examples/3rpr.toml"),
        "--vary",
        "leg*.platform_radius=0.05:0.07:3",
        "--vary",
        "leg*.housing_length=0.08:0.1:2",
        "--vary",
        "leg1.actuator.locked_stiffness=1e7:2e7:2",
        "--region=-10,10,-10,10,0,0,3,3,1",
        "--link-modes",
        "0",
    ],
    [
        "optimize",
        "--design",
        str(ROOT / "examples/symmetric_3ppr.toml"),
        "--vary",
        "leg*.platform_radius=0.02:0.04",
        "--vary",
        "leg1.actuator.locked_stiffness=5e4:5e5",
        "--budget",
        "10",
        "--region=-10,10,-10,10,0,0,3,3,1",
        "--out",
        "{tmp}/best.toml",
    ],
    [
        "identify",
        "--measurements",
        str(ROOT / "examples/identification/measurements.csv"),
        "--free",
        "leg1.guide.yaw,leg2.guide.yaw,leg*.actuator.locked_stiffness",
    ],
    ["analyze", "--tolerances", str(ROOT / "examples/identification/tolerances.toml")],
    # spatial designs: six legs' actuators, the 6-D pose, a load along a direction
    [
        "deflect",
        "--design",
        str(ROOT / "examples/hexapod_6ups.toml"),
        "--direction",
        "100,-50,200,5,-3,2",
        "--tool-point",
        "10,-20,50",
    ],
    ["deflect", "--design", str(ROOT / "examples/3prs.toml"), "--rx", "5", "--mode", "moment"],
    [  # both curves' tables; the round-off components once cut the load header
        "deflect",
        "--design",
        str(ROOT / "examples/3prs.toml"),
        "--direction",
        "0,0,-1,0,0,0",
        "--geometry",
        "moving",
    ],
    [
        "identify",
        "--design",
        str(ROOT / "examples/3rps.toml"),
        "--measurements",
        str(ROOT / "examples/identification/3rps_measurements.csv"),
        "--free",
        "leg1.actuator.k_a,leg2.actuator.k_a,leg3.actuator.k_a,leg*.base_revolute.tilt,"
        "leg*.guide.lateral",
    ],
    ["modes"],
    ["modes", "--design", str(ROOT / "examples/3prs.toml"), "--wrench", "5,5,20,0,0,0.1"],
]


def test_every_command_is_covered() -> None:
    assert {line[0] for line in LINES} == set(COMMANDS)


@pytest.mark.parametrize("argv", LINES, ids=lambda a: " ".join(a[:3]))
def test_output_fits_80_columns(
    argv: list[str],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    if argv[0] == "validate":
        pytest.importorskip("Pynite", reason="PyNite is in the 'validate' extra")
    monkeypatch.setattr(console, "width", 80)
    code = main([a.replace("{tmp}", str(tmp_path)) for a in argv])
    out, err = capsys.readouterr()
    assert code == 0, err
    lines = out.splitlines()
    assert lines
    too_long = [line for line in lines if len(line) > 80]
    assert not too_long, too_long
    assert not [line for line in lines if "…" in line]
