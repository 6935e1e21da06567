"""Options that do not go together are refused with one line and exit 2, and tables
are headed by what they show (issue 27, item 5)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.cli.common import POSE_OPTIONS
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import default_design
from ppm_stiffness.statics.moving_deflection import moving_deflection

ROOT = Path(__file__).parents[1]
EQ22 = str(ROOT / "src/ppm_stiffness/data/paper_eq22.csv")


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith("ppm-stiffness: error: ") and "Traceback" not in err
    return err


@pytest.mark.parametrize("option", list(POSE_OPTIONS))
def test_matrix_refuses_every_pose_option(option: str, capsys: pytest.CaptureFixture[str]) -> None:
    """--matrix analyses a given K: a pose option has nothing to act on. Before the fix
    only --x, --y and --phi were refused; --z, --rx, --ry and --rz were ignored."""
    assert main(["analyze", "--matrix", EQ22, f"--{option}", "5"]) == 2
    err = _one_line(capsys)
    assert "--matrix cannot be combined with" in err and f"--{option}" in err


def test_deflect_refuses_linear_with_moving_geometry(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The moving curve solves the equilibrium with the actuator law: 'linear' (the
    unloaded K for every load) was silently not applied to it."""
    argv = ["deflect", "--geometry", "moving", "--method", "linear", "--max", "10"]
    assert main(argv) == 2
    assert "--method linear cannot be combined with --geometry moving" in _one_line(capsys)
    with pytest.raises(InputDataError, match="method 'linear'.*moving geometry"):
        moving_deflection(
            default_design(), np.array([0, 0, 0, 1.0, 0, 0]), [1.0, 2.0], method="linear"
        )


def test_deflect_help_says_what_method_does_with_moving_geometry(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["deflect", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "With --geometry moving it is the frozen curve's method" in text


def test_a_load_margin_map_is_headed_load_margin(capsys: pytest.CaptureFixture[str]) -> None:
    """A map of the load margin alone (here under a zero wrench: 1000, the end of the
    search, everywhere) was headed "principal stiffness over the workspace"."""
    argv = ["map", "--quantities", "load-margin", "--actuators=0,0,0,0,0,0", "--grid", "4"]
    assert main([*argv, "--quiet"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "load margin over the workspace" in out
    assert "principal stiffness" not in out
    assert main([*argv[:2], "paper,load-margin", *argv[3:], "--quiet"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "quantities over the workspace" in out and "principal stiffness" not in out
