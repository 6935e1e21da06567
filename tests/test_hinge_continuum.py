"""The continuum check of a notch hinge (issue 29 item 5): a 2-D plane-stress FE model
(scikit-fem) beside the Euler-Bernoulli integrals.

Model and boundary conditions: src/ppm_stiffness/validation/hinge_continuum.py.
Figures: docs/flexures.md, "Continuum check".
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.legs.flexure_hinge import FlexureHinge

pytest.importorskip("skfem")

from ppm_stiffness.validation.hinge_continuum import (  # noqa: E402
    continuum_stiffness,
    mesh_stiffness,
    richardson,
    waist_stress_factor,
)

E, NU, B = 71.7e9, 0.33, 5e-3  # Al 7075-T6, 5 mm wide
MATERIAL = {"young_modulus": E, "poisson_ratio": NU}


def circular(radius: float, thickness: float) -> FlexureHinge:
    profile = {"profile": "circular", "radius": radius, "thickness": thickness}
    return FlexureHinge(profile=profile, width=B, material=MATERIAL)


def test_richardson_recovers_a_known_sequence() -> None:
    values = [1.0 + 3.0 * 4.0**-k for k in range(3)]  # error 3 h^2, h halved
    limit, order = richardson(values)
    assert limit == pytest.approx(1.0, abs=1e-15)
    assert order == pytest.approx(2.0, abs=1e-12)
    assert richardson([1.0, 2.0, 4.0]) == (4.0, None)  # increments growing: no limit


def test_plain_leaf_equals_the_beam_formulas() -> None:
    """A long thin leaf (L/t = 20) under a pure moment is in pure bending, which plane
    stress carries exactly: K_phiz = E b t^3 / (12 L), K_x = E b t / L. Measured on the
    coarsest mesh (4 rows, 3186 unknowns): 9.7e-8 and 1.2e-5 relative (the clamp's hold
    on the Poisson contraction, one section depth away from the notch's end section:
    finer meshes leave it, 1.7e-7 and 1.2e-5). Plane strain: E / (1 - nu^2)."""
    length, t = 20e-3, 1e-3
    leaf = FlexureHinge(
        profile={"profile": "leaf", "length": length, "thickness": t}, width=B, material=MATERIAL
    )
    k_rot, k_ax = E * B * t**3 / (12 * length), E * B * t / length
    r = mesh_stiffness(leaf, 4)
    print("leaf: K_phiz", r.rotational / k_rot - 1, "K_x", r.axial / k_ax - 1)
    assert r.rotational == pytest.approx(k_rot, rel=1e-6)
    assert r.axial == pytest.approx(k_ax, rel=5e-5)
    strain = mesh_stiffness(leaf, 4, state="strain")
    assert strain.rotational == pytest.approx(k_rot / (1 - NU**2), rel=1e-6)


def test_the_mesh_converges_at_second_order() -> None:
    """The stage's hinge (R = 2 mm, t = 0.3 mm): increments of K_phiz on 4, 8, 16 rows
    measured -6.77e-3 and -1.34e-3 N·m/rad (ratio 5.05, observed order 2.34), of K_x
    ratio 4.9 (order 2.29); the extrapolated limit lies beyond the finest mesh, 0.04 %
    from it."""
    r = continuum_stiffness(circular(2e-3, 0.3e-3))
    for values, order in (
        ([m.rotational for m in r.meshes], r.order_rotational),
        ([m.axial for m in r.meshes], r.order_axial),
    ):
        d = np.diff(values)
        print("increments", d, "order", order)
        assert np.all(d < 0) and abs(d[1]) < abs(d[0]) / 3
        assert order is not None and 1.8 < order < 2.8
    assert r.rotational < r.meshes[-1].rotational
    assert r.rotational == pytest.approx(r.meshes[-1].rotational, rel=1e-3)


def test_beam_integrals_overestimate_thick_circular_notches() -> None:
    """K_EB / K_FE - 1 of a circular notch's rotational stiffness is positive and grows
    with t/R: measured 0.0395 at t/R = 0.1, 0.1123 at 0.3, 0.291 at 1 (3 meshes; 4 meshes
    move them by at most 2e-4)."""
    measured = {0.1: 0.0395, 0.3: 0.1123, 1.0: 0.2912}
    excess = []
    for ratio, expected in measured.items():
        r = continuum_stiffness(circular(2e-3, 2e-3 * ratio))
        excess.append(r.rotational_eb / r.rotational - 1.0)
        print(f"t/R = {ratio}: K_EB / K_FE - 1 = {excess[-1]:.4f}")
        assert excess[-1] == pytest.approx(expected, abs=1e-3)
    assert excess[0] > 0 and np.all(np.diff(excess) > 0)


def test_the_stress_concentration_fit_is_the_plane_stress_models_within_two_percent() -> None:
    """The circular notch's K_t of statics/hinge_stress.py, (1 + t/2R)^(9/20), against the
    waist stress of the plane-stress model under a pure moment, over 6 M / (b t^2):
    measured FE 1.0099, 1.0582, 1.1834 against the fit's 1.0112, 1.0649, 1.2002 at t/R
    = 0.05, 0.3, 1 (16 rows; 8 rows within 4.2e-4); the fit errs on the safe side, by at
    most 1.4 %."""
    from ppm_stiffness.statics.hinge_stress import stress_concentration

    for ratio in (0.05, 0.3, 1.0):
        hinge = circular(2e-3, 2e-3 * ratio)
        fe = waist_stress_factor(hinge, rows=16)
        assert abs(waist_stress_factor(hinge, rows=8) - fe) < 1e-3 * fe
        assert 0.0 <= stress_concentration(hinge) / fe - 1.0 <= 0.02


def test_cli_prints_both_values(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from ppm_stiffness.cli import main

    path = tmp_path / "hinge.toml"
    path.write_text(
        'width = 5e-3\nprofile = { profile = "circular", radius = 2e-3, thickness = 0.3e-3 }\n'
        "material = { young_modulus = 71.7e9, poisson_ratio = 0.33 }\n",
        encoding="utf-8",
    )
    assert main(["validate", "--hinge", str(path), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "901.2e-3" in out and "851.4e-3" in out and "+0.0586" in out  # plane stress
    assert "955.4e-3" in out and "-0.0567" in out  # plane strain


@pytest.mark.parametrize(
    ("text", "extra", "message"),
    [
        ("width = 1\n", [], "neither a design .no \\[\\[legs\\]\\]. nor a hinge"),
        ("width = 1\n", ["--poses", "3"], "--hinge checks hinges alone: give it without --poses"),
    ],
)
def test_cli_refuses_bad_hinge_input(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    text: str,
    extra: list[str],
    message: str,
) -> None:
    from ppm_stiffness.cli import main

    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["validate", "--hinge", str(path), *extra]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert re.search(message, err)
