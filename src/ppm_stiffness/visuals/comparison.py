"""Stiffness maps of several designs side by side, one colour scale per quantity.

One row per design (a :class:`~ppm_stiffness.maps.workspace.StiffnessMap` at one
orientation), columns k_phi [N·m/rad], k_x and k_y [N/m]; every panel of a column shares
its colour levels, so that the colours compare across designs (``compare``, and the
before/after maps of ``optimize``). When a column's values span more than
:data:`LOG_SPAN` (designs of different orders of magnitude) its scale is logarithmic.
The required region's box is drawn dashed.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ppm_stiffness.maps.workspace import StiffnessMap
from ppm_stiffness.visuals.maps import PANELS

#: Height of one row [inch].
ROW_HEIGHT = 3.2
#: Width of one panel with its colour bar [inch].
PANEL_WIDTH = 4.2
#: Largest max/min ratio of a column drawn on a linear colour scale.
LOG_SPAN = 10.0


def _common_levels(maps: Sequence[StiffnessMap], name: str, n: int = 14) -> tuple[Any, Any]:
    """Contour levels and norm (None: linear) shared by one column."""
    values = [m.fields()[name].compressed() for m in maps if np.any(m.reachable)]
    finite = np.concatenate(values) if values else np.array([])
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        return n, None
    lo, hi = float(finite.min()), float(finite.max())
    if hi - lo <= 1e-9 * max(abs(hi), 1e-300):
        pad = max(abs(hi) * 1e-6, 1e-12)
        return np.linspace(lo - pad, hi + pad, 3), None
    if lo > 0 and hi / lo > LOG_SPAN:
        from matplotlib.colors import LogNorm

        return np.geomspace(lo, hi, 2 * n), LogNorm(vmin=lo, vmax=hi)
    return np.linspace(lo, hi, n), None


def plot_maps_side_by_side(
    maps: Sequence[StiffnessMap],
    labels: Sequence[str],
    region_box: Sequence[float] | None = None,
    title: str | None = None,
) -> Any:
    """Figure: one row per map, k_phi, k_x, k_y on one colour scale per column.

    Parameters
    ----------
    maps : sequence of StiffnessMap
        Same orientation, locked actuators typically.
    labels : sequence of str
        One per map (the row titles).
    region_box : (x_min, x_max, y_min, y_max) [m], optional
        Drawn as a dashed rectangle on every panel.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    if not maps or len(maps) != len(labels):
        raise ValueError("one label per map, and at least one map")
    fig = Figure(figsize=(3 * PANEL_WIDTH, ROW_HEIGHT * len(maps) + 0.6), layout="constrained")
    axes = fig.subplots(len(maps), 3, squeeze=False)
    levels = {name: _common_levels(maps, name) for name, _, _ in PANELS}
    for col, (name, symbol, unit) in enumerate(PANELS):
        mappable = None
        for row, (m, label) in enumerate(zip(maps, labels, strict=True)):
            ax = axes[row, col]
            xs, ys = m.x * 1e3, m.y * 1e3
            if np.any(m.reachable):
                lv, norm = levels[name]
                mappable = ax.contourf(
                    xs, ys, m.fields()[name], levels=lv, norm=norm, cmap="viridis"
                )
            else:
                ax.text(
                    0.5, 0.5, "no reachable pose", ha="center", va="center", transform=ax.transAxes
                )
            if region_box is not None:
                x0, x1, y0, y1 = (1e3 * float(v) for v in region_box)
                ax.add_patch(
                    Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ls="--", lw=1.0, ec="k")
                )
            ax.set_xlim(xs[0], xs[-1])
            ax.set_ylim(ys[0], ys[-1])
            ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_title(f"{label}: {symbol}", fontsize=9)
        if mappable is not None:
            cbar = fig.colorbar(mappable, ax=axes[:, col], shrink=0.9)
            cbar.set_label(f"{symbol} [{unit}]")
            lv, norm = levels[name]
            if norm is None:
                cbar.formatter.set_powerlimits((-3, 4))  # type: ignore[attr-defined]
                cbar.update_ticks()
            else:  # decades as ticks
                exps = np.arange(np.ceil(np.log10(lv[0])), np.floor(np.log10(lv[-1])) + 1)
                cbar.set_ticks(list(10.0**exps), labels=[f"1e{int(e)}" for e in exps])
                cbar.minorticks_off()
    phi = np.degrees(maps[0].phi)
    fig.suptitle(title or f"Principal stiffness, actuators locked, φ = {phi:.4g}° (region dashed)")
    return fig
