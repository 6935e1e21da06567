"""Contour maps of the principal stiffnesses over a slice of the workspace (paper
Figures 6-7).

Rows of up to three panels per :class:`~ppm_stiffness.maps.result.StiffnessMap`, one
panel per quantity of the map in its order (k_phi, k_x, k_y for a planar design's map:
one row, the paper's layout; the rotational then the translational principal
stiffnesses of a spatial design's: two rows), the axes in the CLI's units (mm for
lengths, degrees for angles) with the map's axis names, colour bars in the quantities'
units with the scale in the unit (kN·m/rad, MN/m: no offset text,
:mod:`ppm_stiffness.visuals.ticks`), the fixed coordinates and the actuator state in
the title; a panel whose quantity varies by less than 5 % over the slice says so under
its title (its colours span the full range all the same). Poses outside the workspace
(masked) are left blank.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ppm_stiffness.maps.result import QUANTITIES
from ppm_stiffness.maps.slices import cli_scale
from ppm_stiffness.maps.workspace import StiffnessMap
from ppm_stiffness.visuals.ticks import SMALL_VARIATION, plain_formatter, scaled_unit, variation

#: (field, symbol, unit) of the paper's three panels.
PANELS = tuple((name, QUANTITIES[name][2], QUANTITIES[name][0]) for name in ("k_phi", "k_x", "k_y"))
#: Panels per row.
PER_ROW = 3
#: Height of one row of panels [inch]; the width follows the grid's aspect ratio.
ROW_HEIGHT = 4.0
#: Width added to each panel for its colour bar and labels [inch].
_PANEL_EXTRA = 1.9
#: Smallest figure width [inch] (the title of a one-panel map of a tall slice).
MIN_WIDTH = 5.5
#: Resolution of saved raster figures [dots per inch].
DPI = 150
_STATE_TEXT = {"max": "actuators locked (maximum)", "min": "actuators at minimum"}


#: What a hinge_range map shows (the drives as the design gives them, no load).
HINGE_RANGE_TEXT = "each drive alone (the others held, no load) until a hinge yields"


def _state_label(smap: StiffnessMap) -> str:
    if set(smap.quantities) == {"hinge_range"}:
        return HINGE_RANGE_TEXT
    if smap.actuators == "min" and smap.reference_force is not None:
        text = f"actuators at minimum ({smap.reference_force:g} N reference force)"
    elif smap.actuators == "wrench" and smap.wrench is not None:
        m, f = smap.wrench[:3], smap.wrench[3:]
        text = f"loaded: f = {np.round(f, 3).tolist()} N, m = {np.round(m, 3).tolist()} N·m"
    else:
        text = _STATE_TEXT.get(smap.actuators, smap.actuators)
    return text + ("; hinge range: " + HINGE_RANGE_TEXT if "hinge_range" in smap.quantities else "")


def slice_label(smap: StiffnessMap) -> str:
    """``"rz = 30°"``, ``"z = 200 mm, rx = 0°, ..."``: the fixed coordinates."""
    parts = []
    for name, value in smap.fixed.items():
        scale, unit = cli_scale(name)
        parts.append(f"{name} = {value * scale:.4g}" + ("°" if unit == "deg" else f" {unit}"))
    return ", ".join(parts)


def axis_grid(smap: StiffnessMap) -> tuple[np.ndarray, np.ndarray, str, str]:
    """The grid values in the CLI's units and the axis labels (``"x [mm]"``)."""
    (fa, ua), (fb, ub) = cli_scale(smap.axes[0]), cli_scale(smap.axes[1])
    return smap.u * fa, smap.v * fb, f"{smap.axes[0]} [{ua}]", f"{smap.axes[1]} [{ub}]"


def aspect_ratio(smap: StiffnessMap) -> float:
    """Width over height of a panel: the grid's (axes of one unit at the same scale),
    1 for axes of different units; within [0.5, 3]."""
    a, b, _, _ = axis_grid(smap)
    same = cli_scale(smap.axes[0])[1] == cli_scale(smap.axes[1])[1]
    return min(max(float(np.ptp(a) / np.ptp(b)) if same else 1.0, 0.5), 3.0)


