"""The shipped studies of docs/optimization.md (issue 31, item 7), run as written there
at a tiny budget (16: one generation of 8) over a 2-value grid of the required region,
so that each takes a few seconds: the command runs, writes a front with the columns the
page states, and every front design written covers the region and meets the
constraints (each design file evaluated again)."""

from __future__ import annotations

import csv
import math
import re
import shlex
from pathlib import Path

import pytest

import ppm_stiffness as pps
from ppm_stiffness.cli import main
from ppm_stiffness.dynamics.legmodes import DEFAULT_LINK_MODES
from ppm_stiffness.optimize.objectives import check_quantities, parse_constraint, quantity
from ppm_stiffness.optimize.summary import summarize

pytest.importorskip("pymoo", reason="pymoo is in the 'pareto' extra")

ROOT = Path(__file__).parents[1]
PAGE = ROOT / "docs/optimization.md"
#: Study (its heading's first words) -> a 2-value grid of its example's required
#: region (the --region option's mm and deg).
SMALL_REGIONS = {
    "A Delta": "-100,100,-100,100,-856.4963411,-756.4963411,2,2,2",
    "A hexapod": "-10,10,-10,10,190,210,-2.8,2.8,-2.8,2.8,-2.8,2.8,2,2,2,2,2,2",
}
#: The outputs the commands write, replaced by files in a temporary folder.
OUTPUTS = ("--out", "--front", "--front-figure")


def _studies() -> dict[str, tuple[list[str], list[str]]]:
    """Heading -> (the command's arguments after ``ppm-stiffness``, the front CSV's
    columns the page states), for each study of the "Shipped studies" section."""
    text = PAGE.read_text(encoding="utf-8")
    section = text.split("## Shipped studies", 1)[1].split("\n## ", 1)[0]
    out = {}
    for part in section.split("\n### ")[1:]:
        heading = part.splitlines()[0]
        block = re.search(r"```bash\n(.*?)```", part, re.S)
        columns = re.search(r"The front CSV's columns: `([^`]*)`", part)
        assert block is not None and columns is not None, heading
        argv = shlex.split(block.group(1).replace("\\\n", " "))
        assert argv[0] == "ppm-stiffness"
        names = [c.strip() for c in columns.group(1).replace("\n", " ").split(",")]
        out[heading] = (argv[1:], names)
    return out


STUDIES = _studies()


def test_both_studies_are_on_the_page() -> None:
    assert [h.split(":")[0] for h in STUDIES] == list(SMALL_REGIONS)


def _smoke(argv: list[str], tmp: Path, region: str) -> list[str]:
    """The command with budget 16, the small region, its outputs in ``tmp``."""
    out = list(argv)
    out[out.index("--budget") + 1] = "16"
    for option in OUTPUTS:
        i = out.index(option)
        out[i + 1] = str(tmp / Path(out[i + 1]).name)
    return [*out, f"--region={region}", "--front-designs", str(tmp), "--quiet"]


@pytest.mark.parametrize("heading", list(STUDIES))
def test_study_runs_and_its_front_is_feasible(
    heading: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(ROOT)  # the commands' paths are the repository's
    argv, columns = STUDIES[heading]
    smoke = _smoke(argv, tmp_path, SMALL_REGIONS[heading.split(":")[0]])
    assert main(smoke) == 0
    front = tmp_path / Path(argv[argv.index("--front") + 1]).name
    with front.open(encoding="utf-8") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert rows and list(rows[0]) == columns
    assert (tmp_path / Path(argv[argv.index("--front-figure") + 1]).name).stat().st_size > 0
    constraints = [parse_constraint(c) for c in _values(argv, "--constraint")]
    objectives = [quantity(n) for n in _values(argv, "--objective")]
    # the f1 of the run: its --link-modes, or the default
    given = _values(argv, "--link-modes")
    link_modes = int(given[0]) if given else DEFAULT_LINK_MODES
    for row in rows:
        design = pps.load_design(tmp_path / f"front_{int(row['row']):03d}.toml")
        check_quantities(design, [*objectives, *(c.quantity for c in constraints)], False)
        region = design.workspace.required
        assert region is not None
        summary = summarize(design, region, reach=True, link_modes=link_modes)
        assert summary.covers, row
        for c in constraints:
            assert c.shortfall(summary) == 0, (row, str(c))
        for q in objectives:  # the front's values are the design file's
            assert q.value(summary) == pytest.approx(float(row[q.name]), rel=1e-9)


def _values(argv: list[str], option: str) -> list[str]:
    return [argv[i + 1] for i, a in enumerate(argv) if a == option]


def test_every_parameter_of_the_studies_has_a_unit() -> None:
    """The tables and CSV of a study print each variable's unit (a parallelogram's width
    was listed without one)."""
    for name in ("delta.toml", "hexapod_6ups.toml"):
        design = pps.load_design(ROOT / "examples" / name)
        missing = [p for p in design.scalar_parameter_names() if not design.parameter_unit(p)]
        assert missing == [], name


#: The studies' catalogue tables: table -> (material's E, G [Pa], rho [kg/m^3], length
#: [m], added mass [kg]: the hexapod rod's ball nut), as the catalogue's header states.
TUBES = {
    "delta_arms": (69e9, 26e9, 2700.0, 0.3, 0.0),
    "delta_forearms": (1.1e11, 2e10, 1550.0, 0.8, 0.0),
    "hexapod_rods": (210e9, 81e9, 7850.0, 0.185, 0.08),
}


@pytest.mark.parametrize("table", list(TUBES))
def test_study_tubes_follow_their_formulas(table: str) -> None:
    """Each tube's section and mass from the D x t of its name, to the digits written
    (6 for the sections, 4 for the masses)."""
    from ppm_stiffness.optimize.catalogue import load_table

    e, g, rho, length, extra = TUBES[table]
    entries = load_table(ROOT / "examples/catalogues/parts.toml", table)
    assert len(entries) >= 3
    for entry in entries:
        match = re.search(r"tube (\d+(?:\.\d+)?) x (\d+(?:\.\d+)?) mm", str(entry["name"]))
        assert match is not None, entry["name"]
        d, t = float(match.group(1)) / 1e3, float(match.group(2)) / 1e3
        area = math.pi * (d**2 - (d - 2 * t) ** 2) / 4
        inertia = math.pi * (d**4 - (d - 2 * t) ** 4) / 64
        assert (entry["young_modulus"], entry["shear_modulus"]) == (e, g)
        for key, value in (("area", area), ("inertia_y", inertia), ("inertia_z", inertia)):
            assert entry[key] == pytest.approx(value, rel=5e-6), (entry["name"], key)
        assert entry["torsion_constant"] == pytest.approx(2 * inertia, rel=5e-6)
        assert entry["mass"] == pytest.approx(rho * area * length + extra, rel=5e-4)


@pytest.mark.parametrize(
    ("example", "part", "table"),
    [
        ("delta.toml", "leg*.arm", "delta_arms"),
        ("delta.toml", "leg*.forearm", "delta_forearms"),
        ("hexapod_6ups.toml", "leg*.rod", "hexapod_rods"),
    ],
)
def test_the_examples_own_tube_is_an_entry(example: str, part: str, table: str) -> None:
    """So that the study's start design is a candidate of the search."""
    from ppm_stiffness.optimize.catalogue import parse_choice

    design = pps.load_design(ROOT / "examples" / example)
    catalogue = ROOT / "examples/catalogues/parts.toml"
    choice = parse_choice(f"{part}={catalogue}:{table}", design)
    assert choice.start(design) is not None
