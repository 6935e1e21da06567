"""CLI, in process: analyze / calibrate tables, JSON keys, and every bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import wide_design
from paper import EQ22, PAPER_WRENCH
from ppm_stiffness.analysis import analyze_design
from ppm_stiffness.cli import main
from ppm_stiffness.design import default_design, dump_design, save_design
from ppm_stiffness.statics.loading import loaded_state

EQ22_CSV = str(Path(__file__).parents[1] / "src/ppm_stiffness/data/paper_eq22.csv")


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_analyze_prints_all_tables(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "analyze")
    assert code == 0, err
    for heading in (
        "Cartesian stiffness K",
        "N·m/rad",
        "Screw springs",
        "M [N/m]",
        "d [mm]",
        "K'_rr",
        "K'_tt",
        "Principal stiffnesses",
        "k_phi =",
    ):
        assert heading in out
    # K_tt(x, x) of (22) appears with its value, in engineering notation
    assert "34.57e3" in out


def test_analyze_json_keys_and_values(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "analyze", "--json", "--x", "2", "--y", "-3", "--phi", "5")
    assert code == 0
    data = json.loads(out)
    assert set(data) >= {
        "pose",
        "actuator_stiffness",
        "stiffness_matrix",
        "eigenscrews",
        "decoupling",
        "principal",
    }
    five = np.radians(5)
    assert data["pose"] == pytest.approx(
        {"x": 0.002, "y": -0.003, "z": 0, "rx": 0, "ry": 0, "rz": five, "phi": five}
    )
    assert len(data["eigenscrews"]) == 6
    assert set(data["eigenscrews"][0]) == {
        "eigenvalue",
        "eigenforce",
        "pitch",
        "axis",
        "position",
        "spring_constant",
    }
    assert set(data["decoupling"]) >= {"M", "d", "K_rr", "K_tt", "residual_coupling"}
    assert data["decoupling"]["method"] == "paper"
    assert set(data["principal"]) == {"rotational", "translational"}
    # directions[j] is the unit direction of values[j]: an eigenpair of K'_rr / K'_tt
    for block, key in (("rotational", "K_rr"), ("translational", "K_tt")):
        values = data["principal"][block]["values"]
        directions = np.array(data["principal"][block]["directions"])
        k = np.array(data["decoupling"][key])
        assert directions.shape == (3, 3)
        for j in range(3):
            np.testing.assert_allclose(np.linalg.norm(directions[j]), 1.0, rtol=1e-12)
            np.testing.assert_allclose(
                k @ directions[j], values[j] * directions[j], atol=1e-9 * np.abs(k).max()
            )
    ref = analyze_design(default_design(), [0.002, -0.003, np.radians(5)]).to_dict()
    np.testing.assert_allclose(data["stiffness_matrix"], ref["stiffness_matrix"], rtol=1e-12)


def test_analyze_with_wrench_reports_actuators(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "analyze", "--json", "--wrench", "5,5,20,0,0,0.1")
    assert code == 0
    data = json.loads(out)
    # the library's loaded state under f = [5, 5, 20] N, m_z = 0.1 N·m (compared with
    # the paper's K_act in test_model_paper.py)
    state = loaded_state(default_design(), PAPER_WRENCH)
    for key in ("actuator_stiffness", "actuator_forces", "actuator_displacements", "twist"):
        np.testing.assert_allclose(data[key], getattr(state, key), rtol=1e-12, err_msg=key)
    code, out, _ = run(capsys, "analyze", "--wrench", "5,5,20,0,0,0.1")
    assert "actuator forces" in out


def test_analyze_matrix(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "analyze", "--matrix", EQ22_CSV, "--json")
    assert code == 0
    data = json.loads(out)
    np.testing.assert_allclose(data["stiffness_matrix"], EQ22)
    # eq. (29): d = [0.0212, 0.0241, 0] m
    np.testing.assert_allclose(data["decoupling"]["d"], [0.0212, 0.0241, 0], atol=1e-4)


def test_calibrate_writes_a_design(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out_file = tmp_path / "cal.toml"
    code, out, err = run(
        capsys,
        "calibrate",
        "--target",
        EQ22_CSV,
        "--free",
        "leg3.bearing_offset,leg3.guide_offset_w",
        "--sigma",
        "5",
        "--bound",
        "leg3.bearing_offset=0:0.149",
        "--out",
        str(out_file),
    )
    assert code == 0, err
    assert "Fitted parameters" in out and "singular values" in out and "Residuals" in out
    code, out, _ = run(capsys, "analyze", "--design", str(out_file), "--json")
    assert code == 0
    k = np.array(json.loads(out)["stiffness_matrix"])
    # the fit reproduces (22) to its printing: every entry within the half-unit 5
    # (measured at most 4.37, on K_phiz_phiz, which the statics fix at 75.6)
    assert np.all(np.abs(k - EQ22) <= 5.0)
    # K_xx, which leg 3's two free offsets set: measured 0.091 N/m from (22)
    assert abs(k[3, 3] - EQ22[3, 3]) < 0.3


def test_calibrate_flags_flat_direction(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(
        capsys,
        "calibrate",
        "--target",
        EQ22_CSV,
        "--free",
        "guide.vertical,bearing.radial_vertical",
    )
    assert code == 0
    assert "flat direction" in out and "undetermined" in out


def _bad(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    code, out, err = run(capsys, *args)
    assert code == 2, (out, err)
    lines = [line for line in err.strip().splitlines() if line]
    assert len(lines) == 1 and "Traceback" not in err and "nan" not in err.lower()
    return err


def test_unreachable_pose(capsys: pytest.CaptureFixture[str]) -> None:
    err = _bad(capsys, "analyze", "--x", "500")
    assert "leg" in err and ("stroke" in err or "rod" in err)


def test_singular_configuration(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    # At phi = 90 deg legs 1 and 2 act along the same vertical line: planar singularity.
    f = tmp_path / "wide.toml"
    save_design(wide_design(), f)
    err = _bad(capsys, "analyze", "--design", str(f), "--phi", "90")
    assert "singular" in err


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (("tilt_lateral = 1010.0", "tilt_lateral = -1010.0"), "bearing.tilt_lateral"),
        (("area = 0.00021", "area = 0.0"), "proximal.area"),
        (("platform_radius = 0.03", "platform_radius = -0.03"), "leg1.platform_radius"),
        (("yaw = 1700.0", 'yaw = "stiff"'), "guide.yaw"),
        (("roll = 4700.0", "roll = 4700.0\ncolour = 1"), "guide.colour"),
        (("locked_stiffness = 111080.0", "locked_stiffness = nan"), "actuator.locked_stiffness"),
    ],
)
def test_malformed_design_names_the_key(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, edit: tuple[str, str], key: str
) -> None:
    text = dump_design(default_design())
    assert edit[0] in text, edit[0]
    f = tmp_path / "bad.toml"
    f.write_text(text.replace(edit[0], edit[1], 1))
    err = _bad(capsys, "analyze", "--design", str(f))
    assert key in err


def test_design_not_toml_and_missing(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    f = tmp_path / "bad.toml"
    f.write_text("this is = = not toml")
    assert "not valid TOML" in _bad(capsys, "analyze", "--design", str(f))
    assert "not found" in _bad(capsys, "analyze", "--design", str(tmp_path / "none.toml"))
    f.write_text('schema = 2\nname = "x"\n')
    assert "key 'legs'" in _bad(capsys, "analyze", "--design", str(f))


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("1,2,3\n4,5,6\n", "6x6"),
        ("\n".join([",".join(["nan"] * 6)] * 6), "not finite"),
        (
            "\n".join(",".join(str(float(i == j) + (i < j)) for j in range(6)) for i in range(6)),
            "not symmetric",
        ),
        ("a,b,c,d,e,f\n" * 6, "numeric"),
    ],
)
def test_bad_matrix(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, content: str, message: str
) -> None:
    f = tmp_path / "k.csv"
    f.write_text(content)
    assert message in _bad(capsys, "analyze", "--matrix", str(f))


def test_singular_matrix_and_missing_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    f = tmp_path / "k.csv"
    f.write_text(
        "\n".join(",".join("1" if i == j and i < 5 else "0" for j in range(6)) for i in range(6))
    )
    assert "singular" in _bad(capsys, "analyze", "--matrix", str(f))
    assert "not found" in _bad(capsys, "analyze", "--matrix", str(tmp_path / "none.csv"))


def test_bad_wrench_and_pose(capsys: pytest.CaptureFixture[str]) -> None:
    assert "6 numbers" in _bad(capsys, "analyze", "--wrench", "1,2,3")
    assert "6 numbers" in _bad(capsys, "analyze", "--wrench", "1,2,x,4,5,6")
    assert "finite" in _bad(capsys, "analyze", "--x", "nan")


def test_usage_error_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "--no-such-option"]) == 2
    assert main(["no-such-command"]) == 2


def test_list_parameters(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "calibrate", "--list-parameters")
    assert code == 0
    assert "leg3.guide_offset_w" in out and "guide.yaw" in out and "1700" in out
    assert "--target" in _bad(capsys, "calibrate", "--free", "guide.yaw")


DATA = Path(__file__).parents[1] / "src/ppm_stiffness/data"


@pytest.mark.parametrize(
    "args",
    [
        [
            "fit-actuator",
            str(DATA / "actuator_synthetic.csv"),
            "--write-design",
            "/nonexistent/x.toml",
        ],
        ["fit-actuator", str(DATA / "actuator_synthetic.csv"), "--plot", "out.xyz"],
        ["deflect", "--csv", "/nonexistent/x.csv"],
        ["deflect", "--plot", "/dev/null/x.png"],
        ["calibrate", "--target", EQ22_CSV, "--free", "guide.yaw", "--out", "/dev/null/x.toml"],
        ["map", "--grid", "5", "--out", "/dev/null/x.png"],
        ["map", "--grid", "5", "--data", "/nonexistent/x.csv"],
        ["springs", "--out", "/nonexistent/s.png"],
        ["mechanism", "--out", "/dev/null/x.png"],
        ["analyze", "--matrix", ""],
        ["analyze", "--design", ""],
        ["analyze", "--matrix", "/tmp"],
    ],
)
def test_bad_paths_are_one_line_errors(capsys: pytest.CaptureFixture[str], args: list[str]) -> None:
    _bad(capsys, *args)
    assert not Path("/nonexistent").exists()  # nothing is created on the user's behalf


def test_report_output_is_checked_first(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    _bad(capsys, "report", "--out", "/dev/null/x", "--quiet", "--grid", "4")
    _bad(capsys, "report", "--out", "/nonexistent/deep/r", "--quiet", "--grid", "4")
    assert "empty" in _bad(capsys, "report", "--out", "", "--quiet", "--grid", "4")
    assert not Path("/nonexistent").exists()


def test_non_utf8_design(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    f = tmp_path / "bin.toml"
    f.write_bytes(b"\xff\xfe\x00name = 1")
    assert "UTF-8" in _bad(capsys, "analyze", "--design", str(f))


def test_not_positive_definite_matrix(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    k = EQ22.copy()
    k[0, 0] = -750.0
    f = tmp_path / "neg.csv"
    np.savetxt(f, k, delimiter=",")
    assert "not positive definite" in _bad(capsys, "analyze", "--matrix", str(f))
    assert "not positive definite" in _bad(
        capsys, "calibrate", "--target", str(f), "--free", "guide.yaw"
    )


def test_loads_beyond_the_model_are_refused(capsys: pytest.CaptureFixture[str]) -> None:
    # a 1e9 N load would push the actuators far past their stroke: refuse, naming it
    err = _bad(capsys, "analyze", "--wrench", "1e9,0,0,0,0,0")
    assert "load too large" in err and "stroke" in err
    assert "load too large" in _bad(capsys, "deflect", "--max", "1e6", "--step", "1e5")
    assert "load too large" in _bad(
        capsys, "deflect", "--mode", "moment", "--max", "100", "--step", "10"
    )


def test_map_with_no_reachable_point(capsys: pytest.CaptureFixture[str]) -> None:
    assert "no grid point" in _bad(capsys, "map", "--bounds=-1000,-900,-1000,-900", "--grid", "10")


def test_small_displacement_limits(capsys: pytest.CaptureFixture[str]) -> None:
    # 1.1 N·m would rotate the platform by about 80 deg: outside the linearised model
    err = _bad(capsys, "deflect", "--mode", "moment", "--max", "1.1", "--step", "0.1")
    assert "rotate" in err
    # a map under a load that drives an actuator past its stroke is refused like analyze
    assert "stroke" in _bad(capsys, "map", "--grid", "5", "--actuators=50,0,0,0,0,0")
    assert "empty" in _bad(capsys, "deflect", "--measurements", "")


def test_method_least_squares_is_shown_first_and_json_keys_keep_their_meaning(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Before: --method least-squares printed the least-squares decoupling twice, never
    the paper's, and put it under the JSON key 'decoupling'."""
    assert main(["analyze", "--method", "least-squares"]) == 0
    out = capsys.readouterr().out
    heads = [line for line in out.splitlines() if line.startswith("Decoupling, method")]
    assert heads == ["Decoupling, method 'least-squares'", "Decoupling, method 'paper'"]
    assert main(["analyze", "--method", "least-squares", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["method"] == "least-squares"
    assert data["decoupling"]["method"] == "paper"
    assert data["decoupling_least_squares"]["method"] == "least-squares"
    # the paper's eq. (29): d = (21.2, 24.1, 0) mm on the built-in design
    np.testing.assert_allclose(data["decoupling"]["d"], [0.0212, 0.0241, 0.0], atol=1e-4)


def test_calibrate_prints_singular_values_when_one_is_zero(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The power-law k_a does not enter the unloaded K: its column of the Jacobian is
    zero. Before, the whole singular-value line was dropped exactly then."""
    code, out, _ = run(
        capsys, "calibrate", "--target", EQ22_CSV, "--free", "leg1.actuator.k_a,guide.yaw"
    )
    assert code == 0
    line = next(s for s in out.splitlines() if s.startswith("singular values"))
    assert line.endswith("(condition infinite)") and ", 0" in line
