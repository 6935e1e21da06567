"""Bad input to the Python API raises InputDataError with one clear line (issue 19,
item 15), with the checks the CLI applies to ``analyze --matrix`` (one function,
:func:`ppm_stiffness.core.inputs.stiffness_and_cholesky`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import ppm_stiffness as pps
from helpers import design_named
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import length_balanced
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.inputs import (
    PRINTED_SYMMETRY_TOLERANCE,
    SYMMETRY_TOLERANCE,
    validate_stiffness_matrix,
    validate_wrench,
)
from ppm_stiffness.model import stiffness_at_pose, workspace_centre

DESIGN = design_named("paper")
POSE = workspace_centre(DESIGN)
K = stiffness_at_pose(DESIGN, POSE)


def asymmetric(relative: float) -> np.ndarray:
    """K with one pair of coupling entries apart by ``relative`` of the largest
    length-balanced entry."""
    k = K.copy()
    scale = np.abs(length_balanced(K)).max()
    k[0, 4] += relative * scale * 0.1  # K_rt entry: balanced = K / L, L = 0.1 m
    return k


BAD_MATRICES = {
    "5x5": (np.eye(5), "must be 6x6, got shape \\(5, 5\\)"),
    "3x3": (np.eye(3), "must be 6x6, got shape \\(3, 3\\)"),
    "text": ("abc", "must be an array of numbers"),
    "nan": (np.where(np.eye(6) > 0, np.nan, K), "has entries that are not finite"),
    "inf": (K * np.where(np.eye(6) > 0, np.inf, 1.0), "has entries that are not finite"),
    "zero": (np.zeros((6, 6)), "is not positive definite: smallest eigenvalue 0 N/m"),
    "negative definite": (-K, "is not positive definite"),
    "indefinite": (np.diag([1.0, 1, 1, 1, 1, -1]), "is not positive definite"),
    "not symmetric": (asymmetric(1e-6), "is not symmetric: the largest \\|K - K\\^T\\| is 1.0e-06"),
}


@pytest.mark.parametrize("case", BAD_MATRICES)
def test_eigenscrews_refuses(case: str) -> None:
    matrix, message = BAD_MATRICES[case]
    with pytest.raises(InputDataError, match=f"^stiffness matrix {message}"):
        pps.eigenscrews(matrix)


@pytest.mark.parametrize("case", BAD_MATRICES)
def test_decouple_refuses(case: str) -> None:
    matrix, message = BAD_MATRICES[case]
    for method in ("paper", "least-squares"):
        with pytest.raises(InputDataError, match=f"^stiffness matrix {message}"):
            pps.decouple(matrix, method)


def test_decouple_refuses_an_unknown_method() -> None:
    with pytest.raises(InputDataError, match="unknown decoupling method 'best'"):
        pps.decouple(K, "best")  # type: ignore[arg-type]


def test_symmetry_tolerance_both_sides() -> None:
    # the library reads one triangle: it accepts round-off asymmetry only
    pps.eigenscrews(asymmetric(0.5 * SYMMETRY_TOLERANCE))
    with pytest.raises(InputDataError, match="not symmetric"):
        pps.eigenscrews(asymmetric(2.0 * SYMMETRY_TOLERANCE))
    # a matrix read from a file carries printed digits: its tolerance is wider, and
    # the symmetric part is what the CLI passes on
    k = validate_stiffness_matrix(asymmetric(0.5 * PRINTED_SYMMETRY_TOLERANCE), "f", 1e-6)
    np.testing.assert_array_equal(k, k.T)
    with pytest.raises(InputDataError, match="^f is not symmetric"):
        validate_stiffness_matrix(asymmetric(2.0 * PRINTED_SYMMETRY_TOLERANCE), "f", 1e-6)


@pytest.mark.parametrize("case", ["zero", "negative definite", "indefinite", "nan", "3x3"])
def test_cli_matrix_refuses_with_the_same_message(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    matrix, message = BAD_MATRICES[case]
    f = tmp_path / "k.csv"
    np.savetxt(f, np.asarray(matrix), delimiter=",")
    assert main(["analyze", "--matrix", str(f)]) == 2
    err = capsys.readouterr().err
    if case == "3x3":  # the CSV reader counts rows first
        assert "must be 6x6" in err
    else:
        assert len(err.strip().splitlines()) == 1
        assert f"{f} {message.replace(chr(92), '')}" in err.replace("\n", "")


BAD_WRENCHES = {
    "three components": (np.array([1.0, 2.0, 3.0]), "a wrench has 6 components"),
    "nan": (np.array([0.0, 0, 0, np.nan, 0, 0]), "wrench components must be finite"),
    "inf": (np.array([0.0, 0, 0, 1, np.inf, 0]), "wrench components must be finite"),
    "text": (["a"] * 6, "a wrench must be an array of numbers"),
}


@pytest.mark.parametrize("case", BAD_WRENCHES)
def test_equilibrium_refuses_a_bad_wrench(case: str) -> None:
    wrench, message = BAD_WRENCHES[case]
    with pytest.raises(InputDataError, match=message):
        pps.loaded_state(DESIGN, wrench, POSE)
    with pytest.raises(InputDataError, match=message):
        validate_wrench(wrench)


@pytest.mark.parametrize(
    ("pose", "message"),
    [
        (np.array([0.0, 0.0]), r"has 3 task coordinates \(x, y, rz\) or 6 coordinates"),
        (np.array([0.0, np.nan, 0.0]), "pose coordinates must be finite"),
    ],
)
def test_equilibrium_refuses_a_bad_pose(pose: np.ndarray, message: str) -> None:
    with pytest.raises(InputDataError, match=message):
        pps.loaded_state(DESIGN, np.zeros(6), pose)


def test_good_input_still_passes() -> None:
    # the same calls with valid input: the paper's design at its centre
    assert pps.eigenscrews(K).eigenvalues.shape == (6,)
    assert pps.decouple(K).residual_coupling > 1.0  # the paper's coupled design
    state = pps.loaded_state(DESIGN, np.array([0.0, 0, 0.1, 5, 5, 20]), POSE)
    assert np.all(np.isfinite(state.twist))
