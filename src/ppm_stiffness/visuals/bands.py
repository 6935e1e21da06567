"""Uncertainty bands in pictures: stiffness maps of the lower band and of the relative
spread (the band of :func:`ppm_stiffness.fit.uncertainty.propagate` over a map's grid).

Three rows per quantity set of the map (k_phi, k_x, k_y for a planar design's map; the
spatial principal stiffnesses for others, three panels a row): the nominal map, the
lower band (5th percentile for QMC, nominal - 2 sigma for first order) and the relative
spread (upper - lower) / nominal [%]. Poses outside the workspace, or where no sample
gave a value, are blank. Axes in the CLI's units (mm, degrees), named as the map's.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ppm_stiffness.maps.result import QUANTITIES
from ppm_stiffness.maps.workspace import StiffnessMap
from ppm_stiffness.visuals.maps import (
    PER_ROW,
    ROW_HEIGHT,
    _levels,
    aspect_ratio,
    axis_grid,
    slice_label,
)


def plot_map_bands(smap: StiffnessMap, bands: Any) -> Any:
    """Figure: nominal, lower band and relative spread of each quantity of the map.

    Parameters
    ----------
    smap : StiffnessMap
        The nominal map (its grid and quantities).
    bands : Bands
        Of :func:`ppm_stiffness.fit.band_outputs.map_output` on that grid, arrays
        (n_quantities, nv, nu) in the map's quantity order.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    xs, ys, xlabel, ylabel = axis_grid(smap)
    panel = (ROW_HEIGHT - 1.0) * aspect_ratio(smap)
    names = list(smap.quantities)
    groups = [names[i : i + PER_ROW] for i in range(0, len(names), PER_ROW)]
    n_rows = 3 * len(groups)
    fig = Figure(figsize=(PER_ROW * (panel + 1.9), n_rows * ROW_HEIGHT + 0.6), layout="constrained")
    axes = fig.subplots(n_rows, PER_ROW, squeeze=False)
    nominal = np.asarray(bands.nominal, dtype=float)
    lower = np.asarray(bands.lower, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        spread = 100 * (np.asarray(bands.upper, dtype=float) - lower) / nominal
    rows = (
        ("nominal", nominal, None),
        (f"lower ({bands.label})", lower, None),
        ("relative spread (upper - lower) / nominal", spread, "%"),
    )
    for g, group in enumerate(groups):
        for r, (title, values, unit_override) in enumerate(rows):
            for c in range(PER_ROW):
                ax = axes[3 * g + r, c]
                if c >= len(group):
                    ax.set_axis_off()
                    continue
                name = group[c]
                unit, symbol = QUANTITIES[name][0], QUANTITIES[name][2]
                v = np.ma.masked_invalid(values[names.index(name)])
                if v.count():
                    cs = ax.contourf(xs, ys, v, levels=_levels(v), cmap="viridis")
                    cbar = fig.colorbar(cs, ax=ax, shrink=0.9)
                    cbar.set_label(f"{symbol} [{unit_override or unit}]")
                else:
                    ax.text(0.5, 0.5, "no value", ha="center", va="center", transform=ax.transAxes)
                ax.set_xlim(xs[0], xs[-1])
                ax.set_ylim(ys[0], ys[-1])
                ax.set_xlabel(xlabel)
                ax.set_ylabel(ylabel)
                ax.set_title(f"{symbol}: {title}", fontsize=9)
    label = slice_label(smap)
    fig.suptitle(
        "Principal stiffness with tolerances"
        + (f", {label}" if label else "")
        + f" ({bands.samples} model evaluations, {bands.failed} failed)"
    )
    return fig


__all__ = ["plot_map_bands"]
