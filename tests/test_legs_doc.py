"""docs/legs.md's key reference is the schema's (scripts/legs_reference.py writes it)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _script():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location(
        "legs_reference", ROOT / "scripts" / "legs_reference.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("legs_reference", module)
    spec.loader.exec_module(module)
    return module


def test_the_key_reference_is_generated_from_the_schema() -> None:
    """Every leg type's and part's keys in docs/legs.md equal the schema's: a key added
    to a leg type or part and not to the page fails here (regenerate with
    `python scripts/legs_reference.py`)."""
    script = _script()
    text = (ROOT / "docs" / "legs.md").read_text(encoding="utf-8")
    section = text.split(script.BEGIN, 1)[1].split(script.END, 1)[0]
    assert section == "\n" + script.reference()


def test_the_reference_lists_every_leg_type() -> None:
    from ppm_stiffness.legs.registry import leg_types

    reference = _script().reference()
    for name in leg_types():
        assert f'#### `type = "{name}"`' in reference
