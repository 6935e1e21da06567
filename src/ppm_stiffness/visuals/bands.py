"""Uncertainty bands in pictures: stiffness maps of the lower band and of the relative
spread (the band of :func:`ppm_stiffness.fit.uncertainty.propagate` over a map's grid).

Three rows of k_phi, k_x, k_y panels: the nominal map, the lower band (5th percentile
for QMC, nominal - 2 sigma for first order) and the relative spread (upper - lower) /
nominal [%]. Poses outside the workspace, or where no sample gave a value, are blank.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ppm_stiffness.maps.workspace import StiffnessMap
from ppm_stiffness.visuals.maps import PANELS, ROW_HEIGHT, _levels


def plot_map_bands(smap: StiffnessMap, bands: Any) -> Any:
    """Figure: nominal, lower band and relative spread of k_phi, k_x, k_y.

    Parameters
    ----------
    smap : StiffnessMap
        The nominal map (its grid).
    bands : Bands
        Of :func:`ppm_stiffness.fit.band_outputs.map_output` on that grid, arrays
        (3, ny, nx).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    xs, ys = smap.x * 1e3, smap.y * 1e3
    aspect = min(max(float(np.ptp(smap.x) / np.ptp(smap.y)), 0.5), 3.0)
    panel = (ROW_HEIGHT - 1.0) * aspect
    fig = Figure(figsize=(3 * (panel + 1.9), 3 * ROW_HEIGHT + 0.6), layout="constrained")
    axes = fig.subplots(3, 3, squeeze=False)
    nominal = np.asarray(bands.nominal, dtype=float)
    lower = np.asarray(bands.lower, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        spread = 100 * (np.asarray(bands.upper, dtype=float) - lower) / nominal
    rows = (
        ("nominal", nominal, None),
        (f"lower ({bands.label})", lower, None),
        ("relative spread (upper - lower) / nominal", spread, "%"),
    )
    for r, (title, values, unit_override) in enumerate(rows):
        for c, (_, symbol, unit) in enumerate(PANELS):
            ax = axes[r, c]
            v = np.ma.masked_invalid(values[c])
            if v.count():
                cs = ax.contourf(xs, ys, v, levels=_levels(v), cmap="viridis")
                cbar = fig.colorbar(cs, ax=ax, shrink=0.9)
                cbar.set_label(f"{symbol} [{unit_override or unit}]")
            else:
                ax.text(0.5, 0.5, "no value", ha="center", va="center", transform=ax.transAxes)
            ax.set_xlim(xs[0], xs[-1])
            ax.set_ylim(ys[0], ys[-1])
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_title(f"{symbol}: {title}", fontsize=9)
    fig.suptitle(
        f"Principal stiffness with tolerances, φ = {np.degrees(smap.phi):.4g}° "
        f"({bands.samples} model evaluations, {bands.failed} failed)"
    )
    return fig


__all__ = ["plot_map_bands"]
