"""The six screw springs of a stiffness matrix in 3D (the paper's Figure 5).

Each screw spring ``s_i`` (:mod:`ppm_stiffness.core.eigenscrews`) is drawn as

- a straight segment along its axis ``e_i`` centred on its position ``p_i`` (the
  point of the axis nearest P), the *spring axis*;
- a helix wound around that segment: right-handed for a positive pitch, left-handed
  for a negative one; its radius and colour grow with the spring constant ``k_i``;
- a label ``s_i`` with ``k_i`` [kN/m] and the pitch ``h_i`` [mm/rad].

The platform polygon D1..Dn and the legs (their links and joints, from each leg's
joint chain, any architecture) are drawn in the plane z = 0 at the same pose. Everything is
relative to P with the axes of F_b, in millimetres, like the stiffness matrix.

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
from ppm_stiffness.legs.chain import Joint, Link
from ppm_stiffness.model import workspace_centre

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MM = 1e3  # drawing unit: millimetre per metre
#: gid prefix of the drawn spring axes
AXIS_GID = "spring-axis-"
#: gid prefix of the drawn helices
HELIX_GID = "spring-helix-"


#: Marker of each joint kind in the pictures (revolute, prismatic, cylindrical).
_MARKERS = {"R": "o", "P": "s", "C": "D"}


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


def _clip_segment(
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


def _draw_mechanism_plane(
    ax: Any, design: Design, pose: FloatArray, lo: FloatArray, hi: FloatArray, legs: bool
) -> None:
    """Platform polygon and legs (links, joints; relative to P, z = 0, mm), clipped."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from ppm_stiffness.visuals.mechanism import platform_order

    geoms = [leg.solve(pose) for leg in design.legs]
    d = np.array([g.points["D"] for g in geoms]) * MM
    order = platform_order(d[:, :2], np.zeros(2))
    poly = d[order]
    ring = np.vstack([poly, poly[:1]])
    ax.add_collection3d(Poly3DCollection([poly], facecolor="0.8", alpha=0.35, edgecolor="none"))
    ax.plot(
        ring[:, 0],
        ring[:, 1],
        np.zeros(len(ring)),
        color="0.2",
        lw=2.0,
        label="platform " + "-".join(f"D{k + 1}" for k in order),
    )
    styles = (
        {"color": "tab:blue", "lw": 2.5, "alpha": 0.6},
        {"color": "0.45", "lw": 1.5, "alpha": 0.9},
    )
    labelled: set[str] = set()
    for i, (leg, g) in enumerate(zip(design.legs, geoms, strict=True), start=1):
        dd = g.points["D"] * MM
        ax.text(dd[0], dd[1], 0.0, f" D{i}", fontsize=7, color="0.2")
        if not legs:
            continue
        links = [e for e in leg.chain(g) if isinstance(e, Link)]
        for j, link in enumerate(links):
            p0, p1 = np.asarray(link.start) * MM, np.asarray(link.end) * MM
            seg = _clip_segment(p0, p1, lo, hi)
            if seg is not None:
                label = None if link.name in labelled else f"{link.name} link"
                labelled.add(link.name)
                ax.plot(*seg.T, label=label, **styles[min(j, 1)])
        for joint in leg.chain(g):
            # the joints at the platform point would hide its label
            if isinstance(joint, Joint) and not np.allclose(joint.point, g.points["D"]):
                point = np.asarray(joint.point) * MM
                if np.all(point >= lo) and np.all(point <= hi):
                    ax.scatter(*point, marker=_MARKERS[joint.kind], s=20, color="0.3")
    ax.scatter([0.0], [0.0], [0.0], marker="+", s=60, color="k")
    ax.text(0.0, 0.0, 0.0, " P", fontsize=8)


def plot_screw_springs(
    springs: ScrewSprings,
    design: Design | None = None,
    pose: ArrayLike | None = None,
    length: float | None = None,
    title: str | None = None,
    show_legs: bool = True,
) -> Figure:
    """3D picture of the six screw springs, with the platform and legs in place.

    Parameters
    ----------
    springs : ScrewSprings
        From :func:`ppm_stiffness.core.eigenscrews.eigenscrews` of a matrix at P (F_b).
    design : Design, optional
        Draws its platform and legs at ``pose`` in the plane z = 0; the legs are
        clipped to the box around the springs (the guide blocks may lie outside).
    pose : array_like, shape (3,), optional
        (x [m], y [m], phi [rad]); default the design's workspace centre.
    length : float, optional
        Drawn length of each spring [m]; default 2.5 times the largest platform
        radius (75 mm for the paper's machine), 75 mm without a design.
    title : str, optional
    show_legs : bool
        Draw the legs (links and joints) as well as the platform.

    Returns
    -------
    matplotlib.figure.Figure
        One 3D axes in mm, origin P; spring axes have gid ``spring-axis-<i>``. The
        legend marks the springs of a repeated eigenvalue ("repeated with s2"): inside
        such a group they are one valid choice (:mod:`ppm_stiffness.core.eigenscrews`).
    """
    import matplotlib.pyplot as plt
    from matplotlib import colors as mcolors

    if length is None:
        length = 2.5 * max(leg.platform_radius for leg in design.legs) if design else 0.075
    k = np.asarray(springs.spring_constants, dtype=float)
    kf = _finite_constants(k)
    norm = mcolors.Normalize(vmin=0.0, vmax=float(np.max(kf)) / 1e3)
    cmap = plt.get_cmap("viridis")
    r_max = 0.08 * length * MM
    segments = spring_axis_segments(springs, length) * MM

    # the box shown: springs, platform, P and each leg's point before the platform (the
    # bearing C of a P-P-R, the elbow of an R-R-R), plus a margin
    pts = [segments.reshape(-1, 3), np.zeros((1, 3))]
    geoms = []
    p0 = np.zeros(3)
    if design is not None:
        p0 = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
        geoms = [leg.solve(p0) for leg in design.legs]
        pts += [np.array([g.points["D"] for g in geoms]) * MM]
        if show_legs:
            pts += [np.array([list(g.points.values())[-2] for g in geoms]) * MM]
    allp = np.vstack(pts)
    margin = r_max + 0.1 * length * MM
    lo, hi = allp.min(axis=0) - margin, allp.max(axis=0) + margin

    fig = plt.figure(figsize=(10.0, 8.0))
    ax: Any = fig.add_subplot(projection="3d")
    if design is not None:
        _draw_mechanism_plane(ax, design, p0, lo, hi, show_legs)

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
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    _equal_box(ax)
    ax.view_init(elev=24, azim=-58)
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    cb = fig.colorbar(sm, ax=ax, shrink=0.5, pad=0.1)
    cb.set_label("spring constant k [kN/m] (colour and helix radius)")
    ax.legend(loc="upper left", bbox_to_anchor=(-0.05, 1.0), fontsize=8, framealpha=0.9)
    ax.set_title(
        title or "Six screw springs of K, relative to P with the axes of F_b",
        fontsize=11,
    )
    return fig


def _equal_box(ax: Any) -> None:
    """True proportions: box aspect equal to the data ranges (mm)."""
    lims = np.array([ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()])
    spans = np.maximum(lims[:, 1] - lims[:, 0], 1e-9)
    ax.set_box_aspect(spans)
