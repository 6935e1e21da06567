"""The notch flexure hinge part (issue 29 item 1): its 6x6 compliance by quadrature.

Conventions: docs/conventions.md, "Flexure hinges"; src/ppm_stiffness/legs/flexure_hinge.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from ppm_stiffness.core.beam import BeamSection, cantilever_compliance
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.legs.flexure_hinge import FlexureHinge, torsion_constant

E, NU, B = 71.7e9, 0.33, 5e-3  # Al 7075-T6, 5 mm wide
ROOT = Path(__file__).resolve().parents[1]
MATERIAL = {"young_modulus": E, "poisson_ratio": NU, "density": 2810.0, "yield_strength": 503e6}


def circular(radius: float, thickness: float) -> FlexureHinge:
    profile = {"profile": "circular", "radius": radius, "thickness": thickness}
    return FlexureHinge(profile=profile, width=B, material=MATERIAL)


def wu_zhou(radius: float, thickness: float) -> float:
    """Exact rotational compliance alpha_z / M_z [rad/(N m)] of a right-circular notch.

    Paros J M, Weisbord L, "How to design flexure hinges", Machine Design 37 (1965)
    151-156, full expression; re-derived in this form by Wu Y, Zhou Z, "Design
    calculations for flexure hinges", Rev. Sci. Instrum. 73 (2002) 3101-3106, eq. for
    alpha_z / M_z with s = R / t. It is the integral int 12 / (E b h^3) dx over
    h = t + 2R (1 - cos theta), x = R sin theta, in closed form (checked here against an
    independent adaptive quadrature, scipy quad at 1e-13, to 1e-14 for s = 1..100).
    """
    s = radius / thickness
    f = 2 * s**3 * (6 * s**2 + 4 * s + 1) / ((2 * s + 1) * (4 * s + 1) ** 2) + 12 * s**4 * (
        2 * s + 1
    ) / (4 * s + 1) ** 2.5 * np.arctan(np.sqrt(4 * s + 1))
    return float(12.0 / (E * B * radius**2) * f)


@pytest.mark.parametrize("ratio", [1.0, 10.0, 100.0, 1000.0])
def test_circular_notch_equals_wu_zhou_closed_form(ratio: float) -> None:
    hinge = circular(2e-3, 2e-3 / ratio)
    c = hinge.compliance()
    exact = wu_zhou(2e-3, 2e-3 / ratio)
    assert c[2, 2] == pytest.approx(exact, rel=1e-10)
    # measured: <= 2.1e-14 relative at the default 16 panels x 24 nodes
    assert abs(c[2, 2] / exact - 1.0) < 1e-12


def test_simplified_paros_weisbord_is_an_approximation() -> None:
    """K = 2 E b t^(5/2) / (9 pi R^(1/2)) (Paros-Weisbord, t << R) against the exact K:
    measured simplified / exact - 1 = -12.22 % at R/t = 1, -1.274 % at 10, -0.1253 % at
    100, -0.01250 % at 1000: it underestimates K by t / (8 R) at first order."""
    measured = {1.0: -0.12224, 10.0: -0.012735, 100.0: -0.0012535, 1000.0: -0.00012504}
    for ratio, expected in measured.items():
        r, t = 2e-3, 2e-3 / ratio
        exact = 1.0 / circular(r, t).compliance()[2, 2]
        simple = 2 * E * B * t**2.5 / (9 * np.pi * r**0.5)
        print(
            f"R/t = {ratio:6g}: K exact {exact:.6g}, simplified {simple:.6g} N m/rad, "
            f"{simple / exact - 1:+.4%}"
        )
        assert simple / exact - 1.0 == pytest.approx(expected, rel=1e-3)
    r, t = 2e-3, 2e-7  # R/t = 1e4: the first-order term -t / (8 R)
    ratio = 2 * E * B * t**2.5 / (9 * np.pi * r**0.5) * circular(r, t).compliance(64)[2, 2]
    assert (ratio - 1.0) * r / t == pytest.approx(-0.125, rel=1e-4)


def test_plain_leaf_equals_beam_formulas() -> None:
    length, t = 8e-3, 0.4e-3
    hinge = FlexureHinge(
        profile={"profile": "leaf", "length": length, "thickness": t}, width=B, material=MATERIAL
    )
    g = E / (2 * (1 + NU))
    section = BeamSection(E, g, B * t, float(torsion_constant(B, t)), t * B**3 / 12, B * t**3 / 12)
    expected = cantilever_compliance(section, length)
    c = hinge.compliance()
    assert np.count_nonzero(expected) == 10  # 6 diagonal + 2 couplings, both signs
    np.testing.assert_allclose(c, expected, rtol=1e-13, atol=0.0)
    assert c[4, 2] == pytest.approx(12 * length**2 / (2 * E * B * t**3), rel=1e-13)
    assert c[5, 1] == pytest.approx(-12 * length**2 / (2 * E * t * B**3), rel=1e-13)


def test_saint_venant_torsion_constant() -> None:
    """J = beta a c^3: Timoshenko & Goodier's table (3 digits) and the square's
    0.1405770 (series value, Roark's 0.1406)."""
    assert torsion_constant(1.0, 1.0) == pytest.approx(0.1405770, abs=1e-7)
    for ratio, beta in [(2.0, 0.229), (10.0, 0.312)]:
        assert torsion_constant(ratio, 1.0) / ratio == pytest.approx(beta, abs=6e-4)
        assert torsion_constant(1.0, ratio) == torsion_constant(ratio, 1.0)
    # thin strip: a c^3 / 3 (1 - 0.630 c / a)
    assert torsion_constant(1000.0, 1.0) == pytest.approx(1000 / 3 * (1 - 0.630249 / 1000))


def test_quadrature_error_falls_with_points() -> None:
    r, t = 2e-3, 2e-5
    exact = wu_zhou(r, t)
    errors = [abs(circular(r, t).compliance(4, n)[2, 2] / exact - 1) for n in (2, 4, 8, 16, 32)]
    print("relative error, 4 panels x 2..32 nodes:", errors)
    assert all(b < a for a, b in zip(errors, errors[1:], strict=False))
    assert errors[0] > 0.1 and errors[-1] < 1e-10


def test_the_default_compliance_is_the_quadrature_once_per_hinge() -> None:
    """The default quadrature is computed once per (frozen) hinge and handed out as a
    new array: equal bit for bit to a fresh quadrature, and a caller's change to the
    array it got does not reach the next caller."""
    from ppm_stiffness.legs.flexure_hinge import (
        PANELS,
        POINTS,
        _default_compliance,
        quadrature_compliance,
    )

    hinge = circular(2e-3, 2e-5)
    held = _default_compliance.cache_size()  # type: ignore[attr-defined]
    first = hinge.compliance()
    hinge.compliance()
    assert _default_compliance.cache_size() == held + 1  # type: ignore[attr-defined]
    assert np.array_equal(first, quadrature_compliance(hinge, PANELS, POINTS))
    first[2, 2] = 0.0
    assert hinge.compliance()[2, 2] == quadrature_compliance(hinge, PANELS, POINTS)[2, 2] > 0


@pytest.mark.parametrize(
    "profile",
    [
        {"profile": "circular", "radius": 2e-3, "thickness": 0.3e-3},
        {"profile": "elliptical", "semi_length": 4e-3, "semi_depth": 1e-3, "thickness": 0.3e-3},
        {"profile": "filleted", "length": 6e-3, "fillet_radius": 1e-3, "thickness": 0.3e-3},
        {"profile": "tabulated", "x": [0, 1e-3, 2e-3, 3e-3], "h": [1e-3, 4e-4, 4e-4, 1e-3]},
    ],
)
def test_symmetric_notch_is_diagonal_at_its_centre(profile: dict[str, object]) -> None:
    hinge = FlexureHinge(profile=profile, width=B, material=MATERIAL)
    c = hinge.centre_compliance()
    scale = np.sqrt(np.outer(np.diag(c), np.diag(c)))
    assert np.max(np.abs(c - np.diag(np.diag(c))) / scale) < 1e-12
    end = hinge.compliance()
    assert abs(end[4, 2]) / np.sqrt(end[4, 4] * end[2, 2]) > 0.5  # coupled at its end


def test_asymmetric_notch_keeps_couplings_at_its_centre() -> None:
    profile = {"profile": "tabulated", "x": [0, 1e-3, 3e-3], "h": [1e-3, 3e-4, 1e-3]}
    c = FlexureHinge(profile=profile, width=B, material=MATERIAL).centre_compliance()
    assert abs(c[4, 2]) / np.sqrt(c[4, 4] * c[2, 2]) > 0.05


def test_profiles_agree_where_they_coincide() -> None:
    """A filleted leaf of length 2r is the circular notch; an ellipse with equal semi-axes too."""
    base = circular(2e-3, 0.2e-3).compliance()
    for profile in (
        {"profile": "filleted", "length": 4e-3, "fillet_radius": 2e-3, "thickness": 0.2e-3},
        {"profile": "elliptical", "semi_length": 2e-3, "semi_depth": 2e-3, "thickness": 0.2e-3},
    ):
        c = FlexureHinge(profile=profile, width=B, material=MATERIAL).compliance()
        np.testing.assert_allclose(c, base, rtol=1e-13, atol=0.0)


def test_bad_hinge_input_is_refused() -> None:
    with pytest.raises(ValidationError, match="exactly one of shear_modulus and poisson_ratio"):
        FlexureHinge(
            profile={"profile": "leaf", "length": 1e-3, "thickness": 1e-4},
            width=B,
            material={"young_modulus": E, "shear_modulus": 27e9, "poisson_ratio": NU},
        )
    with pytest.raises(ValidationError, match="x must start at 0 and increase strictly"):
        FlexureHinge(
            profile={"profile": "tabulated", "x": [0, 2e-3, 1e-3], "h": [1e-3, 1e-4, 1e-3]},
            width=B,
            material=MATERIAL,
        )
    with pytest.raises(ValidationError, match="two fillet radii exceed the length"):
        FlexureHinge(
            profile={
                "profile": "filleted",
                "length": 1e-3,
                "fillet_radius": 1e-3,
                "thickness": 1e-4,
            },
            width=B,
            material=MATERIAL,
        )


# --- a hinge in a chain leg (issue 29 item 2) -------------------------------------------

NOTCH = {"profile": "circular", "radius": 2e-3, "thickness": 0.3e-3}
HINGE = {"profile": NOTCH, "width": B, "material": MATERIAL}


@pytest.mark.parametrize(
    ("centre", "tolerance"), [((0.0, 0.0, 0.0), 2e-15), ((-0.05, 0.02, 0.0), 5e-11)]
)
def test_a_single_hinge_leg_is_the_hinge_compliance_transported(
    centre: tuple[float, float, float], tolerance: float
) -> None:
    """A leg made of one hinge R (centre c, axis z, notch along x) whose far side is the
    platform: its compliance inv(K) at P = 0 is the hinge's end compliance (clamped at
    its base side) transported from its loaded end c + L/2 x to P (closed form,
    ``T C T^T``), max |dC_ij| / sqrt(C_ii C_jj) measured 5.4e-16 with c = P, and 9.2e-12
    with c 54 mm from P (the round-off of inverting K: cond(C) = 2.2e8 there); the
    elastic rotation's stiffness is 1 / C_phiz_phiz, the Wu-Zhou closed form's."""
    from ppm_stiffness.core.conventions import twist_b_from_twist_a
    from ppm_stiffness.core.solver import leg_stiffness
    from ppm_stiffness.legs.chain import Joint, leg_springs
    from ppm_stiffness.legs.types.chain_leg import JointElement

    c = np.array(centre)
    axis, along = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    element = JointElement(
        joint="R", point=centre, axis=tuple(axis), axis2=tuple(along), hinge=HINGE
    )
    hinge = FlexureHinge(**HINGE)
    joint = Joint(
        "R", axis, c, element.stiffnesses(), axis2=along, elastic=element.elastic_stiffnesses()
    )
    k_leg = leg_stiffness(leg_springs([joint], None))
    t = twist_b_from_twist_a(np.eye(3), c + hinge.length / 2 * along)
    expected = t @ hinge.compliance() @ t.T
    d = np.sqrt(np.diag(expected))
    assert np.max(np.abs(np.linalg.inv(k_leg) - expected) / np.outer(d, d)) < tolerance
    elastic = element.elastic_stiffnesses()
    assert elastic is not None and elastic[0] == 1.0 / hinge.compliance()[2, 2]
    assert elastic[0] == pytest.approx(1.0 / wu_zhou(2e-3, 0.3e-3), rel=1e-12)


def test_a_hinge_in_a_design_is_an_elastic_r_with_five_springs() -> None:
    """examples/6rus_flexure.toml with its crank drive's bearing replaced by a notch
    hinge (a piezo-lever stage's base hinge: drive in parallel) and its crank rigid:
    the chain's R at home has the hinge's elastic rotation and its five springs 1 / C_ii
    along the joint frame e1 = axis (hinge z), e2 = axis2 (hinge x, along the notch),
    e3 (hinge y). With the crank a beam beside the hinge the design is refused (its span
    would start at the notch's centre)."""
    from helpers import design_named
    from ppm_stiffness.design import design_from_dict
    from ppm_stiffness.legs.chain import Joint
    from ppm_stiffness.model import full_pose, solve_legs, stiffness_at_pose

    data = design_named("6rus_flexure").model_dump()
    notch = []
    for leg in data["legs"]:
        crank, far = leg["elements"][0], leg["elements"][2]
        along = np.subtract(far["point"], crank["point"])
        notch.append(along / np.linalg.norm(along))
        crank.update(springs=None, hinge=HINGE, axis2=tuple(notch[-1]))
        leg["elements"][1]["link"] = "rigid"  # a beam link beside a hinge is refused
    design = design_from_dict(data)
    leg = data["legs"][0]
    leg["elements"][1]["link"] = design_named("6rus_flexure").model_dump()["legs"][0]["elements"][
        1
    ]["link"]
    with pytest.raises(DesignError, match="a beam link beside a notch hinge is not modelled"):
        design_from_dict(data)
    leg_pose = solve_legs(design, full_pose(design))[0]
    joint = next(e for e in design.legs[0].chain(leg_pose) if isinstance(e, Joint))
    c = np.diag(FlexureHinge(**HINGE).centre_compliance())
    # R constrained: rotation e2 (x), e3 (y); translation e1 (z), e2 (x), e3 (y)
    np.testing.assert_array_equal(joint.springs, 1.0 / c[[0, 1, 5, 3, 4]])
    np.testing.assert_array_equal(joint.elastic, [1.0 / c[2]])
    e1, e2, _ = joint.frame()
    np.testing.assert_allclose(e2, notch[0], atol=1e-15)
    assert np.all(np.isfinite(stiffness_at_pose(design)))


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"joint": "U", "axis2": (0.0, 1.0, 0.0)}, "a notch hinge is an R joint, not a universal"),
        ({"springs": 1e6}, "the hinge gives the joint's springs and elastic"),
        ({"elastic": 3.0}, "the hinge gives the joint's springs and elastic"),
        ({"axis2": None}, "give axis2, the notch's direction"),
        (
            {
                "hinge": {
                    **HINGE,
                    "profile": {
                        "profile": "tabulated",
                        "x": [0, 1e-3, 3e-3],
                        "h": [1e-3, 3e-4, 1e-3],
                    },
                }
            },
            "the profile is not symmetric about its centre",
        ),
    ],
)
def test_bad_hinge_joints_are_refused(changes: dict[str, object], message: str) -> None:
    from ppm_stiffness.legs.types.chain_leg import JointElement

    good = {
        "joint": "R",
        "point": (0.0, 0.0, 0.0),
        "axis": (0.0, 0.0, 1.0),
        "axis2": (1.0, 0.0, 0.0),
        "hinge": HINGE,
    }
    JointElement(**good)
    with pytest.raises(ValidationError, match=message):
        JointElement(**{**good, **changes})


