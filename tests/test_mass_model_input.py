"""The mass model in design files and at the CLI: strict numbers, unit mistakes named,
what a mass model needs, the `modes` command, `analyze`'s first frequency, units at
the edges, and the mode-shape picture."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.core import pose as P
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import (
    default_design,
    design_from_dict,
    design_to_dict,
    dump_design,
    load_design,
)
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.dynamics.mass import mass_matrix_at_pose
from ppm_stiffness.dynamics.modes import natural_frequencies
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.poses import home_pose

ROOT = Path(__file__).parents[1]


def _refused(data: dict[str, Any]) -> str:
    with pytest.raises(DesignError) as err:
        design_from_dict(data, source="f.toml")
    return str(err.value)


def _paper() -> dict[str, Any]:
    return design_to_dict(default_design())


# -- strict numbers and unit mistakes ---------------------------------------------------


@pytest.mark.parametrize(
    ("table", "key", "value", "expected"),
    [
        ("distal", "mass", True, "key 'parts.distal.mass': expected a number, got a boolean"),
        ("distal", "mass", "0.06", "key 'parts.distal.mass': expected a number, got a string"),
        ("actuator", "carriage_mass", float("nan"), "expected a finite number, got not-a-number"),
        (
            "distal",
            "mass",
            63.13e3,
            "masses in design files are in kg (<= 10000 kg); did you mean 63.13 (g)?",
        ),
        (
            "distal",
            "inertia_transverse",
            134.7,
            "inertias in design files are in kg·m^2 (radius of gyration sqrt(I / m) = 46.2 m > "
            "10 m); did you mean 0.0001347 (kg·mm^2)?",
        ),
        (
            "actuator",
            "rotor_inertia",
            30.0,
            "rotor_inertia = 30: inertias in design files are in kg·m^2 (a rotor <= 1 kg·m^2); "
            "did you mean 3e-05 (kg·mm^2)?",
        ),
        ("distal", "mass", -0.1, "greater than or equal to 0"),
    ],
)
def test_mass_values_are_strict_numbers_in_si(
    table: str, key: str, value: Any, expected: str
) -> None:
    data = _paper()
    data["parts"][table][key] = value
    assert expected in _refused(data)


def test_a_platform_mass_in_grams_is_named_by_its_density() -> None:
    data = _paper()
    data["platform"]["mass"] = 232.0
    message = _refused(data)
    assert "key 'platform" in message and "denser than any material" in message
    assert "did you mean 0.232 (g)?" in message


@pytest.mark.parametrize(
    ("platform", "expected"),
    [
        (
            {"mass": 1.0, "inertia": [[1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]], "shape": "box"},
            "give the inertia or a shape with its dimensions, not both",
        ),
        (
            {"mass": 1.0},
            'give the inertia [kg·m^2] about the centre of mass, or shape = "cylinder"',
        ),
        ({"mass": 1.0, "shape": "cylinder", "radius": 0.1}, "missing height"),
        ({"mass": 1.0, "shape": "box", "size": [0.1, 0.1, 0.01], "radius": 0.1}, "radius is not"),
        (
            {"mass": 1.0, "inertia": [[1e-3, 2e-4, 0], [0, 1e-3, 0], [0, 0, 1e-3]]},
            "inertia must be a symmetric",
        ),
        (
            {"mass": 1.0, "inertia": [[1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 3e-3]]},
            "break the triangle inequality",
        ),
        (
            {"mass": 1.0, "inertia": [[5e3, 0, 0], [0, 5e3, 0], [0, 0, 9e3]]},
            "did you mean 0.009 (kg·mm^2)?",
        ),
        ({"mass": 1.0, "shape": "cylinder", "radius": 80.0, "height": 0.01}, "did you mean 0.08?"),
    ],
)
def test_the_platform_table_is_one_real_body(platform: dict[str, Any], expected: str) -> None:
    data = _paper()
    data["platform"] = platform
    assert expected in _refused(data)


def test_leg_masses_need_the_platform_and_their_own_mass() -> None:
    data = _paper()
    del data["platform"]
    assert "the legs carry masses but the design has no [platform] table" in _refused(data)
    data = _paper()
    del data["parts"]["distal"]["mass"]
    assert "mass_centre, inertia_transverse, mass_centre_from given without the link's mass" in (
        _refused(data)
    )
    data = _paper()
    data["parts"]["actuator"]["rotor_inertia"] = 3e-5
    assert "rotor_inertia of a linear actuator needs actuator.gear_ratio [rad/m]" in _refused(data)
    data["parts"]["actuator"].pop("rotor_inertia")
    data["parts"]["actuator"]["gear_ratio"] = 50.0
    assert "gear_ratio given without rotor_inertia" in _refused(data)


def test_a_design_without_a_mass_model_works_as_before(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """No [platform] and no masses: analyze prints no frequency, modes says what is
    missing in one line (exit 2)."""
    data = _paper()
    del data["platform"]
    for table in data["parts"].values():
        for key in (
            "mass",
            "mass_centre",
            "mass_centre_from",
            "inertia_transverse",
            "carriage_mass",
        ):
            table.pop(key, None)
    path = tmp_path / "massless.toml"
    design = design_from_dict(data)
    path.write_text(dump_design(design), encoding="utf-8")
    assert "[platform]" not in path.read_text("utf-8") and "mass" not in path.read_text("utf-8")
    assert main(["analyze", "--design", str(path), "--json"]) == 0
    assert "first_frequency" not in json.loads(capsys.readouterr().out)
    assert main(["modes", "--design", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "has no mass model: add a [platform] table" in err


# -- analyze and modes at the CLI ---------------------------------------------------------


def test_analyze_adds_the_first_frequency_of_the_modes(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "--json"]) == 0
    analysis = json.loads(capsys.readouterr().out)
    assert main(["modes", "--json"]) == 0
    modes = json.loads(capsys.readouterr().out)
    assert analysis["first_frequency"] == modes["frequencies"][0]
    assert analysis["first_mode_direction"] == modes["modes"][0]["direction"]
    assert analysis["units"]["first_frequency"] == "Hz"
    assert main(["analyze"]) == 0
    text = capsys.readouterr().out
    assert f"first natural frequency: {modes['frequencies'][0]:.4g} Hz" in text


def test_modes_in_cli_units_equal_the_library_in_si(capsys: pytest.CaptureFixture[str]) -> None:
    """--x/--y in mm, --phi in deg, --tool-point in mm: the library's numbers at the pose
    in m and rad; the frequencies do not depend on the tool point (residual 2e-15)."""
    design = default_design()
    assert main(["modes", "--json", "--x", "2", "--y", "-3", "--phi", "1.5"]) == 0
    at_p = json.loads(capsys.readouterr().out)
    pose = (0.002, -0.003, math.radians(1.5))
    library = modal_analysis(design, pose).to_dict()
    assert at_p["frequencies"] == library["frequencies"]
    argv = ["modes", "--json", "--x", "2", "--y", "-3", "--phi", "1.5", "--tool-point", "10,-5,20"]
    assert main(argv) == 0
    at_t = json.loads(capsys.readouterr().out)
    assert at_t["tool_point"] == [0.01, -0.005, 0.02]
    assert np.allclose(at_t["frequencies"], at_p["frequencies"], rtol=1e-14, atol=0)
    assert at_t["mass_matrix"] != at_p["mass_matrix"]


def test_frequencies_survive_the_design_file_round_trip(tmp_path: Path) -> None:
    """Written and read back, every shipped design is the same model (every field equal)
    and its mass model gives the same frequencies, bit for bit (SI throughout: nothing
    is converted; the condensed frequencies, which read every mass, inertia and
    stiffness the link modes read)."""
    for path in [*sorted((ROOT / "examples").glob("*.toml"))]:
        design = load_design(path)
        again = tmp_path / path.name
        again.write_text(dump_design(design), encoding="utf-8")
        read = load_design(again)
        assert read.model_dump() == design.model_dump()
        assert (
            modal_analysis(read, link_modes=0).to_dict()["frequencies"]
            == (modal_analysis(design, link_modes=0).to_dict()["frequencies"])
        )


def test_doubling_every_mass_divides_the_frequencies_by_sqrt_2() -> None:
    """M is linear in the masses and inertias, K does not depend on them (residual
    4e-15)."""
    design = default_design()
    names = [
        n
        for n in design.scalar_parameter_names()
        if n.split(".")[-1] in ("mass", "inertia_transverse", "carriage_mass")
    ]
    assert "platform.mass" in names and design.parameter_unit("platform.mass") == "kg"
    heavier = design.with_parameters({n: 2 * design.parameter(n) for n in names})
    p = home_pose(design)
    k = stiffness_at_pose(design, p)
    f = natural_frequencies(k, mass_matrix_at_pose(design, p))
    f2 = natural_frequencies(k, mass_matrix_at_pose(heavier, p))
    assert np.allclose(f2 * math.sqrt(2), f, rtol=2e-14, atol=0)


def test_modes_table_and_picture(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from helpers import capture_saved_figures

    monkeypatch = pytest.MonkeyPatch()
    try:
        figures = capture_saved_figures(monkeypatch)
        out = tmp_path / "modes.png"
        assert main(["modes", "--design", str(ROOT / "examples/3rrr.toml"), "--out", str(out)]) == 0
        text = capsys.readouterr().out
        assert out.stat().st_size > 0 and "figure written to" in text
        assert "repeated frequencies (modes 2, 3; 5, 6)" in text
        assert main(["modes", "--json", "--out", str(out), "--overwrite"]) == 0
        doc, err = capsys.readouterr()
        json.loads(doc)  # the message went to stderr
        assert "figure written to" in err
    finally:
        monkeypatch.undo()
    assert len(figures) == 2


@pytest.mark.parametrize("name", ["3rrr", "hexapod_6ups"])
def test_the_picture_displaces_the_platform_along_each_mode(name: str) -> None:
    """The drawn polygon of each mode is the platform at ``displaced_pose(pose, a v)``;
    the largest displacement of a platform point is AMPLITUDE of its size."""
    import matplotlib

    matplotlib.use("Agg")
    from ppm_stiffness.visuals import modes as pictures

    design = load_design(ROOT / "examples" / f"{name}.toml")
    result = modal_analysis(design).to_dict()
    pose = home_pose(design)
    shapes = np.array([m["shape"] for m in result["modes"]])
    fig = pictures.plot_modes(
        design, pose, result["frequencies"], shapes, [m["direction"] for m in result["modes"]]
    )
    amp = pictures.mode_amplitude(design, shapes)
    rest = pictures.platform_polygon(design, pose)
    size = np.max(np.linalg.norm(rest[:-1] - pose[:3], axis=1))
    moved_most = 0.0
    for j, ax in enumerate(fig.axes):
        line = next(x for x in ax.get_lines() if x.get_gid() == f"platform-mode-{j + 1}")
        drawn = np.array(line.get_data_3d() if hasattr(line, "get_data_3d") else line.get_data())
        expected = pictures.platform_polygon(design, P.displaced_pose(pose, amp * shapes[j])) * 1e3
        if drawn.shape[0] == 3:
            assert np.allclose(drawn.T, expected, rtol=0, atol=1e-9)
        else:
            view = ax.get_xlabel()[0], ax.get_ylabel()[0]
            cols = ["xyz".index(view[0]), "xyz".index(view[1])]
            assert np.allclose(drawn.T, expected[:, cols], rtol=0, atol=1e-9)
        moved_most = max(moved_most, float(np.max(np.linalg.norm(expected / 1e3 - rest, axis=1))))
    # first order in the amplitude: within its square of the stated share
    assert moved_most == pytest.approx(pictures.AMPLITUDE * size, rel=0.05)


def test_the_python_example_of_docs_dynamics_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    from test_examples import _python_blocks

    monkeypatch.chdir(ROOT)
    blocks = _python_blocks(ROOT / "docs" / "dynamics.md")
    assert blocks
    for block in blocks:
        exec(compile(block, "docs/dynamics.md", "exec"), {})


def test_modes_prints_the_actuator_stiffness_in_its_unit(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The text names the actuators' stiffness unit (N/m for linear, N·m/rad for the
    3-RRR's rotary actuators), not "SI"."""
    assert main(["modes"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "actuators locked (stiffness 1.111e+05, 1.111e+05, 1.111e+05 N/m)" in out
    assert main(["modes", "--design", str(ROOT / "examples/3rrr.toml")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "N·m/rad)" in out and "SI)" not in out
