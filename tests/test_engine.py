"""The batched engine (legs/engine.py) against the definition (chain springs and the
leg stiffness of core.solver), on planar and spatial legs."""

from __future__ import annotations

import numpy as np

from helpers import design_named
from ppm_stiffness.core import pose as P
from ppm_stiffness.core.solver import leg_stiffness
from ppm_stiffness.legs import engine
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.legs.completion import complete_poses
from spatial_legs import hexapod_legs, prs_legs, rps_legs

S = np.array([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])  # length balancing, L = 0.1 m


def worst_difference(legs, poses: np.ndarray) -> float:  # type: ignore[no-untyped-def]
    n = poses.shape[0]
    worst = 0.0
    k_act = np.linspace(0.5, 2.0, n)  # a different actuator stiffness at every pose
    for leg in legs:
        lp = leg.solve(poses)
        fast = engine.leg_stiffness(engine.reduce_chain(leg.chain(lp), n), k_act * 1e7)
        for i in range(0, n, max(1, n // 7)):
            one = leg.solve(poses[i])
            ref = leg_stiffness(leg_springs(leg.chain(one), k_act[i] * 1e7))
            scale = np.max(np.abs(ref * S[:, None] * S[None, :]))
            diff = np.max(np.abs((fast[i] - ref) * S[:, None] * S[None, :]))
            worst = max(worst, diff / scale)
    return worst


def test_engine_equals_the_definition_on_spatial_legs() -> None:
    rng = np.random.default_rng(2)
    poses = np.array([0, 0, 0.25, 0, 0, 0]) + np.concatenate(
        [rng.uniform(-0.02, 0.02, (40, 3)), rng.uniform(-0.1, 0.1, (40, 3))], axis=1
    )
    assert worst_difference(hexapod_legs(), poses) < 1e-12
    for legs in (prs_legs(), rps_legs()):
        start = np.zeros((40, 6))
        start[:, 2] = 0.2 + rng.uniform(-0.02, 0.02, 40)
        start[:, 3:5] = rng.uniform(-0.3, 0.3, (40, 2))
        q, ok = complete_poses(legs, [0, 1, 5], start)
        assert ok.all()
        assert worst_difference(legs, q) < 1e-12


def test_engine_equals_the_definition_on_planar_legs() -> None:
    rng = np.random.default_rng(4)
    for name in ("paper", "3rpr", "3prr", "3rrr", "redundant_4ppr"):
        design = design_named(name)
        ws = design.workspace
        planar = np.stack(
            [
                ws.centre_x + rng.uniform(-0.005, 0.005, 20),
                ws.centre_y + rng.uniform(-0.005, 0.005, 20),
                rng.uniform(-0.05, 0.05, 20),
            ],
            axis=1,
        )
        assert worst_difference(design.legs, P.planar_pose(planar)) < 1e-12
