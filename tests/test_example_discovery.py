"""The tests' discovery of the shipped examples (tests/helpers.py): a new example file
is picked up by every test that applies to it, filtered by properties of its design."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import helpers
from helpers import (
    check_entries,
    design_named,
    example_designs,
    has_reduced_form,
    is_planar,
    is_spatial,
    rotational_symmetry,
)
from ppm_stiffness.design import design_from_dict, design_to_dict


def test_a_new_example_file_is_discovered(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A file added to examples/ is listed (by its stem, sorted), and by the filters its
    design satisfies."""
    for name in ("3rpr", "hexapod_6ups"):
        shutil.copy(helpers.EXAMPLES_DIR / f"{name}.toml", tmp_path / f"{name}.toml")
    shutil.copy(helpers.EXAMPLES_DIR / "3prs.toml", tmp_path / "a_new_tripod.toml")
    monkeypatch.setattr(helpers, "EXAMPLES_DIR", tmp_path)
    assert example_designs() == ["3rpr", "a_new_tripod", "hexapod_6ups"]
    assert example_designs(is_spatial) == ["a_new_tripod", "hexapod_6ups"]
    assert example_designs(is_planar, paper=True) == ["paper", "3rpr"]


def test_every_shipped_example_is_listed_once() -> None:
    stems = sorted(p.stem for p in (helpers.ROOT / "examples").glob("*.toml"))
    assert example_designs() == stems
    assert sorted(example_designs(is_planar) + example_designs(is_spatial)) == stems
    assert set(example_designs(has_reduced_form)) <= set(example_designs(is_planar))


def test_rotational_symmetry_is_read_from_the_legs() -> None:
    """The symmetric 3-PPR is 3-fold, the redundant 4-PPR 4-fold, the paper's design
    has none; moving one leg's platform joint breaks the symmetry."""
    assert rotational_symmetry(design_named("symmetric_3ppr")) == 3
    assert rotational_symmetry(design_named("redundant_4ppr")) == 4
    assert rotational_symmetry(design_named("paper")) == 1
    data = design_to_dict(design_named("symmetric_3ppr"))
    leg = data["legs"][0]
    leg["platform_radius"] += 1e-3
    assert rotational_symmetry(design_from_dict(data)) == 1


def test_a_missing_reference_entry_is_named() -> None:
    check_entries({"a": 1, "b": 2}, ["a"], "T")
    with pytest.raises(AssertionError, match=r"T: no entry for the example\(s\) \['c'\]"):
        check_entries({"a": 1}, ["a", "c"], "T")
