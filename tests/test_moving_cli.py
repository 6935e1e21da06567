"""``analyze --wrench ... --geometry moving``: which model was used, the displaced pose,
K_F, its difference from the frozen K and the load margin, in the tables and in the JSON
document (validated against docs/schemas/analyze.schema.json); bad combinations are one
line and exit 2."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from tests.helpers import design_named
from tests.paper import PAPER_WRENCH

from ppm_stiffness.cli import main
from ppm_stiffness.cli.common import console
from ppm_stiffness.statics.moving import moving_equilibrium

jsonschema = pytest.importorskip("jsonschema", reason="jsonschema is in the 'test' extra")

ROOT = Path(__file__).parents[1]
SCHEMA = ROOT / "docs" / "schemas" / "analyze.schema.json"
PAPER_LOAD = "5,5,20,0,0,0.1"  # FX,FY,FZ,MX,MY,MZ: PAPER_WRENCH


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict:  # type: ignore[type-arg]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert err == ""
    data: dict = json.loads(out)  # type: ignore[type-arg]
    return data


def test_moving_geometry_document_validates_and_carries_the_library_values(
    capsys: pytest.CaptureFixture[str],
) -> None:
    doc = _json(capsys, ["analyze", "--json", "--wrench", PAPER_LOAD, "--geometry", "moving"])
    jsonschema.validate(
        doc, json.loads(SCHEMA.read_text(encoding="utf-8")), cls=jsonschema.Draft202012Validator
    )
    assert doc["geometry"] == "moving"
    state = moving_equilibrium(design_named("paper"), PAPER_WRENCH)
    mg = doc["moving_geometry"]
    np.testing.assert_allclose(mg["stiffness_matrix"], state.stiffness_matrix, rtol=1e-12)
    np.testing.assert_allclose(
        np.asarray(mg["difference"]),
        state.stiffness_matrix - state.frozen_stiffness,
        rtol=1e-12,
        atol=1e-12 * np.abs(state.stiffness_matrix).max(),
    )
    k_f = state.stiffness_matrix
    np.testing.assert_allclose(doc["stiffness_matrix"], 0.5 * (k_f + k_f.T), rtol=1e-12)
    assert mg["displaced_pose"]["rz"] == pytest.approx(state.displaced_pose[5], rel=1e-12)
    assert mg["load_margin"]["kind"] == "limit point"
    assert mg["load_margin"]["mode_direction"] == "rotation about z"
    assert mg["load_margin"]["factor"] == pytest.approx(3.2618, abs=5e-5)
    assert doc["twist"] == pytest.approx(state.twist.tolist(), rel=1e-12)


def test_frozen_geometry_is_the_default_and_says_so(capsys: pytest.CaptureFixture[str]) -> None:
    doc = _json(capsys, ["analyze", "--json", "--wrench", PAPER_LOAD])
    assert doc["geometry"] == "frozen" and "moving_geometry" not in doc
    assert main(["analyze", "--wrench", PAPER_LOAD]) == 0
    out = capsys.readouterr().out
    assert "geometry: frozen (the paper's model" in out


def test_moving_geometry_tables(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The tables name the model and fit 80 columns (no line longer, no cell cut)."""
    monkeypatch.setattr(console, "width", 80)
    design = str(ROOT / "examples/hexapod_6ups.toml")
    argv = [
        "analyze",
        "--design",
        design,
        "--wrench",
        "200,-100,-500,0,0,2",
        "--geometry",
        "moving",
    ]
    assert main(argv) == 0
    out = capsys.readouterr().out
    for text in (
        "geometry: moving",
        "displaced pose (P in F_b): x = ",
        "Loaded tangent stiffness K_F at the displaced P",
        "K_F - K (frozen geometry, same load)",
        "K_F differs from the frozen K by",
        "load margin: no instability up to 1000 times the load",
        "Symmetric part of K_F at the displaced P",
    ):
        assert text in out, text
    assert not [line for line in out.splitlines() if len(line) > 80 or "…" in line]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["analyze", "--geometry", "moving"], "--geometry moving needs a --wrench"),
        (
            [
                "analyze",
                "--matrix",
                str(ROOT / "src/ppm_stiffness/data/paper_eq22.csv"),
                "--geometry",
                "moving",
            ],
            "--matrix cannot be combined",
        ),
        (["analyze", "--wrench", PAPER_LOAD, "--geometry", "bent"], "invalid choice: 'bent'"),
        (["analyze", "--wrench", "20,20,80,0,0,0.4", "--geometry", "moving"], "no equilibrium"),
    ],
)
def test_bad_combinations_are_one_line(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and message in err, err


def test_the_statics_page_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """The Python example of docs/statics.md runs (from the clone's top folder)."""
    text = (ROOT / "docs" / "statics.md").read_text(encoding="utf-8")
    blocks = [b.split("```", 1)[0] for b in text.split("```python\n")[1:]]
    assert blocks
    monkeypatch.chdir(ROOT)
    for block in blocks:
        exec(compile(block, "docs/statics.md", "exec"), {})
