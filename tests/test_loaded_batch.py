"""The batched loaded state (maps.loaded.loaded_poses) against the single-pose
equilibrium (statics.loading.loaded_state) at seeded poses of every shipped design.

Both are one implementation (the single pose is the batch of one of
statics.equilibrium.loaded_states); the batch evaluates chunks of poses, whose numpy
reductions may round differently than one pose alone. Measured: at most 4e-14 relative
(twist, forces, actuator stiffness, K), with the same iteration counts; the bound 1e-11
is Newton's tolerance (1e-12) with a margin of 10.
"""

from __future__ import annotations

import numpy as np
import pytest

from helpers import design_named, example_designs, is_planar, poses_around_workspace
from ppm_stiffness.core.errors import InputDataError, PPMStiffnessError
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.design import Design
from ppm_stiffness.maps.loaded import loaded_poses
from ppm_stiffness.maps.workspace import workspace_bounds
from ppm_stiffness.statics.equilibrium import LegStructures, loaded_states
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
    [(n, 0.3 if n == "paper" else 1.0) for n in example_designs(is_planar, paper=True)]
    + [("redundant_4ppr", 0.2)],
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
    for scale in (10, 30):
        # The equilibrium exists, but the actuators would travel 26 m and 3.4 km:
        # loaded_state refuses it. Before, at 10 times the batch's Newton stalled at a
        # residual of 1.6e-10 N (the single pose at 1.5e-11 N) against a tolerance of
        # 1.3e-10 N that ignored the 6e5 N terms |M| delta(G) of the residual: round-off
        # decided; at 30 times both failed (residual 5e-9 N against 4e8 N terms).
        big = loaded_poses(design, np.stack([pose, pose]), scale * WRENCH)
        assert big.solved.all() and not big.valid.any()
        assert np.all(big.refusal == Refusal.BEYOND_STROKE)
        with pytest.raises(InputDataError, match="load too large.*stroke"):
            loaded_state(design, scale * WRENCH, pose)
        # the equilibrium, computed from the legs: each actuator carries its leg's
        # wrench along its twist, G_i = a_i . w_i (w_i = K_i^S (t - a_i delta_i)), up to
        # Newton's tolerance 1e-12 of its force scale, here 5.4 times the elastic
        # forces K_i^S a_i delta_i (2e6 N, 2.5e8 N; measured 3.8e-14 of them)
        st = loaded_states(design, pose[None], scale * WRENCH)
        rigid = LegStructures(design, pose).terms.rigid[0]
        a = _actuators(design, pose)
        elastic = np.max(np.abs(np.einsum("lij,lj->li", rigid, a * st.displacements[0, :, None])))
        np.testing.assert_allclose(
            np.einsum("li,li->l", st.leg_wrenches[0], a),
            st.forces[0],
            rtol=0,
            atol=1e-11 * elastic,
        )


def _actuators(design: Design, pose: np.ndarray) -> np.ndarray:
    from ppm_stiffness.model import actuator_screws_at_pose

    return actuator_screws_at_pose(design, pose)


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
