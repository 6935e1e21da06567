"""Pictures of sweeps and optimisations: the convergence of ``optimize`` and the
figures of ``sweep`` (curves for one variable, a heat map for two).

Designs that do not cover the required region are drawn apart (grey crosses, or left
blank in a heat map): their figures are over the covered poses only.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike


def plot_convergence(
    history: Sequence[tuple[int, float]], objective: str, unit: str, maximise: bool
) -> Any:
    """Best feasible objective so far against design evaluations (a step curve).

    Parameters
    ----------
    history : sequence of (evaluations, best objective)
        From :class:`~ppm_stiffness.optimize.optimizer.OptimizationResult`.
    objective, unit : str
        Name and SI unit of the objective.
    maximise : bool
        Whether larger is better (for the axis label).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    n = np.array([h[0] for h in history], dtype=float)
    best = np.array([h[1] for h in history], dtype=float)
    fig = Figure(figsize=(6.0, 3.8), layout="constrained")
    ax = fig.subplots()
    ax.step(n, best, where="post", marker="o", ms=3)
    if np.isfinite(best[0]):
        ax.axhline(best[0], color="0.5", ls=":", lw=1, label="start design")
        ax.legend(loc="best", fontsize=8)
    ax.set_xlabel("design evaluations")
    ax.set_ylabel(f"{objective} [{unit}]")
    ax.set_title(f"best feasible {objective} so far ({'maximised' if maximise else 'minimised'})")
    ax.grid(True, alpha=0.3)
    return fig


def plot_sweep(
    points: ArrayLike,
    values: ArrayLike,
    covers: ArrayLike,
    names: Sequence[str],
    units: Sequence[str],
    quantity: str,
    quantity_unit: str,
    shape: tuple[int, ...] | None = None,
) -> Any:
    """One figure of a sweep: a curve for one variable, a heat map (grid) or a scatter
    (Sobol) for two.

    Parameters
    ----------
    points : array_like (n, n_variables)
        Variable values [their SI units].
    values : array_like (n,)
        The quantity of each design [quantity_unit].
    covers : array_like of bool (n,)
        Whether each design covers the region.
    names, units : sequence of str
        The variables' names and units.
    quantity, quantity_unit : str
    shape : tuple, optional
        Grid shape (n1, n2) for a heat map; None for a sample (scatter).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    p = np.asarray(points, dtype=float)
    v = np.asarray(values, dtype=float)
    ok = np.asarray(covers, dtype=bool)
    fig = Figure(figsize=(6.4, 4.4), layout="constrained")
    ax = fig.subplots()
    label = f"{quantity} [{quantity_unit}]"
    if p.shape[1] == 1:
        order = np.argsort(p[:, 0], kind="stable")
        x, y, c = p[order, 0], v[order], ok[order]
        ax.plot(x, np.where(c, y, np.nan), "-o", ms=3, label="covers the region")
        if np.any(~c):
            ax.plot(x[~c], y[~c], "x", color="0.5", label="does not cover it")
        ax.set_xlabel(f"{names[0]} [{units[0]}]")
        ax.set_ylabel(label)
        ax.legend(loc="best", fontsize=8)
        ax.grid(True, alpha=0.3)
    elif p.shape[1] == 2:
        if shape is not None:
            grid = np.where(ok, v, np.nan).reshape(shape)
            x = p[:, 0].reshape(shape)[:, 0]
            y = p[:, 1].reshape(shape)[0, :]
            mesh: Any = ax.pcolormesh(x, y, grid.T, shading="nearest", cmap="viridis")
        else:
            mesh = ax.scatter(p[ok, 0], p[ok, 1], c=v[ok], cmap="viridis", s=18)
            if np.any(~ok):
                ax.plot(p[~ok, 0], p[~ok, 1], "x", color="0.5", ms=4, label="does not cover")
                ax.legend(loc="best", fontsize=8)
        cbar = fig.colorbar(mesh, ax=ax)
        cbar.set_label(label)
        ax.set_xlabel(f"{names[0]} [{units[0]}]")
        ax.set_ylabel(f"{names[1]} [{units[1]}]")
    else:
        raise ValueError("a sweep picture shows one or two variables")
    ax.set_title(
        f"sweep: {quantity}" + ("" if np.all(ok) else " (blank/grey: region not covered)"),
        fontsize=10,
    )
    return fig


def plot_front(
    front: ArrayLike,
    feasible: ArrayLike,
    start: Sequence[float],
    chosen: int,
    names: Sequence[str],
    units: Sequence[str],
    maximise: Sequence[bool],
    rule: str,
    start_label: str = "start design",
) -> Any:
    """A Pareto front: for two objectives the front over the cloud of feasible designs
    evaluated, for more a scatter matrix of every pair; the start design (a star) and
    the chosen design (a ringed point) marked.

    Parameters
    ----------
    front : array_like (k, m)
        The front's objectives [their units], sorted by the first.
    feasible : array_like (n, m)
        The objectives of every feasible design evaluated [their units].
    start : sequence of float (m,)
        The start design's objectives.
    chosen : int
        Index in ``front`` of the chosen design.
    names, units : sequence of str (m,)
    maximise : sequence of bool (m,)
    rule : str
        How the design was chosen (the legend says it).
    start_label : str
        The start design's legend entry (e.g. saying that it is infeasible).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    f = np.asarray(front, dtype=float)
    cloud = np.asarray(feasible, dtype=float)
    s = np.asarray(start, dtype=float)
    m = f.shape[1]
    labels = [
        f"{n} [{u}] ({'max' if up else 'min'})"
        for n, u, up in zip(names, units, maximise, strict=True)
    ]
    if m == 2:
        fig = Figure(figsize=(6.4, 4.6), layout="constrained")
        ax = fig.subplots()
        _front_panel(ax, f, cloud, s, chosen, 0, 1, rule, m == 2, start_label)
        ax.set_xlabel(labels[0])
        ax.set_ylabel(labels[1])
        ax.set_title(_front_title(len(f), len(cloud)))
        ax.legend(loc="best", fontsize=8)
        return fig
    fig = Figure(figsize=(2.6 * (m - 1), 2.4 * (m - 1)), layout="constrained")
    axes = np.atleast_2d(fig.subplots(m - 1, m - 1, squeeze=False))
    for row in range(1, m):
        for col in range(m - 1):
            ax = axes[row - 1, col]
            if col >= row:
                ax.set_axis_off()
                continue
            _front_panel(ax, f, cloud, s, chosen, col, row, rule, False, start_label)
            if row == m - 1:
                ax.set_xlabel(labels[col], fontsize=8)
            if col == 0:
                ax.set_ylabel(labels[row], fontsize=8)
    handles, text = axes[-1, 0].get_legend_handles_labels()
    axes[0, -1].legend(handles, text, loc="center", fontsize=8)  # an empty panel
    fig.suptitle(_front_title(len(f), len(cloud)))
    return fig


