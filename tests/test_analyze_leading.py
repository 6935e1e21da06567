"""``analyze`` leads with what fits the design (issue 27, item 8): a spatial design
with the spatial principal stiffnesses (C = K^-1) and the least-squares decoupling,
the paper's eq. (19) and its planar k_phi, k_x, k_y on request (``--method paper``,
alias ``--decoupling paper``); a planar design with the paper's eq. (19), unchanged."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main

ROOT = Path(__file__).resolve().parents[1]
TRIPOD = str(ROOT / "examples" / "3prs.toml")


def _run(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    assert main(list(args)) == 0
    return capsys.readouterr().out


def test_spatial_design_leads_with_least_squares(capsys: pytest.CaptureFixture[str]) -> None:
    """Before: the 3-PRS's first decoupling was eq. (19) (residual coupling 2.0: it
    doubles K_rt) followed by the planar k_phi, k_x, k_y."""
    out = _run(capsys, "analyze", "--design", TRIPOD)
    heads = [line for line in out.splitlines() if line.startswith("Decoupling, method")]
    assert heads == ["Decoupling, method 'least-squares'"]
    assert "k_phi =" not in out
    assert out.index("Principal stiffnesses from C = K^-1") < out.index("Decoupling, method")
    assert "residual coupling 2.0000): --method paper" in " ".join(out.split())
    data = json.loads(_run(capsys, "analyze", "--design", TRIPOD, "--json"))
    assert data["method"] == "least-squares" and data["planar"] is False
    assert data["leading"][:2] == ["principal_compliance", "decoupling_least_squares"]
    # the keys keep their meaning (backward compatible): eq. (19) is still there
    assert data["decoupling"]["method"] == "paper"
    assert data["decoupling"]["residual_coupling"] == pytest.approx(2.0, abs=1e-9)
    assert data["decoupling_least_squares"]["residual_coupling"] < 1e-9
    keys = list(data)
    assert keys.index("principal_compliance") < keys.index("decoupling")
    assert keys.index("decoupling_least_squares") < keys.index("decoupling")


@pytest.mark.parametrize("option", ["--method", "--decoupling"])
def test_spatial_design_paper_on_request(capsys: pytest.CaptureFixture[str], option: str) -> None:
    out = _run(capsys, "analyze", "--design", TRIPOD, option, "paper")
    heads = [line for line in out.splitlines() if line.startswith("Decoupling, method")]
    assert heads == ["Decoupling, method 'paper'", "Decoupling, method 'least-squares'"]
    assert "planar definitions, of a spatial design" in " ".join(out.split())
    data = json.loads(_run(capsys, "analyze", "--design", TRIPOD, option, "paper", "--json"))
    assert data["paper_definitions"] is True and data["method"] == "paper"


def test_planar_design_keeps_the_paper_first(capsys: pytest.CaptureFixture[str]) -> None:
    out = _run(capsys, "analyze")
    heads = [line for line in out.splitlines() if line.startswith("Decoupling, method")]
    assert heads == ["Decoupling, method 'paper'", "Decoupling, method 'least-squares'"]
    assert "(paper's definitions)" in " ".join(out.split())
    data = json.loads(_run(capsys, "analyze", "--json"))
    assert data["planar"] is True and data["leading"] == ["decoupling", "principal"]
    keys = list(data)
    assert keys.index("decoupling") < keys.index("decoupling_least_squares")
    assert np.isfinite(data["principal"]["rotational"]["values"]).all()
