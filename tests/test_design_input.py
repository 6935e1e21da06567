"""Design input that is wrong in form: numbers given as booleans or strings, a tool
point in the wrong unit, a file that is empty, lacks `schema`, carries a byte-order
mark or a misspelt key, and several errors in one file (all reported at once)."""

from __future__ import annotations

import ast
import re
import tomllib
import warnings
from importlib import resources
from pathlib import Path
from typing import Any

import pytest
import tomli_w

from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import DesignError, DesignFormatWarning
from ppm_stiffness.design import (
    default_design,
    design_from_dict,
    design_to_dict,
    dump_design,
    load_design,
    save_design,
)

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src/ppm_stiffness"
SHIPPED = [
    PACKAGE / "data/paper_3ppr.toml",
    ROOT / "docs/layout_start.toml",
    *sorted((ROOT / "examples").glob("*.toml")),
]


def _refused(data: dict[str, Any], source: str = "f.toml") -> str:
    with pytest.raises(DesignError) as err:
        design_from_dict(data, source=source)
    return str(err.value)


def _example(name: str) -> dict[str, Any]:
    return tomllib.loads((ROOT / "examples" / name).read_text("utf-8"))


# -- item 4: strict numbers ------------------------------------------------------------


def _set(data: dict[str, Any], path: str, value: Any) -> None:
    keys: list[Any] = [int(k) if k.isdigit() else k for k in path.split(".")]
    target = data
    for key in keys[:-1]:
        target = target[key]
    target[keys[-1]] = value


@pytest.mark.parametrize(
    ("example", "path", "value", "key", "got"),
    [
        # before: 1 N/m, 1 m and 4000 N·m/rad, accepted
        (
            "3rpr.toml",
            "legs.0.actuator",
            {"locked_stiffness": True},
            "leg1.actuator.locked_stiffness",
            "a boolean",
        ),  # noqa: E501
        ("3rpr.toml", "legs.0.housing_length", True, "leg1.housing_length", "a boolean"),
        ("3rrr.toml", "parts.elbow_revolute.tilt", "4e3", "parts.elbow_revolute.tilt", "a string"),  # noqa: E501
        ("3rrr.toml", "legs.1.branch", True, "leg2.branch", "a boolean"),
        ("3rrr.toml", "legs.2.stroke", [-1.0, "1.0"], "leg3.stroke.1", "a string"),
        ("3prr.toml", "legs.0.base_point", [False, 0.1], "leg1.base_point.0", "a boolean"),
        ("3prr.toml", "parts.actuator.q", "0.5", "parts.actuator.q", "a string"),
        ("3prr.toml", "parts.guide.roll", [4700.0], "parts.guide.roll", "a list"),
        ("3prr.toml", "parts.distal.area", {"value": 1e-4}, "parts.distal.area", "a table"),
        (
            "symmetric_3ppr.toml",
            "legs.0.rod_length_range",
            [True, 0.1],
            "leg1.rod_length_range.0",
            "a boolean",
        ),  # noqa: E501
        ("symmetric_3ppr.toml", "workspace.centre_x", True, "workspace.centre_x", "a boolean"),
        (
            "symmetric_3ppr.toml",
            "workspace.required.grid",
            [True, 3, 3],
            "workspace.required.grid.0",
            "a boolean",
        ),  # noqa: E501
        ("symmetric_3ppr.toml", "tool_point", [0.0, "0", 0.0], "tool_point.1", "a string"),
    ],
)
def test_booleans_and_strings_are_not_numbers(
    example: str, path: str, value: Any, key: str, got: str
) -> None:
    data = _example(example)
    if path == "legs.0.actuator":  # a leg's own actuator, over the [parts] one
        value = {**data["parts"]["actuator"], **value}
    _set(data, path, value)
    assert _refused(data) == f"f.toml: key '{key}': expected a number, got {got}"


def test_integers_are_numbers() -> None:
    data = _example("3rrr.toml")
    data["parts"]["actuator"]["q"] = 1
    data["workspace"]["centre_x"] = 0
    data["tool_point"] = [0, 0, 0]
    design = design_from_dict(data)
    assert design.legs[0].actuator.q == 1.0 and isinstance(design.legs[0].actuator.q, float)
    assert design.workspace.centre_x == 0.0 and design.legs[0].branch == 1


@pytest.mark.parametrize(
    ("path", "value", "key", "message"),
    [
        # before: "Input should be greater than 0" for a NaN, pydantic's words elsewhere
        (
            "parts.guide.yaw",
            float("nan"),
            "parts.guide.yaw",
            "expected a finite number, got not-a-number",
        ),
        (
            "tool_point",
            [-float("inf"), 0.0, 0.0],
            "tool_point.0",
            "expected a finite number, got minus infinity",
        ),  # noqa: E501
        (
            "parts.guide.yaw",
            10**400,
            "parts.guide.yaw",
            "expected a finite number, got infinity",
        ),  # noqa: E501
        ("workspace", 5, "workspace", "expected a table, got an integer"),
        ("tool_point", "abc", "tool_point", "expected a list, got a string"),
        ("name", 5, "name", "expected a string, got an integer"),
        (
            "workspace.required.grid",
            [7.0, 9, 5],
            "workspace.required.grid.0",
            "expected an integer, got a float",
        ),  # noqa: E501
        ("legs.0.guide", 5, "leg1.guide", "expected a table, got an integer"),
        ("parts", 5, "parts", "expected a table, got an integer"),  # legs' parts not "required"
    ],
)
def test_wrong_kinds_of_value_are_named_in_toml_words(
    path: str, value: Any, key: str, message: str
) -> None:
    data = design_to_dict(default_design())
    _set(data, path, value)
    assert _refused(data) == f"f.toml: key '{key}': {message}"


