"""Design files, schema 2: per-leg parts, [parts] defaults, dotted names and globs, the
v1 format read with a warning, errors that name the key."""

from __future__ import annotations

import tomllib
import warnings
from importlib import resources
from pathlib import Path

import pytest

from ppm_stiffness.core.errors import DesignError, DesignFormatWarning
from ppm_stiffness.design import (
    default_design,
    design_from_dict,
    design_to_dict,
    dump_design,
    load_design,
)
from ppm_stiffness.legs.registry import leg_types

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_every_shipped_file_is_schema_2_and_round_trips(tmp_path: Path) -> None:
    paths = sorted(EXAMPLES.glob("*.toml"))
    assert {p.stem for p in paths} >= {"3rpr", "3prr", "3rrr", "symmetric_3ppr", "redundant_4ppr"}
    text = resources.files("ppm_stiffness").joinpath("data/paper_3ppr.toml").read_text("utf-8")
    assert tomllib.loads(text)["schema"] == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error", DesignFormatWarning)  # none of them is v1
        for p in paths:
            assert tomllib.loads(p.read_text("utf-8"))["schema"] == 2
            d = load_design(p)
            out = tmp_path / p.name
            out.write_text(dump_design(d), encoding="utf-8")
            assert load_design(out) == d


def _v1_of_builtin() -> dict[str, object]:
    """The built-in design written as a v1 file (shared part tables, no type, no schema)."""
    data = design_to_dict(default_design())
    v1: dict[str, object] = {
        "name": data["name"],
        "architecture": "PPR",
        "workspace": data["workspace"],
        "platform": data["platform"],  # the mass model (schema 2 only added it)
        **data["parts"],
    }
    v1["legs"] = [{k: v for k, v in leg.items() if k != "type"} for leg in data["legs"]]
    return v1


def test_v1_file_loads_with_one_warning_and_the_same_design() -> None:
    with pytest.warns(DesignFormatWarning, match="schema") as record:
        d = design_from_dict(_v1_of_builtin(), source="old.toml")
    assert len(record) == 1 and "\n" not in str(record[0].message)
    assert d == default_design()


def test_parts_defaults_are_overridden_key_by_key() -> None:
    data = design_to_dict(default_design())
    data["legs"][1]["guide"] = {"lateral": 1.0e6}
    d = design_from_dict(data)
    assert d.legs[1].guide.lateral == 1.0e6
    assert d.legs[1].guide.yaw == d.legs[0].guide.yaw == 1700.0
    assert d.legs[0].guide.lateral == 2.5e6


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d["legs"][1]["guide"].__setitem__("lateral", -1.0), "leg2.guide.lateral"),
        (lambda d: d["legs"][0].__setitem__("rol", 1.0), "leg1.rol"),
        (lambda d: d["legs"][2].__setitem__("type", "XYZ"), "leg3.type"),
        (lambda d: d["parts"].__setitem__("elbow", {}), "parts.elbow"),
        (lambda d: d.__setitem__("schema", 3), "schema"),
    ],
)
def test_errors_name_the_key(edit, key: str) -> None:  # type: ignore[no-untyped-def]
    data = design_to_dict(default_design())
    for leg in data["legs"]:
        leg["guide"] = dict(data["parts"]["guide"])
    edit(data)
    with pytest.raises(DesignError, match=f"key '{key}'"):
        design_from_dict(data)


def test_unknown_leg_type_lists_the_known_ones() -> None:
    data = design_to_dict(default_design())
    data["legs"][0]["type"] = "RPP"
    with pytest.raises(DesignError) as err:
        design_from_dict(data)
    for name in leg_types():
        assert name in str(err.value)


def test_parameter_names_globs_and_units() -> None:
    d = load_design(EXAMPLES / "3rrr.toml")
    names = d.scalar_parameter_names()
    assert "leg2.elbow_revolute.tilt" in names and "leg3.actuator.k_a" in names
    assert d.expand("leg*.distal_length") == [f"leg{i}.distal_length" for i in (1, 2, 3)]
    assert d.expand("distal_length") == d.expand("leg*.distal_length")  # v1-style name
    assert d.parameter("leg*.distal_length") == 0.15
    assert d.parameter_unit("leg1.actuator.locked_stiffness") == "N·m/rad"
    assert d.parameter_unit("leg1.proximal_length") == "m"
    changed = d.with_parameters({"leg*.distal_length": 0.16})
    assert [leg.distal_length for leg in changed.legs] == [0.16] * 3
    with pytest.raises(DesignError, match="unknown design parameter"):
        d.expand("leg*.bearing.tilt_lateral")
    unequal = d.with_parameters({"leg2.distal_length": 0.17})
    with pytest.raises(DesignError, match="differ"):
        unequal.parameter("leg*.distal_length")


def test_architecture_names() -> None:
    assert default_design().architecture == "3-PPR"
    assert load_design(EXAMPLES / "redundant_4ppr.toml").architecture == "4-PPR"
    assert load_design(EXAMPLES / "3prr.toml").architecture == "3-PRR"


