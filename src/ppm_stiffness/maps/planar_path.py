"""The planar engine path: the stiffness of a planar design at many poses, by blocks.

The planar engine (:mod:`ppm_stiffness.legs.planar`, any planar joint chain: every
shipped planar leg type, redundant designs) evaluates the general model in closed form
per in-plane and out-of-plane block over arrays of poses, about 10x the general path;
``"auto"`` takes it for a planar design whose legs offer no reduced form. It returns
K's 12 structurally nonzero entries (:class:`~ppm_stiffness.maps.reduced_path
.PlanarEntries`) and the projector's by blocks.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray
from ppm_stiffness.design import Design
from ppm_stiffness.legs import planar as engine
from ppm_stiffness.maps.engine_path import solve_chunk, take
from ppm_stiffness.maps.reduced_path import PlanarEntries
from ppm_stiffness.model import transmission_blocks

#: Poses per chunk of the planar engine (about 2 kB per pose of temporaries).
PLANAR_CHUNK = 16384


def planar_engine_entries(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike,
    completed: BoolArray | None = None,
) -> tuple[PlanarEntries, PlanarEntries, BoolArray] | None:
    """Stiffness entries at poses by the planar engine (:mod:`ppm_stiffness.legs.planar`),
    one chunk.

    Same inputs as :func:`ppm_stiffness.maps.engine_path.general_stiffness`. Returns the
    planar entries of K (n,) (meaningless where not reachable), those of the legs'
    summed projector ``Pi`` (:mod:`ppm_stiffness.core.singularity`) and the
    reachability mask, or None when a leg's chain is not planar at these poses (use
    the general path). Poses
    where a leg's reduced compliance is singular give non-finite entries (masked by
    :func:`~ppm_stiffness.maps.transmission.nonsingular_from_entries`).
    """
    k_act, leg_poses, reach = solve_chunk(design, poses, actuator_stiffness, completed)
    n = reach.size
    index: np.ndarray | None = None
    if not reach.all():
        index = np.flatnonzero(reach)
        leg_poses = [take(lp, index) for lp in leg_poses]
        k_act = np.take(k_act, index, axis=0)
    legs, found = [], []
    with np.errstate(all="ignore"):
        for i, (leg, lp) in enumerate(zip(design.legs, leg_poses, strict=True)):
            blocks = engine.leg_blocks(leg.chain(lp))
            if blocks is None:
                return None
            found.append(blocks)
            k_leg: engine.Scalar = k_act[:, i]
            if k_act.shape[0] and np.all(k_act[:, i] == k_act[0, i]):
                k_leg = float(k_act[0, i])  # one value for every pose: a constant
            legs.append(engine.leg_stiffness_blocks(blocks, k_leg))
        total_in, total_out = engine.sum_blocks(legs)
        pi_in, pi_out = transmission_blocks(found)
    m = n if index is None else index.size

    def spread(entries: list[engine.Scalar]) -> PlanarEntries:
        values = [np.broadcast_to(np.asarray(v, dtype=float), (m,)) for v in entries]
        if index is not None:
            full = []
            for v in values:
                f = np.zeros(n)
                f[index] = v
                full.append(f)
            values = full
        return PlanarEntries(*values)

    return spread(total_in + total_out), spread(pi_in + pi_out), reach
