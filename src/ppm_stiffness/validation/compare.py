"""Compare the virtual-joint stiffness with the FE frame model, block by block.

The planar block is (phi_z, x, y) = indices (2, 3, 4), the out-of-plane block
(phi_x, phi_y, z) = (0, 1, 5). Within a block, an entry is compared when it is at
least ``ENTRY_THRESHOLD`` (1%) of the block's largest entry after length balancing
(:func:`~ppm_stiffness.core.conventions.length_balanced`: K_rr / L^2, K_rt / L, K_tt
with L = ``LENGTH_SCALE``): in raw
SI units N·m/rad, N and N/m are not comparable and the rotational stiffness would
never reach 1% of the translational one. The relative difference of an entry is
``|K_fe - K_vj| / |K_vj|`` (unit free); a block's figure is the largest over its
compared entries.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, length_balanced
from ppm_stiffness.core.errors import InputDataError, PPMStiffnessError, UnreachablePoseError
from ppm_stiffness.core.solver import cartesian_stiffness
from ppm_stiffness.design import Design
from ppm_stiffness.model import (
    check_nonsingular,
    leg_springs_at_pose,
    stiffness_at_pose,
    workspace_centre,
)
from ppm_stiffness.validation.fe_model import FESettings, fe_stiffness_at_pose

#: Indices of the blocks in the library's twist order (phi_x, phi_y, phi_z, x, y, z).
BLOCKS: dict[str, tuple[int, int, int]] = {"planar": (2, 3, 4), "out_of_plane": (0, 1, 5)}
#: Entries below this fraction of the block's largest (balanced) entry are not compared.
ENTRY_THRESHOLD = 0.01
#: Acceptance limits of the issue: planar 2%, out-of-plane 5%.
TOLERANCES: dict[str, float] = {"planar": 0.02, "out_of_plane": 0.05}


def block_difference(
    reference: ArrayLike,
    other: ArrayLike,
    block: Sequence[int],
    threshold: float = ENTRY_THRESHOLD,
) -> float:
    """Largest relative difference of ``other`` to ``reference`` over one block.

    Parameters
    ----------
    reference, other : array_like, shape (6, 6)
        Stiffness matrices at the same point and axes (SI, library order).
    block : sequence of int
        Component indices of the block, e.g. ``BLOCKS["planar"]``.
    threshold : float
        Entries of ``reference`` below ``threshold`` times the block's largest
        (after length balancing, :func:`~ppm_stiffness.core.conventions.length_balanced`)
        are left out.

    Returns
    -------
    float
        ``max |other - reference| / |reference|`` over the compared entries.
    """
    idx = np.ix_(list(block), list(block))
    a = length_balanced(reference)[idx]
    b = length_balanced(other)[idx]
    mask = np.abs(a) >= threshold * np.max(np.abs(a))
    return float(np.max(np.abs(b - a)[mask] / np.abs(a)[mask]))


def cross_coupling(stiffness: ArrayLike) -> float:
    """Largest entry coupling the planar and out-of-plane blocks, relative to the
    largest entry of K (length-balanced). Zero for a planar mechanism."""
    kb = length_balanced(stiffness)
    cross = kb[np.ix_(BLOCKS["planar"], BLOCKS["out_of_plane"])]
    return float(np.max(np.abs(cross)) / np.max(np.abs(kb)))


@dataclass(frozen=True)
class PoseComparison:
    """Both stiffness matrices at one pose and their per-block differences.

    Attributes
    ----------
    pose : ndarray, shape (3,)
        (x [m], y [m], phi [rad]).
    k_virtual_joint, k_fe : ndarray, shape (6, 6)
        At P, axes of F_b (SI, library order).
    differences : dict
        Block name -> :func:`block_difference` of the FE matrix to the virtual-joint one.
    fe_asymmetry : float
        Reciprocity check of the FE solution (see ``FEResult.asymmetry``).
    fe_cross_coupling : float
        :func:`cross_coupling` of the FE matrix.
    time_virtual_joint, time_fe : float
        Wall time [s] of each model at this pose (the FE time includes building).
    """

    pose: FloatArray
    k_virtual_joint: FloatArray
    k_fe: FloatArray
    differences: dict[str, float]
    fe_asymmetry: float
    fe_cross_coupling: float
    time_virtual_joint: float
    time_fe: float

    def within_tolerances(self) -> bool:
        """True when every block is within :data:`TOLERANCES`."""
        return all(self.differences[b] <= TOLERANCES[b] for b in BLOCKS)


def compare_at_pose(
    design: Design,
    pose: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None,
) -> PoseComparison:
    """Virtual-joint and FE stiffness at one pose, compared per block."""
    p = np.asarray(pose, dtype=float)
    t0 = time.perf_counter()
    k_vj = stiffness_at_pose(design, p, actuator_stiffness)
    t1 = time.perf_counter()
    fe = fe_stiffness_at_pose(design, p, actuator_stiffness, settings)
    t2 = time.perf_counter()
    return PoseComparison(
        pose=p,
        k_virtual_joint=k_vj,
        k_fe=fe.stiffness,
        differences={
            name: block_difference(k_vj, fe.stiffness, idx) for name, idx in BLOCKS.items()
        },
        fe_asymmetry=fe.asymmetry,
        fe_cross_coupling=cross_coupling(fe.stiffness),
        time_virtual_joint=t1 - t0,
        time_fe=t2 - t1,
    )


def sample_reachable_poses(
    design: Design,
    n: int,
    seed: int = 0,
    radius: float = 0.01,
    angle: float = float(np.radians(5.0)),
    max_tries: int = 1000,
) -> FloatArray:
    """``n`` seeded poses around the workspace centre where the model is defined.

    Poses are drawn uniformly in the box ``centre +- (radius, radius, angle)``, in
    order; a draw is kept when every leg reaches it (:meth:`LegModel.solve` and
    :meth:`LegModel.reachable`: inverse kinematics and joint limits, any leg type)
    and K is not singular (:func:`ppm_stiffness.model.check_nonsingular`).

    Parameters
    ----------
    design : Design
    n : int
        Number of poses (>= 0).
    seed : int
        Seed of ``numpy.random.default_rng``.
    radius : float
        Half-width of the box in x and y [m].
    angle : float
        Half-range of phi [rad].
    max_tries : int
        Draws allowed per requested pose before giving up.

    Returns
    -------
    ndarray, shape (n, 3)

    Raises
    ------
    UnreachablePoseError
        If too few draws are reachable.
    InputDataError
        ``n`` negative, or ``radius`` / ``angle`` not finite and >= 0.
    """
    if n < 0:
        raise InputDataError(f"the number of poses must be >= 0, got {n}")
    for name, value in (("radius", radius), ("angle", angle)):
        if not np.isfinite(value) or value < 0:
            raise InputDataError(f"{name} must be finite and >= 0, got {value}")
    rng = np.random.default_rng(seed)
    half = np.array([radius, radius, angle])
    draws = workspace_centre(design) + rng.uniform(-1.0, 1.0, (max_tries * max(n, 1), 3)) * half
    ok = np.ones(len(draws), dtype=bool)
    for leg in design.legs:
        ok &= leg.reachable(leg.solve(draws))
    out: list[FloatArray] = []
    for pose in draws[ok]:
        if len(out) == n:
            break
        try:
            k = cartesian_stiffness(leg_springs_at_pose(design, pose))
            check_nonsingular(k)
        except PPMStiffnessError:
            continue
        out.append(pose)
    if len(out) < n:
        raise UnreachablePoseError(
            f"only {len(out)} of {n} random poses within +-{radius * 1e3:.1f} mm, "
            f"+-{np.degrees(angle):.1f} deg of the centre are reachable"
        )
    return np.array(out).reshape(n, 3)


def validation_poses(
    design: Design,
    n: int,
    seed: int = 0,
    radius: float = 0.01,
    angle: float = float(np.radians(5.0)),
) -> FloatArray:
    """The workspace centre followed by ``n`` seeded reachable poses; shape (n + 1, 3)."""
    return np.vstack(
        [workspace_centre(design)[None, :], sample_reachable_poses(design, n, seed, radius, angle)]
    )


def compare_poses(
    design: Design,
    poses: Iterable[ArrayLike],
    settings: FESettings | None = None,
) -> list[PoseComparison]:
    """:func:`compare_at_pose` at each pose (locked actuators)."""
    return [compare_at_pose(design, p, settings=settings) for p in poses]


def csv_rows(comparisons: Iterable[PoseComparison]) -> list[dict[str, float | str]]:
    """One row per pose and block: pose_x_mm, pose_y_mm, phi_deg, block, max_rel_diff."""
    rows: list[dict[str, float | str]] = []
    for c in comparisons:
        for name in BLOCKS:
            rows.append(
                {
                    "pose_x_mm": float(c.pose[0] * 1e3),
                    "pose_y_mm": float(c.pose[1] * 1e3),
                    "phi_deg": float(np.degrees(c.pose[2])),
                    "block": name,
                    "max_rel_diff": c.differences[name],
                }
            )
    return rows
