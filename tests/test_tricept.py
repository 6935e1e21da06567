"""The Tricept-type example (``examples/tricept.toml``): three actuated U-P-S legs
written as chains and a passive constraining leg (U at the base centre, passive P, the
inner tube fixed to the platform), against closed forms.

- The completion: the central U at the base origin with a P along its line keeps P on a
  line through the U's centre along the platform's z axis, and the U (e1 = x on the
  base, e2 = y on the tube) lets the platform turn only as ``R = Rx(a) Ry(b)``, whose
  entry R_xy is 0. With R = Rz(rz) Ry(ry) Rx(rx) (docs/conventions.md),
  ``R_xy = cos rz sin ry sin rx - sin rz cos rx = 0``: ``tan rz = sin ry tan rx``, and
  ``(x, y) = rho (R e_z)_xy`` with ``rho = z / (R e_z)_z``.
- Each U-P-S leg is a two-force member along its line A-B: ``K_i = k_i s_i s_i^T`` with
  ``s_i = ((B_i - P) x n_i ; n_i)`` and ``1/k_i = 1/k_a + L_cyl/EA_cyl + L_ram/EA_ram +
  1/k_U + 1/k_S,axial``, L_ram the ram's current free length (from the P joint's
  bushing to the S: it changes with the stroke). The U's translational springs are
  isotropic (radial = axial), so a force along the leg meets 1/k_U whatever the U's
  angles; its torsion and the guide's springs carry no load from a force on the line.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import length_balanced
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design.io import design_from_dict
from ppm_stiffness.model import leg_stiffnesses_at_pose, solve_legs, stiffness_at_pose
from ppm_stiffness.poses import full_pose
from ppm_stiffness.statics.equilibrium import equilibrium
from ppm_stiffness.visuals.leg_geometry import mechanism_view

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "tricept.toml"


def _data() -> dict[str, Any]:
    with open(EXAMPLE, "rb") as f:
        return tomllib.load(f)


def _random_task(rng: np.random.Generator, n: int) -> np.ndarray:
    """n task poses (z, rx, ry) [m, rad] in and around the required region."""
    return np.column_stack(
        [rng.uniform(0.5, 0.6, n), rng.uniform(-0.15, 0.15, n), rng.uniform(-0.15, 0.15, n)]
    )


def test_the_completion_is_the_central_legs_closed_form() -> None:
    design = design_from_dict(_data())
    worst = 0.0
    for z, rx, ry in _random_task(np.random.default_rng(28), 12):
        pose = full_pose(design, [z, rx, ry])
        rz = np.arctan(np.sin(ry) * np.tan(rx))
        normal = pose6.rotation(np.array([0.0, 0.0, 0.0, rx, ry, rz]))[:, 2]
        rho = z / normal[2]
        expected = np.array([rho * normal[0], rho * normal[1], z, rx, ry, rz])
        worst = max(worst, float(np.max(np.abs(pose - expected))))
    assert worst < 1e-12  # measured 1.4e-17 (m and rad); the completion stops at 1e-12


def _leg_line(leg_pose: Any) -> tuple[np.ndarray, np.ndarray]:
    """A and B (relative to P, F_b) of a U-P-S chain leg: its first and last points."""
    points = list(leg_pose.points.values())
    return np.reshape(points[0], 3), np.reshape(points[-1], 3)


def _two_force_stiffness(leg: Any, a: np.ndarray, b: np.ndarray, free_length: float) -> np.ndarray:
    """k s s^T (6, 6) at P for the U-P-S chain leg ``leg`` on the line A-B (module doc)
    with the ram's free length ``free_length`` [m]."""
    u, cylinder, _, ram, s = leg.elements
    n = (b - a) / np.linalg.norm(b - a)
    compliance = (
        1.0 / leg.actuator.locked_stiffness
        + cylinder_length(leg) / (cylinder.link.young_modulus * cylinder.link.area)
        + free_length / (ram.link.young_modulus * ram.link.area)
        + 1.0 / u.springs.axial
        + 1.0 / s.springs.axial
    )
    assert u.springs.axial == u.springs.radial  # isotropic: 1/k_U along any line
    screw = np.concatenate([np.cross(b, n), n])
    return np.outer(screw, screw) / compliance


def cylinder_length(leg: Any) -> float:
    """|bushing - A| [m]: the cylinder from the U to the P joint's bushing."""
    u, _, p, _, _ = leg.elements
    return float(np.linalg.norm(np.subtract(p.point, u.point)))


def test_each_ups_leg_is_k_s_s_with_the_rams_current_free_length() -> None:
    design = design_from_dict(_data())
    worst, smallest_miss = 0.0, np.inf
    for task in _random_task(np.random.default_rng(7), 6):
        pose = full_pose(design, task)
        legs_k = leg_stiffnesses_at_pose(design, pose)
        for i, (leg, lp) in enumerate(zip(design.legs, solve_legs(design, pose), strict=True)):
            if not leg.is_actuated():
                continue
            a, b = _leg_line(lp)
            stroke = float(lp.coordinates["actuated"])
            home_free = float(
                np.linalg.norm(np.subtract(leg.elements[4].point, leg.elements[2].point))
            )
            free = float(np.linalg.norm(b - a)) - cylinder_length(leg)
            assert free == pytest.approx(home_free + stroke, abs=1e-12)  # the bushing stays
            expected = _two_force_stiffness(leg, a, b, free)
            scale = np.max(np.abs(length_balanced(expected)))
            miss = np.max(np.abs(length_balanced(legs_k[i] - expected))) / scale
            worst = max(worst, float(miss))
            # a ram carried rigidly (its home free length) misses by far more
            rigid = _two_force_stiffness(leg, a, b, home_free)
            smallest_miss = min(
                smallest_miss, float(np.max(np.abs(length_balanced(legs_k[i] - rigid))) / scale)
            )
    assert worst < 1e-14  # measured 1.6e-15
    assert smallest_miss > 1e-3  # measured 4.2e-3 (strokes of 12 to 63 mm from home)