def _levels(values: np.ma.MaskedArray, n: int = 14) -> Any:
    lo, hi = float(values.min()), float(values.max())
    if not np.isfinite(lo) or not np.isfinite(hi):
        return n
    if hi - lo <= 1e-9 * max(abs(hi), 1e-300):  # (nearly) constant: a thin band around it
        pad = max(abs(hi) * 1e-6, 1e-12)
        return np.linspace(lo - pad, hi + pad, 3)
    return np.linspace(lo, hi, n)


def rows_of(smap: StiffnessMap) -> int:
    """Rows of panels of one map."""
    return -(-len(smap.quantities) // PER_ROW)


def plot_stiffness_maps(
    smap: StiffnessMap | Sequence[StiffnessMap], title: str | None = None
) -> Any:
    """Figure with a contour map of each quantity of one or several maps.

    Parameters
    ----------
    smap : StiffnessMap or sequence of StiffnessMap
        E.g. ``[max_map, min_map]`` for the layout of Figure 6 (a)/(b).
    title : str, optional
        Figure title; by default the slice and actuator state.

    Returns
    -------
    matplotlib.figure.Figure
        ``ROW_HEIGHT`` inches per row of panels, panel widths following the grid's
        aspect ratio, constrained layout.
    """
    from matplotlib.figure import Figure

    maps = [smap] if isinstance(smap, StiffnessMap) else list(smap)
    if not maps:
        raise ValueError("no stiffness map to plot")
    panel = (ROW_HEIGHT - 1.0) * max(aspect_ratio(m) for m in maps)
    rows = [rows_of(m) for m in maps]
    cols = min(PER_ROW, max(len(m.quantities) for m in maps))  # one map of f1: one panel
    fig = Figure(
        # at least MIN_WIDTH: a one-panel map of a tall slice keeps its title whole
        figsize=(max(cols * (panel + _PANEL_EXTRA), MIN_WIDTH), ROW_HEIGHT * sum(rows) + 0.4),
        layout="constrained",
    )
    subfigs = fig.subfigures(len(maps), 1, squeeze=False, height_ratios=rows)[:, 0]
    for sub, m, n_rows in zip(subfigs, maps, rows, strict=True):
        xs, ys, xlabel, ylabel = axis_grid(m)
        axes = sub.subplots(n_rows, cols, squeeze=False).ravel()
        for ax in axes[len(m.quantities) :]:
            ax.set_axis_off()
        for ax, (name, values) in zip(axes, m.quantities.items(), strict=False):
            unit, symbol = m.unit(name), QUANTITIES[name][2]
            panel_title = symbol
            if np.any(m.reachable):
                levels = _levels(values)
                cs = ax.contourf(xs, ys, values, levels=levels, cmap="viridis")
                cbar = sub.colorbar(cs, ax=ax, shrink=0.9)
                # the scale in the unit, no offset text (visuals.ticks)
                factor, shown = scaled_unit(float(np.ma.max(np.abs(values))), unit)
                step = float(np.min(np.diff(cbar.get_ticks()))) if len(cbar.get_ticks()) > 1 else 0
                cbar.formatter = plain_formatter(factor, step)
                cbar.set_label(f"{symbol} [{shown}]")
                cbar.update_ticks()
                var = variation(values)
                if var < SMALL_VARIATION:
                    panel_title += f"\nvariation {100 * var:.2g} % over the slice"
            else:
                ax.text(
                    0.5, 0.5, "no reachable pose", ha="center", va="center", transform=ax.transAxes
                )
            ax.set_xlim(xs[0], xs[-1])
            ax.set_ylim(ys[0], ys[-1])
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
            ax.set_title(panel_title, fontsize=11)
        label = slice_label(m)
        sub.suptitle((f"{label}, " if label else "") + _state_label(m), fontsize=10)
    names = {n for m in maps for n in m.quantities}
    default = (
        "Hinge range (the smallest drive's, to yield)"
        if names == {"hinge_range"}
        else "Principal stiffness"
        if "f1" not in names
        else "First natural frequency"
        if names == {"f1"}
        else "Stiffness and first natural frequency"
    )
    fig.suptitle(title if title is not None else f"{default} over the workspace")
    return fig


def save_map_figure(fig: Any, path: str | Path, dpi: int = DPI) -> Path:
    """Save ``fig`` (format from the suffix: .png, .svg, .pdf) at exactly its figure size
    (``figsize * dpi`` pixels for PNG) and release it."""
    p = Path(path)
    fig.savefig(p, dpi=dpi)
    return p
