"""Contour maps of the principal stiffnesses over the workspace (paper Figures 6-7).

One row of three panels (k_phi, k_x, k_y) per :class:`~ppm_stiffness.maps.workspace.StiffnessMap`,
positions in mm, colour bars in N·m/rad and N/m. Poses outside the workspace (masked)
are left blank.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ppm_stiffness.maps.workspace import StiffnessMap

#: (field, symbol, unit) of the three panels.
PANELS = (
    ("k_phi", r"$k_\phi$", "N·m/rad"),
    ("k_x", r"$k_x$", "N/m"),
    ("k_y", r"$k_y$", "N/m"),
)
#: Height of one row of panels [inch]; the width follows the workspace's aspect ratio.
ROW_HEIGHT = 4.0
#: Width added to each panel for its colour bar and labels [inch].
_PANEL_EXTRA = 1.9
#: Resolution of saved raster figures [dots per inch].
DPI = 150
_STATE_TEXT = {"max": "actuators locked (maximum)", "min": "actuators at minimum"}


def _state_label(smap: StiffnessMap) -> str:
    if smap.actuators == "min" and smap.reference_force is not None:
        return f"actuators at minimum ({smap.reference_force:g} N reference force)"
    if smap.actuators == "wrench" and smap.wrench is not None:
        m, f = smap.wrench[:3], smap.wrench[3:]
        return f"loaded: f = {np.round(f, 3).tolist()} N, m = {np.round(m, 3).tolist()} N·m"
    return _STATE_TEXT.get(smap.actuators, smap.actuators)


def _levels(values: np.ma.MaskedArray, n: int = 14) -> Any:
    lo, hi = float(values.min()), float(values.max())
    if not np.isfinite(lo) or not np.isfinite(hi):
        return n
    if hi - lo <= 1e-9 * max(abs(hi), 1e-300):  # (nearly) constant: a thin band around it
        pad = max(abs(hi) * 1e-6, 1e-12)
        return np.linspace(lo - pad, hi + pad, 3)
    return np.linspace(lo, hi, n)


def plot_stiffness_maps(
    smap: StiffnessMap | Sequence[StiffnessMap], title: str | None = None
) -> Any:
    """Figure with k_phi, k_x and k_y contour maps of one or several maps (one row each).

    Parameters
    ----------
    smap : StiffnessMap or sequence of StiffnessMap
        E.g. ``[max_map, min_map]`` for the layout of Figure 6 (a)/(b).
    title : str, optional
        Figure title; by default the orientation and actuator state.

    Returns
    -------
    matplotlib.figure.Figure
        ``ROW_HEIGHT`` inches per row, panel widths following the grid's aspect
        ratio (x and y at about the same scale), constrained layout.
    """
    from matplotlib.figure import Figure

    maps = [smap] if isinstance(smap, StiffnessMap) else list(smap)
    if not maps:
        raise ValueError("no stiffness map to plot")
    aspect = max(float(np.ptp(m.x) / np.ptp(m.y)) for m in maps)
    panel = (ROW_HEIGHT - 1.0) * min(max(aspect, 0.5), 3.0)
    fig = Figure(
        figsize=(3 * (panel + _PANEL_EXTRA), ROW_HEIGHT * len(maps) + 0.4),
        layout="constrained",
    )
    subfigs = fig.subfigures(len(maps), 1, squeeze=False)[:, 0]
    for sub, m in zip(subfigs, maps, strict=True):
        xs, ys = m.x * 1e3, m.y * 1e3
        axes = sub.subplots(1, 3)
        for ax, (name, symbol, unit) in zip(axes, PANELS, strict=True):
            values = m.fields()[name]
            if np.any(m.reachable):
                cs = ax.contourf(xs, ys, values, levels=_levels(values), cmap="viridis")
                cbar = sub.colorbar(cs, ax=ax, shrink=0.9)
                cbar.set_label(f"{symbol} [{unit}]")
                cbar.formatter.set_powerlimits((-3, 4))
                cbar.update_ticks()
            else:
                ax.text(
                    0.5, 0.5, "no reachable pose", ha="center", va="center", transform=ax.transAxes
                )
            ax.set_xlim(xs[0], xs[-1])
            ax.set_ylim(ys[0], ys[-1])
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_title(symbol, fontsize=11)
        sub.suptitle(f"φ = {np.degrees(m.phi):.4g}°, {_state_label(m)}", fontsize=10)
    fig.suptitle(title if title is not None else "Principal stiffness over the workspace")
    return fig


def save_map_figure(fig: Any, path: str | Path, dpi: int = DPI) -> Path:
    """Save ``fig`` (format from the suffix: .png, .svg, .pdf) at exactly its figure size
    (``figsize * dpi`` pixels for PNG) and release it."""
    p = Path(path)
    fig.savefig(p, dpi=dpi)
    return p
