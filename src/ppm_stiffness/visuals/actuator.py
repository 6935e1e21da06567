"""Figure of an actuator force-displacement fit (data and the fitted eq. 20)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.statics.actuator_fit import PowerLawFit, power_law_force


def plot_actuator_fit(
    displacement_m: ArrayLike,
    force_n: ArrayLike,
    fit: PowerLawFit,
    reference: tuple[float, float] | None = None,
    title: str = "actuator force-displacement",
    reference_label: str = "reference",
) -> Any:
    """Data and fitted law, on linear axes (left) and log-log axes (right).

    Parameters
    ----------
    displacement_m, force_n : array_like, shape (n,)
        The data [m, N] (plotted in mm and N).
    fit : PowerLawFit
    reference : (k_a, q), optional
        Another law to draw for comparison (e.g. the design's), dashed.
    title : str
    reference_label : str
        Legend name of ``reference``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    d = np.asarray(displacement_m, dtype=float)
    g = np.asarray(force_n, dtype=float)
    ad = np.abs(d[d != 0])
    lo, hi = (float(ad.min()), float(ad.max())) if ad.size else (1e-6, 1e-3)
    grid = np.geomspace(lo / 1.5, hi * 1.5, 300)
    fig = Figure(figsize=(10, 4), layout="constrained")
    axes = fig.subplots(1, 2)
    label = (
        f"fit: k_a = {fit.k_a:.4g} ± {fit.k_a_std:.2g} N/m^q, "
        f"q = {fit.q:.4f} ± {fit.q_std:.4f}, R² = {fit.r_squared:.4f}"
    )
    for ax, log in zip(axes, (False, True), strict=True):
        ax.plot(np.abs(d) * 1e3, np.abs(g), "o", ms=4, label=f"data (n = {fit.n})")
        ax.plot(grid * 1e3, power_law_force(grid, fit.k_a, fit.q), "-", label=label)
        if reference is not None:
            ax.plot(
                grid * 1e3,
                power_law_force(grid, *reference),
                "--",
                label=f"{reference_label}: k_a = {reference[0]:.4g}, q = {reference[1]:.4g}",
            )
        ax.set_xlabel("actuator displacement |δ| [mm]")
        ax.set_ylabel("force |G| [N]")
        ax.grid(True, which="both", alpha=0.3)
        if log:
            ax.set_xscale("log")
            ax.set_yscale("log")
    axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle(title)
    return fig
