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
    n^-2 (2.8e-1, 6.4e-2, 1.6e-2 relative with 8, 16, 32 members: ratios 4.39, 4.10)."""
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


def test_the_stage_fe_converges_to_the_model_at_second_order(stage: Path) -> None:
    """The 3-RRR flexure stage (nine circular notch hinges, piezo drives in parallel with
    the base hinges) at home: the FE frame with each hinge as n members against the
    virtual-joint K, max |dK_ij| / sqrt(K_ii K_jj) measured 1.15e-1, 2.88e-2, 7.19e-3 at
    n = 8, 16, 32 (observed order 2.00), and 2.6e-5 for the Richardson limit of n = 16
    and 32."""
    from ppm_stiffness.design import load_design
    from ppm_stiffness.validation.compare import hinge_convergence

    r = hinge_convergence(load_design(stage))
    print("differences", r.differences, "order", r.order, "limit", r.extrapolated)
    d = r.differences
    assert d[0] / d[1] > 3.5 and d[1] / d[2] > 3.5
    assert r.order is not None and abs(r.order - 2.0) < 0.1
    assert r.extrapolated < 1e-4


def test_the_modal_fe_takes_the_hinge_members(stage: Path) -> None:
    """The modal FE (validation/modal.py) of the stage: the hinges' members are not
    design links (their mass is not modelled). f1 (z translation) of the FE against the
    mass model: measured 310.8162 and 310.8198 Hz (1.2e-5)."""
    import warnings

    from ppm_stiffness.design import load_design
    from ppm_stiffness.validation.fe_model import FESettings
    from ppm_stiffness.validation.modal import modal_comparison

    with warnings.catch_warnings():  # the legs carry no mass: their own frequency is inf
        warnings.simplefilter("ignore", RuntimeWarning)
        r = modal_comparison(load_design(stage), settings=FESettings(hinge_segments=8))
    print("f1 model, FE:", r.model_frequencies[0], r.reduced_frequencies[0])
    assert r.reduced_frequencies[0] == pytest.approx(r.model_frequencies[0], rel=3e-4)
