"""The first natural frequency at many poses, for the maps (``map --quantities f1``).

At each pose the map has accepted (its refusal code 0), M is built at the map's poses
by :func:`ppm_stiffness.dynamics.mass.mass_matrix` (vectorised over them, with the
actuator stiffnesses the map's K was built with: locked, "min", or the loaded tangent
ones under a wrench), and f1 [Hz] is the lowest of :func:`ppm_stiffness.dynamics.modes
.natural_frequencies` of the map's own K and that M, both at P (the frequencies do not
depend on the reference point: a tool point changes neither). With link modes, each
leg's own modes with the platform held are added (Craig-Bampton,
:mod:`ppm_stiffness.dynamics.legmodes`, the same arithmetic as ``modal_analysis(...,
link_modes=N)``) and f1 is the lowest frequency of the reduced pair.

A pose where M is not finite or not positive definite, or where the eigenproblem has
no real solution (K not positive semi-definite), is refused as the single-pose
:func:`ppm_stiffness.dynamics.analysis.modal_analysis` refuses it: code
:attr:`~ppm_stiffness.core.refusals.Refusal.SINGULAR` (a
:class:`~ppm_stiffness.core.errors.SingularConfigurationError` there), never a NaN
presented as a value.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.refusals import Refusal, RefusalArray
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.mass import mass_matrix, require_mass_model
from ppm_stiffness.dynamics.modes import natural_frequencies

#: The map quantity of this module: the first natural frequency [Hz].
FIRST_FREQUENCY = "f1"


def first_frequencies(
    design: Design,
    poses: ArrayLike,
    stiffness: ArrayLike,
    actuator_stiffness: ArrayLike,
    valid: ArrayLike | None = None,
    link_modes: int = 0,
) -> tuple[FloatArray, BoolArray]:
    """f1 (n,) [Hz] at full poses (n, 6) from their K, and where it exists.

    Parameters
    ----------
    design : Design
        With a mass model.
    poses : array_like (n, 6)
        Full poses [m, rad].
    stiffness : array_like (n, 6, 6)
        K at P, axes of F_b (SI), built with ``actuator_stiffness``.
    actuator_stiffness : array_like (n, n_legs) or (n_legs,)
        [N/m or N·m/rad].
    valid : array_like of bool (n,), optional
        The poses to evaluate (the others get NaN and False); all if None.
    link_modes : int
        Each leg's own modes with the platform held (Craig-Bampton,
        :mod:`ppm_stiffness.dynamics.legmodes`), batched over the poses (the maps'
        and optimize's default: :data:`~ppm_stiffness.dynamics.legmodes
        .DEFAULT_LINK_MODES`, resolved by them); 0: the static condensation alone.

    Returns
    -------
    f1 : ndarray (n,) [Hz]
        NaN where not ``ok``.
    ok : ndarray of bool (n,)
        ``valid`` and M finite and positive definite and the eigenvalues real and
        non-negative.

    Raises
    ------
    DesignError
        If the design has no mass model.
    """
    require_mass_model(design)
    q = np.asarray(poses, dtype=float)
    n = q.shape[0]
    k = np.asarray(stiffness, dtype=float)
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), (n, len(design.legs)))
    want = np.ones(n, dtype=bool) if valid is None else np.asarray(valid, dtype=bool)
    f1 = np.full(n, np.nan)
    index = np.flatnonzero(want)
    if index.size:
        every = index.size == n
        sub = (lambda a: a) if every else (lambda a: np.take(a, index, axis=0))
        with np.errstate(all="ignore"):
            m = mass_matrix(design, sub(q), sub(k_act))
            if link_modes == 0:
                f1[index] = natural_frequencies(sub(k), m)[:, 0]
            else:
                f1[index] = _with_link_modes(design, sub(q), sub(k), m, sub(k_act), link_modes)
    return f1, np.isfinite(f1)


def _with_link_modes(
    design: Design,
    poses: FloatArray,
    stiffness: FloatArray,
    mass: FloatArray,
    actuator_stiffness: FloatArray,
    count: int,
) -> FloatArray:
    """f1 (n,) with each leg's ``count`` own modes, in chunks of poses."""
    from ppm_stiffness.dynamics.legmodes import (
        design_leg_modes,
        reduced_frequencies,
        reduced_matrices,
        stack_leg_modes,
    )
    from ppm_stiffness.dynamics.mass import MASS_CHUNK

    out = np.full(poses.shape[0], np.nan)
    for lo in range(0, poses.shape[0], MASS_CHUNK):
        hi = lo + MASS_CHUNK
        legs = design_leg_modes(
            design, poses[lo:hi], actuator_stiffness[lo:hi], count, checks=False
        )
        kr, mr = reduced_matrices(stiffness[lo:hi], mass[lo:hi], *stack_leg_modes(legs))
        out[lo:hi] = reduced_frequencies(kr, mr)[:, 0]
    return out


def refuse_failed(codes: RefusalArray, ok: BoolArray, f1_ok: BoolArray) -> RefusalArray:
    """The map's codes with the poses it accepted but where f1 failed refused as
    singular (module doc)."""
    out = np.array(codes, dtype=np.int8, copy=True)
    out[np.asarray(ok, dtype=bool) & ~np.asarray(f1_ok, dtype=bool)] = Refusal.SINGULAR
    return out
