"""Deflection of the loaded platform with the actuators' nonlinear law in the loop,
the loaded stiffness by finite differences, and the comparison with measurements."""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from paper import PAPER_WRENCH
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.solver import LegSprings
from ppm_stiffness.design import Design, default_design
from ppm_stiffness.model import leg_springs_at_pose, stiffness_at_pose, workspace_centre
from ppm_stiffness.statics import actuator as act
from ppm_stiffness.statics.deflection import (
    MODES,
    actuator_displacement,
    closed_form_twist,
    deflection_curve,
    deflection_path,
    threshold_force,
)
from ppm_stiffness.statics.loading import actuator_forces, loaded_state
from ppm_stiffness.statics.measurements import Measurements, read_measurements, rms_differences

DESIGN = default_design()
LAW = DESIGN.actuator
#: Top loads used for the three Fig. 9 modes [N, N·m, N].
TOP = {"planar-force": 10.0, "moment": 0.5, "vertical-force": 20.0}


def _scaled_error(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / sqrt(b_ii b_jj): entries compared on the scale of the diagonal."""
    d = np.sqrt(np.outer(np.diag(b), np.diag(b)))
    return float(np.max(np.abs(a - b) / d))


# --------------------------------------------------------------- independent leg solver
def _leg_wrench(leg: LegSprings, twist: np.ndarray, design: Design) -> np.ndarray:
    """Wrench (6,) that one leg exerts for a platform twist, solving the leg's own
    equilibrium: all springs in series carry the leg wrench w, the actuator deflects
    by its nonlinear law, the passive joints move freely and carry nothing:

        J C' J^T w + a delta(a . w) + J_q q = t,    J_q^T w = 0

    (C' the structural spring compliances, a the actuator screw). Damped Newton on
    the 9 unknowns (w, q); independent of the bordered inverse and of the closed form.
    """
    j, c, jq = leg.screws, leg.compliance.copy(), leg.passive
    ia = leg.actuator_index
    a = j[:, ia].copy()
    c[ia, :] = 0.0
    c[:, ia] = 0.0
    cs = j @ c @ j.T
    weight = np.r_[1, 1, 1, 10, 10, 10, 1, 1, 1]

    def resid(x: np.ndarray) -> np.ndarray:
        w, q = x[:6], x[6:]
        r1 = cs @ w + a * actuator_displacement(design.actuator, a @ w) + jq @ q - twist
        return np.concatenate([r1, jq.T @ w])

    x = np.zeros(9)
    for _ in range(200):
        r = resid(x)
        k = act.stiffness_from_force(design.actuator, a @ x[:6])
        m = np.zeros((9, 9))
        m[:6, :6] = cs + np.outer(a, a) / k
        m[:6, 6:] = jq
        m[6:, :6] = jq.T
        dx = np.linalg.solve(m, -r)
        n0 = np.linalg.norm(r * weight)
        lam = 1.0
        while lam > 1e-8 and np.linalg.norm(resid(x + lam * dx) * weight) >= n0 > 0:
            lam /= 2
        x = x + lam * dx
        if np.linalg.norm(lam * dx[:6]) <= 1e-15 * (1 + np.linalg.norm(x[:6])):
            break
    assert np.linalg.norm(resid(x)[:6]) < 1e-15
    return x[:6]


def _equilibrium_wrench(
    legs: list[LegSprings], twist: np.ndarray, design: Design = DESIGN
) -> np.ndarray:
    return np.asarray(sum(_leg_wrench(leg, twist, design) for leg in legs))


def test_loaded_stiffness_is_the_derivative_of_the_equilibrium_wrench() -> None:
    """FD check at the centre under the paper wrench (f = [5, 5, 20] N, m_z = 0.1 N·m).

    The closed-form twist is an equilibrium of the independent leg solver (the legs'
    wrenches sum to the applied one), and central differences of that solver's
    wrench in the six twist directions equal loading.loaded_state(...).stiffness_matrix
    (each entry to 1e-6 of sqrt(K_ii K_jj)). Included: every structural spring,
    passive joints, the actuator law (its force follows delta(G) as t changes).
    Not included in either: the geometric stiffness of the preloaded joints (terms
    from the change of geometry under load), as in the paper's model.
    """
    p = workspace_centre(DESIGN)
    legs = leg_springs_at_pose(DESIGN, p)
    t0 = closed_form_twist(DESIGN, PAPER_WRENCH, p)
    w0 = _equilibrium_wrench(legs, t0)
    np.testing.assert_allclose(w0, PAPER_WRENCH, atol=1e-11)
    k = loaded_state(DESIGN, PAPER_WRENCH, p).stiffness_matrix
    h = np.array([1e-7, 1e-7, 1e-7, 1e-8, 1e-8, 1e-8])
    kfd = np.zeros((6, 6))
    for i in range(6):
        e = np.zeros(6)
        e[i] = h[i]
        kfd[:, i] = (_equilibrium_wrench(legs, t0 + e) - _equilibrium_wrench(legs, t0 - e)) / (
            2 * h[i]
        )
    assert _scaled_error(kfd, k) < 1e-6
    # and it is not the unloaded matrix: the powered actuators soften the planar block
    assert _scaled_error(stiffness_at_pose(DESIGN, p), k) > 0.5


# --------------------------------------------------------------------- the path
def test_affine_compliance_behind_the_closed_form() -> None:
    """C(k) - B^T diag(1/k) B does not depend on k: the actuators enter the
    compliance only through their own determinate forces (reciprocity): the 3-PPR's
    actuator forces per unit wrench, B, do not depend on k either."""
    b = np.array([actuator_forces(DESIGN, e) for e in np.eye(6)]).T
    k0 = np.full(3, LAW.locked_stiffness)
    c_s = np.linalg.inv(stiffness_at_pose(DESIGN)) - b.T @ np.diag(1 / k0) @ b
    rng = np.random.default_rng(7)
    for _ in range(3):
        k = 10 ** rng.uniform(3, 6, 3)
        c = np.linalg.inv(stiffness_at_pose(DESIGN, None, k))
        np.testing.assert_allclose(
            c - b.T @ np.diag(1 / k) @ b,
            c_s,
            atol=1e-12 * np.abs(c).max(),
        )


@pytest.mark.parametrize("mode", MODES)
def test_integrated_path_equals_closed_form(mode: str) -> None:
    """Integrating dt/dL = K(L)^-1 w_hat equals C_s w + B^T delta(B w) to 1e-8 of the
    largest deflection component (DOP853 at rtol 1e-10, cut at the locked threshold)."""
    loads = np.linspace(0.0, TOP[mode], 11)
    ti = deflection_curve(DESIGN, mode, loads).twists
    tc = deflection_curve(DESIGN, mode, loads, method="closed-form").twists
    for group in (slice(0, 3), slice(3, 6)):  # rotations [rad], translations [m]
        scale = np.abs(tc[:, group]).max()
        assert np.abs(ti[:, group] - tc[:, group]).max() <= 1e-8 * scale


def test_linear_actuators_give_c_times_w_exactly() -> None:
    """q = 1 with no locked branch: the actuator is a linear spring k_a and the path
    is t = C(k_a) w at every load (eq. 20 with q = 1)."""
    lin_design = DESIGN.with_parameters(
        {"actuator.q": 1.0, "actuator.k_a": 2.0e4, "actuator.threshold_displacement": 0.0}
    )
    c = np.linalg.inv(stiffness_at_pose(lin_design, None, 2.0e4))
    w = PAPER_WRENCH / np.linalg.norm(PAPER_WRENCH)
    loads = np.linspace(0.0, 30.0, 7)
    curve = deflection_path(lin_design, w, loads)
    expected = loads[:, None] * (c @ w)[None, :]
    np.testing.assert_allclose(curve.twists, expected, rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(curve.actuator_stiffness[1:], 2.0e4)


def test_constant_actuators_give_the_unloaded_compliance() -> None:
    """A threshold beyond every displacement (the shortest stroke, 50 mm) keeps the
    actuators locked (constant 1.1108e5 N/m): t = C(locked) w, which is also what
    method="linear" gives."""
    locked = DESIGN.with_parameters({"actuator.threshold_displacement": 0.05})
    c = np.linalg.inv(stiffness_at_pose(locked))
    loads = np.linspace(0.0, 10.0, 6)
    for design, method in ((locked, "integrate"), (DESIGN, "linear")):
        curve = deflection_curve(design, "planar-force", loads, method=method)
        expected = loads[:, None] * (c @ curve.unit_wrench)[None, :]
        np.testing.assert_allclose(curve.twists, expected, rtol=1e-9, atol=1e-14)


def test_single_actuator_closed_form() -> None:
    """A force F along x through D_3 (leg 3's force line) loads actuator 3 alone.
    The displacement of D_3 along x (the conjugate displacement) is that of two
    springs in series: F / k_s3 + delta(F), with the leg's structural stiffness k_s3
    from the unloaded model (1/k_leg3 - 1/K_locked) and, written out here,
    delta(F) = F/K_locked below G_th = k_a delta_th^q, and
    G_th/K_locked + (F/k_a)^(1/q) - delta_th above."""
    r = DESIGN.legs[2].platform_radius
    w_hat = np.array([0.0, 0.0, -r, 1.0, 0.0, 0.0])  # (0, r, 0) x (1, 0, 0)
    loads = np.array([0.0, 1.0, 2.5, 5.0, 7.5, 10.0, 12.0])
    curve = deflection_path(DESIGN, w_hat, loads)
    np.testing.assert_allclose(curve.actuator_forces[:, :2], 0.0, atol=1e-12)
    np.testing.assert_allclose(curve.actuator_forces[:, 2], loads, rtol=1e-12)
    c_leg = w_hat @ np.linalg.inv(stiffness_at_pose(DESIGN)) @ w_hat
    c_s3 = c_leg - 1 / LAW.locked_stiffness
    g_th = LAW.k_a * LAW.threshold_displacement**LAW.q
    assert g_th == pytest.approx(2.9914, abs=1e-4)
    delta = np.where(
        loads <= g_th,
        loads / LAW.locked_stiffness,
        g_th / LAW.locked_stiffness + (loads / LAW.k_a) ** (1 / LAW.q) - LAW.threshold_displacement,
    )
    np.testing.assert_allclose(
        curve.conjugate_displacement(), loads * c_s3 + delta, rtol=1e-9, atol=1e-15
    )
    # 10 N on the paper's law: (10/44.75)^(1/0.225) = 1.2811 mm, plus 20.9 um for the
    # locked start (G_th / K_locked - delta_th)
    assert delta[5] == pytest.approx(1.3020e-3, rel=1e-4)


@pytest.mark.parametrize("mode", MODES)
def test_path_is_monotone_for_the_paper_law(mode: str) -> None:
    """The displacement conjugate to the load grows strictly (w_hat C w_hat > 0 at
    every load) and so does each actuator's displacement magnitude. At the centre
    each twist component is also monotone for these modes."""
    loads = np.linspace(0.0, TOP[mode], 21)
    curve = deflection_curve(DESIGN, mode, loads)
    assert np.all(np.diff(curve.conjugate_displacement()) > 0)
    # >= 0 up to the integration's round-off floor: 1e-15 m on displacements of ~1 mm
    # (a pure moment leaves leg 3's force at 1e-20 N of noise)
    assert np.all(np.diff(np.abs(curve.actuator_displacements), axis=0) >= -1e-15)
    for j in range(6):
        d = np.diff(curve.twists[:, j])
        assert np.all(d >= -1e-18) or np.all(d <= 1e-18)


def test_monotone_conjugate_displacement_at_random_poses() -> None:
    rng = np.random.default_rng(11)
    for _ in range(4):
        pose = np.array([*rng.uniform(-0.005, 0.005, 2), rng.uniform(-0.08, 0.08)])
        alpha = rng.uniform(0, 2 * math.pi)
        curve = deflection_curve(DESIGN, "planar-force", np.linspace(0, 8, 9), pose, alpha)
        assert np.all(np.diff(curve.conjugate_displacement()) > 0)


def test_powered_actuators_soften_the_path() -> None:
    """Under the planar force the nonlinear path deflects more than the unloaded
    linear model, and the final actuator stiffnesses are those of loaded_state."""
    loads = np.linspace(0.0, 10.0, 11)
    nl = deflection_curve(DESIGN, "planar-force", loads)
    li = deflection_curve(DESIGN, "planar-force", loads, method="linear")
    assert nl.conjugate_displacement()[-1] > 2 * li.conjugate_displacement()[-1]
    state = loaded_state(DESIGN, nl.wrenches[-1])
    np.testing.assert_allclose(nl.actuator_stiffness[-1], state.actuator_stiffness, rtol=1e-12)


def test_vertical_force_leaves_the_actuators_unloaded() -> None:
    """f_z loads no actuator (the leg forces along u are in-plane): the path is linear."""
    curve = deflection_curve(DESIGN, "vertical-force", np.linspace(0.0, 20.0, 5))
    np.testing.assert_allclose(curve.actuator_forces, 0.0, atol=1e-12)
    c = np.linalg.inv(stiffness_at_pose(DESIGN))
    np.testing.assert_allclose(curve.twists[-1], 20.0 * c[:, 5], rtol=1e-9, atol=1e-15)


def test_actuator_displacement_integrates_the_tangent_compliance() -> None:
    """delta(G) is odd, continuous at the threshold force, and its derivative is the
    tangent compliance 1/K_act of eq. (21) (central differences)."""
    g_th = threshold_force(LAW)
    g = np.array([0.5, 2.0, g_th * 1.01, 4.0, 7.31, 12.0])
    h = 1e-6
    deriv = (actuator_displacement(LAW, g + h) - actuator_displacement(LAW, g - h)) / (2 * h)
    np.testing.assert_allclose(deriv, 1 / act.stiffness_from_force(LAW, g), rtol=1e-6)
    np.testing.assert_allclose(actuator_displacement(LAW, -g), -actuator_displacement(LAW, g))
    below, above = actuator_displacement(LAW, [g_th * (1 - 1e-12), g_th * (1 + 1e-12)])
    assert above - below == pytest.approx(0.0, abs=1e-15)
    # above the threshold it exceeds the bare law (eq. 20) by the constant
    # G_th / K_locked - delta_th = 26.93 um - 6 um
    for g_i in (3.5, 7.31, 12.0):
        off = actuator_displacement(LAW, g_i) - act.displacement_from_force(LAW, g_i)
        assert off == pytest.approx(g_th / LAW.locked_stiffness - LAW.threshold_displacement)
        assert off == pytest.approx(20.930e-6, abs=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"loads": [0.0, 2.0, 1.0]}, "increasing"),
        ({"loads": [-1.0, 0.0]}, ">= 0"),
        ({"loads": [[0.0, 1.0]]}, "1-D"),
        ({"loads": [0.0, np.nan]}, "finite"),
        ({"mode": "twist"}, "unknown loading mode"),
        ({"method": "secant"}, "unknown method"),
    ],
)
def test_bad_curve_input(kwargs: dict[str, object], match: str) -> None:
    args: dict[str, object] = {"mode": "planar-force", "loads": [0.0, 1.0]}
    args.update(kwargs)
    with pytest.raises(InputDataError, match=match):
        deflection_curve(DESIGN, **args)


@pytest.mark.parametrize("wrench", [np.ones(5), np.ones(7), np.ones((2, 6))])
def test_wrench_of_wrong_length(wrench: np.ndarray) -> None:
    with pytest.raises(InputDataError, match="6 components"):
        deflection_path(DESIGN, wrench, [0.0, 1.0])
    with pytest.raises(InputDataError, match="6 components"):
        closed_form_twist(DESIGN, wrench)


# ------------------------------------------------------------------ measurements
def _shipped(name: str) -> Path:
    return Path(str(resources.files("ppm_stiffness").joinpath(f"data/{name}")))


def _fake(
    curve_loads: np.ndarray, twists: np.ndarray, comps: tuple[int, ...], mode: str
) -> Measurements:
    t = np.full_like(twists, np.nan)
    t[:, list(comps)] = twists[:, list(comps)]
    return Measurements(curve_loads, t, comps, {"mode": mode}, "fake")


def test_rms_of_known_offsets() -> None:
    """Measurements = model + (0.1 deg on phi_z; 0.03, 0.04 mm on x, y) at every load:
    orientation RMS 0.1 deg, position RMS 0.05 mm (norm of the in-plane error)."""
    curve = deflection_curve(DESIGN, "planar-force", np.linspace(0, 10, 11))
    off = np.array([0, 0, math.radians(0.1), 3e-5, 4e-5, 0])
    m = _fake(curve.loads[1:], curve.twists[1:] + off, (2, 3, 4), "planar-force")
    rms = rms_differences(curve, m)
    assert rms["orientation_deg"] == pytest.approx(0.1, rel=1e-9)
    assert rms["position_mm"] == pytest.approx(0.05, rel=1e-9)
    assert rms["components"]["x_mm"] == pytest.approx(0.03, rel=1e-9)
    assert rms["interpolated"] is False
    # z only (vertical mode, dial indicator): no orientation figure
    vz = deflection_curve(DESIGN, "vertical-force", np.linspace(0, 20, 5))
    rz = rms_differences(vz, _fake(vz.loads, vz.twists + 1e-5, (5,), "vertical-force"))
    assert rz["orientation_deg"] is None
    assert rz["position_mm"] == pytest.approx(0.01, rel=1e-9)


def test_rms_interpolates_between_curve_loads_and_refuses_extrapolation() -> None:
    fine = deflection_curve(DESIGN, "moment", np.linspace(0, 0.4, 401))
    coarse = deflection_curve(DESIGN, "moment", np.linspace(0, 0.4, 41))
    m = _fake(fine.loads[5::10], fine.twists[5::10], (2, 3, 4), "moment")
    rms = rms_differences(coarse, m)
    assert rms["interpolated"] is True
    assert rms["orientation_deg"] < 0.01 * np.degrees(np.abs(fine.twists[:, 2]).max())
    with pytest.raises(InputDataError, match="beyond"):
        rms_differences(deflection_curve(DESIGN, "moment", [0.0, 0.1]), m)
    with pytest.raises(InputDataError, match="mode"):
        rms_differences(deflection_curve(DESIGN, "planar-force", [0.0, 1.0]), m)


@pytest.mark.parametrize(
    ("name", "mode", "sigmas"),
    [
        ("planar", "planar-force", (1, 2)),
        ("moment", "moment", (1, 2)),
        ("vertical", "vertical-force", (0, 1)),
    ],
)
def test_shipped_synthetic_measurements_match_the_model_within_their_noise(
    name: str, mode: str, sigmas: tuple[int, int]
) -> None:
    """The shipped files are model + N(0, 0.05) (deg, mm) per column, seeds stated.
    Their RMS difference to the model is within the 99.9% chi range of that noise:
    orientation over 1 column, position over 2 (x, y) or 1 (z) columns, 10 loads."""
    m = read_measurements(_shipped(f"measurements_synthetic_{name}.csv"))
    assert m.mode == mode
    text = _shipped(f"measurements_synthetic_{name}.csv").read_text()
    assert "SYNTHETIC" in text and "seed=" in text
    curve = deflection_curve(DESIGN, mode, np.union1d([0.0], m.loads))
    rms = rms_differences(curve, m)
    n_rot, n_pos = sigmas
    for key, k in (("orientation_deg", n_rot), ("position_mm", n_pos)):
        if k == 0:
            assert rms[key] is None
            continue
        dof = k * m.loads.size
        lo, hi = np.sqrt(stats.chi2.ppf([0.0005, 0.9995], dof) / dof * k) * 0.05
        assert lo < rms[key] < hi


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("load,phi_z_deg,x_m\n1,0.1,0.2\n", r"unknown column 'x_m' \(did you mean 'x_mm'\?\)"),
        ("phi_z_deg,x_mm\n0.1,0.2\n", "displacements with no wrench"),  # no load column
        ("load\n1\n", "no displacement column"),  # no component
        ("load,x_mm\n1,abc\n", "line 2, column 'x_mm': 'abc' is not numeric"),
        ("load,x_mm\n1\n", "line 2: 1 fields, the header has 2"),
        ("load,x_mm\n-1,0.2\n", "line 2: load -1: loads must be >= 0"),
        ("load,x_mm,x_mm\n1,0.2,0.2\n", "column 'x_mm' appears more than once"),
        ("load,x_mm\n", "needs a header row and at least one data row"),  # no data
    ],
)
def test_malformed_measurements(tmp_path: Path, text: str, message: str) -> None:
    p = tmp_path / "m.csv"
    p.write_text(text)
    with pytest.raises(InputDataError, match=message):
        read_measurements(p)
