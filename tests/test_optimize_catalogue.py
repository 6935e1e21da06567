"""Catalogue choices (issue 31, item 2): the shipped catalogue against its formulas, a
front whose best entries are known by enumeration, and the bad catalogues."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

import ppm_stiffness as pps
from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.optimize.catalogue import load_table, parse_choice
from ppm_stiffness.optimize.objectives import OBJECTIVES
from ppm_stiffness.optimize.pareto import non_dominated, optimize_front, signed
from ppm_stiffness.optimize.region import make_region
from ppm_stiffness.optimize.summary import summarize_candidate
from ppm_stiffness.optimize.variables import parse_variable

ROOT = Path(__file__).parents[1]
CATALOGUE = ROOT / "examples/catalogues/parts.toml"
RODS = f"leg*.distal={CATALOGUE}:rods"
REGION = make_region((-0.01, 0.01), (-0.01, 0.01), (-0.1, 0.1), (3, 3, 3))
PAIR = [OBJECTIVES["worst-k-translational"], OBJECTIVES["moving-mass"]]
#: Material -> (E [Pa], G [Pa], rho [kg/m^3]) as the catalogue's header states them.
MATERIALS = {"steel": (210e9, 81e9, 7850.0), "aluminium 6061-T6": (69e9, 26e9, 2700.0)}


def _design() -> pps.Design:
    return pps.load_design(ROOT / "examples/symmetric_3ppr.toml")


def test_shipped_rods_follow_their_formulas() -> None:
    """Each rod's values from its name's diameter and material, L = 0.16 m, to the 6
    significant digits written."""
    entries = load_table(CATALOGUE, "rods")
    assert len(entries) == 8
    for entry in entries:
        match = re.fullmatch(r"(.+) round bar (\d+) mm x 160 mm", str(entry["name"]))
        assert match is not None and "computed" in str(entry["source"])
        e, g, rho = MATERIALS[match.group(1)]
        d, length = int(match.group(2)) / 1000, 0.16
        area = math.pi * d**2 / 4
        mass = rho * area * length
        expected = {
            "young_modulus": e,
            "shear_modulus": g,
            "area": area,
            "torsion_constant": math.pi * d**4 / 32,
            "inertia_y": math.pi * d**4 / 64,
            "inertia_z": math.pi * d**4 / 64,
            "mass": mass,
            "inertia_transverse": mass * length**2 / 12,
        }
        for key, value in expected.items():
            assert entry[key] == pytest.approx(value, rel=5e-6), (entry["name"], key)


def test_best_entries_known_by_enumeration() -> None:
    """Worst translational stiffness against moving mass over the eight rods for the
    symmetric 3-PPR's distal links: enumeration gives a front of the four aluminium
    bars (each steel bar is beaten by an aluminium one, lighter and stiffer in bending
    per kilogram); the optimiser finds exactly those, evaluating each design once."""
    design = _design()
    choice = parse_choice(RODS, design)
    summaries = [
        summarize_candidate(design, choice.values(i), REGION, None, False, False)
        for i in range(len(choice.entries))
    ]
    values = [[q.value(s) for q in PAIR] for s in summaries]
    best = non_dominated(signed(PAIR, values))
    assert [choice.entry_name(i).split()[0] for i in best] == ["aluminium"] * 4
    result = optimize_front(design, [], PAIR, REGION, budget=33, seed=1, choices=[choice])
    assert result.outside == [("leg*.distal", None)]  # the file's rod is rounded: no entry
    assert result.evaluations == 1 + len(choice.entries)
    found = {(d.choices["leg*.distal"], d.objectives) for d in result.front}
    assert found == {(choice.entry_name(i), tuple(values[i])) for i in best}


def test_a_choice_and_a_continuous_variable_together() -> None:
    """Mixed variables: the choice's column stays on entry indices (every design has
    an entry) and the run is reproducible."""
    design = _design()
    choice = parse_choice(RODS, design)
    radius = parse_variable("leg*.platform_radius=0.02:0.04", design, False)
    runs = [
        optimize_front(design, [radius], PAIR, REGION, budget=40, seed=2, choices=[choice])
        for _ in range(2)
    ]
    names = {n for n, _ in choice.entries}
    assert all(d.choices["leg*.distal"] in names for d in runs[0].front)
    assert [(d.parameters, d.choices) for d in runs[0].front] == [
        (d.parameters, d.choices) for d in runs[1].front
    ]


@pytest.mark.parametrize(
    ("text", "body", "message"),
    [
        ("leg*.distal=CAT:rods", "[[rods]]\nname='a'\narea=1e-5\n", "has one entry"),
        ("leg*.distal=CAT:tubes", "[[rods]]\nname='a'\narea=1e-5\n", r"no table \[\[tubes\]\]"),
        (
            "leg*.distal=CAT:rods",
            "[[rods]]\nname='a'\narea=1e-5\n[[rods]]\nname='b'\ncolour=2.0\n",
            "entry 'b' sets leg\\*.distal.colour, not a parameter",
        ),
        (
            "leg*.distal=CAT:rods",
            "[[rods]]\nname='a'\narea=1e-5\n[[rods]]\nname='b'\narea='big'\n",
            "area must be a number",
        ),
        (
            "leg*.distal=CAT:rods",
            "[[rods]]\nname='a'\narea=1e-5\n[[rods]]\nname='b'\narea=-1.0\n",
            "entry 'b' is refused by the design",
        ),
        ("leg*.distal", "", "--choose must be PART=FILE.toml:TABLE"),
    ],
)
def test_bad_catalogues(tmp_path: Path, text: str, body: str, message: str) -> None:
    path = tmp_path / "cat.toml"
    path.write_text(body, encoding="utf-8")
    with pytest.raises(InputDataError, match=message):
        parse_choice(text.replace("CAT", str(path)), _design())


def test_cli_choose_writes_the_entries_and_refuses_a_double_setting(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["optimize", "--design", str(ROOT / "examples/symmetric_3ppr.toml"), "--quiet"]
    argv += ["--region=-10,10,-10,10,-5.7,5.7,3,3,3", "--budget", "17", "--choose", RODS]
    argv += ["--objective", "worst-k-translational", "--objective", "moving-mass"]
    front = tmp_path / "front.csv"
    assert main([*argv, "--out", str(tmp_path / "c.toml"), "--front", str(front)]) == 0
    text = front.read_text(encoding="utf-8")
    assert "leg*.distal" in text.splitlines()[1] and "aluminium 6061-T6 round bar" in text
    chosen = pps.load_design(tmp_path / "c.toml")
    assert chosen.parameter("leg*.distal.young_modulus") == 69e9
    capsys.readouterr()
    bad = [*argv, "--vary", "leg*.distal.area=1e-5:1e-4", "--out", str(tmp_path / "d.toml")]
    assert main(bad) == 2
    assert "--choose leg*.distal and --vary leg*.distal.area both set" in capsys.readouterr().err
