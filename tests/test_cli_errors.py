"""Bad command lines give one line on stderr and exit code 2, never a usage block or a
traceback: argparse's own errors (every command), seeds out of numpy's range, and an
FE solve PyNite cannot carry out."""

from __future__ import annotations

from pathlib import Path

import pytest
import tomli_w

from ppm_stiffness.cli import COMMANDS, main
from ppm_stiffness.core.errors import SingularConfigurationError
from ppm_stiffness.design import design_from_dict, load_design
from ppm_stiffness.design.io import design_to_dict

ROOT = Path(__file__).parents[1]
SYMMETRIC = str(ROOT / "examples/symmetric_3ppr.toml")
REGION = "--region=-10,10,-10,10,-5.7,5.7,3,3,3"


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith("ppm-stiffness: error: ") and "usage:" not in err
    return err


@pytest.mark.parametrize("command", [None, *COMMANDS])
def test_an_unknown_option_is_one_line_with_the_help_hint(
    command: str | None, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ([] if command is None else [command]) + ["--no-such-option"]
    assert main(argv) == 2
    err = _one_line(capsys)
    prog = "ppm-stiffness" if command is None else f"ppm-stiffness {command}"
    # argparse reports missing required arguments first (fit-actuator's DATA.csv, ...)
    assert "unrecognized arguments: --no-such-option" in err or "are required: " in err
    assert err.rstrip().endswith(f"see `{prog} --help`")


@pytest.mark.parametrize(
    ("argv", "message", "prog"),
    [
        ([], "the following arguments are required: COMMAND", "ppm-stiffness"),
        (["nosuch"], "invalid choice: 'nosuch'", "ppm-stiffness"),
        (["map", "--grid", "x"], "argument --grid: invalid int value: 'x'", "ppm-stiffness map"),
        (
            ["deflect", "--mode", "twist"],
            "argument --mode: invalid choice",
            "ppm-stiffness deflect",
        ),
        (["identify"], "required: --measurements, --free", "ppm-stiffness identify"),
    ],
)
def test_argparse_errors_are_one_line(
    argv: list[str], message: str, prog: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    err = _one_line(capsys)
    assert message in err and err.rstrip().endswith(f"see `{prog} --help`")


@pytest.mark.parametrize(
    "argv",
    [
        ["validate", "--poses", "0"],
        ["sweep", "--design", SYMMETRIC, REGION, "--sample", "sobol:4"]
        + ["--vary", "leg*.platform_radius=0.02:0.04"],
        ["optimize", "--design", SYMMETRIC, REGION, "--out", "{d}/best.toml"]
        + ["--vary", "leg*.platform_radius=0.02:0.06"],
        ["calibrate", "--target", str(ROOT / "src/ppm_stiffness/data/paper_eq22.csv")]
        + ["--free", "leg1.guide.yaw", "--starts", "2"],
    ],
    ids=["validate", "sweep", "optimize", "calibrate"],
)
@pytest.mark.parametrize("seed", ["-1", "x"])
def test_a_seed_out_of_range_names_the_option_and_the_range(
    argv: list[str], seed: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """numpy's SeedSequence takes integers >= 0 only: a negative seed was a traceback."""
    args = [a.replace("{d}", str(tmp_path)) for a in argv]
    assert main([*args, "--seed", seed]) == 2
    err = _one_line(capsys)
    assert "argument --seed: a seed is an integer >= 0" in err
    assert list(tmp_path.iterdir()) == []


def _rigid_3rpr(tmp_path: Path) -> Path:
    """The 3-RPR example with every Young's modulus 1e20 Pa (near-rigid links)."""
    data = design_to_dict(load_design(ROOT / "examples/3rpr.toml"))
    for part in ("proximal", "distal"):
        data["parts"][part]["young_modulus"] = 1e20
    design_from_dict(data)  # a valid design: the virtual-joint model accepts it
    path = tmp_path / "rigid.toml"
    path.write_text(tomli_w.dumps(data), encoding="utf-8")
    return path


def test_an_fe_solve_pynite_cannot_carry_out_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """PyNite raised a bare Exception ("stiffness matrix is singular") for moduli of
    1e20 Pa: now SingularConfigurationError, one line and exit 2 at the CLI."""
    pytest.importorskip("Pynite", reason="validate needs the 'validate' extra (PyNite)")
    from ppm_stiffness.model import workspace_centre
    from ppm_stiffness.validation.fe_model import fe_stiffness_at_pose

    path = _rigid_3rpr(tmp_path)
    design = load_design(path)
    with pytest.raises(SingularConfigurationError, match="ill-conditioned"):
        fe_stiffness_at_pose(design, workspace_centre(design))
    csv = tmp_path / "v.csv"
    assert main(["validate", "--design", str(path), "--poses", "0", "--csv", str(csv)]) == 2
    err = _one_line(capsys)
    assert "FE model: PyNite finds the frame's stiffness matrix singular" in err
    assert "1e20 Pa" in err and not csv.exists()


@pytest.mark.parametrize(
    ("region", "message"),
    [
        # metres where the option takes mm: 0.02 mm across was accepted
        (
            "-0.01,0.01,-0.01,0.01,-1,1,3,3,3",
            "--region X0,X1 = -0.01,0.01 mm: 0.02 mm across, less than 0.1 mm; the option "
            "takes mm: were these metres (-10,10 mm)?",
        ),
        # errors in the option's units, not the design file's radians and metres
        (
            "-10,10,-10,10,-1000,1000,3,3,3",
            "--region PHI0,PHI1 = -1000,1000 deg: beyond +-180 deg",
        ),
        ("-1e5,10,-10,10,-1,1,3,3,3", "--region X0,X1 = -100000,10 mm: beyond +-1000 mm"),
        ("10,-10,-10,10,-1,1,3,3,3", "--region X0,X1 = 10,-10 mm: inverted range (X0 > X1)"),
        ("-10,10,-10,10,2,2,3,3,3", "--region PHI0,PHI1 = 2,2 deg with NPHI = 3"),
        ("-10,10,-10,10,-1,1,0,3,3", "NX, NY, NPHI must be between 1 and 1000, got [0, 3, 3]"),
    ],
)
def test_region_errors_speak_the_options_units(
    region: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["compare", f"--region={region}", "--quiet"]) == 2
    err = _one_line(capsys)
    assert message in err
    assert "radian" not in err and "metres (a region" not in err


def test_a_region_of_metre_like_values_is_warned_about(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # 0.1 mm across passes (the threshold), without a warning when y spans 20 mm
    assert main(["compare", "--region=0,0.1,-10,10,0,0,2,3,1", "--quiet", "--link-modes", "0"]) == 0
    assert capsys.readouterr().err.count("warning") == 0
    assert (
        main(["compare", "--region=-0.5,0.5,-0.5,0.5,-1,1,3,3,3", "--quiet", "--link-modes", "0"])
        == 0
    )
    err = capsys.readouterr().err
    assert "warning: --region: x and y within +-1 mm; the option takes mm (if these are " in err
    assert "metres, write -500,500,-500,500)" in err
