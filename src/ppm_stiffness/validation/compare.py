"""Compare the virtual-joint stiffness with the FE frame model.

Figures per pose (:func:`figure_names`):

- a planar design: the planar block (phi_z, x, y) = indices (2, 3, 4) and the
  out-of-plane block (phi_x, phi_y, z) = (0, 1, 5), as ever (K of a planar mechanism
  has no entry coupling them);
- any other design: the whole 6x6 matrix (``"full"``);
- every design: ``"directions"``, the largest relative difference of the stiffness
  along any twist, ``max |lambda - 1|`` over the generalised eigenvalues of
  ``K_fe t = lambda K_vj t`` (independent of the reference point, the axes and the
  length balancing, and blind to no direction: a soft direction whose entries are
  all below the threshold below is still compared).

Within a block, an entry is compared when it is at least ``ENTRY_THRESHOLD`` (1%) of
the block's largest entry after length balancing
(:func:`~ppm_stiffness.core.conventions.length_balanced`: K_rr / L^2, K_rt / L, K_tt
with L = ``LENGTH_SCALE``): in raw SI units N·m/rad, N and N/m are not comparable and
the rotational stiffness would never reach 1% of the translational one. The relative
difference of an entry is ``|K_fe - K_vj| / |K_vj|`` (unit free); a block's figure is
the largest over its compared entries.

Poses are full poses (x, y, z, rx, ry, rz) [m, rad] (:mod:`ppm_stiffness.poses`),
drawn over the design's task coordinates (:func:`sample_reachable_poses`).
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, length_balanced
from ppm_stiffness.core.errors import (
    InputDataError,
    PPMStiffnessError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.core.pose import ANGLE_COORDINATES, POSE_COORDINATES, POSE_CSV_COLUMNS
from ppm_stiffness.core.singularity import nonsingular
from ppm_stiffness.design import Design
from ppm_stiffness.model import stiffness_at_pose, transmission_at_pose, validate_pose
from ppm_stiffness.poses import full_poses, home_pose, task_indices
from ppm_stiffness.validation.fe_model import FESettings, fe_stiffness_at_pose

#: Indices of the blocks of a planar design in the library's twist order
#: (phi_x, phi_y, phi_z, x, y, z).
BLOCKS: dict[str, tuple[int, ...]] = {"planar": (2, 3, 4), "out_of_plane": (0, 1, 5)}
#: The block of any other design: the whole matrix.
SPATIAL_BLOCKS: dict[str, tuple[int, ...]] = {"full": (0, 1, 2, 3, 4, 5)}
#: The figure over every twist direction (module doc).
DIRECTIONS = "directions"
#: Entries below this fraction of the block's largest (balanced) entry are not compared.
ENTRY_THRESHOLD = 0.01
#: Acceptance limits: planar 2 %, out-of-plane 5 % (the planar designs' acceptance);
#: the whole matrix of a spatial design 2 % (as the block that carries a planar
#: design's stiffness), every direction 5 % (as the softer block).
TOLERANCES: dict[str, float] = {
    "planar": 0.02,
    "out_of_plane": 0.05,
    "full": 0.02,
    DIRECTIONS: 0.05,
}


def design_blocks(design: Design) -> dict[str, tuple[int, ...]]:
    """The entry blocks compared for ``design``: :data:`BLOCKS` for a planar design,
    :data:`SPATIAL_BLOCKS` for any other."""
    return BLOCKS if design.planar else SPATIAL_BLOCKS


def figure_names(design: Design) -> tuple[str, ...]:
    """The figures compared per pose: the design's blocks, then ``"directions"``."""
    return (*design_blocks(design), DIRECTIONS)


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


def direction_difference(reference: ArrayLike, other: ArrayLike) -> float:
    """Largest relative difference of the stiffness along any twist direction.

    ``max |lambda - 1|`` over the generalised eigenvalues of ``other t = lambda
    reference t``: for every twist t, ``|t.other.t - t.reference.t| <= figure *
    t.reference.t``, with equality along some t. It does not depend on the reference
    point, the axes or the units.

    Parameters
    ----------
    reference, other : array_like, shape (6, 6)
        Symmetric stiffness matrices at the same point and axes; ``reference``
        positive definite.

    Returns
    -------
    float
    """
    a = length_balanced(reference)
    b = length_balanced(other)
    # reference = L L^T: the eigenvalues of L^-1 other L^-T, symmetric
    chol = np.linalg.cholesky(0.5 * (a + a.T))
    m = np.linalg.solve(chol, np.linalg.solve(chol, 0.5 * (b + b.T)).T)
    lam = np.linalg.eigvalsh(0.5 * (m + m.T))
    return float(np.max(np.abs(lam - 1.0)))