# --- the 3-RRR flexure stage of scripts/chain_examples.py (issue 29 item 4) ----------


@pytest.fixture(scope="module")
def stage_file() -> Path:
    """The shipped 3-RRR flexure stage (equal to scripts/chain_examples.py's
    flexure_3rrr(): tested)."""
    return ROOT / "examples" / "flexure_3rrr.toml"


def test_the_stage_is_its_hinges_compliances_transported(stage_file: Path) -> None:
    """K at home of the 3-RRR flexure stage (rigid links, nine circular notch hinges,
    piezo-lever drives in parallel with the base hinges) equals the closed form
    sum over legs of inv(sum over hinges of T_j R_j C_j R_j^T T_j^T), C_j the hinge's
    centre compliance in its axes (its rotation 1/(k_hinge + k_a) at a driven hinge),
    R_j its axes in F_b, T_j the transport from its centre to P: measured max
    |dK_ij| / sqrt(K_ii K_jj) 4.4e-11, the round-off of inverting a leg's compliance
    (condition number 5.6e6; every hinge frame turned by 90 deg about its axis: 24).
    The stage is 3-fold symmetric: K_xx = K_yy, no x-y coupling, no coupling between
    x, y and phi_z at P (measured 4.4e-16, 3.1e-17 and 4.5e-16 of the balanced K)."""
    from ppm_stiffness.core.conventions import twist_b_from_twist_a
    from ppm_stiffness.design import load_design
    from ppm_stiffness.legs.types.chain_leg import JointElement
    from ppm_stiffness.model import stiffness_at_pose

    design = load_design(stage_file)
    k = stiffness_at_pose(design)
    expected = np.zeros((6, 6))
    for leg in design.legs:
        compliance = np.zeros((6, 6))
        for element in leg.elements:
            if not isinstance(element, JointElement):
                continue
            assert element.hinge is not None and element.axis2 is not None
            c = element.hinge.centre_compliance().copy()
            if element.actuated:
                c[2, 2] = 1.0 / (1.0 / c[2, 2] + leg.actuator.locked_stiffness)
            x, z = np.array(element.axis2), np.array(element.axis)
            rot = np.column_stack([x, np.cross(z, x), z])
            frame = twist_b_from_twist_a(rot, element.point)
            compliance += frame @ c @ frame.T
        expected += np.linalg.inv(compliance)
    d = np.sqrt(np.diag(expected))
    residual = np.max(np.abs(k - expected) / np.outer(d, d))
    print("stage K residual", residual, "K_phiz, K_xx:", k[2, 2], k[3, 3])
    assert residual < 2e-10
    balanced = k / np.sqrt(np.outer(np.diag(k), np.diag(k)))
    assert k[3, 3] == pytest.approx(k[4, 4], rel=1e-12)
    print("symmetry", k[3, 3] / k[4, 4] - 1, balanced[3, 4], balanced[2, 3:5])
    assert abs(balanced[3, 4]) < 1e-12
    assert np.max(np.abs(balanced[2, 3:5])) < 1e-12


