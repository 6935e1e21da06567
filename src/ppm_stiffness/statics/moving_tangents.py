"""Two more evaluations of the moving-geometry model (statics/moving.py), for checks.

:func:`held_wrenches`: the wrench the legs exert with the platform held at given poses
(the legs solved, the platform's equilibrium not imposed): its derivative is K_F
(tests/test_moving_geometry.py). :func:`reference_tangent`: K_F's formula on the
*unloaded* geometry with the frozen model's leg wrenches, the second-order ("P-Delta")
approximation that validation/second_order.py compares with the FE frame model.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, wrench_b_from_wrench_a
from ppm_stiffness.core.errors import EquilibriumError
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.core.pose import rotation
from ppm_stiffness.design import Design
from ppm_stiffness.legs.screw_chain import cross
from ppm_stiffness.model import tool_offset, validate_pose
from ppm_stiffness.statics.equilibrium import loaded_states, raise_refusal
from ppm_stiffness.statics.moving import MovingLoadedState
from ppm_stiffness.statics.moving_core import ChainState, linearize, newton, zero_state
from ppm_stiffness.statics.moving_path import bar_forces, load_point, platform_chains


def held_wrenches(
    design: Design,
    state: MovingLoadedState,
    poses: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """The wrench the legs exert with the platform held at poses (m, 6) near a state's
    displaced pose: every leg's chain closed there, its springs following their laws and
    its passive joints unloaded (Newton from the state's coordinates), the platform's
    own equilibrium not imposed.

    Returns
    -------
    wrenches : ndarray (m, 6)
        The legs' total wrench about the load point at each pose [N·m, N], axes of F_b
        (equal to ``state.wrench`` at ``state.displaced_pose``).
    stiffness : ndarray (m, 6, 6)
        K_F there.

    Raises
    ------
    EquilibriumError
        Where the legs cannot be solved.
    """
    q = np.asarray(poses, dtype=float).reshape(-1, 6)
    m = q.shape[0]
    ref = state.pose.reshape(1, 6)
    offset = tool_offset(ref, state.tool_point).reshape(1, 3)
    system = platform_chains(design, ref, offset).take(np.zeros(m, dtype=int))
    r0 = rotation(ref)[0]
    rot = rotation(q) @ r0.T
    c0 = ref[0, :3] + offset[0]
    translation = q[:, :3] + np.einsum("kij,j->ki", rotation(q), state.tool_point) - c0
    start = ChainState(
        rot,
        translation,
        tuple(np.tile(x, (m, 1)) for x in state.coordinates),
        np.tile(state.leg_wrenches, (m, 1, 1)),
    )
    res = newton(system, start, np.zeros((m, 6)), fixed=True)
    if not np.all(res.converged):
        raise EquilibriumError("the legs could not be closed at a held pose")
    return res.state.wrenches.sum(axis=1), res.stiffness


def reference_tangent(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike | None = None,
    tool_point: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray]:
    """The loaded tangent at the *unloaded* geometry: K_F's formula (:mod:`.moving_core`)
    evaluated with every chain coordinate at 0 and the legs carrying the frozen model's
    wrenches (the second-order, "P-Delta" approximation: the geometric term of the
    first-order internal forces on the undeformed geometry; the classical linearised
    buckling tangent).

    Returns
    -------
    stiffness : ndarray (6, 6)
        At the (unloaded) load point, axes of F_b.
    frozen : ndarray (6, 6)
        The frozen model's loaded K there: the same without the geometric term.
    """
    w = validate_wrench(wrench)
    b = load_point(design, tool_point)
    p = validate_pose(design, pose).reshape(1, 6)
    offset = tool_offset(p, b).reshape(1, 3)
    w_p = wrench_b_from_wrench_a(np.eye(3), offset[0]) @ w
    frozen = loaded_states(design, p, w_p)
    raise_refusal(design, frozen, 0)
    system = platform_chains(design, p, offset)
    start = zero_state(system)
    wrenches = frozen.leg_wrenches.copy()
    wrenches[..., :3] -= cross(offset[:, None, :], wrenches[..., 3:])
    coordinates = tuple(  # a parallelogram's bars carry the leg's wrench as their forces
        x
        if chain.bars is None
        else np.concatenate([x[:, :-2], bar_forces(chain, wrenches[:, i])], axis=1)
        for i, (x, chain) in enumerate(zip(start.coordinates, system.chains, strict=True))
    )
    loaded = ChainState(start.rotation, start.translation, coordinates, wrenches)
    stiffness = linearize(system, loaded, w[None]).stiffness[0]
    frozen_k = linearize(system, loaded, w[None], geometric=False).stiffness[0]
    return stiffness, frozen_k