def cross_coupling(stiffness: ArrayLike) -> float:
    """Largest entry coupling the planar and out-of-plane blocks, relative to the
    largest entry of K (length-balanced). Zero for a planar mechanism."""
    kb = length_balanced(stiffness)
    cross = kb[np.ix_(BLOCKS["planar"], BLOCKS["out_of_plane"])]
    return float(np.max(np.abs(cross)) / np.max(np.abs(kb)))


def differences(design: Design, k_vj: ArrayLike, k_fe: ArrayLike) -> dict[str, float]:
    """The figures of :func:`figure_names` of ``k_fe`` against ``k_vj``."""
    out = {name: block_difference(k_vj, k_fe, idx) for name, idx in design_blocks(design).items()}
    out[DIRECTIONS] = direction_difference(k_vj, k_fe)
    return out


@dataclass(frozen=True)
class PoseComparison:
    """Both stiffness matrices at one pose and their differences.

    Attributes
    ----------
    pose : ndarray, shape (6,)
        The full pose (x, y, z [m], rx, ry, rz [rad]).
    k_virtual_joint, k_fe : ndarray, shape (6, 6)
        At P, axes of F_b (SI, library order).
    differences : dict
        Figure name (:func:`figure_names`) -> relative difference of the FE matrix to
        the virtual-joint one.
    fe_asymmetry : float
        Reciprocity check of the FE solution (see ``FEResult.asymmetry``).
    fe_cross_coupling : float
        :func:`cross_coupling` of the FE matrix (zero for a planar mechanism).
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
        """True when every figure is within :data:`TOLERANCES`."""
        return all(v <= TOLERANCES[name] for name, v in self.differences.items())


def compare_at_pose(
    design: Design,
    pose: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None,
) -> PoseComparison:
    """Virtual-joint and FE stiffness at one pose (task coordinates or a full pose),
    compared (:func:`differences`)."""
    p = validate_pose(design, pose)
    t0 = time.perf_counter()
    k_vj = stiffness_at_pose(design, p, actuator_stiffness)
    t1 = time.perf_counter()
    fe = fe_stiffness_at_pose(design, p, actuator_stiffness, settings)
    t2 = time.perf_counter()
    return PoseComparison(
        pose=p,
        k_virtual_joint=k_vj,
        k_fe=fe.stiffness,
        differences=differences(design, k_vj, fe.stiffness),
        fe_asymmetry=fe.asymmetry,
        fe_cross_coupling=cross_coupling(fe.stiffness),
        time_virtual_joint=t1 - t0,
        time_fe=t2 - t1,
    )


def sampling_box(
    design: Design,
    radius: float = 0.01,
    angle: float = float(np.radians(5.0)),
    region: bool = False,
) -> tuple[FloatArray, FloatArray]:
    """Centre and half-widths (n_task,) of the box the poses are drawn from, over the
    design's task coordinates (in pose order) [m, rad].

    Parameters
    ----------
    radius : float
        Half-width [m] about the home pose of every length task coordinate (x, y, z).
    angle : float
        Half-width [rad] about the home pose of every angle task coordinate (rx, ry, rz).
    region : bool
        The design's required region (``[workspace.required]``) instead.

    Raises
    ------
    InputDataError
        ``radius`` / ``angle`` not finite and >= 0, or ``region`` without a required
        region in the design.
    """
    for name, value in (("radius", radius), ("angle", angle)):
        if not np.isfinite(value) or value < 0:
            raise InputDataError(f"{name} must be finite and >= 0, got {value}")
    names = design.task_coordinates
    if region:
        required = design.workspace.required
        if required is None:
            raise InputDataError(
                f"{design.name!r} has no required region ([workspace.required]) to draw "
                "the poses from"
            )
        lo, hi = np.array([required.range(n) for n in names]).T
        return 0.5 * (lo + hi), 0.5 * (hi - lo)
    centre = home_pose(design)[list(task_indices(design))]
    half = np.array([angle if n in ANGLE_COORDINATES else radius for n in names])
    return centre, half


def describe_box(design: Design, centre: FloatArray, half: FloatArray) -> str:
    """``"x in [-10.0, 10.0] mm, rz in [-5.0, 5.0] deg"``: the box, in CLI units."""
    parts = []
    for name, c, h in zip(design.task_coordinates, centre, half, strict=True):
        if name in ANGLE_COORDINATES:
            parts.append(f"{name} in [{np.degrees(c - h):.1f}, {np.degrees(c + h):.1f}] deg")
        else:
            parts.append(f"{name} in [{(c - h) * 1e3:.1f}, {(c + h) * 1e3:.1f}] mm")
    return ", ".join(parts)


def _accepted(design: Design, pose: FloatArray) -> bool:
    """The model accepts the full pose: it is not singular by the transmission index
    (:func:`ppm_stiffness.model.transmission_at_pose`), whatever the parts' stiffness."""
    try:
        return bool(nonsingular(transmission_at_pose(design, pose)))
    except PPMStiffnessError:
        return False


