"""The single-pose shortcuts equal the batched numpy computations they replace
(issue 22, item 2): ``conventions.cross`` is ``np.cross`` bit for bit, and the engine's
reciprocal basis of one pose (Python floats) is the batched one's row bit for bit,
dependent twists (NaN) included."""

from __future__ import annotations

import numpy as np
import pytest

from ppm_stiffness.core.conventions import cross
from ppm_stiffness.legs.engine import reciprocal_basis


@pytest.mark.parametrize(
    ("shape_a", "shape_b"), [((3,), (3,)), ((1, 3), (3,)), ((5, 3), (5, 3)), ((3,), (4, 3))]
)
def test_cross_is_numpys_bit_for_bit(shape_a: tuple[int, ...], shape_b: tuple[int, ...]) -> None:
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=shape_a), rng.normal(size=shape_b)
    got = cross(a, b)
    assert got.shape == np.cross(a, b).shape
    assert np.array_equal(got, np.cross(a, b))


def test_cross_keeps_non_finite_entries_as_numpy() -> None:
    a = np.array([np.inf, 1.0, 0.0])
    b = np.array([0.0, np.nan, 2.0])
    assert np.array_equal(cross(a, b), np.cross(a, b), equal_nan=True)


@pytest.mark.parametrize("passive", range(6))
def test_one_pose_reciprocal_basis_is_the_batched_row(passive: int) -> None:
    rng = np.random.default_rng(passive)
    for trial in range(20):
        twists = [rng.normal(size=(3, 6)) * [1, 1, 1, 0.1, 0.1, 0.1] for _ in range(passive)]
        if passive >= 2 and trial == 0:
            twists[1] = 2.0 * twists[0]  # dependent: NaN in both paths
        batched = reciprocal_basis(twists, 3)
        for i in range(3):
            one = reciprocal_basis([t[i : i + 1] for t in twists], 1)
            assert np.array_equal(one[0], batched[i], equal_nan=True)
