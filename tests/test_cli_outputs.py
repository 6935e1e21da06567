"""What every writing command shares: existing files are refused without --overwrite,
the installed package is read-only, negative numbers work in comma lists, and the
table number format (engineering notation, never ``-0``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import join_negative_values, main
from ppm_stiffness.cli.common import eng

PACKAGE = Path(__file__).parents[1] / "src" / "ppm_stiffness"

#: (command arguments before the output path, the output option, file name)
WRITERS = [
    (["springs"], "--out", "springs.png"),
    (["mechanism"], "--out", "mechanism.png"),
    (["map", "--grid", "4"], "--out", "map.png"),
    (["map", "--grid", "4"], "--data", "map.csv"),
    (["deflect", "--mode", "moment"], "--csv", "curve.csv"),
    (["fit-actuator"], "--plot", "fit.png"),
    (
        [
            "calibrate",
            "--target",
            str(PACKAGE / "data/paper_eq22.csv"),
            "--free",
            "leg1.guide.lateral",
        ],
        "--out",
        "c.toml",
    ),
]


@pytest.mark.parametrize(("args", "option", "name"), WRITERS)
def test_existing_output_is_refused_and_kept(
    args: list[str], option: str, name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / name
    target.write_text("keep me")
    if args[0] == "fit-actuator":
        args = [*args, str(PACKAGE / "data/actuator_synthetic.csv")]
    code = main([*args, option, str(target)])
    err = capsys.readouterr().err
    assert code == 2
    assert "file exists; pass --overwrite" in err
    assert target.read_text() == "keep me"


def test_overwrite_replaces(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "map.csv"
    target.write_text("old")
    code = main(["map", "--grid", "4", "--data", str(target), "--overwrite", "--quiet"])
    assert code == 0, capsys.readouterr().err
    assert target.read_text().startswith(("#", "x"))


def test_report_refuses_an_existing_report(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "report.html").write_text("keep me")
    code = main(["report", "--out", str(tmp_path), "--grid", "4", "--quiet"])
    assert code == 2
    assert "file exists" in capsys.readouterr().err
    assert (tmp_path / "report.html").read_text() == "keep me"


def test_package_data_is_read_only(capsys: pytest.CaptureFixture[str]) -> None:
    target = PACKAGE / "data" / "new_design.toml"
    code = main(
        [
            "calibrate",
            "--target",
            str(PACKAGE / "data/paper_eq22.csv"),
            "--free",
            "leg1.guide.lateral",
        ]
        + ["--out", str(target)]
    )
    assert code == 2
    assert "read-only" in capsys.readouterr().err
    assert not target.exists()


def test_negative_numbers_in_comma_lists_need_no_equals(
    capsys: pytest.CaptureFixture[str],
) -> None:
    joined = main(["analyze", "--json", "--wrench", "-5,5,20,0,0,0.1"])
    out_joined = capsys.readouterr().out
    with_equals = main(["analyze", "--json", "--wrench=-5,5,20,0,0,0.1"])
    out_equals = capsys.readouterr().out
    assert joined == with_equals == 0
    assert out_joined == out_equals


def test_join_negative_values_leaves_other_arguments_alone() -> None:
    assert join_negative_values(["--x", "-3", "--y", "4", "-q", "--a=-1,2"]) == [
        "--x=-3",
        "--y",
        "4",
        "-q",
        "--a=-1,2",
    ]


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (0.0, "0"),
        (-0.0, "0"),
        (-1e-30 * 0, "0"),
        (75.629, "75.63"),
        (142290.0, "142.3e3"),
        (-4.1e-6, "-4.1e-6"),
        (999.96, "1e3"),
        (0.00123, "1.23e-3"),
        (float("nan"), "nan"),
    ],
)
def test_engineering_notation(value: float, text: str) -> None:
    assert eng(value) == text


def test_unreachable_pose_names_what_is_reachable(capsys: pytest.CaptureFixture[str]) -> None:
    """The message gives the x, y extent at the asked phi and the phi range at the asked
    (x, y); poses just inside that phi range are reachable, poses 0.2 deg outside not."""
    import re

    from ppm_stiffness.core.errors import UnreachablePoseError
    from ppm_stiffness.design import default_design
    from ppm_stiffness.maps.workspace import workspace_bounds
    from ppm_stiffness.model import solve_legs

    assert main(["analyze", "--phi", "90"]) == 2
    err = capsys.readouterr().err
    assert "no position is reachable at phi = 90 deg" in err
    lo, hi = (float(v) for v in re.search(r"phi may be in \[(\S+), (\S+)\] deg", err).groups())
    design = default_design()
    for phi in (lo, hi):
        solve_legs(design, [0.0, 0.0, np.radians(phi)])
    for phi in (lo - 0.2, hi + 0.2):
        with pytest.raises(UnreachablePoseError, match=r"leg \d: actuator coordinate .* outside"):
            solve_legs(design, [0.0, 0.0, np.radians(phi)])

    assert main(["analyze", "--x", "100"]) == 2
    err = capsys.readouterr().err
    box = 1e3 * workspace_bounds(design, 0.0)
    assert f"x in [{box[0]:.2f}, {box[1]:.2f}] mm, y in [{box[2]:.2f}, {box[3]:.2f}] mm" in err
    assert "no orientation is reachable at (100.00, 0.00) mm" in err


def test_a_numerical_warning_is_one_sentence(capsys: pytest.CaptureFixture[str]) -> None:
    """A RuntimeWarning raised inside a command reaches the user as one line naming the
    file and line it came from, not as numpy's two-line source dump."""
    import warnings

    from ppm_stiffness.cli import _one_line_warning

    with warnings.catch_warnings():
        warnings.showwarning = _one_line_warning
        warnings.simplefilter("always")
        np.divide(np.ones(1), np.zeros(1))
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith("ppm-stiffness: warning: a numerical routine reported ")
    assert "'divide by zero encountered in divide' (at test_cli_outputs.py:" in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        # before: "parameters: key 'leg1.actuator.q': ..." blamed the design file
        (["deflect", "--q", "2"], "--q: actuator.q = 2: Input should be less than or equal to 1"),
        # before: a range in degrees was accepted silently
        (
            ["calibrate", "--target", str(PACKAGE / "data/paper_eq22.csv"), "--free", "leg1.alpha"]
            + ["--bound", "leg1.alpha=0:90"],
            "alpha = 90: angles in design files are in radians (|angle| <= 2 pi); "
            "did you mean 1.5708?",
        ),
        # before: accepted, peaking at 11 GB
        (["map", "--grid", "10000"], "--grid 10000: about 11 GB of memory estimated"),
    ],
)
def test_input_mistakes_name_the_option_and_the_valid_range(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