def test_a_v1_file_names_its_keys_as_written() -> None:
    data = design_to_dict(default_design())
    v1 = {"name": data["name"], "architecture": "PPR", **data["parts"]}
    v1["legs"] = [{k: v for k, v in leg.items() if k != "type"} for leg in data["legs"]]
    v1["guide"]["roll"] = True
    with pytest.warns(DesignFormatWarning):
        assert _refused(v1) == "f.toml: key 'guide.roll': expected a number, got a boolean"


# -- item 5: the tool point's unit ---------------------------------------------------------


def test_a_tool_point_in_mm_is_refused_in_the_design_file() -> None:
    data = design_to_dict(default_design())
    data["tool_point"] = [0, 0, 50]  # before: a 50 m tool, accepted
    assert _refused(data) == (
        "f.toml: key 'tool_point': tool_point = 50: lengths in design files are in "
        "metres (|length| <= 10 m); did you mean 0.05?"
    )
    data["tool_point"] = [0, 0, 10]  # 10 m: the limit itself is a length
    assert design_from_dict(data).tool_point == (0.0, 0.0, 10.0)


def test_a_tool_point_option_beyond_10_m_is_refused_in_mm(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["analyze", "--tool-point", "1e9,0,0"]) == 2  # before: accepted
    out, err = capsys.readouterr()
    assert out == ""
    assert err == (
        "ppm-stiffness: error: --tool-point 1e9,0,0: 1e+09 mm is beyond the 10000 mm "
        "(10 m) any length of a design may have; X,Y,Z are in mm\n"
    )
    assert main(["analyze", "--tool-point", "0,-10000,0", "--json"]) == 0
    capsys.readouterr()


# -- item 12: what is wrong with a file ----------------------------------------------------


@pytest.mark.parametrize("text", ["", "\n\n", "# only a comment\n"])
def test_an_empty_file_says_so(tmp_path: Path, text: str) -> None:
    path = tmp_path / "empty.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(DesignError) as err:  # before: "List should have at least 3 items"
        load_design(path)
    assert str(err.value) == (
        f"{path}: file is empty; a design needs `schema = 2` and at least 3 [[legs]]"
    )


@pytest.mark.parametrize("name", ["paper_3ppr.toml", "3rpr.toml"])
def test_a_schema_2_file_without_schema_is_told_to_add_it(tmp_path: Path, name: str) -> None:
    source = next(p for p in SHIPPED if p.name == name)
    text = source.read_text("utf-8").replace("schema = 2\n", "", 1)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error", DesignFormatWarning)  # no v1 warning first
        with pytest.raises(DesignError) as err:  # before: "key 'leg1.actuator': Field required"
            load_design(path)
    assert str(err.value) == (
        f"{path}: no 'schema' key: add `schema = 2` (it has a [parts] table and legs "
        "with a 'type', as schema 2 files do)"
    )


def test_a_file_with_neither_layout_is_told_to_add_schema() -> None:
    data = {"name": "x", "legs": [{"psi": 0.0}] * 3}
    assert _refused(data) == "f.toml: no 'schema' key: add `schema = 2`"


def test_a_v1_file_still_loads_with_its_warning() -> None:
    data = design_to_dict(default_design())
    v1 = {"name": data["name"], "architecture": "PPR", "platform": data["platform"]}
    v1.update(data["parts"])
    v1["legs"] = [{k: v for k, v in leg.items() if k != "type"} for leg in data["legs"]]
    with pytest.warns(DesignFormatWarning, match="design format v1"):
        design = design_from_dict(v1)
    assert design.legs == default_design().legs


def test_a_byte_order_mark_is_skipped(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + dump_design(default_design()).encode("utf-8"))
    assert load_design(path) == default_design()  # before: "Invalid statement (line 1)"


def test_a_misspelt_key_is_named_with_its_match_and_nothing_else() -> None:
    data = design_to_dict(default_design())
    leg = data["legs"][0]
    data["legs"][0] = {
        ("platfrom_radius" if k == "platform_radius" else k): v for k, v in leg.items()
    }
    # before: "key 'leg1.platform_radius': Field required"
    assert _refused(data) == (
        "f.toml: key 'leg1.platfrom_radius': unknown key; did you mean 'platform_radius'?"
    )


