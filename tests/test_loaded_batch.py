"""The batched loaded state (maps.loaded.loaded_poses) against the single-pose
equilibrium (statics.loading.loaded_state) at seeded poses of every shipped design.

Both run Newton's method to the same force tolerance (1e-12 of the force scale), so
their results can differ by about that much; measured: at most 4e-14 relative (twist,
forces, actuator stiffness, K), with the same iteration counts. The bound 1e-11 is the
solver's tolerance with a margin of 10.
"""

from __future__ import annotations

import numpy as np
import pytest

from helpers import design_named, poses_around_workspace
from ppm_stiffness.core.errors import EquilibriumError, InputDataError, PPMStiffnessError
from ppm_stiffness.design import Design
from ppm_stiffness.maps.loaded import loaded_poses
from ppm_stiffness.maps.workspace import workspace_bounds
from ppm_stiffness.statics.loading import loaded_state

#: The asymmetric wrench of test_statics_redundant.py (m [N·m], f [N]), scaled per case.
WRENCH = np.array([0.05, -0.03, 0.4, 15.0, -8.0, 10.0])
RTOL = 1e-11


def poses_over(design: Design, n: int, seed: int) -> np.ndarray:
    return poses_around_workspace(design, n, seed, pad=0.1, phi_max=0.2)


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(np.asarray(a) - b)) / np.max(np.abs(b)))


@pytest.mark.parametrize(
    ("name", "scale"),
    [
        ("paper", 0.3),
        ("symmetric_3ppr", 1.0),
        ("redundant_4ppr", 1.0),
        ("redundant_4ppr", 0.2),
        ("3rpr", 1.0),
        ("3prr", 1.0),
        ("3rrr", 1.0),
    ],
)
def test_loaded_poses_equal_loaded_state(name: str, scale: float) -> None:
    design = design_named(name)
    wrench = scale * WRENCH
    poses = poses_over(design, 40, 21)
    res = loaded_poses(design, poses, wrench, matrices=True, chunk_size=16)
    assert res.stiffness is not None
    checked = 0
    for i, pose in enumerate(poses):
        try:
            state = loaded_state(design, wrench, pose)
        except PPMStiffnessError:
            assert not res.valid[i]
            assert res.k_phi.mask[i]
            continue
        assert res.valid[i] and res.solved[i] and res.reachable[i]
        checked += 1
        assert rel(res.twist[i], state.twist) <= RTOL
        assert rel(res.actuator_forces[i], state.actuator_forces) <= RTOL
        assert rel(res.actuator_displacements[i], state.actuator_displacements) <= RTOL
        assert rel(res.actuator_stiffness[i], state.actuator_stiffness) <= RTOL
        assert rel(res.stiffness[i], state.stiffness_matrix) <= RTOL
        assert res.iterations[i] == state.iterations
    assert checked >= 10
    assert not res.reachable.all() or name == "redundant_4ppr"
    # twist and forces are masked exactly where no equilibrium was solved
    np.testing.assert_array_equal(res.twist.mask.any(axis=-1), ~res.solved)
    assert np.all(np.isfinite(res.twist.compressed()))


def test_redundant_design_iterates_and_a_too_large_load_is_flagged() -> None:
    design = design_named("redundant_4ppr")
    pose = np.array([0.015, -0.015, np.radians(-12.0)])
    res = loaded_poses(design, pose, WRENCH)
    assert res.valid and res.iterations > 0  # the secant law shares the load
    np.testing.assert_allclose(
        res.actuator_forces, loaded_state(design, WRENCH, pose).actuator_forces, rtol=RTOL
    )
    big = loaded_poses(design, np.stack([pose, pose]), 10 * WRENCH)
    # solved, but beyond the small-displacement model: loaded_state refuses it
    assert big.solved.all() and not big.valid.any()
    with pytest.raises(InputDataError, match="load too large"):
        loaded_state(design, 10 * WRENCH, pose)
    # 30 times: Newton's method fails in both (100 iterations, residual 5e-9 N)
    huge = loaded_poses(design, pose, 30 * WRENCH)
    assert huge.reachable and not huge.singular and not huge.solved
    assert huge.iterations == -1 and huge.twist.mask.all()
    with pytest.raises(EquilibriumError):
        loaded_state(design, 30 * WRENCH, pose)


def test_the_worst_deflection_over_a_grid() -> None:
    """The optimisation use: the largest |(dx, dy)| and |phi_z| over a pose grid."""
    design = design_named("3rrr")
    box = workspace_bounds(design, 0.0)
    x, y = np.meshgrid(np.linspace(box[0], box[1], 9), np.linspace(box[2], box[3], 7))
    poses = np.stack([x, y, np.zeros_like(x)], axis=-1)
    res = loaded_poses(design, poses, WRENCH)
    assert res.twist.shape == (7, 9, 6) and res.valid.shape == (7, 9)
    dxy = np.hypot(res.twist[..., 3], res.twist[..., 4])
    j, i = np.unravel_index(np.ma.argmax(dxy), dxy.shape)
    state = loaded_state(design, WRENCH, poses[j, i])
    assert float(dxy.max()) == pytest.approx(float(np.hypot(*state.twist[3:5])), rel=RTOL)
    assert float(np.abs(res.twist[..., 2]).max()) > 0