def test_analyze_runs_on_the_stage(stage_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from ppm_stiffness.cli import main

    assert main(["analyze", "--design", str(stage_file)]) == 0
    assert "Principal stiffnesses" in capsys.readouterr().out


def test_a_hinges_dimensions_are_design_parameters(stage_file: Path) -> None:
    """The hinge's keys are named parameters with their units, and setting the notch's
    thickness changes the stage's K_phiz: the elastic R's k follows it (K_phiz of the
    stage is k_a-dominated; the elbow and platform hinges' k scale as t^(5/2) at
    first order)."""
    from ppm_stiffness.design import load_design
    from ppm_stiffness.model import stiffness_at_pose

    design = load_design(stage_file)
    name = "leg1.elbow_hinge.hinge.profile.thickness"
    assert design.parameter(name) == 0.3e-3
    assert design.parameter_unit(name) == "m"
    assert design.parameter_unit("leg1.elbow_hinge.hinge.material.young_modulus") == "Pa"
    thicker = design.with_parameters(
        {f"leg{i}.elbow_hinge.hinge.profile.thickness": 0.6e-3 for i in (1, 2, 3)}
    )
    element = thicker.legs[0].elements[2]
    assert element.hinge.profile.thickness == 0.6e-3
    k0, k1 = stiffness_at_pose(design), stiffness_at_pose(thicker)
    assert k1[2, 2] > k0[2, 2] * (1 + 1e-4)
