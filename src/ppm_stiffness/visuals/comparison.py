"""Stiffness maps of several designs side by side, one colour scale per quantity.

One row per design (a :class:`~ppm_stiffness.maps.workspace.StiffnessMap` over one
slice), one column per quantity of the maps (a planar design's k_phi [N·m/rad], k_x and
k_y [N/m]; another's worst-direction principal stiffnesses, ``rotational_min``
[N·m/rad] and ``translational_min`` [N/m]), labelled from the quantities and the
slice's axes (:data:`ppm_stiffness.maps.result.QUANTITIES`); every panel of a column
shares its colour levels, so that the colours compare across designs (``compare``, and the
before/after maps of ``optimize``). When a column's values span more than
:data:`LOG_SPAN` (designs of different orders of magnitude) its scale is logarithmic.
The required region's box is drawn dashed.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ppm_stiffness.maps.result import QUANTITIES
from ppm_stiffness.maps.workspace import StiffnessMap
from ppm_stiffness.visuals.maps import axis_grid, slice_label

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
    """Figure: one row per map, one column per quantity, one colour scale per column.

    Parameters
    ----------
    maps : sequence of StiffnessMap
        Same slice (axes, fixed coordinates) and quantities, locked actuators typically.
    labels : sequence of str
        One per map (the row titles).
    region_box : (u_min, u_max, v_min, v_max) [m or rad], optional
        The region's ranges of the maps' two axes, drawn as a dashed rectangle on every
        panel.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    if not maps or len(maps) != len(labels):
        raise ValueError("one label per map, and at least one map")
    panels = [(name, QUANTITIES[name][2], QUANTITIES[name][0]) for name in maps[0].quantities]
    ncol = len(panels)
    fig = Figure(figsize=(ncol * PANEL_WIDTH, ROW_HEIGHT * len(maps) + 0.6), layout="constrained")
    axes = fig.subplots(len(maps), ncol, squeeze=False)
    levels = {name: _common_levels(maps, name) for name, _, _ in panels}
    _, _, u_label, v_label = axis_grid(maps[0])
    scale_u, scale_v = _scales(maps[0])
    same_unit = u_label.split("[")[-1] == v_label.split("[")[-1]
    for col, (name, symbol, unit) in enumerate(panels):
        mappable = None
        for row, (m, label) in enumerate(zip(maps, labels, strict=True)):
            ax = axes[row, col]
            xs, ys, _, _ = axis_grid(m)
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
                x0, x1 = (scale_u * float(v) for v in region_box[:2])
                y0, y1 = (scale_v * float(v) for v in region_box[2:])
                ax.add_patch(
                    Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ls="--", lw=1.0, ec="k")
                )
            ax.set_xlim(xs[0], xs[-1])
            ax.set_ylim(ys[0], ys[-1])
            if same_unit:
                ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel(u_label)
            ax.set_ylabel(v_label)
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
    if title is None:
        if tuple(maps[0].axes) == ("x", "y") and set(maps[0].fixed) == {"rz"}:
            where = f"φ = {np.degrees(maps[0].phi):.4g}°"
        else:
            where = slice_label(maps[0])
        title = f"Principal stiffness, actuators locked, {where} (region dashed)"
    fig.suptitle(title)
    return fig


def _scales(smap: StiffnessMap) -> tuple[float, float]:
    """The factors from SI to the CLI's units (mm, deg) of the map's two axes."""
    from ppm_stiffness.maps.slices import cli_scale

    return cli_scale(smap.axes[0])[0], cli_scale(smap.axes[1])[0]
