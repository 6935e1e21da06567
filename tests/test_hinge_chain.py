"""Notch hinges in the FE frame of ``validate`` as chains of beam members (issue 29
item 6): src/ppm_stiffness/validation/hinge_chain.py; figures in docs/flexures.md."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import twist_b_from_twist_a
from ppm_stiffness.legs.flexure_hinge import FlexureHinge

pytest.importorskip("Pynite")

from ppm_stiffness.validation.hinge_chain import segment_sections, stations  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
MATERIAL = {"young_modulus": 71.7e9, "poisson_ratio": 0.33}
NOTCH = {"profile": "circular", "radius": 2e-3, "thickness": 0.3e-3}


def chain_compliance(hinge: FlexureHinge, n: int) -> np.ndarray:
    """The members' cantilever compliances transported to the notch's centre (the
    compliance of the chain clamped at x = 0, referred to x = L / 2)."""
    edges = stations(hinge, n)
    out = np.zeros((6, 6))
    for k, section in enumerate(segment_sections(hinge, edges)):
        t = twist_b_from_twist_a(np.eye(3), [edges[k + 1] - hinge.length / 2, 0.0, 0.0])
        c = cantilever_compliance(section, edges[k + 1] - edges[k])
        out += t @ c @ t.T
    return out


def test_harmonic_means_keep_the_rotational_and_axial_compliances_exact() -> None:
    """Harmonic-mean sections give C_phiz, C_phiy, C_phix and C_x of the chain equal to
    the hinge's integrals for any n (measured 2.2e-16); the transverse C_vy falls as
    n^-2 (1.8e-1, 4.2e-2, 1.0e-2 relative with 8, 16, 32 members: ratios 4.30, 4.10)."""
    hinge = FlexureHinge(profile=NOTCH, width=5e-3, material=MATERIAL)
    exact = hinge.centre_compliance()
    errors = []
    for n in (8, 16, 32):
        c = chain_compliance(hinge, n)
        rel = np.diag(c) / np.diag(exact) - 1.0
        assert np.max(np.abs(rel[[0, 1, 2, 3]])) < 1e-12
        errors.append(abs(rel[4]))
    print("C_vy errors", errors)
    assert 4.0 < errors[0] / errors[1] < 4.6
    assert 3.9 < errors[1] / errors[2] < errors[0] / errors[1]


@pytest.fixture(scope="module")
def stage() -> Path:
    """The shipped 3-RRR flexure stage (equal to scripts/chain_examples.py's
    flexure_3rrr(): tested)."""
    return ROOT / "examples" / "flexure_3rrr.toml"


def test_the_stage_fe_reaches_the_model_within_1e_4_at_second_order(stage: Path) -> None:
    """The 3-RRR flexure stage (nine circular notch hinges, piezo drives in parallel with
    the base hinges) at home: the FE frame with each hinge as n members against the
    virtual-joint K, max |dK_ij| / sqrt(K_ii K_jj) measured 1.18e-3, 3.00e-4, 8.07e-5 at
    n = 64, 128, 256 (observed order 2.00 from the increments), the compliance at P
    reciprocal to 2.4e-6 at n = 256 (its round-off in K, from changing the length unit:
    6.4e-5; docs/flexures.md, "FE frame"). Before (members of equal int dx / h, PyNite's
    residual check) n = 64 and finer were refused (SingularConfigurationError) and
    n = 256 gave 1.15e-4 (check off)."""
    from ppm_stiffness.design import load_design
    from ppm_stiffness.validation.compare import hinge_convergence

    r = hinge_convergence(load_design(stage), segments=(64, 128, 256))
    print("differences", r.differences, "order", r.order, "asymmetry", r.asymmetry)
    d = r.differences
    assert d[0] / d[1] > 3.5 and d[1] / d[2] > 3.5
    assert r.order is not None and abs(r.order - 2.0) < 0.1
    assert d[-1] < 1e-4
    assert max(r.asymmetry) < 2e-5


def test_the_richardson_limit_of_the_stage_fe_is_the_model(stage: Path) -> None:
    """Where the solve's round-off is negligible (n = 32, 64), the Richardson limit at
    order 2 equals the virtual-joint K to 1.3e-6 (measured; the rigid parts' own 1e12 N/m
    compliance is 7.6e-6 of K): the FE chains and the model are the same structure.
    Before, the mesh of 64 was refused by PyNite's residual check."""
    from ppm_stiffness.design import load_design
    from ppm_stiffness.validation.compare import hinge_convergence

    r = hinge_convergence(load_design(stage), segments=(32, 64))
    print("differences", r.differences, "limit", r.extrapolated)
    assert r.extrapolated < 5e-6


def test_cli_hinge_segments_bad_input(stage: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--hinge-segments: 0 or a multiple of 4 up to 256, else one line and exit 2."""
    from ppm_stiffness.cli import main

    for bad in ("6", "512", "-4"):
        argv = ["validate", "--design", str(stage), "--region", "--hinge-segments", bad]
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "--hinge-segments" in err


def test_the_modal_fe_takes_the_hinge_members(stage: Path) -> None:
    """The modal FE (validation/modal.py) of the stage: the hinges' members are not
    design links (their mass is not modelled). f1 (z translation) of the FE against the
    mass model: measured 310.8059 and 310.8198 Hz (4.5e-5)."""
    import warnings

    from ppm_stiffness.design import load_design
    from ppm_stiffness.validation.fe_model import FESettings
    from ppm_stiffness.validation.modal import modal_comparison

    with warnings.catch_warnings():  # the legs carry no mass: their own frequency is inf
        warnings.simplefilter("ignore", RuntimeWarning)
        r = modal_comparison(load_design(stage), settings=FESettings(hinge_segments=8))
    print("f1 model, FE:", r.model_frequencies[0], r.reduced_frequencies[0])
    assert r.reduced_frequencies[0] == pytest.approx(r.model_frequencies[0], rel=3e-4)