def test_an_actuator_table_on_a_passive_leg_is_refused() -> None:
    data = _data()
    data["legs"][1]["actuator"] = copy.deepcopy(data["legs"][0]["actuator"])
    with pytest.raises(
        DesignError,
        match=r"leg2\.actuator': this leg has no actuated joint \(a passive constraining leg\)",
    ):
        design_from_dict(data)


def test_an_actuated_leg_without_its_actuator_table_is_refused() -> None:
    data = _data()
    del data["legs"][0]["actuator"]
    with pytest.raises(
        DesignError, match=r"leg1\.actuator': the law of the leg's actuated joint is required"
    ):
        design_from_dict(data)


def test_the_passive_leg_has_no_actuated_coordinate_and_no_actuator() -> None:
    design = design_from_dict(_data())
    central = design.legs[3]
    assert not central.is_actuated() and central.actuator is None
    assert "actuated" not in central.limits()
    assert "actuated" not in central.solve(full_pose(design, [0.55, 0.0, 0.0])).coordinates
    with pytest.raises(DesignError, match="a passive constraining leg .* has none"):
        central.law("the test")


def test_the_loaded_state_is_c_times_the_wrench_with_linear_actuators() -> None:
    """The examples' actuators are linear: the frozen loaded twist is K^-1 w, the
    passive leg carries no actuator force."""
    design = design_from_dict(_data())
    pose = full_pose(design, [0.56, 0.05, -0.04])
    wrench = np.array([10.0, 20.0, 5.0, 100.0, -200.0, -1000.0])
    state = equilibrium(design, wrench, pose)
    k = stiffness_at_pose(design, pose)
    np.testing.assert_allclose(state.twist, np.linalg.solve(k, wrench), rtol=1e-10)
    assert state.actuator_forces[3] == 0.0 and state.actuator_displacements[3] == 0.0
    assert np.all(state.actuator_forces[:3] != 0.0)


def test_the_pictures_platform_is_the_three_joints_not_the_central_tube() -> None:
    design = design_from_dict(_data())
    view = mechanism_view(design)
    assert view.platform_order == [0, 1, 2]


def test_too_few_actuated_legs_for_the_task_coordinates_are_refused() -> None:
    """Two actuated legs and the passive one for z, rx, ry: a mechanism with its
    actuators locked (before: the design was read)."""
    data = _data()
    data["legs"][0]["pattern"] = {"copies": 2}
    with pytest.raises(DesignError, match=r"2 actuated leg\(s\) for 3 task coordinates"):
        design_from_dict(data)


@pytest.mark.parametrize("task", [[0.55, 0.0, 0.0], [0.57, 0.08, -0.06], [0.53, -0.1, 0.1]])
def test_the_passive_leg_alone_is_the_fe_frames_and_resists_none_of_its_freedoms(
    task: list[float],
) -> None:
    """The central leg's stiffness equals the FE frame's of the same elements (PyNite;
    measured 3.8e-14 to 5.7e-14 of the largest balanced entry), has rank 3, and resists
    neither a turn of the platform about the U's base axis x through O nor a slide along
    the tube (R e_z)."""
    pytest.importorskip("Pynite", reason="the FE cross-check needs the validate extra")
    from ppm_stiffness.validation.fe_model import fe_leg_stiffness

    design = design_from_dict(_data())
    pose = full_pose(design, task)
    k = leg_stiffnesses_at_pose(design, pose)[3]
    scale = np.max(np.abs(length_balanced(k)))
    k_fe = fe_leg_stiffness(design, 3, pose)
    assert np.max(np.abs(length_balanced(k_fe) - length_balanced(k))) < 3e-13 * scale
    assert np.linalg.matrix_rank(length_balanced(k), tol=1e-9 * scale) == 3
    p = pose[:3]
    turn = np.concatenate([[1.0, 0.0, 0.0], np.cross([1.0, 0.0, 0.0], p)])
    slide = np.concatenate([np.zeros(3), pose6.rotation(pose)[:, 2]])
    for twist in (turn, slide):
        wrench = k @ twist
        assert np.max(np.abs(wrench)) < 1e-9 * np.max(np.abs(k)), twist


def test_deflect_lists_the_actuated_legs_and_names_the_passive_one(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The actuator table has columns for legs 1-3 only (before: K4 = inf, G4 = 0)."""
    from ppm_stiffness.cli import main

    assert main(["deflect", "--design", str(EXAMPLE)]) == 0
    out = capsys.readouterr().out
    assert "K3" in out and "K4" not in out and "G4" not in out and "inf" not in out
    assert "leg(s) 4: passive (no actuator)" in out


def test_the_mass_summary_counts_the_chain_legs_links() -> None:
    """links = every beam link's mass, the pattern's three copies and the central
    tubes (before: 0 kg for chain legs, whose links are elements, not fields)."""
    from ppm_stiffness.dynamics.mass import moving_mass

    data = _data()
    masses = [[e["link"]["mass"] for e in leg["elements"] if "link" in e] for leg in data["legs"]]
    expected = 3 * sum(masses[0]) + sum(masses[1])
    assert moving_mass(design_from_dict(data))["links"] == pytest.approx(expected, rel=1e-15)