def sample_reachable_poses(
    design: Design,
    n: int,
    seed: int = 0,
    radius: float = 0.01,
    angle: float = float(np.radians(5.0)),
    max_tries: int = 1000,
    region: bool = False,
) -> FloatArray:
    """``n`` seeded full poses over the design's task coordinates where the model is
    defined.

    Task coordinates are drawn uniformly in the box of :func:`sampling_box` (about the
    home pose, or the required region), in order, and completed
    (:func:`ppm_stiffness.poses.full_poses`); a draw is kept when the completion
    converges, every leg reaches it (:meth:`LegModel.solve` and
    :meth:`LegModel.reachable`: inverse kinematics and joint limits, any leg type) and
    it is not singular by the transmission index (a question of the joints' geometry:
    a design of near-rigid parts is not skipped).

    Parameters
    ----------
    design : Design
    n : int
        Number of poses (>= 0).
    seed : int
        Seed of ``numpy.random.default_rng``.
    radius, angle, region
        The box (:func:`sampling_box`) [m, rad].
    max_tries : int
        Draws allowed per requested pose before giving up.

    Returns
    -------
    ndarray, shape (n, 6)
        Full poses (x, y, z [m], rx, ry, rz [rad]).

    Raises
    ------
    UnreachablePoseError
        If too few draws are reachable.
    InputDataError
        ``n`` negative, or a bad box (:func:`sampling_box`).
    """
    if n < 0:
        raise InputDataError(f"the number of poses must be >= 0, got {n}")
    centre, half = sampling_box(design, radius, angle, region)
    rng = np.random.default_rng(seed)
    draws = centre + rng.uniform(-1.0, 1.0, (max_tries * max(n, 1), len(centre))) * half
    poses, ok = full_poses(design, draws)
    for leg in design.legs:
        ok &= leg.reachable(leg.solve(poses))
    out: list[FloatArray] = []
    for pose in poses[ok]:
        if len(out) == n:
            break
        if _accepted(design, pose):
            out.append(pose)
    if len(out) < n:
        raise UnreachablePoseError(
            f"only {len(out)} of {n} random poses with {describe_box(design, centre, half)} "
            "are reachable"
        )
    return np.array(out).reshape(n, 6)


def validation_poses(
    design: Design,
    n: int,
    seed: int = 0,
    radius: float = 0.01,
    angle: float = float(np.radians(5.0)),
    region: bool = False,
) -> FloatArray:
    """The home pose followed by ``n`` seeded reachable poses
    (:func:`sample_reachable_poses`); full poses, shape (n + 1, 6)."""
    samples = sample_reachable_poses(design, n, seed, radius, angle, region=region)
    return np.vstack([home_pose(design)[None, :], samples])


def compare_poses(
    design: Design,
    poses: Iterable[ArrayLike],
    settings: FESettings | None = None,
) -> list[PoseComparison]:
    """:func:`compare_at_pose` at each pose (locked actuators)."""
    return [compare_at_pose(design, p, settings=settings) for p in poses]


#: CSV pose columns: the six coordinates in mm and degrees, and phi_deg (= rz, the
#: planar name of earlier files).
POSE_COLUMNS = POSE_CSV_COLUMNS + ("phi_deg",)


def csv_rows(comparisons: Iterable[PoseComparison]) -> list[dict[str, float | str]]:
    """One row per pose and figure: the :data:`POSE_COLUMNS`, block, max_rel_diff."""
    rows: list[dict[str, float | str]] = []
    for c in comparisons:
        scaled = [
            float(np.degrees(v)) if n in ANGLE_COORDINATES else float(v * 1e3)
            for n, v in zip(POSE_COORDINATES, c.pose, strict=True)
        ]
        pose = dict(zip(POSE_COLUMNS, [*scaled, scaled[5]], strict=True))
        for name, value in c.differences.items():
            rows.append({**pose, "block": name, "max_rel_diff": value})
    return rows


def has_notch_hinges(design: Design) -> bool:
    """Whether a chain leg of ``design`` has an R joint with a ``hinge`` table."""
    from ppm_stiffness.legs.types.chain_leg import ChainLeg, JointElement

    return any(
        isinstance(e, JointElement) and e.hinge is not None
        for leg in design.legs
        if isinstance(leg, ChainLeg)
        for e in leg.elements
    )


#: FE settings of :func:`hinge_convergence` (its doc).
HINGE_SETTINGS = FESettings(rigid_stiffness=1e12, length_unit=0.01, check_stability=False)
#: The meshes of :func:`hinge_convergence` (members per hinge).
HINGE_MESHES = (64, 128, 256)
#: Largest Maxwell-Betti asymmetry of the FE compliance at P accepted by
#: :func:`hinge_convergence` (its doc): half the 1e-4 the finest mesh must reach.
HINGE_ROUND_OFF = 5e-5


