"""The six screw springs of a stiffness matrix in 3D (the paper's Figure 5).

Each screw spring ``s_i`` (:mod:`ppm_stiffness.core.eigenscrews`) is drawn as

- a straight segment along its axis ``e_i`` centred on its position ``p_i`` (the
  point of the axis nearest P), the *spring axis*;
- a helix wound around that segment: right-handed for a positive pitch, left-handed
  for a negative one; its radius and colour grow with the spring constant ``k_i``;
- a label ``s_i`` with ``k_i`` [kN/m] and the pitch ``h_i`` [mm/rad].

The mechanism at the same pose is the backdrop, drawn from the same leg geometry as
the mechanism pictures (:mod:`ppm_stiffness.visuals.leg_geometry`,
:func:`ppm_stiffness.visuals.mechanism3d.draw_mechanism_3d`): the platform polygon and
each leg's links and joints (by kind), any architecture. A planar design lies in the
plane z = 0, its legs clipped to the box around the springs (its rails and guide
blocks may lie far out); a spatial design is drawn whole, with its base and rails.
Everything is relative to P (or the tool point T, where K is given) with the axes of
F_b, in millimetres, like the stiffness matrix; the axis labels (``x − x_P [mm]``) and
the title ("drawn relative to P ... with the axes of F_b") say so: the mechanism
picture is in F_b.

The spring-axis lines carry the gid ``"spring-axis-<i>"`` and the helices
``"spring-helix-<i>"`` (i from 1) so that tests and users can read back the plotted
data (``line.get_data_3d()``, mm).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.eigenscrews import ScrewSprings
from ppm_stiffness.design import Design

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MM = 1e3  # drawing unit: millimetre per metre
#: gid prefix of the drawn spring axes
AXIS_GID = "spring-axis-"
#: gid prefix of the drawn helices
HELIX_GID = "spring-helix-"


def spring_axis_segments(springs: ScrewSprings, length: float) -> FloatArray:
    """End points of the drawn spring axes: ``p_i -+ length/2 e_i``.

    Parameters
    ----------
    springs : ScrewSprings
        positions (6, 3) [m] from P and unit axes (6, 3), F_b.
    length : float
        Drawn length of each axis [m].

    Returns
    -------
    ndarray, shape (6, 2, 3) [m]
        Start and end point of each segment, relative to P in F_b.
    """
    p = np.asarray(springs.positions, dtype=float)
    e = np.asarray(springs.axes, dtype=float)
    e = e / np.linalg.norm(e, axis=1, keepdims=True)
    return np.stack([p - 0.5 * length * e, p + 0.5 * length * e], axis=1)


def helix_points(
    position: ArrayLike,
    axis: ArrayLike,
    length: float,
    radius: float,
    pitch_sign: float,
    turns: float = 5.0,
    samples: int = 240,
) -> FloatArray:
    """Points of a helix around the axis through ``position`` along ``axis``.

    The helix advances from ``position - length/2 axis`` to ``position + length/2 axis``
    while turning ``turns`` times about ``axis``: positively (right-handed) when
    ``pitch_sign >= 0``, negatively (left-handed) otherwise.

    Returns
    -------
    ndarray, shape (samples, 3)
        In the units of ``position``, ``length`` and ``radius``.
    """
    p = np.asarray(position, dtype=float)
    e = np.asarray(axis, dtype=float)
    e = e / np.linalg.norm(e)
    # any unit vector normal to e, then the right-handed frame (a, b, e)
    trial = np.array([1.0, 0.0, 0.0]) if abs(e[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    a = np.cross(trial, e)
    a /= np.linalg.norm(a)
    b = np.cross(e, a)
    t = np.linspace(0.0, 2.0 * np.pi * turns, samples)
    s = -0.5 * length + length * t / t[-1]
    hand = 1.0 if pitch_sign >= 0 else -1.0
    return np.asarray(
        p + s[:, None] * e + radius * (np.cos(t)[:, None] * a + hand * np.sin(t)[:, None] * b)
    )


def _finite_constants(k: FloatArray) -> FloatArray:
    finite = np.isfinite(k)
    top = float(np.max(k[finite])) if finite.any() else 1.0
    return np.where(finite, k, top)


def clip_segment(
    p0: FloatArray, p1: FloatArray, lo: FloatArray, hi: FloatArray
) -> FloatArray | None:
    """The part of segment p0-p1 inside the box [lo, hi] (Liang-Barsky), or None."""
    t0, t1 = 0.0, 1.0
    delta = p1 - p0
    for j in range(len(lo)):
        for q_sign, bound in ((-1.0, lo[j]), (1.0, hi[j])):
            num = q_sign * (bound - p0[j])
            den = q_sign * delta[j]
            if den == 0.0:
                if num < 0.0:
                    return None
                continue
            t = num / den
            if den < 0.0:
                t0 = max(t0, t)
            else:
                t1 = min(t1, t)
    if t0 > t1:
        return None
    return np.stack([p0 + t0 * delta, p0 + t1 * delta])


def plot_screw_springs(
    springs: ScrewSprings,
    design: Design | None = None,
    pose: ArrayLike | None = None,
    length: float | None = None,
    title: str | None = None,
    show_legs: bool = True,
    tool_point: ArrayLike | None = None,
) -> Figure:
    """3D picture of the six screw springs, with the platform and legs in place.

    Parameters
    ----------
    springs : ScrewSprings
        From :func:`ppm_stiffness.core.eigenscrews.eigenscrews` of a matrix at P (F_b).
    design : Design, optional
        Draws its mechanism at ``pose`` (module doc): a planar design's platform and
        legs in the plane z = 0, clipped to the box around the springs (the guide
        blocks may lie outside); a spatial design's base, legs and platform whole.
    pose : array_like, shape (n_task,) or (6,), optional
        The design's task coordinates ((x [m], y [m], phi [rad]) for a planar design)
        or a full pose [m, rad]; default the home pose. The springs must be those of
        K at this pose (their positions are relative to P).
    length : float, optional
        Drawn length of each spring [m]; default 2.5 times the largest distance from
        P to a leg's platform point (the platform radius: 75 mm for the paper's
        machine), 75 mm without a design.
    title : str, optional
    show_legs : bool
        Draw the legs (links and joints) as well as the platform.
    tool_point : array_like (3,), optional
        The point of the platform K is given at (platform frame [m]), where the
        springs' positions start: the picture's origin. Default P.

    Returns
    -------
    matplotlib.figure.Figure
        One 3D axes in mm, origin the point K is given at (P by default; the tool
        point T, marked, otherwise); spring axes have gid ``spring-axis-<i>``; the
        mechanism's artists carry the gids of
        :mod:`ppm_stiffness.visuals.mechanism3d` (relative to P). The legend marks the
        springs of a repeated eigenvalue ("repeated with s2"): inside such a group they
        are one valid choice (:mod:`ppm_stiffness.core.eigenscrews`).
    """
    import matplotlib.pyplot as plt
    from matplotlib import colors as mcolors

    from ppm_stiffness.visuals.leg_geometry import mechanism_view
    from ppm_stiffness.visuals.mechanism3d import draw_mechanism_3d, view_extent

    view = None if design is None else mechanism_view(design, pose)
    # the origin of the picture: the point of K, in F_b (P, or the tool point)
    t = np.zeros(3) if tool_point is None else np.asarray(tool_point, dtype=float)
    origin = np.zeros(3) if view is None else view.centre + view.rotation @ t
    if length is None:
        length = (
            2.5 * float(np.max(np.linalg.norm(view.platform - view.centre, axis=1)))
            if view is not None
            else 0.075
        )
    k = np.asarray(springs.spring_constants, dtype=float)
    kf = _finite_constants(k)
    norm = mcolors.Normalize(vmin=0.0, vmax=float(np.max(kf)) / 1e3)
    cmap = plt.get_cmap("viridis")
    r_max = 0.08 * length * MM
    segments = spring_axis_segments(springs, length) * MM

    # the box shown: springs, P, the platform and, for a planar design, each leg's
    # point before the platform (the bearing C of a P-P-R, the elbow of an R-R-R); a
    # spatial design whole; plus a margin
    pts = [segments.reshape(-1, 3), np.zeros((1, 3))]
    if view is not None:
        pts.append((np.vstack([view.platform, view.centre]) - origin) * MM)
        if not view.design.planar:
            pts.append((np.stack(view_extent(view)) - origin) * MM)
        elif show_legs:
            solved = [v for v in view.legs if v.solvable]
            pts += [np.array([list(v.points.values())[-2] - origin for v in solved]) * MM]
    allp = np.vstack([q.reshape(-1, 3) for q in pts])
    margin = r_max + 0.1 * length * MM
    lo, hi = allp.min(axis=0) - margin, allp.max(axis=0) + margin

    fig = plt.figure(figsize=(10.0, 8.0))
    ax: Any = fig.add_subplot(projection="3d")
    if view is not None:
        planar = view.design.planar
        draw_mechanism_3d(
            ax,
            view,
            0.03 * float(np.max(hi - lo)),
            origin,
            clip=(lo, hi) if planar else None,
            bases=not planar,
            legs=show_legs,
            labels=False,
            fade=1.0 if planar else 0.55,
        )
        p = (view.centre - origin) * MM
        ax.plot(*p[:, None], marker="+", ms=8, color="k", ls="", gid="P")
        ax.text(*p, " P", fontsize=8)
        if np.any(t != 0.0):
            ax.plot([0.0], [0.0], [0.0], marker="*", ms=11, mfc="gold", mec="k", ls="", gid="tool")
            ax.text(0.0, 0.0, 0.0, " T", fontsize=8)

    for i in range(6):
        colour = cmap(norm(kf[i] / 1e3))
        seg = segments[i]
        ax.plot(*seg.T, color=colour, lw=1.0, ls="--", gid=f"{AXIS_GID}{i + 1}")
        radius = r_max * (0.35 + 0.65 * kf[i] / np.max(kf))
        hel = helix_points(
            springs.positions[i] * MM, springs.axes[i], length * MM, radius, springs.pitches[i]
        )
        hand = "right-handed" if springs.pitches[i] >= 0 else "left-handed"
        # a spring of a repeated eigenvalue is one choice among many (core.eigenscrews)
        partners = [f"s{j + 1}" for g in springs.repeated if i in g for j in g if j != i]
        if partners:
            hand += "; repeated with " + ", ".join(partners)
        k_txt = "inf" if not np.isfinite(k[i]) else f"{k[i] / 1e3:.1f}"
        ax.plot(
            *hel.T,
            color=colour,
            lw=1.8,
            gid=f"{HELIX_GID}{i + 1}",
            label=f"s{i + 1}: k = {k_txt} kN/m, h = {springs.pitches[i] * 1e3:+.1f} mm/rad "
            f"({hand})",
        )
        pos = springs.positions[i] * MM
        ax.scatter(*pos, color=colour, s=16, edgecolor="k", linewidth=0.5)
        # label pairs at opposite ends so that mirrored springs do not overlap
        tip = seg[1] if i < 3 else seg[0]
        ax.text(*tip, f"s{i + 1}", fontsize=9, fontweight="bold", color="k")

    ax.set_xlim3d(lo[0], hi[0])
    ax.set_ylim3d(lo[1], hi[1])
    ax.set_zlim3d(lo[2], hi[2])
    # the frame: the axes of F_b, the origin at the point of K (not F_b's origin O)
    at = "T" if np.any(t != 0.0) else "P"
    for setter, name in ((ax.set_xlabel, "x"), (ax.set_ylabel, "y"), (ax.set_zlabel, "z")):
        setter(f"{name} − {name}$_{at}$ [mm]")
    _equal_box(ax)
    if view is None or view.design.planar:
        ax.view_init(elev=24, azim=-58)
    else:
        from ppm_stiffness.visuals.mechanism3d import best_azimuth

        ax.view_init(elev=20, azim=best_azimuth(view))
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    label = "spring constant k [kN/m] (colour and helix radius)"
    if view is None or view.design.planar:
        cb = fig.colorbar(sm, ax=ax, shrink=0.5, pad=0.1)
        ax.legend(loc="upper left", bbox_to_anchor=(-0.05, 1.0), fontsize=8, framealpha=0.9)
    else:  # a spatial mechanism fills the box: the legend beside it, the colour bar below
        fig.set_size_inches(13.0, 9.0)
        cb = fig.colorbar(sm, ax=ax, shrink=0.45, pad=0.1, orientation="horizontal")
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, framealpha=0.9)
    cb.set_label(label)
    ax.set_title(
        (title or "Six screw springs of K")
        + f"\ndrawn relative to {at} ({'tool point' if at == 'T' else 'platform point'}) "
        "with the axes of F_b",
        fontsize=11,
    )
    from ppm_stiffness.visuals.mechanism3d import declutter_labels

    declutter_labels(ax)  # P, T, the springs' and joints' names apart on screen
    return fig


def _equal_box(ax: Any) -> None:
    """True proportions: box aspect equal to the data ranges (mm)."""
    lims = np.array([ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()])
    spans = np.maximum(lims[:, 1] - lims[:, 0], 1e-9)
    ax.set_box_aspect(spans)