def _front_title(front: int, feasible: int) -> str:
    return (
        f"Pareto front: {front} design{'' if front == 1 else 's'} of {feasible} feasible evaluated"
    )


def _front_panel(
    ax: Any,
    front: np.ndarray,
    cloud: np.ndarray,
    start: np.ndarray,
    chosen: int,
    i: int,
    j: int,
    rule: str,
    line: bool,
    start_label: str = "start design",
) -> None:
    """One panel of :func:`plot_front`: objective i across, j up."""
    ax.scatter(cloud[:, i], cloud[:, j], s=8, color="0.75", label="feasible designs")
    style = "-o" if line else "o"
    ax.plot(front[:, i], front[:, j], style, ms=4, lw=1, color="C0", label="front")
    ax.plot(start[i], start[j], "*", ms=12, color="C3", label=start_label)
    ax.plot(
        front[chosen, i],
        front[chosen, j],
        "o",
        ms=11,
        mfc="none",
        mew=1.8,
        color="C2",
        label=f"chosen ({rule})",
    )
    ax.grid(True, alpha=0.3)
    _large_ticks(ax.xaxis, np.concatenate([cloud[:, i], front[:, i], start[i : i + 1]]))
    _large_ticks(ax.yaxis, np.concatenate([cloud[:, j], front[:, j], start[j : j + 1]]))


def _large_ticks(axis: Any, values: np.ndarray) -> None:
    """Ticks with an SI prefix (50k, 5M) on an axis of values of 10^4 and more: an offset
    text (1e6) would sit on a neighbouring panel's label."""
    from matplotlib.ticker import EngFormatter

    finite = values[np.isfinite(values)]
    if finite.size and np.max(np.abs(finite)) >= 1e4:
        axis.set_major_formatter(EngFormatter(sep=""))
