"""The spatial principal stiffnesses (core/principal.py): properties that pin them."""

from __future__ import annotations

import numpy as np
import pytest

from helpers import design_named, example_designs
from ppm_stiffness.core.conventions import stiffness_b_from_stiffness_a
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.pose import rotation_from_angles
from ppm_stiffness.core.principal import principal_compliance, principal_compliance_values
from ppm_stiffness.model import stiffness_at_pose

RNG = np.random.default_rng(314)


def random_spd() -> np.ndarray:
    a = RNG.normal(size=(6, 6)) * np.array([0.1, 0.1, 0.1, 1, 1, 1])[:, None]
    return a @ a.T + np.diag([10.0, 20.0, 30.0, 1e4, 2e4, 3e4])


def test_decoupled_matrix_gives_its_blocks_eigenvalues() -> None:
    """With K_rt = 0, C_rr^-1 = K_rr and C_tt^-1 = K_tt."""
    k = np.zeros((6, 6))
    k[:3, :3] = np.diag([300.0, 200.0, 100.0])
    k[3:, 3:] = np.diag([1e5, 3e5, 2e5])
    pc = principal_compliance(k)
    np.testing.assert_allclose(pc.rotational_values, [300.0, 200.0, 100.0], rtol=1e-14)
    np.testing.assert_allclose(pc.translational_values, [1e5, 3e5, 2e5], rtol=1e-14)
    assert pc.worst_rotational == pytest.approx(100.0, rel=1e-14)
    assert pc.worst_translational == pytest.approx(1e5, rel=1e-14)


def test_rotational_values_do_not_depend_on_the_point_translational_do() -> None:
    for _ in range(5):
        k = random_spd()
        moved = stiffness_b_from_stiffness_a(k, np.eye(3), RNG.normal(0, 0.2, 3))
        a, b = principal_compliance(k), principal_compliance(moved)
        np.testing.assert_allclose(
            np.sort(a.rotational_values), np.sort(b.rotational_values), rtol=1e-11
        )
        assert not np.allclose(np.sort(a.translational_values), np.sort(b.translational_values))


def test_values_turn_with_the_frame() -> None:
    """Axes of F_b turned by R: the same values, directions turned by R."""
    k = random_spd()
    r = rotation_from_angles([0.3, -0.5, 1.1])
    turned = stiffness_b_from_stiffness_a(k, r, np.zeros(3))
    a, b = principal_compliance(k), principal_compliance(turned)
    np.testing.assert_allclose(
        np.sort(a.rotational_values), np.sort(b.rotational_values), rtol=1e-12
    )
    np.testing.assert_allclose(
        np.sort(a.translational_values), np.sort(b.translational_values), rtol=1e-12
    )


def test_worst_is_one_over_the_largest_compliance_and_a_pure_moment_check() -> None:
    k = random_spd()
    c = np.linalg.inv(k)
    pc = principal_compliance(k)
    assert pc.worst_rotational == pytest.approx(1 / np.linalg.eigvalsh(c[:3, :3])[-1], rel=1e-12)
    assert pc.worst_translational == pytest.approx(1 / np.linalg.eigvalsh(c[3:, 3:])[-1], rel=1e-12)
    # a pure moment m along a principal direction rotates the platform by m / value
    for j in range(3):
        d = pc.rotational_directions[:, j]
        t = c @ np.concatenate([d, np.zeros(3)])
        np.testing.assert_allclose(t[:3], d / pc.rotational_values[j], rtol=1e-10)


@pytest.mark.parametrize("name", example_designs(paper=True))
def test_batched_values_are_the_single_ones_sorted(name: str) -> None:
    k = stiffness_at_pose(design_named(name))
    rot, tra = principal_compliance_values(np.stack([k, 2 * k]))
    pc = principal_compliance(k)
    np.testing.assert_allclose(rot[0], np.sort(pc.rotational_values), rtol=1e-12)
    np.testing.assert_allclose(tra[1], 2 * np.sort(pc.translational_values), rtol=1e-12)


def test_refuses_a_matrix_that_is_not_a_stiffness() -> None:
    with pytest.raises(InputDataError, match="positive definite"):
        principal_compliance(-np.eye(6))