@dataclass(frozen=True)
class HingeConvergence:
    """The FE frame's notch hinges as chains of n beam members, against the model.

    Attributes
    ----------
    segments : tuple of int
        Members per hinge, each twice the one before.
    differences : tuple of float
        ``max |K_fe - K_vj|_ij / sqrt(K_vj_ii K_vj_jj)`` for each n.
    order : float or None
        Observed order: log2 of the ratio of the last two increments of K_fe (same
        measure); None with fewer than three meshes.
    extrapolated : float
        The same measure for the Richardson limit of the last two meshes at order 2,
        ``K_2n + (K_2n - K_n) / 3``.
    asymmetry : tuple of float
        The Maxwell-Betti asymmetry of each mesh's compliance at P
        (:attr:`FEResult.asymmetry`): the solve's round-off in it.
    """

    segments: tuple[int, ...]
    differences: tuple[float, ...]
    order: float | None
    extrapolated: float
    asymmetry: tuple[float, ...]


def hinge_convergence(
    design: Design,
    pose: ArrayLike | None = None,
    segments: Sequence[int] = HINGE_MESHES,
    settings: FESettings | None = None,
) -> HingeConvergence:
    """K of the FE frame with its notch hinges as ``n`` members each
    (:mod:`ppm_stiffness.validation.hinge_chain`) for each n of ``segments``, against the
    virtual-joint K, at ``pose`` (the home pose when None).

    ``settings`` default to :data:`HINGE_SETTINGS`: rigid parts 10 times stiffer than
    the frame's default, so that their own compliance (7.6e-5 of K on the 3-RRR flexure
    stage at the default 1e11 N/m) stays well below the target 1e-4; a length unit of
    1 cm; and PyNite's residual check off, replaced by the compliance's reciprocity.
    The chains' short members make the frame's stiffness matrix ill-conditioned as n^3
    (a member's transverse stiffness 12 EI / D^3 beside the hinges' rotational
    stiffness): PyNite's check, ``|K x - f| <= 1e-6 |f|``, refuses any backward-stable
    solve once ``eps |K| |x| / |f|`` passes 1e-6 (the stage from n = 64 on), whatever
    the accuracy of the displacements at P. Their round-off shows instead in the
    asymmetry of the compliance at P (Maxwell-Betti), which must stay below
    :data:`HINGE_ROUND_OFF` (on the stage 2.4e-6 at n = 256; a frame PyNite cannot solve,
    moduli of 1e20 Pa, 3e-4 to 1e-2). The asymmetry understates the round-off in K:
    on the stage K at n = 256 changes by 6.4e-5 of its diagonal with the length unit
    (1 cm against 10 cm; 9.5e-6 at n = 128), so that finer meshes gain nothing.

    Raises
    ------
    InputDataError
        Fewer than two meshes, or a count that does not double.
    SingularConfigurationError
        A mesh whose compliance at P is less reciprocal than :data:`HINGE_ROUND_OFF`.
    """
    from dataclasses import replace

    counts = tuple(int(n) for n in segments)
    if len(counts) < 2 or any(b != 2 * a for a, b in zip(counts, counts[1:], strict=False)):
        raise InputDataError(f"hinge segments: two or more counts, each doubling, got {counts}")
    p = home_pose(design) if pose is None else np.asarray(pose, dtype=float)
    k = stiffness_at_pose(design, p)
    scale = np.sqrt(np.outer(np.diag(k), np.diag(k)))
    base = settings or HINGE_SETTINGS
    results = [
        fe_stiffness_at_pose(design, p, settings=replace(base, hinge_segments=n)) for n in counts
    ]
    for n, r in zip(counts, results, strict=True):
        if r.asymmetry > HINGE_ROUND_OFF:
            raise SingularConfigurationError(
                f"FE model with {n} members per notch hinge: its compliance at P is "
                f"reciprocal only to {r.asymmetry:.1e} (round-off; at most "
                f"{HINGE_ROUND_OFF:.0e}): use fewer members"
            )
    ks = [r.stiffness for r in results]

    def measure(a: FloatArray, b: FloatArray) -> float:
        return float(np.max(np.abs(a - b) / scale))

    order = None
    if len(ks) >= 3:
        order = float(np.log2(measure(ks[-2], ks[-3]) / measure(ks[-1], ks[-2])))
    limit = ks[-1] + (ks[-1] - ks[-2]) / 3.0
    return HingeConvergence(
        counts,
        tuple(measure(x, k) for x in ks),
        order,
        measure(limit, k),
        tuple(r.asymmetry for r in results),
    )
