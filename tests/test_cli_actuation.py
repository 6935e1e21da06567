"""CLI: ``fit-actuator`` and ``deflect`` (in-process, exit codes and outputs)."""

from __future__ import annotations

import json
import math
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from paper import PAPER_WRENCH
from ppm_stiffness.cli import main
from ppm_stiffness.design import default_design, dump_design, load_design
from ppm_stiffness.statics.actuator_fit import fit_power_law, read_force_displacement
from ppm_stiffness.statics.deflection import closed_form_twist, deflection_curve
from ppm_stiffness.statics.measurements import read_measurements, rms_differences


def data(name: str) -> str:
    return str(resources.files("ppm_stiffness").joinpath(f"data/{name}"))


ACT = data("actuator_synthetic.csv")
PLANAR = data("measurements_synthetic_planar.csv")


def run_ok(args: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    code = main(args)
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def run_bad(args: list[str], capsys: pytest.CaptureFixture[str], match: str) -> None:
    code = main(args)
    out, err = capsys.readouterr()
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ppm-stiffness: error:")
    assert match in lines[0]


# ------------------------------------------------------------------ fit-actuator
def test_fit_actuator_prints_and_writes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = read_force_displacement(ACT)
    fit = fit_power_law(d.displacement_m, d.force_n)
    out = run_ok(["fit-actuator", ACT], capsys)
    assert f"{fit.k_a:.4f}" in out and f"{fit.q:.5f}" in out and "SYNTHETIC" in out
    res = json.loads(run_ok(["fit-actuator", ACT, "--json"], capsys))
    assert res["k_a"] == pytest.approx(fit.k_a, rel=1e-12)
    assert res["q_std"] == pytest.approx(fit.q_std, rel=1e-12)
    assert res["displacement_unit"] == "mm"
    design_out = tmp_path / "fitted.toml"
    fig = tmp_path / "fit.png"
    run_ok(["fit-actuator", ACT, "--write-design", str(design_out), "--plot", str(fig)], capsys)
    new = load_design(design_out)
    assert new.actuator.k_a == pytest.approx(fit.k_a, rel=1e-12)
    assert new.actuator.q == pytest.approx(fit.q, rel=1e-12)
    # everything else is the built-in design's
    assert new.with_parameters({"actuator.k_a": 44.75, "actuator.q": 0.225}) == default_design()
    assert fig.stat().st_size > 10_000


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("displacement,force\n0.1,5\n", "header"),
        ("displacement_mm,force_N\n0.1,five\n", "not numeric"),
        ("displacement_mm,force_N\n0.1,5\n0.2,6\n", "at least 3"),
    ],
)
def test_fit_actuator_malformed_csv(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, match: str
) -> None:
    p = tmp_path / "bad.csv"
    p.write_text(text)
    run_bad(["fit-actuator", str(p)], capsys, match)


