"""Deflection-load curves like the paper's Fig. 10, with measurements overlaid.

Rotations in degrees, displacements in millimetres. A planar design's curves of the
paper's modes show the components those modes move (Fig. 10); a spatial design's
show all six (rotations about x, y, z; displacements along x, y, z).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.core.decoupling import DECOUPLED_TOLERANCE
from ppm_stiffness.statics.deflection import DeflectionCurve
from ppm_stiffness.statics.measurements import Measurements

_NAMES = ("φx", "φy", "φz", "x", "y", "z")
#: Components drawn for each mode: (orientation indices, position indices).
_RELEVANT = {
    "planar-force": ((2,), (3, 4)),
    "moment": ((2,), (3, 4)),
    "vertical-force": ((0, 1), (5,)),
}
_STYLES = ("-", "--", ":", "-.")


def _components(curves: list[DeflectionCurve], meas: list[Measurements]) -> tuple[list[int], ...]:
    mode = curves[0].mode
    if not all(c.planar for c in curves):
        rot, pos = [0, 1, 2], [3, 4, 5]
    elif mode in _RELEVANT:
        rot, pos = (list(c) for c in _RELEVANT[mode])
    else:
        big = np.max(np.abs(np.vstack([c.twists for c in curves])), axis=0)
        rot = [i for i in range(3) if big[i] > 1e-9 * max(big[:3].max(), 1e-300)]
        pos = [i for i in range(3, 6) if big[i] > 1e-9 * max(big[3:].max(), 1e-300)]
    for m in meas:
        rot += [i for i in m.components if i < 3 and i not in rot]
        pos += [i for i in m.components if i >= 3 and i not in pos]
    return sorted(rot), sorted(pos)


def round_off_as_zero(twists: Any) -> FloatArray:
    """Twists (n, 6) [rad, m] with the components that are round-off set to 0.

    A component is round-off when its largest |value| along the curve, length-balanced
    (rotations times ``conventions.LENGTH_SCALE``), is at most
    :data:`~ppm_stiffness.core.decoupling.DECOUPLED_TOLERANCE` of the largest
    component's: the rotation of a decoupled design under a force, drawn otherwise as
    noise on a 1e-17 deg axis.
    """
    t = np.asarray(twists, dtype=float)
    big = np.max(np.abs(t) / BALANCE, axis=0)
    return np.asarray(t * (big > DECOUPLED_TOLERANCE * np.max(big)))


def plot_deflection_curves(
    curves: Sequence[DeflectionCurve] | DeflectionCurve,
    measurements: Sequence[Measurements | None] | Measurements | None = None,
    bands: Sequence[Any | None] | None = None,
) -> Any:
    """Orientation [deg] and position [mm] of the tool point against the load, one row
    per load direction.

    Components of the model (and of its bands) that are round-off are drawn as 0
    (:func:`round_off_as_zero`); a spatial design's curves show all six components
    (module doc).

    Parameters
    ----------
    curves : DeflectionCurve or sequence of them
        Curves of the same mode and load direction share a row (e.g. the integrated
        law and the linear model), drawn with different line styles.
    measurements : Measurements, or a sequence aligned with ``curves``, optional
        Drawn as markers in the row of their curve.
    bands : sequence aligned with ``curves`` of Bands (twists (n_loads, 6)) or None
        Uncertainty bands (:func:`ppm_stiffness.fit.uncertainty.propagate`), drawn
        shaded around their curve.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    cs = [curves] if isinstance(curves, DeflectionCurve) else list(curves)
    if not cs:
        raise ValueError("no curves to plot")
    if measurements is None or isinstance(measurements, Measurements):
        ms: list[Measurements | None] = [measurements] + [None] * (len(cs) - 1)
    else:
        ms = list(measurements) + [None] * (len(cs) - len(measurements))
    groups: dict[tuple[str, tuple[float, ...]], list[int]] = {}
    for k, c in enumerate(cs):
        key = (c.mode, tuple(np.round(c.unit_wrench, 12).tolist()))
        groups.setdefault(key, []).append(k)
    fig = Figure(figsize=(10, 3.4 * len(groups)), layout="constrained")
    axes = np.atleast_2d(fig.subplots(len(groups), 2, squeeze=False))
    colours = [f"C{i}" for i in range(10)]
    for row, idx in enumerate(groups.values()):
        meas = [m for k in idx if (m := ms[k]) is not None]
        rot, pos = _components([cs[k] for k in idx], meas)
        unit = cs[idx[0]].load_unit
        for ax, comps, factor, name in (
            (axes[row, 0], rot, 180 / math.pi, "orientation [deg]"),
            (axes[row, 1], pos, 1e3, "position [mm]"),
        ):
            for j, k in enumerate(idx):
                c = cs[k]
                band = bands[k] if bands is not None and k < len(bands) else None
                twists = round_off_as_zero(c.twists)
                if band is not None:
                    lower, upper = round_off_as_zero(band.lower), round_off_as_zero(band.upper)
                for n, i in enumerate(comps):
                    if band is not None:
                        ax.fill_between(
                            c.loads,
                            lower[:, i] * factor,
                            upper[:, i] * factor,
                            color=colours[n % 10],
                            alpha=0.2,
                            lw=0,
                            label=f"{_NAMES[i]} {band.label}",
                        )
                    ax.plot(
                        c.loads,
                        twists[:, i] * factor,
                        _STYLES[j % len(_STYLES)],
                        color=colours[n % 10],
                        label=f"{_NAMES[i]} model ({c.method})",
                    )
            for m in meas:
                for n, i in enumerate(comps):
                    if i in m.components:
                        ax.plot(
                            m.load_values(),
                            m.twists[:, i] * factor,
                            "o",
                            ms=4,
                            mfc="none",
                            color=colours[n % 10],
                            label=f"{_NAMES[i]} measured",
                        )
            ax.set_xlabel(f"load [{unit}]")
            ax.set_ylabel(name)
            ax.grid(True, alpha=0.3)
            if comps:
                ax.legend(fontsize=7)
            else:
                ax.text(0.5, 0.5, "(none)", ha="center", va="center", transform=ax.transAxes)
        axes[row, 0].set_title(_title(cs[idx[0]]), loc="left", fontsize=10)
    return fig


def _title(curve: DeflectionCurve) -> str:
    """The mode, with the planar force's angle or the load per unit (f, m)."""
    if math.isfinite(curve.alpha):
        return f"{curve.mode}, α = {math.degrees(curve.alpha):g}°"
    if curve.mode in ("direction", "wrench"):
        w = curve.unit_wrench
        f = ", ".join(f"{v:.3g}" for v in w[3:])
        m = ", ".join(f"{v:.3g}" for v in w[:3])
        return f"{curve.mode}: f = ({f}) N, m = ({m}) N·m per {curve.load_unit}"
    return curve.mode
