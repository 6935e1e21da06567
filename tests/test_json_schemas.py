"""Every ``--json`` document validates against its JSON Schema in ``docs/schemas/`` and
carries the common head: schema_version, ppm_stiffness_version, command and units."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ppm_stiffness import __version__
from ppm_stiffness.analysis import JSON_SCHEMA_VERSION
from ppm_stiffness.cli import main

jsonschema = pytest.importorskip("jsonschema", reason="jsonschema is in the 'test' extra")

ROOT = Path(__file__).parents[1]
SCHEMAS = ROOT / "docs" / "schemas"
DATA = ROOT / "src" / "ppm_stiffness" / "data"
TOLERANCES = ROOT / "examples" / "identification" / "tolerances.toml"

#: A small required region for compare, sweep and optimize [mm, mm, deg, counts].
_REGION = ["--region=-5,5,-5,5,0,0,3,3,1"]

#: (schema name, command line) pairs: every command that prints JSON, in the variants
#: whose documents differ in their keys.
CASES = [
    ("analyze", ["analyze", "--json"]),
    ("analyze", ["analyze", "--json", "--wrench", "5,5,20,0,0,0.1"]),
    ("analyze", ["analyze", "--json", "--design", str(ROOT / "examples/3rrr.toml")]),
    ("analyze", ["analyze", "--json", "--matrix", str(DATA / "paper_eq22.csv")]),
    ("deflect", ["deflect", "--json", "--mode", "moment"]),
    ("fit-actuator", ["fit-actuator", "--json", str(DATA / "actuator_synthetic.csv")]),
    (
        "calibrate",
        ["calibrate", "--json", "--target", str(DATA / "paper_eq22.csv"), "--free", "leg1.psi"],
    ),
    ("map", ["map", "--json", "--grid", "8"]),
    ("analyze", ["analyze", "--json", "--tolerances", str(TOLERANCES)]),
    ("map", ["map", "--json", "--grid", "6", "--tolerances", str(TOLERANCES)]),
    ("deflect", ["deflect", "--json", "--mode", "moment", "--tolerances", str(TOLERANCES)]),
    (
        "identify",
        [
            "identify",
            "--json",
            "--measurements",
            str(ROOT / "examples/identification/measurements.csv"),
            "--free",
            "leg1.guide.yaw,leg2.guide.yaw",
        ],
    ),
    ("map", ["map", "--json", "--grid", "8", "--actuators", "5,5,20,0,0,0.1"]),
    ("modes", ["modes", "--json"]),
    ("modes", ["modes", "--json", "--wrench", "5,5,20,0,0,0.1", "--tool-point", "10,0,5"]),
    ("modes", ["modes", "--json", "--design", str(ROOT / "examples/3prs.toml")]),
    (
        "modes",
        [
            "modes",
            "--json",
            "--design",
            str(ROOT / "examples/hexapod_6ups.toml"),
            "--tolerances",
            str(ROOT / "examples/identification/hexapod_mass_tolerances.toml"),
        ],
    ),
    (
        "analyze",
        [
            "analyze",
            "--json",
            "--design",
            str(ROOT / "examples/hexapod_6ups.toml"),
            "--tolerances",
            str(ROOT / "examples/identification/hexapod_mass_tolerances.toml"),
        ],
    ),
    ("map", ["map", "--json", "--grid", "6", "--design", str(ROOT / "examples/hexapod_6ups.toml")]),
    (
        "map",
        [
            "map",
            "--json",
            "--grid",
            "6",
            "--design",
            str(ROOT / "examples/3prs.toml"),
            "--axes",
            "rx,ry",
        ],
    ),
    ("map", ["map", "--json", "--grid", "6", "--quantities", "all"]),
    (
        "map",
        [
            "map",
            "--json",
            "--grid",
            "6",
            "--design",
            str(ROOT / "examples/hexapod_6ups.toml"),
            "--quantities",
            "f1,translational_min",
            "--link-modes",
            "0",
        ],
    ),
    (
        "compare",
        ["compare", "--json", "--design", str(ROOT / "examples/3rrr.toml"), *_REGION]
        + ["--link-modes", "0"],
    ),
    (
        "compare",
        [
            "compare",
            "--json",
            "--design",
            str(ROOT / "examples/3prr.toml"),
            "--wrench",
            "5,5,0,0,0,0.1",
            *_REGION,
            "--link-modes",
            "2",
        ],
    ),
    (
        "sweep",
        [
            "sweep",
            "--json",
            "--design",
            str(ROOT / "examples/3rpr.toml"),
            "--vary",
            "leg*.platform_radius=0.05:0.07:3",
            *_REGION,
            "--link-modes",
            "0",
        ],
    ),
    # spatial designs: 6-D poses, a load along a direction, bands, 6-D measurement rows
    (
        "deflect",
        [
            "deflect",
            "--json",
            "--design",
            str(ROOT / "examples/hexapod_6ups.toml"),
            "--direction",
            "0,0,0,0,0,3",
            "--tool-point",
            "0,0,50",
        ],
    ),
    (
        "deflect",
        [
            "deflect",
            "--json",
            "--design",
            str(ROOT / "examples/3rps.toml"),
            "--direction",
            "100,0,50,0,0,2",
            "--tolerances",
            str(ROOT / "examples/identification/3rps_tolerances.toml"),
        ],
    ),
    (
        "analyze",
        [
            "analyze",
            "--json",
            "--design",
            str(ROOT / "examples/3rps.toml"),
            "--wrench",
            "100,0,50,0,0,2",
            "--tolerances",
            str(ROOT / "examples/identification/3rps_tolerances.toml"),
        ],
    ),
    (
        "identify",
        [
            "identify",
            "--json",
            "--design",
            str(ROOT / "examples/3rps.toml"),
            "--measurements",
            str(ROOT / "examples/identification/3rps_measurements.csv"),
            "--free",
            "leg1.actuator.k_a,leg*.base_revolute.tilt",
        ],
    ),
]


def _document(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict[str, object]:
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 0, err
    data: dict[str, object] = json.loads(out)
    return data


@pytest.mark.parametrize(("schema", "argv"), CASES)
def test_json_output_validates(
    schema: str, argv: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    document = _document(capsys, argv)
    spec = json.loads((SCHEMAS / f"{schema}.schema.json").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(spec)
    jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)
    assert document["schema_version"] == JSON_SCHEMA_VERSION
    assert document["ppm_stiffness_version"] == __version__
    assert list(document)[:4] == ["schema_version", "ppm_stiffness_version", "command", "units"]


def test_validate_json_validates(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("Pynite", reason="PyNite is in the 'validate' extra")
    document = _document(capsys, ["validate", "--json", "--poses", "1"])
    spec = json.loads((SCHEMAS / "validate.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)


def test_a_schema_rejects_a_wrong_document(capsys: pytest.CaptureFixture[str]) -> None:
    """The schemas are not vacuous: a 5x6 stiffness matrix is refused."""
    document = _document(capsys, ["analyze", "--json"])
    document["stiffness_matrix"] = document["stiffness_matrix"][:5]  # type: ignore[index]
    spec = json.loads((SCHEMAS / "analyze.schema.json").read_text(encoding="utf-8"))
    with pytest.raises(jsonschema.ValidationError, match="is too short") as err:
        jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)
    assert list(err.value.absolute_path) == ["stiffness_matrix"]


def test_optimize_json_validates(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    argv = ["optimize", "--json", "--design", str(ROOT / "examples/symmetric_3ppr.toml")]
    argv += ["--vary", "leg*.platform_radius=0.02:0.04", "--budget", "10", *_REGION]
    document = _document(capsys, [*argv, "--out", str(tmp_path / "best.toml")])
    spec = json.loads((SCHEMAS / "optimize.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)


def test_optimize_front_json_validates(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("pymoo", reason="pymoo is in the 'pareto' extra")
    argv = ["optimize", "--json", "--design", str(ROOT / "examples/symmetric_3ppr.toml")]
    argv += ["--vary", "leg*.platform_radius=0.02:0.04", "--budget", "16", *_REGION]
    argv += ["--objective", "worst-k-translational", "--objective", "moving-mass"]
    document = _document(capsys, [*argv, "--out", str(tmp_path / "chosen.toml")])
    spec = json.loads((SCHEMAS / "optimize-front.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)


def test_uncertainty_is_described_by_the_schemas(capsys: pytest.CaptureFixture[str]) -> None:
    """Review finding: the bands were unchecked (no schema named ``uncertainty``); now a
    band with a wrong shape is refused."""
    document = _document(capsys, ["analyze", "--json", "--tolerances", str(TOLERANCES)])
    spec = json.loads((SCHEMAS / "analyze.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)
    document["uncertainty"]["stiffness_matrix_lower"] = [[0.0]]  # type: ignore[index]
    with pytest.raises(jsonschema.ValidationError, match="is too short") as err:
        jsonschema.validate(document, spec, cls=jsonschema.Draft202012Validator)
    assert list(err.value.absolute_path) == ["uncertainty", "stiffness_matrix_lower"]


def test_every_schema_has_a_case() -> None:
    covered = {name for name, _ in CASES} | {"validate", "optimize", "optimize-front"}
    assert {p.name.removesuffix(".schema.json") for p in SCHEMAS.glob("*.schema.json")} == covered


def test_identify_schema_ties_a_bound_to_a_null_sigma(capsys: pytest.CaptureFixture[str]) -> None:
    """An estimate at a bound has no valid standard error (issue 27, item 4): the schema
    refuses a number there, and a null one where the estimate is not at a bound."""
    argv = next(a for name, a in CASES if name == "identify")
    document = _document(capsys, argv)
    spec = json.loads((SCHEMAS / "identify.schema.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(spec)
    parameter = document["parameters"][0]  # type: ignore[index]
    assert parameter["at_bound"] is None and document["warnings"] == []
    parameter["at_bound"] = "lower"
    assert not validator.is_valid(document)
    parameter["standard_error"] = None
    assert validator.is_valid(document)
    parameter["at_bound"] = None
    assert not validator.is_valid(document)