def test_fit_actuator_refuses_to_write_a_hardening_law(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Data following q = 1.5 fit fine but make no design (q must lie in (0, 1])."""
    d = np.geomspace(0.01, 1.0, 10)
    p = tmp_path / "hard.csv"
    p.write_text(
        "displacement_mm,force_N\n" + "".join(f"{x},{1e5 * (x * 1e-3) ** 1.5}\n" for x in d)
    )
    out = tmp_path / "x.toml"
    run_bad(["fit-actuator", str(p), "--write-design", str(out)], capsys, "outside (0, 1]")
    assert not out.exists()


# ----------------------------------------------------------------------- deflect
def test_deflect_csv_matches_the_library(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    csv = tmp_path / "d.csv"
    out = run_ok(
        [
            "deflect",
            "--mode",
            "planar-force",
            "--alpha",
            "30",
            "--max",
            "8",
            "--step",
            "2",
            "--csv",
            str(csv),
        ],
        capsys,
    )
    assert "planar-force" in out
    lines = [ln for ln in csv.read_text().splitlines() if not ln.startswith("#")]
    assert lines[0] == "load,phi_x_deg,phi_y_deg,phi_z_deg,x_mm,y_mm,z_mm"
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    curve = deflection_curve(
        default_design(), "planar-force", [0, 2, 4, 6, 8], None, math.radians(30)
    )
    np.testing.assert_allclose(rows[:, 0], curve.loads)
    expect = curve.twists * np.array([180 / math.pi] * 3 + [1e3] * 3)
    np.testing.assert_allclose(rows[:, 1:], expect, rtol=1e-8, atol=1e-12)
    # the CSV is a valid measurement file of its own curve: zero RMS difference
    rms = rms_differences(curve, read_measurements(csv))
    assert rms["orientation_deg"] < 1e-8 and rms["position_mm"] < 1e-8


def test_deflect_with_measurements(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    fig = tmp_path / "f.png"
    res = json.loads(
        run_ok(["deflect", "--measurements", PLANAR, "--plot", str(fig), "--json"], capsys)
    )
    assert res["mode"] == "planar-force" and res["alpha_deg"] == pytest.approx(45)
    m = read_measurements(PLANAR)
    curve = deflection_curve(
        default_design(), "planar-force", np.union1d(np.linspace(0, 10, 21), m.loads)
    )
    expected = rms_differences(curve, m)
    assert res["rms_differences"]["orientation_deg"] == pytest.approx(
        expected["orientation_deg"], rel=1e-9
    )
    assert res["rms_differences"]["position_mm"] == pytest.approx(expected["position_mm"], rel=1e-9)
    assert fig.stat().st_size > 10_000
    out = run_ok(["deflect", "--measurements", PLANAR], capsys)
    assert f"{expected['position_mm']:.3f} mm" in out


def test_deflect_wrench_mode_reaches_the_closed_form(capsys: pytest.CaptureFixture[str]) -> None:
    res = json.loads(
        run_ok(
            [
                "deflect",
                "--mode",
                "wrench",
                "--wrench",
                "5,5,20,0,0,0.1",
                "--max",
                "1",
                "--step",
                "0.25",
                "--json",
            ],
            capsys,
        )
    )
    np.testing.assert_allclose(res["wrenches"][-1], PAPER_WRENCH)
    t = closed_form_twist(default_design(), PAPER_WRENCH)
    np.testing.assert_allclose(res["twists"][-1], t, rtol=1e-8, atol=1e-14)


def test_deflect_actuator_overrides(capsys: pytest.CaptureFixture[str]) -> None:
    """--q 1 --k-a 2e4: linear actuators above the locked threshold, as in the library."""
    res = json.loads(
        run_ok(
            [
                "deflect",
                "--mode",
                "moment",
                "--q",
                "1",
                "--k-a",
                "2e4",
                "--max",
                "0.4",
                "--step",
                "0.1",
                "--json",
            ],
            capsys,
        )
    )
    design = default_design().with_parameters({"actuator.q": 1.0, "actuator.k_a": 2e4})
    curve = deflection_curve(design, "moment", [0, 0.1, 0.2, 0.3, 0.4])
    np.testing.assert_allclose(res["twists"], curve.twists, rtol=1e-9, atol=1e-15)
    assert res["actuator_stiffness"][-1][0] == pytest.approx(2e4)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--k-a", "-1"], "k_a"),
        (["--q", "1.5"], "actuator.q"),
        (["--q", "0"], "actuator.q"),
        (["--mode", "wrench", "--wrench", "1,2,3"], "6 numbers"),
        (["--mode", "wrench", "--wrench", "0,0,0,0,0,0"], "zero"),
        (["--wrench", "1,2,3,4,5,6"], "--mode wrench"),
        (["--max", "-1"], "--max"),
        (["--step", "0"], "--step"),
        (["--mode", "moment", "--measurements", PLANAR], "mode"),
        (["--alpha", "30", "--measurements", PLANAR], "alpha"),
        (["--x", "500"], "outside"),
    ],
)
def test_deflect_bad_input(capsys: pytest.CaptureFixture[str], args: list[str], match: str) -> None:
    run_bad(["deflect", *args], capsys, match)


def test_deflect_bad_design_and_measurement_files(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = dump_design(default_design()).replace("k_a = 44.75", "k_a = -44.75")
    bad_design = tmp_path / "neg.toml"
    bad_design.write_text(text)
    run_bad(["deflect", "--design", str(bad_design)], capsys, "actuator.k_a")
    bad = tmp_path / "m.csv"
    bad.write_text("load,phi_z_deg\n1,abc\n")
    run_bad(["deflect", "--measurements", str(bad)], capsys, "not numeric")


def test_deflect_linear_actuator_from_the_cli(capsys) -> None:  # type: ignore[no-untyped-def]
    # --q 1 --threshold 0: a linear actuator of stiffness k_a, so the deflection is C w
    import json

    import numpy as np

    from ppm_stiffness.design import default_design
    from ppm_stiffness.model import stiffness_at_pose

    assert (
        main(
            [
                "deflect",
                "--mode",
                "moment",
                "--max",
                "0.2",
                "--step",
                "0.1",
                "--q",
                "1",
                "--k-a",
                "1e5",
                "--threshold",
                "0",
                "--json",
            ]
        )
        == 0
    )
    data = json.loads(capsys.readouterr().out)
    k = stiffness_at_pose(default_design(), None, 1e5)
    expected = np.linalg.solve(k, [0, 0, 0.2, 0, 0, 0])
    twists = np.array(data["twists"])
    # measured 3.5e-16 of the largest component; cond(length-balanced K) = 51, so
    # round-off can reach 51 x 2.2e-16 = 1.1e-14: 2e-14 allowed
    np.testing.assert_allclose(twists[-1], expected, rtol=0, atol=2e-14 * np.abs(expected).max())
