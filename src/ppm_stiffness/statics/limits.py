"""The limits of the small-displacement model under a load, as masks and as errors.

The model linearises the geometry about the unloaded pose (the paper's): a load that
drives an actuator beyond its whole stroke, or turns the platform by more than
:data:`MAX_ROTATION`, is outside it, and so is a loaded tangent K that is not positive
definite. Each limit is one mask function (:func:`within_stroke`, :func:`small_rotation`,
:func:`positive_definite`), used by the batched equilibrium
(:func:`ppm_stiffness.statics.equilibrium.loaded_states`) and the deflection curves;
the ``check_*`` functions raise exactly where their mask is False, with a message that
names the actuator or the angle.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, BoolArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import LegModel

#: Largest platform rotation [rad] a deflection may reach: the model linearises the
#: geometry about the unloaded pose (small displacements).
MAX_ROTATION = 0.1


def _stroke_span(leg: LegModel) -> float:
    """The whole travel of a leg's actuated coordinate (its limits' span) [m or rad];
    inf for a passive constraining leg (no actuator: its displacement is always 0)."""
    lo, hi = leg.limits().get(leg.ACTUATED_COORDINATE, (-np.inf, np.inf))
    return float(hi - lo)


def within_stroke(design: Design, displacements: ArrayLike) -> BoolArray:
    """Mask (...): every actuator displacement (..., n_legs) [m or rad] within its
    leg's whole stroke (the span of its actuated coordinate); False where not finite."""
    d = np.abs(np.asarray(displacements, dtype=float))
    spans = np.array([_stroke_span(leg) for leg in design.legs])
    return np.asarray(np.all(d <= spans, axis=-1))


def small_rotation(twists: ArrayLike) -> BoolArray:
    """Mask (...): the rotation of each twist (..., 6) at most :data:`MAX_ROTATION`."""
    t = np.asarray(twists, dtype=float)
    return np.asarray(np.linalg.norm(t[..., :3], axis=-1) <= MAX_ROTATION)


def check_actuator_travel(design: Design, displacements: ArrayLike) -> None:
    """Refuse loads under which an actuator would travel beyond its stroke.

    The model is one of small displacements about a fixed geometry; an actuator
    displaced by more than its whole stroke (the span of its leg's actuated coordinate) is
    far outside it, and its stiffness from eq. (21) is meaningless. Raises exactly where
    :func:`within_stroke` is False.

    Parameters
    ----------
    displacements : array_like, shape (..., n_legs)
        Actuator displacements [m, or rad for a rotary actuator].
    """
    d = np.abs(np.asarray(displacements, dtype=float)).reshape(-1, len(design.legs))
    ok = within_stroke(design, d)
    if np.all(ok):
        return
    spans = np.array([_stroke_span(leg) for leg in design.legs])
    worst = np.where(np.isnan(d[~ok]), np.inf, d[~ok]).max(axis=0)
    i = int(np.argmax(worst / spans))
    leg = design.legs[i]
    rotary = leg.coordinate(leg.ACTUATED_COORDINATE).unit == "rad"
    scale, unit = (180 / np.pi, "deg") if rotary else (1e3, "mm")
    raise InputDataError(
        f"load too large: actuator {i + 1} would move {worst[i] * scale:.4g} {unit}, "
        f"more than its whole stroke of {spans[i] * scale:.4g} {unit} (the model is "
        "for small deflections)"
    )


def check_small_rotation(twists: ArrayLike) -> None:
    """Refuse deflections whose rotation exceeds :data:`MAX_ROTATION` (5.7 deg), exactly
    where :func:`small_rotation` is False.

    Parameters
    ----------
    twists : array_like, shape (..., 6)
        Platform twists (rotation first) [rad, m].
    """
    t = np.asarray(twists, dtype=float).reshape(-1, 6)
    ok = small_rotation(t)
    if np.all(ok):
        return
    rotation = np.linalg.norm(t[~ok, :3], axis=1)
    worst = float(np.max(np.where(np.isnan(rotation), np.inf, rotation)))
    raise InputDataError(
        f"load too large: the platform would rotate {np.degrees(worst):.3g} deg, "
        f"beyond the {np.degrees(MAX_ROTATION):.2g} deg a small-displacement model covers"
    )


def positive_definite(stiffness: ArrayLike) -> BoolArray:
    """Mask (...): K (..., 6, 6) finite and positive definite, by a Cholesky
    factorisation of the length-balanced matrix (every pivot > 0), vectorised over the
    batch."""
    k = np.asarray(stiffness, dtype=float) * BALANCE[:, None] * BALANCE[None, :]
    ok = np.all(np.isfinite(k), axis=(-2, -1))
    a = np.where(ok[..., None, None], k, np.eye(6))
    low = np.zeros_like(a)
    with np.errstate(invalid="ignore"):
        for j in range(6):
            pivot = a[..., j, j] - np.sum(low[..., j, :j] ** 2, axis=-1)
            ok = ok & (pivot > 0)
            root = np.sqrt(np.where(pivot > 0, pivot, 1.0))
            low[..., j, j] = root
            for i in range(j + 1, 6):
                low[..., i, j] = (
                    a[..., i, j] - np.sum(low[..., i, :j] * low[..., j, :j], axis=-1)
                ) / root
    return np.asarray(ok)
