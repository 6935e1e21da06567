"""3-D view of a spatial parallel manipulator at a pose: what the model contains.

Drawn from the same leg geometry as the planar top view
(:mod:`ppm_stiffness.visuals.leg_geometry`: each leg's inverse kinematics, joint chain,
base feature and limits), in the base frame F_b, millimetres, equal scale on the three
axes:

- the **base** polygon through the legs' base points (U or R pivots, rail origins) and
  each leg's **rail** for a base prismatic joint: the line from its origin (marked x,
  actuator coordinate 0) along the rail, dotted, a light band over the actuator stroke
  with ticks at its ends (a P-R-S tripod's columns);
- each leg's **links** as bars, one style per link name (``cylinder``, ``rod``,
  ``link``, ...) and thin grey lines where two of its points are joined without a link
  (not along its rail, which is drawn);
- its **joints**, one symbol per kind at the joint's point: revolute R a white circle
  with a black bar along its axis; universal U a white cross with black bars along its
  two axes e1, e2; spherical S a ball in the leg's colour; prismatic P a square with a
  slider bar along its axis; cylindrical C a diamond with a black sleeve; the actuated
  joint has a gold ring;
- the **platform** polygon through the legs' platform points (B1..Bn or D1..Dn,
  counter-clockwise about the platform's z axis), its reference point **P** with the
  platform axes x_p, y_p, z_p (the columns of R), the **tool point** T (``p + R t``,
  dashed from P) when the design has one, and the base axes x_b, y_b, z_b at O;
- the name of each point with its leg number (A1, C1, B1, ...), "leg i" at each base
  point.

The title names the design, the pose (its task coordinates, then the parasitic
coordinates the legs impose), each joint coordinate of every leg, and, at a pose
outside the legs' limits (``mechanism --allow-unreachable``), every violated limit;
a leg whose inverse kinematics has no solution is not drawn (its base feature is) and
is named.

Every artist is a 3-D line with a gid, so the plotted data can be read back with
``line.get_data_3d()`` (mm, F_b): ``platform`` and ``base-polygon`` (closed rings),
``base-<i>`` (the rail line or the pivot), ``stroke-<i>`` (the rail over the stroke),
``link-<i>-<j>`` (the j-th link of leg i, from 1), ``joint-<i>-<j>`` (the j-th joint:
one point), ``joint-axis-<i>-<j>-<k>`` (its bar along axis k = 1 (e1), 2 (e2)),
``rigid-<i>-<k>`` (points k and k+1 of leg i without a link), ``P``, ``tool``,
``frame-b-<x|y|z>``, ``frame-p-<x|y|z>`` (from the origin along the axis).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.chain import frame_from_axis
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.visuals.leg_geometry import (
    JointView,
    LegView,
    MechanismView,
    platform_order,
    title_text,
)
from ppm_stiffness.visuals.mechanism import LEG_COLOURS, LINK_STYLES, link_label

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MM = 1e3

Once = Callable[[str], "str | None"]


def _labeller() -> Once:
    labelled: set[str] = set()

    def once(label: str) -> str | None:
        if label in labelled:
            return None
        labelled.add(label)
        return label

    return once


def _normal(u: FloatArray) -> FloatArray:
    """A unit vector normal to ``u`` (the joint-frame convention's e2)."""
    return np.asarray(frame_from_axis(u)[1])


def _clipped(seg: FloatArray, clip: tuple[FloatArray, FloatArray] | None) -> FloatArray | None:
    """The part of the segment ``seg`` (2, 3) inside the box ``clip``, or None."""
    if clip is None:
        return seg
    from ppm_stiffness.visuals.springs import clip_segment

    return clip_segment(seg[0], seg[1], clip[0], clip[1])


def _inside(point: FloatArray, clip: tuple[FloatArray, FloatArray] | None) -> bool:
    return clip is None or bool(np.all(point >= clip[0]) and np.all(point <= clip[1]))


def _on_rail(view: LegView, a: FloatArray, b: FloatArray) -> bool:
    """Both points on the leg's rail line (the carriage's travel, drawn as the rail)."""
    if view.base.kind != "rail":
        return False
    u = np.asarray(view.base.axis, dtype=float)
    o = np.asarray(view.base.point, dtype=float)
    span = max(float(np.linalg.norm(b - a)), 1e-3)
    return all(float(np.linalg.norm(np.cross(q - o, u))) <= 1e-9 * span for q in (a, b))


def _is_link(view: LegView, a: FloatArray, b: FloatArray) -> bool:
    for link in view.links:
        tol = 1e-9 * max(float(np.linalg.norm(link.end - link.start)), 1e-3)
        for s, e in ((link.start, link.end), (link.end, link.start)):
            if np.allclose(a, s, rtol=0, atol=tol) and np.allclose(b, e, rtol=0, atol=tol):
                return True
    return False


def best_azimuth(view: MechanismView, candidates: Any = None) -> float:
    """The azimuth [deg] that best separates the legs on screen: the one that maximises
    the smallest horizontal distance, seen from that azimuth, between two legs' points
    of the same name (base, carriage, platform point); ties go to the first candidate
    (default -58, -62, -54, ... deg over [-90, -20] deg, the classic oblique view
    first)."""
    if candidates is None:
        steps = np.arange(0.0, 36.0, 4.0)
        candidates = [-58.0] + [a for s in steps[1:] for a in (-58.0 - s, -58.0 + s) if a >= -90]
    legs = [v for v in view.legs if v.solvable]
    best, score = float(candidates[0]), -1.0
    for azim in candidates:
        a = np.radians(azim)
        h = np.array([-np.sin(a), np.cos(a), 0.0])  # the screen's horizontal axis
        gap = np.inf
        for m, u in enumerate(legs):
            for w in legs[m + 1 :]:
                for name in u.points.keys() & w.points.keys():
                    gap = min(gap, abs(float((u.points[name] - w.points[name]) @ h)))
        if gap > score + 1e-9:
            best, score = float(azim), gap
    return best


def view_extent(view: MechanismView) -> tuple[FloatArray, FloatArray]:
    """The box (lo, hi) (3,) [m] of everything the 3-D view draws (F_b), no margin."""
    cloud = [view.centre[None], np.zeros((1, 3)), view.platform, view.tool[None]]
    for v in view.legs:
        base = v.base
        cloud.append(np.asarray(base.point, dtype=float)[None])
        if base.kind == "rail" and base.stroke is not None:
            u = np.asarray(base.axis, dtype=float)
            ends = [min(0.0, base.stroke[0]), max(0.0, base.stroke[1])]
            cloud.append(np.asarray(base.point) + np.outer(ends, u))
        if v.solvable:
            cloud.append(np.array(list(v.points.values())))
    allp = np.vstack(cloud)
    return allp.min(axis=0), allp.max(axis=0)


def draw_mechanism_3d(
    ax: Any,
    view: MechanismView,
    unit: float,
    origin: FloatArray | None = None,
    *,
    clip: tuple[FloatArray, FloatArray] | None = None,
    bases: bool = True,
    legs: bool = True,
    labels: bool = True,
    once: Once | None = None,
    fade: float = 1.0,
) -> None:
    """Draw the legs, base and platform of ``view`` into a 3-D axes (module doc).

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.Axes3D
    view : MechanismView
    unit : float
        Size of the joint bars and ticks [mm].
    origin : ndarray (3,), optional
        Drawn at the origin of the axes [m, F_b] (P for the screw-spring picture,
        whose axes are relative to P); default O.
    clip : (lo, hi), optional
        A box [mm, relative to ``origin``]: links, rails and joints outside it are cut
        or left out.
    bases : bool
        Draw the base polygon and the base features (rails, pivots).
    legs : bool
        Draw the legs (links, joints); else the platform (and base) only.
    labels : bool
        Name every point (A1, C1, B1, ...) and the legs, and give the joints and rails
        legend entries; else name the platform points only, and only the platform,
        the base and the links are in the legend (a backdrop).
    once : callable, optional
        ``once(label)``: the label the first time, None after (shared legend entries).
    fade : float
        Factor on the opacity of everything drawn (a backdrop: < 1).
    """
    first = (len(ax.get_lines()), len(ax.texts), len(ax.collections))
    _draw(ax, view, unit, origin, clip, bases, legs, labels, once or _labeller())
    if fade != 1.0:
        new = ax.get_lines()[first[0] :] + ax.texts[first[1] :] + ax.collections[first[2] :]
        for artist in new:
            artist.set_alpha(fade * (artist.get_alpha() or 1.0))


def _draw(
    ax: Any,
    view: MechanismView,
    unit: float,
    origin: FloatArray | None,
    clip: tuple[FloatArray, FloatArray] | None,
    bases: bool,
    legs: bool,
    labels: bool,
    once: Once,
) -> None:
    """:func:`draw_mechanism_3d` without the fading."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    o = np.zeros(3) if origin is None else np.asarray(origin, dtype=float)
    minor: Once = once if labels else (lambda _label: None)  # joints, rails

    def at(point: Any) -> FloatArray:
        return (np.asarray(point, dtype=float) - o) * MM

    # the platform polygon (filled, then its outline)
    order = view.platform_order
    poly = at(view.platform[order])
    ring = np.vstack([poly, poly[:1]])
    ax.add_collection3d(Poly3DCollection([poly], facecolor="0.75", alpha=0.3, edgecolor="none"))
    names = [view.legs[k].platform_name for k in order]
    label = "platform " + "-".join(names)
    if len(label) > PLATFORM_LABEL_LENGTH:  # long point names (a chain leg's elements)
        label = f"platform {names[0]}-...-{names[-1]}"
    ax.plot(*ring.T, color="0.15", lw=2.0, gid="platform", label=label)
    if bases and not view.design.planar and len(view.legs) >= 3:
        pts = np.array([v.base.point for v in view.legs], dtype=float)
        border = platform_order(pts - pts.mean(axis=0), np.zeros(3))
        base = at(pts[border])
        ring = np.vstack([base, base[:1]])
        ax.add_collection3d(
            Poly3DCollection([base], facecolor="0.55", alpha=0.18, edgecolor="none")
        )
        ax.plot(*ring.T, color="0.45", lw=1.5, ls="-", gid="base-polygon", label="base")

    link_names: list[str] = []
    for v in view.legs:
        i = v.index
        col = LEG_COLOURS[(i - 1) % len(LEG_COLOURS)]
        if bases:
            _draw_base(ax, v, col, unit, at, minor)
        if labels:
            ax.text(
                *at(v.base.point) + _outward(view, v, 1.6 * unit),
                f"leg {i}",
                fontsize=8,
                color=col,
                fontweight="bold",
                ha="center",
                va="center",
            )
        if not legs:
            ax.text(*at(v.platform_point), f" {v.platform_name}", fontsize=7, color="0.2")
            continue
        if not v.solvable:
            continue
        named = list(v.points.values())
        for k in range(len(named) - 1):
            a, b = named[k], named[k + 1]
            if _is_link(v, a, b) or _on_rail(v, a, b):
                continue
            seg = _clipped(np.stack([at(a), at(b)]), clip)
            if seg is not None:
                ax.plot(
                    *seg.T,
                    color="0.35",
                    lw=1.2,
                    gid=f"rigid-{i}-{k + 1}",
                    label=minor("rigid connection (a rigid body: no compliance)"),
                )
        for j, link in enumerate(v.links, start=1):
            if link.name not in link_names:
                link_names.append(link.name)
            style = LINK_STYLES[link_names.index(link.name) % len(LINK_STYLES)]
            seg = _clipped(np.stack([at(link.start), at(link.end)]), clip)
            if seg is None:
                continue
            ax.plot(
                *seg.T,
                color=col if style["lw"] > 5 else "0.1",
                gid=f"link-{i}-{j}",
                label=once(link_label(link.name)),
                **style,
            )
        for j, joint in enumerate(v.joints, start=1):
            if _inside(at(joint.point), clip):
                _draw_joint(ax, joint, i, j, col, unit, at, minor)
        if labels:
            for name, pt in v.points.items():
                if float(np.linalg.norm(pt - view.centre)) < AT_ORIGIN:
                    continue  # a leg fixed at P (a Tricept's central tube): "P" marks it
                ax.text(*at(pt), f" {name}{i}", fontsize=7, color="0.15")
        else:
            ax.text(*at(v.platform_point), f" {v.platform_name}", fontsize=7, color="0.2")


def _outward(view: MechanismView, v: LegView, distance: float) -> FloatArray:
    """An offset [mm] of ``distance`` in the base plane, from the base's centre
    towards the leg's base point (where its "leg i" label goes)."""
    pts = np.array([w.base.point for w in view.legs], dtype=float)
    d = np.asarray(v.base.point, dtype=float) - pts.mean(axis=0)
    d[2] = 0.0
    n = float(np.linalg.norm(d))
    return np.zeros(3) if n == 0.0 else distance * d / n


def _draw_base(
    ax: Any, v: LegView, col: str, unit: float, at: Callable[[Any], FloatArray], once: Once
) -> None:
    """A rail (dotted line from its origin, band over the stroke, end ticks) or a
    pivot (a dot at the base point) [mm]."""
    base = v.base
    a = np.asarray(base.point, dtype=float)
    i = v.index
    if base.kind != "rail":
        ax.plot(*at(a)[:, None], marker=".", ms=4, color="0.3", ls="", gid=f"base-{i}")
        return
    u = np.asarray(base.axis, dtype=float)
    stroke = base.stroke or (0.0, 0.0)
    ends = np.array([min(0.0, stroke[0]), max(0.0, stroke[1])])
    line = np.stack([at(a + s * u) for s in ends])
    ax.plot(*line.T, color=col, ls=":", lw=1.2, alpha=0.8, gid=f"base-{i}")
    ax.plot(
        *at(a)[:, None],
        marker="x",
        ms=6,
        color=col,
        ls="",
        label=once("rail origin (actuator coordinate 0)"),
    )
    if base.stroke is None:
        return
    band = np.stack([at(a + s * u) for s in base.stroke])
    ax.plot(
        *band.T,
        color=col,
        lw=6.0,
        alpha=0.3,
        solid_capstyle="butt",
        gid=f"stroke-{i}",
        label=once("rail over the actuator stroke"),
    )
    nrm = _normal(u) * 0.4 * unit
    for e in band:
        ax.plot(*np.stack([e - nrm, e + nrm]).T, color=col, lw=1.5)


def _draw_joint(
    ax: Any,
    joint: JointView,
    i: int,
    j: int,
    col: str,
    unit: float,
    at: Callable[[Any], FloatArray],
    once: Once,
) -> None:
    """A joint's symbol at its point (its kind's record): bars along its axes, ring if
    actuated [mm]."""
    kind = joint_kind(joint.kind)
    q = at(joint.point)
    if kind.bar is not None:
        colour, width = kind.bar.colour, kind.bar.width
        axes = [joint.axis] + ([joint.axis2] if joint.axis2 is not None else [])
        half = kind.bar.half * unit
        for k, e in enumerate(axes, start=1):
            seg = np.stack([q - half * e, q + half * e])
            ax.plot(
                *seg.T,
                color=colour or col,
                lw=width,
                alpha=0.85,
                solid_capstyle="butt",
                gid=f"joint-axis-{i}-{j}-{k}",
            )
    face = col if kind.filled else "w"
    ax.plot(
        *q[:, None],
        marker=kind.marker,
        ms=kind.size_3d,
        mfc=face,
        mec="k",
        mew=1.0,
        ls="",
        gid=f"joint-{i}-{j}",
        label=once(kind.legend),
    )
    if joint.actuated:
        ax.plot(
            *q[:, None],
            marker="o",
            ms=17,
            mfc="none",
            mec="gold",
            mew=2.5,
            ls="",
            label=once("actuated joint"),
        )


def _draw_frames(ax: Any, view: MechanismView, length: float) -> None:
    """Base axes at O (grey) and platform axes (R's columns) at P (black) [mm]; the base
    axes' labels beyond the platform's when P is within an axis' length of O (a wrist),
    so that they stay clear of the platform's; P at O is labelled "P = O" alone, and O
    is not labelled where a leg's base joint sits on it (a Tricept's central U: its own
    label marks the point)."""
    close = float(np.linalg.norm(view.centre * MM)) < length
    for name, origin, axes, col, at in (
        ("b", np.zeros(3), np.eye(3), "0.45", 1.7 if close else 1.15),
        ("p", view.centre * MM, view.rotation, "k", 1.15),
    ):
        for k, lab in enumerate("xyz"):
            tip = origin + length * axes[:, k]
            ax.plot(*np.stack([origin, tip]).T, color=col, lw=1.6, gid=f"frame-{name}-{lab}")
            ax.text(*(origin + at * length * axes[:, k]), f"${lab}_{name}$", color=col, fontsize=9)
    joint_at_o = any(float(np.linalg.norm(v.base.point)) < AT_ORIGIN for v in view.legs)
    if float(np.linalg.norm(view.centre)) >= AT_ORIGIN and not joint_at_o:  # else "P = O"
        ax.text(0.0, 0.0, 0.0, "O ", color="0.45", fontsize=9, ha="right", va="top")


def plot_mechanism_3d(
    view: MechanismView,
    title: str | None = None,
    ax: Any = None,
    elev: float = 22.0,
    azim: float | None = None,
) -> Figure:
    """3-D view of the manipulator at one pose (module doc).

    Parameters
    ----------
    view : MechanismView
        From :func:`ppm_stiffness.visuals.leg_geometry.mechanism_view`.
    title : str, optional
        First lines of the title (default: the design name and the pose).
    ax : Axes3D, optional
        Draw into this 3-D axes instead of a new figure.
    elev, azim : float
        The view's elevation and azimuth [deg]; by default the azimuth that best
        separates the legs on screen (:func:`best_azimuth`).

    Returns
    -------
    matplotlib.figure.Figure
        One 3-D axes in mm (F_b), equal scale on x, y and z.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        fig = plt.figure(figsize=(11.0, 9.0))
        ax = fig.add_subplot(projection="3d")
    else:
        fig = ax.figure
    lo, hi = view_extent(view)
    span = float(np.max(hi - lo)) * MM
    unit = 0.05 * span
    once = _labeller()
    draw_mechanism_3d(ax, view, unit, once=once)
    _draw_frames(ax, view, 2.0 * unit)
    p = view.centre * MM
    ax.plot(
        *p[:, None],
        marker="+",
        ms=12,
        mew=2.0,
        color="k",
        ls="",
        gid="P",
        label=POINT_LEGEND,
    )
    at_o = float(np.linalg.norm(view.centre)) < AT_ORIGIN
    ax.text(*p, "  P = O" if at_o else "  P", fontsize=9)
    if view.has_tool:
        t = view.tool * MM
        ax.plot(*np.stack([p, t]).T, color="goldenrod", lw=1.2, ls="--", gid="tool-offset")
        ax.plot(
            *t[:, None],
            marker="*",
            ms=14,
            mfc="gold",
            mec="k",
            ls="",
            gid="tool",
            label="tool point T",
        )
        ax.text(*t, "  T", fontsize=9)

    margin = 0.08 * span
    lo_mm, hi_mm = lo * MM - margin, hi * MM + margin
    ax.set_xlim3d(lo_mm[0], hi_mm[0])
    ax.set_ylim3d(lo_mm[1], hi_mm[1])
    ax.set_zlim3d(lo_mm[2], hi_mm[2])
    ax.set_box_aspect(tuple(hi_mm - lo_mm))  # equal scale: the box has the data's shape
    ax.set_xlabel("x [mm] (F_b)", fontsize=9)
    ax.set_ylabel("y [mm] (F_b)", fontsize=9)
    ax.set_zlabel("z [mm] (F_b)", fontsize=9)
    ax.tick_params(labelsize=8)
    ax.view_init(elev=elev, azim=best_azimuth(view) if azim is None else azim)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, framealpha=0.9)
    ax.set_title(
        title_text(view, title, width=100),
        fontsize=9,
        color="tab:red" if view.violations else "k",
    )
    declutter_labels(ax)
    return fig


#: Distance [m] of P from O below which the picture labels them as one point.
AT_ORIGIN = 1e-9
#: Longest legend entry of the platform polygon listing its points by name [characters].
PLATFORM_LABEL_LENGTH = 40
#: The legend's name of the platform point P (not a joint: the prismatic joint's
#: legend says "type letter P").
POINT_LEGEND = "P: platform point (origin of F_p)"
#: Where a label may sit about its point (ha, va), in order of preference.
_PLACEMENTS = (
    ("left", "bottom"),
    ("right", "bottom"),
    ("left", "top"),
    ("right", "top"),
    ("center", "bottom"),
    ("center", "top"),
)


def label_boxes(ax: Any) -> list[tuple[Any, Any]]:
    """Each text of a 3-D axes with its box on screen (display pixels) as drawn: its
    3-D position projected with the axes' current view, then its alignment."""
    from matplotlib.transforms import Bbox
    from mpl_toolkits.mplot3d import proj3d

    fig = ax.figure
    fig.canvas.draw()  # the layout and the projection ax.M as they will be drawn
    renderer = fig.canvas.get_renderer()
    out = []
    for t in ax.texts:
        if not t.get_visible() or not t.get_text().strip():
            continue
        out.append((t, _box(t, ax, renderer, proj3d, Bbox)))
    return out


def _box(t: Any, ax: Any, renderer: Any, proj3d: Any, bbox: Any) -> Any:
    """The box (display) of 3-D text ``t`` at its alignment."""
    x, y, z = t.get_position_3d()
    xs, ys, _ = proj3d.proj_transform(x, y, z, ax.M)
    px, py = ax.transData.transform((xs, ys))
    ext = t.get_window_extent(renderer)
    w, h = ext.width, ext.height
    x0 = {"left": px, "right": px - w, "center": px - w / 2}[t.get_ha()]
    y0 = {"bottom": py, "top": py - h, "center": py - h / 2, "baseline": py}.get(t.get_va(), py)
    return bbox.from_bounds(x0, y0, w, h)


#: Half the side [px] of the box a joint's marker takes on screen for the labels.
MARKER_HALF = 4.0


def marker_boxes(ax: Any) -> list[Any]:
    """The screen boxes (display pixels) of the single-point markers of a 3-D axes
    (joints, P, T): :data:`MARKER_HALF` about each projected point."""
    from matplotlib.transforms import Bbox
    from mpl_toolkits.mplot3d import proj3d

    out = []
    for line in ax.get_lines():
        if line.get_marker() in (None, "None", "", " "):
            continue
        xs, ys, zs = (np.atleast_1d(c) for c in line.get_data_3d())
        if xs.size != 1:
            continue
        u, v, _ = proj3d.proj_transform(xs[0], ys[0], zs[0], ax.M)
        px, py = ax.transData.transform((u, v))
        out.append(
            Bbox.from_bounds(px - MARKER_HALF, py - MARKER_HALF, 2 * MARKER_HALF, 2 * MARKER_HALF)
        )
    return out


def _anchor(t: Any, ax: Any) -> tuple[float, float]:
    from mpl_toolkits.mplot3d import proj3d

    x, y, z = t.get_position_3d()
    u, v, _ = proj3d.proj_transform(x, y, z, ax.M)
    px, py = ax.transData.transform((u, v))
    return float(px), float(py)


def declutter_labels(ax: Any) -> int:
    """Move colliding labels of a 3-D axes to another side of their point.

    Labels are placed in drawing order; one whose box overlaps a placed one tries the
    alignments of :data:`_PLACEMENTS` (a leading space to the left of its point, a
    trailing one to the right) and keeps the first that overlaps none. Returns the
    number of labels that still overlap another label or a marker (0 when all are
    apart). The other points' markers (:func:`marker_boxes`) are obstacles as well."""
    from matplotlib.transforms import Bbox
    from mpl_toolkits.mplot3d import proj3d

    boxes = label_boxes(ax)
    renderer = ax.figure.canvas.get_renderer()
    markers = marker_boxes(ax)
    placed: list[Any] = []
    left = 0
    for t, box in boxes:
        px, py = _anchor(t, ax)
        # the other points' markers are obstacles too (not the label's own point)
        obstacles = placed + [m for m in markers if not m.contains(px, py)]
        if any(box.overlaps(b) for b in obstacles):
            word, ha0, va0 = t.get_text(), t.get_ha(), t.get_va()
            core = word.strip()
            for ha, va in _PLACEMENTS:
                t.set_text({"left": " " + core, "right": core + " "}.get(ha, core))
                t.set_ha(ha)
                t.set_va(va)
                box = _box(t, ax, renderer, proj3d, Bbox)
                if not any(box.overlaps(b) for b in obstacles):
                    break
            else:  # no free side: as it was
                t.set_text(word)
                t.set_ha(ha0)
                t.set_va(va0)
                box = _box(t, ax, renderer, proj3d, Bbox)
                left += 1
        placed.append(box)
    return left


__all__ = [
    "POINT_LEGEND",
    "declutter_labels",
    "draw_mechanism_3d",
    "label_boxes",
    "plot_mechanism_3d",
    "view_extent",
]
