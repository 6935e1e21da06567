"""``ppm-stiffness identify``: output files, JSON, and ill-posed input (one line on
stderr, exit code 2, nothing written)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema  # the 'test' extra: every --json document is checked against its schema
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.design import load_design

ROOT = Path(__file__).parents[1]
DATA = ROOT / "examples/identification/measurements.csv"
#: The known factors of the synthetic prototype (scripts/synthetic_identification_data.py).
TRUE = {"leg1.guide.yaw": 0.80 * 1700.0, "leg2.guide.yaw": 1.15 * 1700.0}
FREE = (
    "leg1.guide.yaw,leg2.guide.yaw,leg*.actuator.locked_stiffness,"
    "leg3.distal.young_modulus,leg1.proximal.young_modulus"
)


def test_identify_writes_the_design_and_a_json_document(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The shipped synthetic data (noise 0.001 deg / 0.001 mm): every estimate within
    3 of its standard errors of the prototype's value; the weighted RMS near 1 (the
    data's sigmas are the noise used to make them)."""
    out = tmp_path / "identified.toml"
    assert (
        main(["identify", "--measurements", str(DATA), "--free", FREE, "--out", str(out), "--json"])
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["command"] == "identify" and doc["identified_design"] == str(out)
    params = {p["name"]: p for p in doc["parameters"]}
    for name, true in TRUE.items():
        p = params[name]
        assert abs(p["estimate"] - true) <= 3 * p["standard_error"]
    assert 0.7 < doc["weighted_rms"] < 1.3
    design = load_design(out)
    assert design.parameter("leg1.guide.yaw") == pytest.approx(params["leg1.guide.yaw"]["estimate"])
    # an existing file is refused without --overwrite, before any computation
    assert (
        main(
            ["identify", "--measurements", str(DATA), "--free", "leg1.guide.yaw", "--out", str(out)]
        )
        == 2
    )
    assert "--overwrite" in capsys.readouterr().err
    schema = json.loads((ROOT / "docs/schemas/identify.schema.json").read_text())
    jsonschema.validate(doc, schema)


def test_identify_tables(capsys: pytest.CaptureFixture[str]) -> None:
    assert (
        main(["identify", "--measurements", str(DATA), "--free", "leg1.guide.yaw,leg2.guide.yaw"])
        == 0
    )
    out = capsys.readouterr().out
    assert "leg1.guide.yaw" in out and "residual RMS" in out and "weighted RMS" in out


@pytest.mark.parametrize(
    ("text", "free", "extra", "match"),
    [
        (
            "fx_N,x_mm,sigma_x_mm\n1,0.01,0.001\n",
            "leg*.guide.yaw,leg1.guide.lateral",
            [],
            "too few measurements",
        ),
        (
            "fx_N,fy_N,x_mm,y_mm\n1,0,0.03,0.001\n0,1,0.001,0.03\n",
            "leg1.guide.roll",
            ["--sigma", "x_mm=0.001,y_mm=0.001"],
            "cannot separate",
        ),
        ("fx_N,pose_x_mm,x_mm\n1,0,0.03\n", "leg1.guide.yaw", [], "missing column 'pose_y_mm'"),
        ("fx_N,x_mm\n1,nan\n", "leg1.guide.yaw", [], "column 'x_mm': nan"),
        ("fx_N,x_mmm\n1,0.01\n", "leg1.guide.yaw", [], "unknown column 'x_mmm'"),
        (
            "fx_N,x_mm\n1,0.01\n2,0.02\n",
            "leg1.guide.yawn",
            ["--sigma", "x_mm=0.001"],
            "unknown design parameter",
        ),
        ("x_mm,y_mm\n0.01,0.02\n", "leg1.guide.yaw", [], "displacements with no wrench"),
        ("fx_N,x_mm\n1,0.01\n2,0.02\n", "leg1.guide.yaw", [], "no noise given for x_mm"),
        ("fx_N,x_mm\n1,0.01\n2,0.02\n", "leg1.guide.yaw", ["--sigma", "x_mm=-1"], "must be > 0"),
        ("fx_N,x_mm\n1,0.01\n2,0.02\n", "leg1.guide.yaw", ["--sigma", "q=1"], "COLUMN=VALUE"),
    ],
)
def test_ill_posed_input_exit_2_nothing_written(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    text: str,
    free: str,
    extra: list[str],
    match: str,
) -> None:
    data = tmp_path / "m.csv"
    data.write_text(text)
    out = tmp_path / "identified.toml"
    args = ["identify", "--measurements", str(data), "--free", free, "--out", str(out), *extra]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("ppm-stiffness: error:") and match in err[0]
    assert not out.exists()


def test_fix_unidentifiable_warns_and_fixes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = [
        "identify",
        "--measurements",
        str(DATA),
        "--free",
        "leg1.guide.yaw,leg2.guide.lateral",
        "--fix-unidentifiable",
        "--json",
    ]
    assert main(args) == 0
    captured = capsys.readouterr()
    assert "warning" in captured.err and "leg2.guide.lateral" in captured.err
    doc = json.loads(captured.out)
    assert doc["fixed"] == ["leg2.guide.lateral"]
    assert [p["name"] for p in doc["parameters"]] == ["leg1.guide.yaw"]