def test_cli_reports_a_v1_file_in_one_line(tmp_path: Path) -> None:
    import subprocess
    import sys

    import tomli_w

    path = tmp_path / "old.toml"
    path.write_text(tomli_w.dumps(_v1_of_builtin()), encoding="utf-8")
    run = subprocess.run(
        [sys.executable, "-m", "ppm_stiffness", "analyze", "--design", str(path), "--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ppm-stiffness: warning: ")
    assert "schema" in lines[0]


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("ppm_stiffness.eigenscrews", "ppm_stiffness.core.eigenscrews"),
        ("ppm_stiffness.decoupling", "ppm_stiffness.core.decoupling"),
        ("ppm_stiffness.workspace", "ppm_stiffness.maps.workspace"),
        ("ppm_stiffness.deflection", "ppm_stiffness.statics.deflection"),
    ],
)
def test_old_module_paths_import_with_a_deprecation_warning(old: str, new: str) -> None:
    """Paths the 0.1 README and docs showed still work and name the new home."""
    import importlib
    import sys

    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=new):
        module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    assert module.__spec__ is not None and module.__spec__.name == new


def test_public_api_names_and_version() -> None:
    import importlib
    import subprocess
    import sys

    import ppm_stiffness as pps

    assert set(pps.__all__) == {"__version__", *pps._API}
    importlib.import_module("ppm_stiffness.eigenscrews")  # the deprecated module path
    assert callable(pps.eigenscrews)  # still the function, not the module
    for name in pps.__all__:
        assert getattr(pps, name) is not None
    run = subprocess.run(
        [sys.executable, "-m", "ppm_stiffness", "--version"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert run.stdout.strip() == f"ppm-stiffness {pps.__version__}"
    assert pps.__version__[0].isdigit()


@pytest.mark.parametrize(
    ("part_key", "value", "key", "hint"),
    [
        ("young_modulus", 69.0, "proximal.young_modulus", "did you mean 6.9e+10 (GPa)?"),
        ("area", 210.0, "proximal.area", "did you mean 0.00021 (mm^2)?"),
        ("inertia_y", 630.0, "proximal.inertia_y", "did you mean 6.3e-10 (mm^4)?"),
        ("shear_modulus", 1e-300, "proximal.shear_modulus", "moduli in design files are in Pa"),
    ],
)
def test_section_unit_mistakes_are_named_with_a_hint(
    part_key: str, value: float, key: str, hint: str
) -> None:
    """Paper Table 2 in its printed units (GPa, mm^2 ...) is refused with the SI value."""
    data = design_to_dict(default_design())
    data["parts"]["proximal"][part_key] = value  # shared by every leg: reported once
    with pytest.raises(DesignError) as err:
        design_from_dict(data)
    assert str(err.value).startswith(f"design: key 'parts.{key}': ") and hint in str(err.value)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize(
    ("leg_key", "value", "key", "hint"),
    [
        ("alpha", 90.0, "leg1.alpha", "did you mean 1.5708?"),  # degrees for radians
        ("platform_radius", 30.0, "leg1.platform_radius", "did you mean 0.03?"),  # mm
        ("stroke", [27.86, 77.86], "leg1.stroke", "did you mean 0.02786?"),
        ("bearing_ofset", 0.1, "leg1.bearing_ofset", "did you mean 'bearing_offset'?"),
    ],
)
def test_unit_mistakes_and_typos_are_named_with_a_hint(
    leg_key: str, value: object, key: str, hint: str
) -> None:
    data = design_to_dict(default_design())
    data["legs"][0][leg_key] = value
    with pytest.raises(DesignError) as err:
        design_from_dict(data)
    assert f"key '{key}'" in str(err.value) and hint in str(err.value)


def test_every_moved_module_path_still_imports() -> None:
    """All 16 old paths of 0.1 (review: 'ppm_stiffness.ppr' pointed at no module)."""
    import importlib
    import sys

    from ppm_stiffness._moved import MOVED

    for old, new in MOVED.items():
        sys.modules.pop(old, None)
        with pytest.warns(DeprecationWarning, match=new):
            assert importlib.import_module(old) is importlib.import_module(new)


def test_bad_pose_and_wrench_shapes_raise_library_errors() -> None:
    from ppm_stiffness.analysis import analyze_design
    from ppm_stiffness.core.errors import InputDataError
    from ppm_stiffness.model import stiffness_at_pose

    with pytest.raises(InputDataError, match="3 task coordinates"):
        stiffness_at_pose(default_design(), [0.0, 0.0])
    with pytest.raises(InputDataError, match="finite"):
        stiffness_at_pose(default_design(), [0.0, float("nan"), 0.0])
    with pytest.raises(InputDataError, match="6 components"):
        analyze_design(default_design(), None, [1.0, 2.0, 3.0])