def test_an_error_in_parts_is_reported_once_where_it_is_written() -> None:
    data = design_to_dict(default_design())
    guide = data["parts"]["guide"]
    data["parts"]["guide"] = {("rol" if k == "roll" else k): v for k, v in guide.items()}
    assert _refused(data) == "f.toml: key 'parts.guide.rol': unknown key; did you mean 'roll'?"
    data = design_to_dict(default_design())
    data["parts"]["gide"] = data["parts"].pop("guide")
    assert _refused(data) == (
        "f.toml: key 'parts.gide': no leg of this design has a part named 'gide'; "
        "did you mean 'guide'?"
    )
    data = design_to_dict(default_design())
    data["prts"] = data.pop("parts")  # [parts] misspelt: its parts are not "required"
    assert _refused(data) == "f.toml: key 'prts': unknown key; did you mean 'parts'?"


def test_every_error_of_a_file_is_reported_at_once_in_file_order(tmp_path: Path) -> None:
    text = (ROOT / "examples/3rpr.toml").read_text("utf-8")
    edits = [
        ("tool_point = [\n    0.0,\n    0.0,\n    0.0,\n]", "tool_point = [0.0, 0.0, 50.0]"),
        ("locked_stiffness = 20000000.0", "locked_stiffness = true"),
        ("psi = -2.617993877991495", "psi = -150.0"),
    ]
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    first_leg = text.index("[[legs]]")
    text = text[:first_leg] + text[first_leg:].replace("housing_length", "housing_lenght", 1)
    path = tmp_path / "three.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(DesignError) as err:  # before: the first error only, one per run
        load_design(path)
    assert str(err.value).splitlines() == [
        f"{path}: key 'tool_point': tool_point = 50: lengths in design files are in metres "
        "(|length| <= 10 m); did you mean 0.05? (1 of 4 errors; the others follow, one a line)",
        f"{path}: key 'parts.actuator.locked_stiffness': expected a number, got a boolean",
        f"{path}: key 'leg1.housing_lenght': unknown key; did you mean 'housing_length'?",
        f"{path}: key 'leg3.psi': psi = -150: angles in design files are in radians "
        "(|angle| <= 2 pi); did you mean -2.61799?",
    ]


def test_the_cli_prints_every_error_of_a_file_under_one_error_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = design_to_dict(default_design())
    data["tool_point"] = [0.0, 0.0, 50.0]
    data["legs"][1]["alpha"] = 90.0
    path = tmp_path / "two.toml"
    path.write_text(tomli_w.dumps(data), encoding="utf-8")
    assert main(["analyze", "--design", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 2
    assert lines[0].startswith(f"ppm-stiffness: error: {path}: key 'tool_point': ")
    assert lines[0].endswith("(1 of 2 errors; the others follow, one a line)")
    assert lines[1].startswith(f"{path}: key 'leg2.alpha': alpha = 90: angles")


def test_a_glob_parameter_failing_in_every_leg_gives_one_message() -> None:
    with pytest.raises(DesignError) as err:
        default_design().check_value("leg*.actuator.q", 2.0)
    assert str(err.value) == "leg*.actuator.q = 2: Input should be less than or equal to 1"


# -- shipped designs; the design package has no import cycle ------------------------------


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_every_shipped_design_loads_and_round_trips(path: Path, tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error", DesignFormatWarning)
        design = load_design(path)
        out = tmp_path / path.name
        save_design(design, out)
        assert load_design(out) == design
    if path.name == "paper_3ppr.toml":
        text = resources.files("ppm_stiffness").joinpath("data/paper_3ppr.toml").read_text()
        assert design == design_from_dict(tomllib.loads(text))


def _imports(module: Path, package: str) -> set[str]:
    """Modules of ``package`` that ``module`` imports anywhere (functions included)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(module.read_text("utf-8"))):
        names = []
        if isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        found |= {n for n in names if re.fullmatch(rf"{re.escape(package)}\.\w+", n)}
    return found


def test_the_design_modules_import_no_cycle() -> None:
    """Before: schema.Design.with_parameters imported design.io, which imports schema."""
    package = "ppm_stiffness.design"
    folder = PACKAGE / "design"
    graph = {
        f"{package}.{p.stem}": _imports(p, package)
        for p in folder.glob("*.py")
        if p.stem != "__init__"
    }
    assert graph[f"{package}.schema"], "the test must see the package's imports"

    def reaches(start: str, goal: str, seen: frozenset[str] = frozenset()) -> bool:
        return any(
            n == goal or (n not in seen and reaches(n, goal, seen | {n}))
            for n in graph.get(start, set())
        )

    assert [m for m in graph if reaches(m, m)] == []


def test_the_same_error_in_every_leg_is_one_line_with_the_leg_glob() -> None:
    data = _example("3rpr.toml")
    for leg in data["legs"]:
        leg["housing_length"] = True
    assert _refused(data) == "f.toml: key 'leg*.housing_length': expected a number, got a boolean"
    data["legs"][2]["housing_length"] = 0.12  # two legs of three: each its own line
    assert _refused(data).splitlines()[1:] == [
        "f.toml: key 'leg2.housing_length': expected a number, got a boolean"
    ]
    with pytest.raises(DesignError) as err:
        default_design().with_parameters({"leg*.platform_radius": -0.01})
    assert (
        str(err.value) == "parameters: key 'leg*.platform_radius': Input should be greater than 0"
    )
