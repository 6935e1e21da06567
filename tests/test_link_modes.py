"""The legs' own modes (Craig-Bampton, issue 30): :mod:`ppm_stiffness.dynamics.legmodes`.

A strut alone against the pinned-pinned beam's closed form, the FE's static shapes
against the condensed model's mass, Rayleigh-Ritz convergence, and the stiff-link limit.
The whole-frame FE comparison is in tests/test_modal_validation.py (its fixture).
Residuals measured when the tolerances were set are given next to each assertion."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.design import Design, design_from_dict, design_to_dict
from ppm_stiffness.dynamics.condensation import leg_mass_matrix
from ppm_stiffness.dynamics.legmodes import (
    LinkModeWarning,
    design_leg_modes,
    fixed_interface_modes,
    reduced_frequencies,
    reduced_matrices,
    stack_leg_modes,
)
from ppm_stiffness.dynamics.mass import mass_matrix_at_pose
from ppm_stiffness.dynamics.modes import natural_frequencies
from ppm_stiffness.legs.chain import Joint, Link, LinkMass
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    solve_legs,
    stiffness_at_pose,
    stiffness_at_tool_point,
)
from ppm_stiffness.poses import full_pose
from test_dynamics import _with_masses

#: A steel rod 20 x 2 mm (the hexapod's), uniform over the whole strut.
SECTION = BeamSection(2.1e11, 8.1e10, 1.13e-4, 9.27e-9, 4.64e-9, 4.64e-9)


def _strut(length: float = 0.3, cylinder: float = 0.17, per_length: float = 0.9) -> list[Any]:
    """A uniform U-P-S strut along z (same section and mass per length [kg/m] on both
    sides of the prismatic joint, ideal joints, a rigid guide), its S at P."""
    base = np.array([0.02, 0.01, -length])
    guide = base + np.array([0.0, 0.0, cylinder])
    top = np.array([0.02, 0.01, 0.0])
    ez = np.array([0.0, 0.0, 1.0])
    return [
        Joint("U", np.array([1.0, 0.0, 0.0]), base, axis2=np.array([0.0, 1.0, 0.0])),
        Link(base, guide, SECTION, mass=LinkMass(per_length * cylinder)),
        Joint("P", ez, guide, actuated=True),
        Link(guide, top, SECTION, mass=LinkMass(per_length * (length - cylinder))),
        Joint("S", ez, top),
    ]


def test_a_uniform_ups_strut_held_at_the_platform_is_pinned_pinned() -> None:
    """Platform held, a uniform U-P-S strut bends as a pinned-pinned beam across its
    prismatic joint: f_k = k^2 (pi / (2 L^2)) sqrt(E I / (rho A)), both planes of each
    pair. 12 elements per link: f1 2.5e-7 high (h^4 convergence; 8 elements: 1.3e-6),
    f2/f1 = 4 within 5e-6 (measured 4.6e-6 with 16)."""
    length, per_length = 0.3, 0.9
    chain = _strut(length, per_length=per_length)
    bending = SECTION.young_modulus * SECTION.inertia_y
    exact = math.pi / (2 * length**2) * math.sqrt(bending / per_length)
    modes = fixed_interface_modes(chain, 3e7, 1, elements=12)
    f = modes.frequencies[0]
    assert f.shape == (2,)  # one requested, the pair kept whole
    assert f == pytest.approx([exact, exact], rel=1e-6)
    more = fixed_interface_modes(chain, 3e7, 6, elements=16).frequencies[0] / exact
    assert more == pytest.approx([1, 1, 4, 4, 9, 9], rel=1e-5)  # measured 5.8e-6 (k = 3)


def test_a_link_clamped_at_both_ends_has_the_beta_roots() -> None:
    """A link from an actuated prismatic joint along it (rigid across: a clamp) to the
    platform (held: a clamp) bends as a clamped-clamped beam: f1 = (beta_1 L)^2 /
    (2 pi L^2) sqrt(E I / (rho A)), beta_1 L = 4.7300407449. 32 elements: 3.3e-7 high
    (24: 1.0e-6)."""
    length, per_length = 0.3, 0.9
    base, top = np.array([0.02, 0.01, -length]), np.array([0.02, 0.01, 0.0])
    axis = np.array([0.0, 0.0, 1.0])
    chain = [
        Joint("P", axis, base, actuated=True),
        Link(base, top, SECTION, mass=LinkMass(per_length * length)),
    ]
    bending = SECTION.young_modulus * SECTION.inertia_y
    root = 4.730040744862704
    exact = root**2 / (2 * math.pi * length**2) * math.sqrt(bending / per_length)
    f = fixed_interface_modes(chain, 3e7, 1, elements=32).frequencies[0]
    assert f == pytest.approx([exact, exact], rel=1e-6)


def test_the_fe_static_shapes_are_the_condensed_models() -> None:
    """The leg FE's constraint shapes Psi carry the condensed leg mass matrix (links as
    uniform beams and as bodies riding on their shape, a centre behind the guide):
    Psi^T M_x Psi = leg_mass_matrix within 1e-8 of its largest entry (measured 7e-10:
    the SVD of the constraint and the springs' range of 1e7)."""
    from helpers import design_named

    for design in (design_named("hexapod_6ups"), design_named("3prr")):
        p = full_pose(design, None)
        k_act = actuator_stiffness_vector(design, None)
        for leg, lp, k in zip(design.legs, solve_legs(design, p), k_act, strict=True):
            chain = leg.chain(lp)
            fe = fixed_interface_modes(chain, float(k), 2).condensed_mass[0]
            ref = leg_mass_matrix(chain, float(k))
            assert np.max(np.abs(fe - ref)) <= 1e-8 * np.max(np.abs(ref))


def _uniform_hexapod(scale: float = 1.0) -> Design:
    """The hexapod with uniform struts of tests/test_modal_validation.py; its links'
    E and G and its joints' springs (the legs' other internal flexibility) times
    ``scale``, its actuators' and masses as they are."""
    design = _with_masses(
        "hexapod_6ups",
        platform={"mass": 1.766, "shape": "cylinder", "radius": 0.12, "height": 0.012},
        masses={"cylinder": {"mass": 0.45}, "rod": {"mass": 0.40}},
    )
    if scale == 1.0:
        return design
    data = design_to_dict(design)
    for name in ("cylinder", "rod"):
        for key in ("young_modulus", "shear_modulus"):
            data["parts"][name][key] *= scale
    for name, keys in {
        "base_joint": ("radial", "axial", "torsion"),
        "platform_joint": ("radial", "axial"),
        "guide": ("roll", "pitch", "yaw", "lateral", "vertical"),
    }.items():
        for key in keys:
            data["parts"][name][key] *= scale
    return design_from_dict(data)


def _frequencies(design: Design, count: int) -> np.ndarray:
    p = full_pose(design, None)
    k = actuator_stiffness_vector(design, None)
    big_k, big_m = stiffness_at_pose(design, p, k), mass_matrix_at_pose(design, p, k)
    if count == 0:
        return natural_frequencies(big_k, big_m)
    legs = design_leg_modes(design, p, k, count)
    return reduced_frequencies(*reduced_matrices(big_k, big_m, *stack_leg_modes(legs)))[0]


def test_adding_modes_converges_from_above() -> None:
    """Rayleigh-Ritz: each added pair of modes lowers every frequency or keeps it, and
    all stay above the leg FE's own result (all its modes); the first pair removes
    nearly all of the condensation's error (f1 198.15 -> 150.330 Hz, then -0.013 Hz
    with three more pairs, 150.313 Hz with all)."""
    design = _uniform_hexapod()
    runs = [_frequencies(design, c) for c in (0, 2, 4, 8)]
    full = _frequencies(design, 200)
    for before, after in zip(runs, runs[1:], strict=False):
        assert np.all(after <= before * (1 + 1e-12))
    assert np.all(runs[-1] >= full * (1 - 1e-8))  # its round-off: 2e-9 (f6)
    first, rest = runs[0][0] - runs[1][0], runs[1][0] - full[0]
    assert rest < 1e-3 * first  # measured 3.6e-4 of it


def test_stiff_links_tend_to_the_condensed_frequencies() -> None:
    """Links (E, G) and joint springs stiffened by s, the same masses and actuators:
    the legs' own modes rise as sqrt(s) and the frequencies with link modes tend to the
    condensed ones, the gap falling as 1 / s (Guyan's error (f1 / f_leg)^2): measured
    1.27e-3 at s = 10^3, 1.27e-4 at 10^4 (0.24 at 1)."""
    gaps = []
    for scale in (1e3, 1e4):
        design = _uniform_hexapod(scale)
        condensed, with_modes = _frequencies(design, 0), _frequencies(design, 4)
        gaps.append(np.max(np.abs(with_modes / condensed - 1)))
    assert gaps[1] <= 2e-4
    assert gaps[1] == pytest.approx(gaps[0] / 10, rel=0.05)


# --- the user's control -------------------------------------------------------------------


def test_no_link_modes_is_the_static_condensation_bit_for_bit() -> None:
    """``link_modes=0`` gives the condensed model's frequencies and shapes exactly (the
    pair K, M at home at the tool point through :func:`mode_shapes`, as before issue
    30) and its JSON without the new keys,
    on every shipped design with a mass model (discovered)."""
    import warnings

    from helpers import design_named, example_designs
    from ppm_stiffness.dynamics.analysis import modal_analysis
    from ppm_stiffness.dynamics.modes import mode_shapes

    names = example_designs(lambda d: d.has_mass_model, paper=True)
    assert len(names) >= 10
    for name in names:
        design = design_named(name)
        with warnings.catch_warnings():
            warnings.simplefilter("error", LinkModeWarning)  # the CLI's, not the library's
            result = modal_analysis(design, link_modes=0)
        p, tool = full_pose(design, None), design.tool_point
        k_t = stiffness_at_tool_point(stiffness_at_pose(design, p), p, tool)
        before = mode_shapes(k_t, stiffness_at_tool_point(mass_matrix_at_pose(design, p), p, tool))
        assert np.array_equal(result.frequencies, before.frequencies), name
        assert np.array_equal(result.modes.shapes, before.shapes), name
        data = result.to_dict()
        assert "link_modes" not in data and "platform_share" not in data["modes"][0]


def test_slow_legs_are_warned_without_link_modes() -> None:
    """The uniform-strut hexapod's struts bend at 180 Hz, 0.91 times the condensed f1 =
    198 Hz: a warning naming both (``modes --link-modes 0`` gives it); none for legs
    ten times faster than f1."""
    import warnings

    from ppm_stiffness.dynamics.analysis import modal_analysis
    from ppm_stiffness.dynamics.legmodes import warn_slow_legs

    design = _uniform_hexapod()
    p, k = full_pose(design, None), actuator_stiffness_vector(design, None)
    f1 = modal_analysis(design, link_modes=0).frequencies[0]
    with pytest.warns(LinkModeWarning, match=r"180\.4 Hz, 0\.91 times the condensed f1 = 198"):
        warn_slow_legs(design, p, k, f1)
    with warnings.catch_warnings():
        warnings.simplefilter("error", LinkModeWarning)
        warn_slow_legs(design, p, k, 18.0)  # f_leg,1 = 10.02 f1
    result = modal_analysis(design, link_modes=2)
    assert result.to_dict()["link_modes"] == 2
    assert result.frequencies[0] == pytest.approx(150.330, abs=1e-3)


@pytest.mark.parametrize("bad", [-1, True, 1.5])
def test_a_bad_number_of_link_modes_is_refused(bad: Any) -> None:
    from ppm_stiffness.core.errors import InputDataError
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    with pytest.raises(InputDataError, match="link modes: a non-negative integer"):
        resolve_link_modes(bad)


def test_modes_cli_link_modes(capsys: pytest.CaptureFixture[str]) -> None:
    """``modes --link-modes N``: the JSON carries ``link_modes`` and each mode's
    platform share (the built-in design: its platform carries 55 % of the first mode's
    kinetic energy); with 0, the warning where a leg is slow (its struts bend at 108.8
    Hz, 3.6 times its condensed f1); a negative N is refused with one line and exit
    code 2."""
    import json

    from ppm_stiffness.cli import main

    assert main(["modes", "--json", "--link-modes", "4"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["link_modes"] == 4
    assert data["modes"][0]["platform_share"] == pytest.approx(0.55, abs=0.005)
    assert main(["modes", "--json", "--link-modes", "0"]) == 0
    out, err = capsys.readouterr()
    assert "link_modes" not in json.loads(out)
    assert "warning: a leg's own first frequency (platform held) is 108.8 Hz, 3.56" in err
    assert main(["modes", "--link-modes", "-1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--link-modes -1" in err


def test_batched_over_poses_is_the_single_pose_analysis() -> None:
    """``first_frequencies(..., link_modes=N)``: the legs' FE batched over poses gives
    the single-pose analysis's f1 at each pose (measured 7.1e-14 relative); the
    condensed f1 is 30 to 34 % higher there."""
    from ppm_stiffness.dynamics.analysis import modal_analysis
    from ppm_stiffness.dynamics.batch import first_frequencies

    design = _uniform_hexapod()
    poses = np.array(
        [
            [0.0, 0.0, 0.2, 0.0, 0.0, 0.0],
            [0.008, -0.005, 0.195, 0.03, -0.02, 0.04],
            [-0.01, 0.004, 0.21, -0.04, 0.01, -0.03],
        ]
    )
    k_act = actuator_stiffness_vector(design, None)
    k = np.array([stiffness_at_pose(design, p, k_act) for p in poses])
    f1, ok = first_frequencies(design, poses, k, k_act, link_modes=8)
    assert ok.all()
    single = [modal_analysis(design, p, link_modes=8).frequencies[0] for p in poses]
    assert f1 == pytest.approx(single, rel=1e-11)
    assert np.all(f1 < 0.8 * first_frequencies(design, poses, k, k_act)[0])  # condensed


def test_a_mode_without_platform_motion_is_the_legs_alone() -> None:
    """A leg mode that does not couple to the twist (C = 0) and lies below the
    platform's: its frequency is its own, it has no shape, its direction is "legs
    only" and the platform carries none of its energy; the platform's six modes keep
    theirs (a unit M and a diagonal K: f = sqrt(k) / 2 pi, platform share 1)."""
    from ppm_stiffness.dynamics.modes import LEG_MODE_DIRECTION, reduced_mode_shapes

    k = np.diag([4.0, 9.0, 16.0, 25.0, 36.0, 49.0, 1.0]) * (2 * np.pi) ** 2
    modes = reduced_mode_shapes(k, np.eye(7), np.eye(6))
    assert modes.frequencies == pytest.approx([1, 2, 3, 4, 5, 6], rel=1e-14)
    assert modes.directions[0] == LEG_MODE_DIRECTION
    assert modes.shares[0] == 0 and not modes.shapes[0].any()
    assert modes.platform_shares == pytest.approx([0, 1, 1, 1, 1, 1], abs=1e-15)
    assert modes.directions[1:] == (
        "rotation about x",
        "rotation about y",
        "rotation about z",
        "x translation",
        "y translation",
    )


def test_analyze_reports_the_first_modes_platform_share() -> None:
    """``analyze`` of the shipped hexapod: f1 with link modes is the first of
    ``modal_analysis`` (a mode of its struts), and its platform kinetic-energy share is
    that mode's (0.33 % measured), printed beside it and valid against the JSON schema
    (which lists "legs only" among the first mode's directions)."""
    import json
    from pathlib import Path

    import jsonschema
    from tests.helpers import design_named

    from ppm_stiffness.analysis import analyze_design
    from ppm_stiffness.dynamics.analysis import modal_analysis

    design = design_named("hexapod_6ups")
    result = analyze_design(design)
    modes = modal_analysis(design)
    shares = modes.modes.platform_shares
    assert shares is not None
    assert result.first_frequency == modes.modes.frequencies[0]
    assert result.first_mode_platform_share == shares[0]
    assert 0.0 < shares[0] < 0.01  # a strut mode
    root = Path(__file__).resolve().parents[1]
    schema = json.loads((root / "docs/schemas/analyze.schema.json").read_text())
    jsonschema.validate(json.loads(result.to_json()), schema)
    assert "legs only" in schema["properties"]["first_mode_direction"]["enum"]
