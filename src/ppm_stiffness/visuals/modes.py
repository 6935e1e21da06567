"""The platform displaced along each of its six vibration modes.

One panel per mode (:mod:`ppm_stiffness.dynamics.modes`), in order of frequency: the
platform polygon (its legs' attachment points, in order of angle about its centre) and
the legs (their chains' joints and links joined in order) at rest in grey, and
displaced along the mode in colour, ``pose' = displaced_pose(pose, a v)``
(:func:`ppm_stiffness.core.pose.displaced_pose`) with the mode shape v at P and one
amplitude a for all panels, chosen so that the platform's points move by
:data:`AMPLITUDE` of the platform's size in the mode that moves them most (stated in
the title: the motion is exaggerated). The legs are drawn at the displaced pose from
their inverse kinematics (rigid legs; a mode that bends them shows as the platform's
motion only; in the side view of a planar design the legs are drawn at rest only, their
kinematics being that of the plane).

A spatial design is drawn in 3-D; a planar one in a top view (x, y), except a mode
whose out-of-plane components (z, rx, ry) carry most of its balanced norm, drawn in a
side view (x, z) or (y, z), whichever shows its motion best. Millimetres, axes of F_b.

Artists carry gids: ``platform-rest-<j>`` and ``platform-mode-<j>`` (the closed
polygons of panel j, from 1; 2-D panels: (x, y) or the view's two coordinates; 3-D:
``get_data_3d()``), so that the plotted data can be read back.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import (
    DIRECTION_NAMES,
    LENGTH_SCALE,
    TWIST_BALANCE,
    FloatArray,
)
from ppm_stiffness.design import Design
from ppm_stiffness.legs.chain import Link

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MM = 1e3
#: Largest displacement of a platform point in the drawn modes, as a share of the
#: platform's size (its largest attachment distance from P).
AMPLITUDE = 0.25
_OUT_OF_PLANE = (0, 1, 5)  # rx, ry, z components of a twist
_VIEWS = {"top": (0, 1), "side x-z": (0, 2), "side y-z": (1, 2)}
_AXIS_NAMES = ("x", "y", "z")


def platform_points(design: Design) -> FloatArray:
    """The legs' platform attachments (n, 3) in the platform frame, in order of angle
    about their centroid (in the platform's x-y plane)."""
    b = np.array([leg.attachment() for leg in design.legs], dtype=float)
    c = b.mean(axis=0)
    order = np.argsort(np.arctan2(b[:, 1] - c[1], b[:, 0] - c[0]), kind="stable")
    return np.asarray(b[order])


def platform_polygon(design: Design, pose: ArrayLike) -> FloatArray:
    """The closed platform polygon (n + 1, 3) in F_b [m] at a full pose (6,)."""
    q = np.asarray(pose, dtype=float)
    pts = pose6.position(q) + pose6.platform_offset(q, platform_points(design))
    return np.asarray(np.vstack([pts, pts[:1]]))


def leg_polylines(design: Design, pose: ArrayLike) -> list[FloatArray]:
    """Each leg's chain as a polyline (k, 3) in F_b [m] at a full pose (6,): its joints'
    points and links' ends in chain order, then the platform point."""
    q = np.asarray(pose, dtype=float)
    lines = []
    for leg in design.legs:
        lp = leg.solve(q)
        pts: list[FloatArray] = []
        for element in leg.chain(lp):
            ends = [element.start, element.end] if isinstance(element, Link) else [element.point]
            pts += [np.asarray(e, dtype=float).reshape(3) for e in ends]
        pts.append(np.asarray(leg.platform_offset(q), dtype=float).reshape(3))
        lines.append(pose6.position(q) + np.array(pts))
    return lines


def mode_amplitude(design: Design, shapes: ArrayLike) -> float:
    """The common amplitude a (module doc) for mode shapes (6, 6) at P."""
    b = platform_points(design)
    size = max(float(np.max(np.linalg.norm(b, axis=1))), LENGTH_SCALE * 0.1)
    worst = 0.0
    for t in np.asarray(shapes, dtype=float):
        moved = t[3:] + np.cross(t[:3], np.vstack([b, np.zeros(3)]))
        worst = max(worst, float(np.max(np.linalg.norm(moved, axis=1))))
    return AMPLITUDE * size / worst if worst > 0 else 0.0


#: Names of the six twist components (rotation about x, ..., z translation).
COMPONENT_NAMES = DIRECTION_NAMES
#: A component is named in a mode's title when it carries at least this share of the
#: mode's balanced norm squared (at most the two largest are named).
NAMED_SHARE = 0.1


def mode_shares(shape: ArrayLike) -> FloatArray:
    """Share of each twist component (6,) in a mode's balanced norm squared: the
    rotations times :data:`LENGTH_SCALE` (so that 1 mrad and 1 mm weigh alike, as in
    :mod:`ppm_stiffness.dynamics.modes`); the shares sum to 1."""
    b = np.asarray(shape, dtype=float) * TWIST_BALANCE
    e = b**2
    return np.asarray(e / np.sum(e))


def mode_names(shapes: ArrayLike) -> list[str]:
    """A distinct name for each mode (6, 6) at P, with its shares: its largest
    component and, when it carries at least :data:`NAMED_SHARE`, the second, each with
    its percentage (``"x translation 71 %, rotation about y 29 %"``). Two modes whose
    names would still be equal (a repeated frequency's pair) get their number
    (``"..., mode 2"``)."""
    names = []
    for v in np.asarray(shapes, dtype=float):
        share = mode_shares(v)
        order = np.argsort(-share, kind="stable")
        parts = [order[0]] + [i for i in order[1:2] if share[i] >= NAMED_SHARE]
        names.append(", ".join(f"{COMPONENT_NAMES[i]} {100 * share[i]:.0f} %" for i in parts))
    for name in list(names):
        if names.count(name) > 1:
            names = [f"{n}, mode {k + 1}" if n == name else n for k, n in enumerate(names)]
    return names


def _view(shape: FloatArray, planar: bool) -> str:
    """The view of a mode's panel (module doc)."""
    if not planar:
        return "3d"
    balanced = shape * TWIST_BALANCE
    if np.sum(balanced[list(_OUT_OF_PLANE)] ** 2) <= 0.5 * np.sum(balanced**2):
        return "top"
    # a tilt about x shows in the y-z plane, one about y in the x-z plane
    return "side y-z" if abs(balanced[0]) > abs(balanced[1]) else "side x-z"


def plot_modes(
    design: Design,
    pose: ArrayLike,
    frequencies: ArrayLike,
    shapes: ArrayLike,
    directions: list[str] | tuple[str, ...],
    title: str = "",
) -> Figure:
    """The six modes, one panel each (module doc).

    Parameters
    ----------
    design : Design
    pose : array_like (6,)
        Full pose [m, rad].
    frequencies : array_like (6,) [Hz]
    shapes : array_like (6, 6)
        ``shapes[j]``: the j-th mode's twist at P (axes of F_b) [rad, m].
    directions : sequence of str
        The name of each mode's dominant component (kept for the callers; the panels
        are titled by :func:`mode_names`, with each named component's share).
    title : str
        Figure title (the amplitude is appended).
    """
    import matplotlib.pyplot as plt

    q = np.asarray(pose, dtype=float)
    v = np.asarray(shapes, dtype=float)
    f = np.asarray(frequencies, dtype=float)
    planar = bool(design.planar)
    amp = mode_amplitude(design, v)
    names = mode_names(v)
    fig = plt.figure(figsize=(13.5, 8.5))
    rest_poly = platform_polygon(design, q) * MM
    rest_legs = [line * MM for line in leg_polylines(design, q)]
    for j in range(6):
        view = _view(v[j], planar)
        moved = pose6.displaced_pose(q, amp * v[j])
        poly = platform_polygon(design, moved) * MM
        legs = [line * MM for line in leg_polylines(design, moved)]
        if view == "3d":
            ax: Any = fig.add_subplot(2, 3, j + 1, projection="3d")
            for line in rest_legs:
                ax.plot(*line.T, color="0.7", lw=1.0)
            for line in legs:
                ax.plot(*line.T, color="tab:blue", lw=1.2)
            ax.plot(*rest_poly.T, color="0.5", ls="--", lw=1.0, gid=f"platform-rest-{j + 1}")
            ax.plot(*poly.T, color="tab:red", lw=2.0, gid=f"platform-mode-{j + 1}")
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_zlabel("z [mm]")
            _equal_3d(ax, np.vstack(rest_legs + [rest_poly]))
        else:
            i, k = _VIEWS[view]
            ax = fig.add_subplot(2, 3, j + 1)
            for line in rest_legs:
                ax.plot(line[:, i], line[:, k], color="0.7", lw=1.0)
            # a planar leg's inverse kinematics is that of the plane: out of it, the
            # legs are drawn at rest only
            for line in legs if view == "top" else []:
                ax.plot(line[:, i], line[:, k], color="tab:blue", lw=1.2)
            ax.plot(
                rest_poly[:, i],
                rest_poly[:, k],
                color="0.5",
                ls="--",
                lw=1.0,
                gid=f"platform-rest-{j + 1}",
            )
            ax.plot(poly[:, i], poly[:, k], color="tab:red", lw=2.0, gid=f"platform-mode-{j + 1}")
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_xlabel(f"{_AXIS_NAMES[i]} [mm]")
            ax.set_ylabel(f"{_AXIS_NAMES[k]} [mm]")
            ax.grid(True, lw=0.3)
        label = "" if view in ("3d", "top") else f", {view} view"
        ax.set_title(
            f"mode {j + 1}: {f[j]:.4g} Hz\n{names[j]}{label}", fontsize=9, gid="mode-title"
        )
    head = title + "\n" if title else ""
    fig.suptitle(
        f"{head}grey: at rest; colour: displaced along each mode (platform points moved by "
        f"up to {AMPLITUDE * 100:.0f} % of the platform's size: exaggerated)\nunder each "
        "mode: its largest components, each with its share of the mode's length-balanced "
        "norm squared (rotations times the length scale)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig


def _equal_3d(ax: Any, points: FloatArray) -> None:
    """Equal scales on a 3-D axes around ``points`` (k, 3)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.55 * float(np.max(hi - lo))
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


__all__ = [
    "COMPONENT_NAMES",
    "leg_polylines",
    "mode_amplitude",
    "mode_names",
    "mode_shares",
    "platform_polygon",
    "plot_modes",
]
