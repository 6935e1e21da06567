"""scripts/loaded_table.py gives the rows of docs/statics.md's measured table (frozen
against moving geometry under the paper's load and load B)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]


def test_the_script_prints_the_documented_rows(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    spec = importlib.util.spec_from_file_location("loaded_table", ROOT / "scripts/loaded_table.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setattr(sys, "argv", ["loaded_table.py", "--designs", "3-RPR,3-RPS"])
    module.main()
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith("| 3-")]
    doc = (ROOT / "docs" / "statics.md").read_text(encoding="utf-8")
    assert len(rows) == 4
    for r in rows:
        assert r in doc, r
