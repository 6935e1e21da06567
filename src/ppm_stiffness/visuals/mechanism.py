"""Top view of a P-P-R manipulator at a pose: what the model contains.

Drawn in the base frame F_b, in millimetres, equal aspect:

- base points A_i (ground triangles) and the rail of each actuator: the line through
  A_i along u_i, solid over the actuator stroke inside the view, dotted beyond;
- the carriage: from the rail point A_i + (rho_i + guide_offset_u) u_i to the guide
  block B_i (square), where the five guide springs act;
- the proximal link B_i-C_i (thick), the bearing at C_i (a short sleeve along w_i);
- the rod C_i-D_i (the free length that bends), the platform triangle D1-D2-D3,
  its centre P and the platform frame F_p; the base frame F_b at the origin;
- leg numbers next to A_i.

Artists carry gids (``platform``, ``rail-<i>``, ``proximal-<i>``, ``rod-<i>``) so
the plotted data can be read back. The title reports the actuator coordinates and rod
lengths, and says if the pose is outside the strokes or rod-length ranges.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.design import Design
from ppm_stiffness.model import workspace_centre

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MM = 1e3
LEG_COLOURS = ("tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:cyan")


def mechanism_points(design: Design, pose: ArrayLike) -> dict[str, FloatArray]:
    """Absolute points of every leg at one pose (F_b, [m]).

    Returns
    -------
    dict
        ``A``, ``B``, ``C``, ``D``, ``R`` (rail point under the carriage), ``u``, ``w``:
        arrays (n_legs, 2); ``P``: (2,); ``rho`` and ``rod``: (n_legs,) [m].
    """
    p = np.asarray(pose, dtype=float)
    geoms = [leg.solve(p) for leg in design.legs]
    pos = p[:2]
    a = np.array([leg.base_point for leg in design.legs], dtype=float)
    u = np.array([leg.directions()[0][:2] for leg in design.legs])
    w = np.array([leg.directions()[1][:2] for leg in design.legs])
    rho = np.array([float(g.coordinates["rho"]) for g in geoms])
    gu = np.array([leg.guide_offset_u for leg in design.legs])
    return {
        "A": a,
        "B": np.array([g.points["B"][:2] for g in geoms]) + pos,
        "C": np.array([g.points["C"][:2] for g in geoms]) + pos,
        "D": np.array([g.points["D"][:2] for g in geoms]) + pos,
        "R": a + (rho + gu)[:, None] * u,
        "u": u,
        "w": w,
        "P": pos.copy(),
        "rho": rho,
        "rod": np.array([float(g.coordinates["rod"]) for g in geoms]),
    }


def _reachability_note(design: Design, pts: dict[str, FloatArray]) -> str:
    bad = []
    for i, leg in enumerate(design.legs):
        if not leg.stroke[0] <= pts["rho"][i] <= leg.stroke[1]:
            bad.append(f"leg {i + 1} outside its stroke")
        if not leg.rod_length_range[0] <= pts["rod"][i] <= leg.rod_length_range[1]:
            bad.append(f"leg {i + 1} rod length out of range")
    return "UNREACHABLE: " + ", ".join(bad) if bad else ""


def _rail_extent(
    a: FloatArray, u: FloatArray, lo: FloatArray, hi: FloatArray
) -> tuple[float, float]:
    """Parameter interval of the line a + s u inside the box [lo, hi] (2D)."""
    s0, s1 = -np.inf, np.inf
    for j in range(2):
        if abs(u[j]) < 1e-12:
            continue
        t = sorted(((lo[j] - a[j]) / u[j], (hi[j] - a[j]) / u[j]))
        s0, s1 = max(s0, t[0]), min(s1, t[1])
    return float(s0), float(s1)


def plot_mechanism(
    design: Design,
    pose: ArrayLike | None = None,
    title: str | None = None,
    ax: Any = None,
) -> Figure:
    """Top view of the manipulator at ``pose`` (F_b, mm, equal aspect).

    Parameters
    ----------
    design : Design
    pose : array_like, shape (3,), optional
        (x [m], y [m], phi [rad]); default the workspace centre. An unreachable pose
        is drawn all the same and flagged in the title.
    title : str, optional
    ax : matplotlib Axes, optional
        Draw into this axes instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    pts = mechanism_points(design, p)
    if ax is None:
        fig = plt.figure(figsize=(9.0, 8.0))
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    n = len(design.legs)
    a, b, c, d, r = (pts[k] * MM for k in ("A", "B", "C", "D", "R"))
    u, w = pts["u"], pts["w"]
    centre = pts["P"] * MM
    allp = np.vstack([a, b, c, d, r, centre[None], np.zeros((1, 2))])
    span = float(np.max(allp.max(axis=0) - allp.min(axis=0)))
    lo, hi = allp.min(axis=0) - 0.12 * span, allp.max(axis=0) + 0.12 * span
    unit = 0.06 * span  # size of frame arrows and sleeves [mm]

    # platform
    ax.add_patch(Polygon(d, closed=True, facecolor="0.85", edgecolor="0.15", lw=2.0,
                         zorder=3, label="platform D1-D2-D3", gid="platform"))
    for i in range(n):
        col = LEG_COLOURS[i % len(LEG_COLOURS)]
        leg = design.legs[i]
        # rail: dotted over the view, solid over the stroke
        s0, s1 = _rail_extent(a[i], u[i], lo, hi)
        ends = a[i] + np.outer([s0, s1], u[i])
        ax.plot(*ends.T, color=col, ls=":", lw=1.0, alpha=0.7, zorder=1, gid=f"rail-{i + 1}")
        st0, st1 = max(s0, leg.stroke[0] * MM), min(s1, leg.stroke[1] * MM)
        if st0 < st1:
            seg = a[i] + np.outer([st0, st1], u[i])
            ax.plot(*seg.T, color=col, lw=4.0, alpha=0.25, solid_capstyle="butt", zorder=1,
                    label="rail (actuator stroke)" if i == 0 else None)
        for s_end in leg.stroke:
            if s0 <= s_end * MM <= s1:
                e = a[i] + s_end * MM * u[i]
                nrm = np.array([-u[i][1], u[i][0]]) * 0.3 * unit
                ax.plot(*np.stack([e - nrm, e + nrm]).T, color=col, lw=1.5, zorder=2)
        # base point
        ax.scatter(*a[i], marker="^", s=90, color=col, edgecolor="k", zorder=5,
                   label="base point A" if i == 0 else None)
        ax.annotate(f"leg {i + 1}\nA{i + 1}", a[i], xytext=(8, -22), textcoords="offset points",
                    fontsize=9, color=col, fontweight="bold")
        # carriage: rail point -> guide block B
        ax.plot(*np.stack([r[i], b[i]]).T, color="0.35", lw=1.5, zorder=2,
                label="carriage" if i == 0 else None)
        ax.scatter(*r[i], marker="|", s=120, color="0.35", zorder=4)
        ax.scatter(*b[i], marker="s", s=70, color=col, edgecolor="k", zorder=5,
                   label="guide block B" if i == 0 else None)
        ax.annotate(f"B{i + 1}", b[i], xytext=(5, 5), textcoords="offset points", fontsize=8)
        # proximal link B -> C
        ax.plot(*np.stack([b[i], c[i]]).T, color=col, lw=5.0, alpha=0.55, gid=f"proximal-{i + 1}",
                solid_capstyle="round", zorder=3, label="proximal link B-C" if i == 0 else None)
        # bearing sleeve at C along w
        sleeve = np.stack([c[i] - 0.5 * unit * w[i], c[i] + 0.5 * unit * w[i]])
        ax.plot(*sleeve.T, color="k", lw=7.0, alpha=0.8, solid_capstyle="butt", zorder=4,
                label="bearing C" if i == 0 else None)
        ax.annotate(f"C{i + 1}", c[i], xytext=(5, -12), textcoords="offset points", fontsize=8)
        # rod C -> D
        ax.plot(*np.stack([c[i], d[i]]).T, color="0.1", lw=1.8, zorder=4, gid=f"rod-{i + 1}",
                label="rod C-D" if i == 0 else None)
        ax.scatter(*d[i], marker="o", s=30, color="w", edgecolor="k", zorder=6)
        out = d[i] - centre
        out = 14.0 * out / max(float(np.linalg.norm(out)), 1e-12)
        ax.annotate(f"D{i + 1}", d[i], xytext=tuple(out), textcoords="offset points",
                    fontsize=8, ha="center", va="center")

    # platform frame at P and base frame at O
    phi = float(p[2])
    rot = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    frames = [(centre, rot, "p", "k")]
    if float(np.linalg.norm(centre)) > 0.5 * unit:  # F_b apart from F_p
        frames.insert(0, (np.zeros(2), np.eye(2), "b", "0.5"))
        ax.annotate("O", (0.0, 0.0), xytext=(-10, -10), textcoords="offset points",
                    fontsize=9, color="0.5")
    for origin, axes, name, col in frames:
        for j, lab in enumerate(("x", "y")):
            ax.annotate("", origin + unit * axes[:, j], origin,
                        arrowprops={"arrowstyle": "-|>", "color": col, "lw": 1.2}, zorder=7)
            ax.annotate(f"${lab}_{name}$", origin + 1.15 * unit * axes[:, j], fontsize=9,
                        color=col, ha="center", va="center")
    ax.scatter(*centre, marker="+", s=80, color="k", zorder=8)
    at_origin = float(np.linalg.norm(centre)) <= 0.5 * unit
    ax.annotate("P = O" if at_origin else "P", centre, xytext=(-8, -12),
                textcoords="offset points", fontsize=9, ha="right")

    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (F_b)")
    ax.set_ylabel("y [mm] (F_b)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8, framealpha=0.9)
    note = _reachability_note(design, pts)
    head = title or (
        f"{design.name}\npose x = {p[0] * MM:.2f} mm, y = {p[1] * MM:.2f} mm, "
        f"phi = {np.degrees(p[2]):.2f} deg"
    )
    joints = ", ".join(
        f"rho{i + 1} = {pts['rho'][i] * MM:.1f}" for i in range(n)
    ) + " mm; rods " + ", ".join(f"{x * MM:.1f}" for x in pts["rod"]) + " mm"
    ax.set_title(head + "\n" + joints + (f"\n{note}" if note else ""), fontsize=9,
                 color="tab:red" if note else "k")
    return fig
