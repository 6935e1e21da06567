"""Picture of a parallel manipulator at a pose: what the model contains.

:func:`plot_mechanism` draws a planar design as a top view (this module) and a spatial
one in 3-D (:mod:`ppm_stiffness.visuals.mechanism3d`); both draw the same leg geometry
(:mod:`ppm_stiffness.visuals.leg_geometry`: points, joints with their kinds and axes,
links, base features and violated limits). The top view works for every planar leg
type: everything drawn comes from the legs' inverse kinematics
(:meth:`~ppm_stiffness.legs.base.LegModel.solve`), joint chains
(:meth:`~ppm_stiffness.legs.base.LegModel.chain`), base features
(:meth:`~ppm_stiffness.legs.base.LegModel.base_feature`) and limits. Drawn in the base
frame F_b, in millimetres, equal aspect:

- the **base feature** of each leg: a rail (the line through its origin along its
  direction, dotted across the view, a light band over the actuator stroke with ticks
  at its ends) for a base prismatic joint; a pivot (a ground triangle) for a base
  revolute, with an arc over the actuated angle's stroke when it is the actuator;
- the leg's named points joined in order (thin grey: rigid connections such as a
  carriage, where no link is modelled) and its **links** as bars, one style per link
  name (``proximal``, ``distal``, ...);
- its **joints**, one symbol per kind: revolute R a white circle, prismatic P a
  square with a slider bar along its axis, cylindrical C a diamond with a sleeve along
  its axis; the actuated joint has a gold ring;
- the **platform** polygon D1..Dn, its centre **P** with the platform axes x_p, y_p,
  the tool point T when the design has one, the base axes x_b, y_b at O (omitted when
  P is at O), and the name of each point with its leg number.

The title gives the pose and the joint coordinates of every leg; at a pose outside
the legs' limits (:meth:`~ppm_stiffness.legs.base.LegModel.limits`) it says which limit
each leg violates, and a leg whose inverse kinematics has no solution is not drawn
(its base feature is) and is named.

Artists carry gids so the plotted data can be read back (mm): ``platform`` (polygon),
``base-<i>`` (rail line or pivot), ``stroke-<i>`` (stroke band or arc),
``link-<i>-<j>`` (the j-th link of leg i, from 1), ``joint-<i>-<j>`` (the j-th joint),
``rigid-<i>-<k>`` (points k to k+1 of leg i joined without a link), ``P`` and
``tool``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import BaseFeature
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.visuals.leg_geometry import (
    JointView,
    LegView,
    LinkView,
    MechanismView,
    limit_violations,
    mechanism_view,
    platform_order,
    title_text,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MM = 1e3
LEG_COLOURS = ("tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:cyan")
#: Styles of the links, by the order in which their names first appear.
LINK_STYLES: tuple[dict[str, Any], ...] = (
    {"lw": 6.0, "alpha": 0.55, "solid_capstyle": "round"},
    {"lw": 2.2, "alpha": 0.95, "solid_capstyle": "round"},
    {"lw": 3.5, "alpha": 0.75, "solid_capstyle": "round", "ls": "--"},
)


def link_label(name: str) -> str:
    """A link's legend entry, ``"rod link"``; a link named "link" (or nothing) is
    ``"link"``."""
    return "link" if name in ("", "link") else f"{name} link"


def mechanism_legs(design: Design, pose: ArrayLike | None = None) -> list[LegView]:
    """Every leg of ``design`` at one pose (task coordinates or a full pose [m, rad]),
    reachable or not (:func:`~ppm_stiffness.visuals.leg_geometry.mechanism_view`)."""
    return mechanism_view(design, pose).legs


def _line_extent(
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


def _stroke_points(base: BaseFeature, radius: float) -> FloatArray | None:
    """The drawn stroke [m]: the rail segment (2, 2), or an arc (n, 2) of ``radius``."""
    if base.stroke is None:
        return None
    a = np.asarray(base.point, dtype=float)[:2]
    if base.kind == "rail":
        u = np.asarray(base.axis, dtype=float)[:2]
        return np.asarray(a + np.outer(base.stroke, u))
    t = np.linspace(base.stroke[0], base.stroke[1], 60)
    return np.asarray(a + radius * np.stack([np.cos(t), np.sin(t)], axis=-1))


def plot_mechanism(
    design: Design,
    pose: ArrayLike | None = None,
    title: str | None = None,
    ax: Any = None,
) -> Figure:
    """The manipulator at ``pose``: a top view of a planar design (F_b, mm, equal aspect;
    module doc), a 3-D view of a spatial one
    (:func:`ppm_stiffness.visuals.mechanism3d.plot_mechanism_3d`).

    Parameters
    ----------
    design : Design
        Any architecture.
    pose : array_like, shape (n_task,) or (6,), optional
        The design's task coordinates ((x [m], y [m], phi [rad]) for a planar design) or
        a full pose (x, y, z [m], rx, ry, rz [rad]); default the home pose. An
        unreachable pose is drawn all the same and flagged in the title; legs without
        an inverse-kinematics solution are left out and named.
    title : str, optional
        First lines of the title (default: the design name and the pose).
    ax : matplotlib Axes, optional
        Draw into this axes instead of a new figure (a 3-D axes for a spatial design).

    Returns
    -------
    matplotlib.figure.Figure
    """
    view = mechanism_view(design, pose)
    if not design.planar:
        from ppm_stiffness.visuals.mechanism3d import plot_mechanism_3d

        return plot_mechanism_3d(view, title, ax)
    return plot_top_view(view, title, ax)


def plot_top_view(view: MechanismView, title: str | None = None, ax: Any = None) -> Figure:
    """Top view of ``view`` (module doc): x-y of F_b [mm]."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    views = view.legs
    if ax is None:
        fig = plt.figure(figsize=(11.0, 8.0))
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    centre = view.centre[:2] * MM
    tool = view.tool[:2] * MM
    has_tool = view.has_tool

    # the view: every point, base feature and stroke, P and O
    pivot_r = 0.5 * float(np.max(np.linalg.norm(view.platform - view.centre, axis=1)))
    cloud = [centre[None], np.zeros((1, 2))]
    for v in views:
        cloud.append(np.asarray(v.base.point)[None, :2] * MM)
        st = _stroke_points(v.base, pivot_r)
        if st is not None:
            cloud.append(st * MM)
        if v.solvable:
            cloud.append(np.array(list(v.points.values()))[:, :2] * MM)
    if has_tool:
        cloud.append(tool[None])
    allp = np.vstack(cloud)
    span = float(np.max(allp.max(axis=0) - allp.min(axis=0)))
    lo, hi = allp.min(axis=0) - 0.1 * span, allp.max(axis=0) + 0.1 * span
    unit = 0.05 * span  # size of frame arrows, sliders and sleeves [mm]

    # platform polygon (the legs' platform points, counter-clockwise around P)
    d_all = view.platform[:, :2] * MM
    order = view.platform_order
    ax.add_patch(
        Polygon(
            d_all[order],
            closed=True,
            facecolor="0.85",
            edgecolor="0.15",
            lw=2.0,
            zorder=3,
            gid="platform",
            label="platform " + "-".join(f"D{k + 1}" for k in order),
        )
    )

    labelled: set[str] = set()

    def once(label: str) -> str | None:
        if label in labelled:
            return None
        labelled.add(label)
        return label

    link_names: list[str] = []
    for v in views:
        i = v.index
        col = LEG_COLOURS[(i - 1) % len(LEG_COLOURS)]
        _draw_base(ax, v.base, i, col, lo, hi, unit, pivot_r * MM, once)
        # "leg i" beside the base feature, away from P
        a = np.asarray(v.base.point)[:2] * MM
        out = a - centre
        out = 24.0 * out / max(float(np.linalg.norm(out)), 1e-12)
        ax.annotate(
            f"leg {i}",
            a,
            xytext=tuple(out),
            textcoords="offset points",
            fontsize=9,
            color=col,
            fontweight="bold",
            ha="center",
            va="center",
            zorder=9,
        )
        if not v.solvable:
            continue
        pts = np.array(list(v.points.values()))[:, :2] * MM
        rigid = [k for k in range(len(pts) - 1) if not _is_link(pts[k], pts[k + 1], v.links)]
        for k in rigid:
            ax.plot(
                *pts[k : k + 2].T,
                color="0.35",
                lw=1.3,
                zorder=2,
                gid=f"rigid-{i}-{k + 1}",
                label=once("rigid connection (a rigid body: no compliance)"),
            )
        for j, link in enumerate(v.links, start=1):
            if link.name not in link_names:
                link_names.append(link.name)
            style = LINK_STYLES[link_names.index(link.name) % len(LINK_STYLES)]
            seg = np.stack([link.start[:2], link.end[:2]]) * MM
            colour = col if style["lw"] > 5 else "0.1"
            ax.plot(
                *seg.T,
                color=colour,
                zorder=4,
                gid=f"link-{i}-{j}",
                label=once(link_label(link.name)),
                **style,
            )
        for j, joint in enumerate(v.joints, start=1):
            _draw_joint(ax, joint, i, j, col, unit, once)
        for name, pt in v.points.items():
            q = pt[:2] * MM
            rel = q - centre
            off = (
                (7.0, 7.0)
                if name != "D"
                else tuple(14.0 * rel / max(float(np.linalg.norm(rel)), 1e-12))
            )
            ax.annotate(
                f"{name}{i}",
                q,
                xytext=off,
                textcoords="offset points",
                fontsize=7,
                color="0.15",
                ha="center",
                va="center",
                zorder=9,
            )

    _draw_frames(ax, view.rotation[:2, :2], centre, unit)
    ax.scatter(*centre, marker="+", s=90, color="k", zorder=8, gid="P", label="P")
    if has_tool:
        ax.scatter(
            *tool,
            marker="*",
            s=110,
            color="gold",
            edgecolor="k",
            zorder=8,
            gid="tool",
            label="tool point T",
        )
        ax.annotate("T", tool, xytext=(7, -9), textcoords="offset points", fontsize=9)

    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (F_b)")
    ax.set_ylabel("y [mm] (F_b)")
    ax.grid(True, alpha=0.3)
    ax.legend(
        loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, framealpha=0.9, borderaxespad=0.0
    )
    ax.set_title(
        title_text(view, title),
        fontsize=9,
        color="tab:red" if view.violations else "k",
    )
    return fig


