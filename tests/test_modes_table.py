"""The table of docs/dynamics.md, "The shipped examples at their home pose", against
the code at its printed precision (printed by scripts/modes_table.py): every mass,
every frequency and the first mode's direction of every row."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.dynamics.analysis import modal_analysis

ROOT = Path(__file__).parents[1]
#: The documented rows' designs (None: the built-in paper design).
FILES = {
    "built-in 3-PPR (paper)": None,
    "symmetric 3-PPR": "examples/symmetric_3ppr.toml",
    "redundant 4-PPR": "examples/redundant_4ppr.toml",
    "3-RPR": "examples/3rpr.toml",
    "3-PRR": "examples/3prr.toml",
    "3-RRR": "examples/3rrr.toml",
    "6-UPS hexapod": "examples/hexapod_6ups.toml",
    "3-PRS spindle head": "examples/3prs.toml",
    "3-RPS tilting table": "examples/3rps.toml",
}


def _documented_rows(
    head: str = "| design | platform [kg] | links [kg] | carriages [kg] |",
) -> dict[str, list[str]]:
    text = (ROOT / "docs" / "dynamics.md").read_text(encoding="utf-8")
    start = text.index(head)
    table = text[start : text.index("\n\n", start)].splitlines()[2:]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in table]
    return {r[0]: r[1:] for r in rows}


def _agrees(printed: str, value: float) -> bool:
    """``value`` rounds to ``printed`` (half a unit of its last digit, plus round-off)."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return abs(value - float(printed)) <= 0.5 * 10.0**-decimals * (1 + 1e-9)


def _design(name: str) -> Design:
    file = FILES[name]
    return default_design() if file is None else load_design(ROOT / file)


ROWS = _documented_rows()
#: The table with the legs' own modes (issue 30).
LINK_ROWS = _documented_rows("| design | f₁ … f₆ [Hz] with link modes |")


def test_the_table_has_every_shipped_design() -> None:
    assert sorted(ROWS) == sorted(FILES)


@pytest.mark.parametrize("name", sorted(FILES))
def test_a_documented_row_is_what_the_code_gives(name: str) -> None:
    platform, links, carriages, frequencies, direction = ROWS[name]
    result = modal_analysis(_design(name), link_modes=0).to_dict()
    masses = result["masses"]
    for printed, key in ((platform, "platform"), (links, "links"), (carriages, "carriages")):
        assert _agrees(printed, masses[key]), (key, printed, masses[key])
    printed_f = re.split(r",\s*", frequencies)
    assert len(printed_f) == 6
    for p, f in zip(printed_f, result["frequencies"], strict=True):
        assert _agrees(p, f), (p, f)
    assert direction == result["modes"][0]["direction"]


@pytest.mark.parametrize("name", sorted(FILES))
def test_a_documented_row_with_link_modes_is_what_the_code_gives(name: str) -> None:
    """The table with each leg's own modes (the default number): f1..f6 and the first
    mode's direction at their printed precision."""
    frequencies, direction = LINK_ROWS[name][:2]
    result = modal_analysis(_design(name)).to_dict()
    for p, f in zip(re.split(r",\s*", frequencies), result["frequencies"], strict=True):
        assert _agrees(p, f), (p, f)
    assert direction == result["modes"][0]["direction"]
