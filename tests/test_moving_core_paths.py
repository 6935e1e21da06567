"""The batched linear solve of the Newton step (statics/moving_core.py): every problem
solved at once where all are regular, one at a time where one is singular, with the
same numbers either way (each problem is solved on its own)."""

from __future__ import annotations

import numpy as np

from ppm_stiffness.statics.moving_core import _solve_equilibrated


def test_a_singular_problem_is_flagged_and_the_others_solved_as_alone() -> None:
    rng = np.random.default_rng(0)
    a = rng.normal(size=(3, 9, 9)) * np.logspace(0, 2, 9)[None, :, None]
    rhs = rng.normal(size=(3, 9, 7))
    regular, ok = _solve_equilibrated(a, rhs)
    assert ok.all()
    for i in range(3):  # the batch equals each problem alone, to the bit
        alone, ok_i = _solve_equilibrated(a[i : i + 1], rhs[i : i + 1])
        assert ok_i[0] and np.array_equal(alone[0], regular[i])
    residual = np.abs(np.einsum("kij,kjc->kic", a, regular) - rhs)
    assert residual.max() < 5e-13  # measured 1.1e-13
    singular = a.copy()
    singular[1, 4] = singular[1, 2]  # two equal rows
    out, ok = _solve_equilibrated(singular, rhs)
    assert ok.tolist() == [True, False, True]
    assert np.isnan(out[1]).all()
    assert np.array_equal(out[[0, 2]], regular[[0, 2]])