def _is_link(a: FloatArray, b: FloatArray, links: list[LinkView]) -> bool:
    """Whether the segment a-b [mm, F_b, x-y] is one of the links (either way round)."""
    for link in links:
        s = link.start[:2] * MM
        e = link.end[:2] * MM
        tol = 1e-9 * max(float(np.linalg.norm(e - s)), 1.0)
        if (np.allclose(a, s, atol=tol) and np.allclose(b, e, atol=tol)) or (
            np.allclose(a, e, atol=tol) and np.allclose(b, s, atol=tol)
        ):
            return True
    return False


def _draw_base(
    ax: Any,
    base: BaseFeature,
    i: int,
    col: str,
    lo: FloatArray,
    hi: FloatArray,
    unit: float,
    pivot_r: float,
    once: Any,
) -> None:
    """A rail (line across the view, stroke band, end ticks) or a pivot (and arc) [mm]."""
    a = np.asarray(base.point, dtype=float)[:2] * MM
    stroke = _stroke_points(base, pivot_r / MM)
    if base.kind == "rail":
        u = np.asarray(base.axis, dtype=float)[:2]
        s0, s1 = _line_extent(a, u, lo, hi)
        ax.plot(
            *(a + np.outer([s0, s1], u)).T,
            color=col,
            ls=":",
            lw=1.0,
            alpha=0.7,
            zorder=1,
            gid=f"base-{i}",
        )
        ax.scatter(
            *a,
            marker="x",
            s=25,
            color=col,
            zorder=2,
            label=once("rail origin (actuator coordinate 0)"),
        )
        if stroke is not None:
            seg = stroke * MM
            ax.plot(
                *seg.T,
                color=col,
                lw=5.0,
                alpha=0.3,
                solid_capstyle="butt",
                zorder=1,
                gid=f"stroke-{i}",
                label=once("rail over the actuator stroke"),
            )
            nrm = np.array([-u[1], u[0]]) * 0.3 * unit
            for e in seg:
                ax.plot(*np.stack([e - nrm, e + nrm]).T, color=col, lw=1.5, zorder=2)
        return
    ax.scatter(
        *a,
        marker="^",
        s=160,
        color=col,
        edgecolor="k",
        hatch="///",
        zorder=5,
        gid=f"base-{i}",
        label=once("base pivot"),
    )
    if stroke is not None:
        arc = stroke * MM
        ax.plot(
            *arc.T,
            color=col,
            lw=4.0,
            alpha=0.35,
            solid_capstyle="butt",
            zorder=1,
            gid=f"stroke-{i}",
            label=once("actuated angle's stroke"),
        )
        for e in (arc[0], arc[-1]):
            r = (e - a) / max(float(np.linalg.norm(e - a)), 1e-12) * 0.3 * unit
            ax.plot(*np.stack([e - r, e + r]).T, color=col, lw=1.5, zorder=2)


