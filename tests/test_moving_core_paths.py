"""The batched linear solve of the Newton step (statics/moving_core.py): every problem
solved at once where all are regular, one at a time where one is singular, with the
same numbers either way (each problem is solved on its own); the legs of one structure
solved as one batch, with each leg's numbers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.design import load_design
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.moving_core import (
    _displacement_size,
    _solve_equilibrated,
    _stackable,
    linearize,
    linearize_leg,
    newton,
    zero_state,
)
from ppm_stiffness.statics.moving_path import platform_chains

EXAMPLES = Path(__file__).parents[1] / "examples"


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


@pytest.mark.parametrize(
    ("example", "wrench"),
    [
        ("3rrr.toml", [0.0, 0.0, 2.0, 400.0, 400.0, 0.0]),
        ("hexapod_6ups.toml", [200.0, 200.0, -500.0, 2000.0, 2000.0, 5000.0]),
    ],
)
def test_legs_of_one_structure_linearized_together_as_each_alone(
    example: str, wrench: list[float]
) -> None:
    """``linearize`` solves the legs of one structure as one batch (issue 32 item 2): each
    leg's step is bit for bit its own ``linearize_leg`` call's, at a loaded state away
    from the reference (the equilibrium under the load, at two poses)."""
    design = load_design(EXAMPLES / example)
    home = home_pose(design)
    poses = np.stack([home, home + np.array([0.002, -0.001, 0, 0, 0, 0])])
    system = platform_chains(design, poses, np.zeros((2, 3)))
    w = np.broadcast_to(np.asarray(wrench), (2, 6)).copy()
    res = newton(system, zero_state(system), w)
    assert res.converged.all()
    assert len(_stackable(system.chains)) == 1  # every leg of one structure
    state = res.state
    lin = linearize(system, state, w)
    disp = _displacement_size(state.rotation, state.translation)
    for i, chain in enumerate(system.chains):
        alone = linearize_leg(
            chain,
            state.coordinates[i],
            state.wrenches[:, i],
            state.rotation,
            state.translation,
            True,
            disp,
        )
        for name in ("dx0", "dx_t", "dw0", "dw_t", "residual", "forces", "ok"):
            assert np.array_equal(getattr(lin.legs[i], name), getattr(alone, name)), name
