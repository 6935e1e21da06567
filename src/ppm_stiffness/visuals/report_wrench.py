"""The report's loaded case: the reference wrench of a design (``docs/report.md``).

In order of precedence:

1. ``report --wrench``;
2. the design file's ``[reference_wrench]`` (force [N], moment [N·m] at the tool
   point, axes of F_b);
3. a planar design: the paper's load, f = (5, 5, 20) N, m_z = 0.1 N·m
   (:data:`PAPER_WRENCH`, the paper's Table 5 case);
4. a spatial design: the paper's load scaled to the design, ``s * PAPER_WRENCH``, with
   the scale s (two significant digits) that makes the reference point (the tool point)
   move by :data:`REFERENCE_DEFLECTION` of the design's size under the unloaded,
   locked K (the size L: the largest distance between two joints of the mechanism at
   the pose, :func:`design_size`). The paper's 21 N load moves the hexapod's tool point
   by 0.00127 mm; the scaled one by 0.01 % of its size, a load of the order a machine
   of that size and stiffness is built for.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.design import Design

#: The paper's loaded case: f = [5, 5, 20] N, m_z = 0.1 N·m, as (m_x, m_y, m_z, f_x, f_y, f_z).
PAPER_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])
#: Deflection of the reference point under a spatial design's default reference wrench,
#: as a share of the design's size (module doc).
REFERENCE_DEFLECTION = 1e-4


@dataclass(frozen=True)
class ReferenceWrench:
    """The report's loaded case.

    Attributes
    ----------
    wrench : ndarray (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the reference point, axes of F_b.
    source : str
        ``"option"``, ``"design file"``, ``"paper"`` or ``"scaled"`` (module doc).
    text : str
        One sentence (HTML) stating where it comes from, shown in the report.
    scale : float
        s of a scaled paper load (1 otherwise).
    size : float
        The design's size L [m] (:func:`design_size`).
    """

    wrench: FloatArray
    source: str
    text: str
    scale: float = 1.0
    size: float = 0.0


def design_size(design: Design, pose: ArrayLike) -> float:
    """The largest distance [m] between two joints of the mechanism (the legs' joint
    points and the platform's attachments, F_b) at a full pose (6,)."""
    from ppm_stiffness.visuals.leg_geometry import mechanism_view

    view = mechanism_view(design, pose)
    pts = [np.asarray(view.platform, dtype=float)]
    pts += [np.array(list(v.points.values()), dtype=float) for v in view.legs if v.solvable]
    cloud = np.vstack([p.reshape(-1, 3) for p in pts])
    diff = cloud[:, None, :] - cloud[None, :, :]
    return float(np.max(np.linalg.norm(diff, axis=2)))


def _two_digits(x: float) -> float:
    """``x`` > 0 rounded to two significant digits."""
    return float(f"{x:.2g}")


def _wrench_text(w: FloatArray) -> str:
    return f"f = ({w[3]:g}, {w[4]:g}, {w[5]:g}) N, m = ({w[0]:g}, {w[1]:g}, {w[2]:g}) N·m"


def reference_wrench(
    design: Design, pose: ArrayLike, stiffness: ArrayLike, given: ArrayLike | None = None
) -> ReferenceWrench:
    """The report's loaded case (module doc).

    Parameters
    ----------
    design : Design
    pose : array_like (6,)
        Full pose [m, rad].
    stiffness : array_like (6, 6)
        The unloaded K at the reference point (the tool point), axes of F_b, SI.
    given : array_like (6,), optional
        ``--wrench`` (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N].
    """
    if given is not None:
        w = np.asarray(given, dtype=float)
        return ReferenceWrench(w, "option", f"{_wrench_text(w)} (given with --wrench)")
    if design.reference_wrench is not None:
        w = np.asarray(design.reference_wrench.wrench(), dtype=float)
        return ReferenceWrench(
            w, "design file", f"{_wrench_text(w)} (the design file's [reference_wrench])"
        )
    if design.planar:
        return ReferenceWrench(
            PAPER_WRENCH.copy(), "paper", f"{_wrench_text(PAPER_WRENCH)} (the paper's load)"
        )
    size = design_size(design, pose)
    twist = np.linalg.solve(np.asarray(stiffness, dtype=float), PAPER_WRENCH)
    moved = float(np.linalg.norm(twist[3:]))
    scale = _two_digits(REFERENCE_DEFLECTION * size / moved)
    w = scale * PAPER_WRENCH
    text = (
        f"{_wrench_text(w)}: the paper's load (f = (5, 5, 20) N, m<sub>z</sub> = 0.1 N·m) "
        f"× {scale:g}, scaled to the design so that the reference point moves by about "
        f"{100 * REFERENCE_DEFLECTION:g} % of the design's size L = {size * 1e3:.4g} mm "
        f"({REFERENCE_DEFLECTION * size * 1e3:.3g} mm) under the unloaded K (the paper's "
        f"load moves it by {moved * 1e3:.3g} mm); a design file sets its own with "
        "[reference_wrench], the command line with --wrench"
    )
    return ReferenceWrench(w, "scaled", text, scale, size)


def describe(ref: ReferenceWrench) -> dict[str, Any]:
    """Plain data of ``ref`` for the report's embedded JSON."""
    return {
        "wrench": [float(x) for x in ref.wrench],
        "source": ref.source,
        "scale": ref.scale,
        "size": ref.size,
    }


__all__ = [
    "PAPER_WRENCH",
    "REFERENCE_DEFLECTION",
    "ReferenceWrench",
    "describe",
    "design_size",
    "reference_wrench",
]