def _draw_joint(
    ax: Any, joint: JointView, i: int, j: int, col: str, unit: float, once: Any
) -> None:
    """A joint's symbol at its point [mm] (its kind's record): slider/sleeve along the
    axis, ring if actuated."""
    kind = joint_kind(joint.kind)
    q = joint.point[:2] * MM
    e = joint.axis[:2]
    if kind.slides and kind.bar is not None and float(np.linalg.norm(e)) > 1e-9:
        e = e / np.linalg.norm(e)
        half = kind.bar.half * unit
        bar = np.stack([q - half * e, q + half * e])
        ax.plot(
            *bar.T,
            color=kind.bar.colour or col,
            lw=kind.bar.width,
            alpha=0.8,
            solid_capstyle="butt",
            zorder=5,
        )
    ax.scatter(
        *q,
        marker=kind.marker,
        s=kind.size_2d,
        color=col if kind.filled else "w",
        edgecolor="k",
        linewidth=1.0,
        zorder=6 if kind.filled else 7,
        gid=f"joint-{i}-{j}",
        label=once(kind.label),
    )
    if joint.actuated:
        ax.scatter(
            *q,
            marker="o",
            s=330,
            facecolor="none",
            edgecolor="gold",
            linewidth=2.5,
            zorder=5,
            label=once("actuated joint"),
        )


def _draw_frames(ax: Any, rot: FloatArray, centre: FloatArray, unit: float) -> None:
    """Platform axes (the columns of ``rot`` (2, 2)) at P and base axes at O (when
    apart) [mm]."""
    frames = [(centre, rot, "p", "k")]
    if float(np.linalg.norm(centre)) > 0.5 * unit:
        frames.insert(0, (np.zeros(2), np.eye(2), "b", "0.5"))
        ax.annotate(
            "O", (0.0, 0.0), xytext=(-10, -10), textcoords="offset points", fontsize=9, color="0.5"
        )
    for origin, axes, name, col in frames:
        for j, lab in enumerate(("x", "y")):
            ax.annotate(
                "",
                origin + unit * axes[:, j],
                origin,
                arrowprops={"arrowstyle": "-|>", "color": col, "lw": 1.2},
                zorder=7,
            )
            ax.annotate(
                f"${lab}_{name}$",
                origin + 1.2 * unit * axes[:, j],
                fontsize=9,
                color=col,
                ha="center",
                va="center",
            )
    at_origin = float(np.linalg.norm(centre)) <= 0.5 * unit
    ax.annotate(
        "P = O" if at_origin else "P",
        centre,
        xytext=(-8, -12),
        textcoords="offset points",
        fontsize=9,
        ha="right",
    )


__all__ = [
    "LegView",
    "limit_violations",
    "mechanism_legs",
    "mechanism_view",
    "platform_order",
    "plot_mechanism",
    "plot_top_view",
]
