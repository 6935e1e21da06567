"""Workspace bounds of a planar design at constant orientation: the box of the x-y map.

The workspace at orientation phi is the set of platform positions (x, y) where every
leg's inverse kinematics has a solution with its joint coordinates inside their limits
(:meth:`ppm_stiffness.legs.base.LegModel.reachable`: strokes, rod ranges, actuator
angles). Its bounding box (:func:`workspace_bounds`), two methods:

exact (half-planes)
    When every leg states its joint limits at fixed phi as half-planes in (x, y)
    (:meth:`~ppm_stiffness.legs.base.LegModel.limit_half_planes`; the P-P-R leg: its
    stroke and rod length are affine in (x, y)), the workspace is a convex polygon and
    its bounding box comes from its vertices (exact to rounding).
sampled (any leg type)
    Reachability is sampled on a 101 x 101 grid over a square around the workspace
    centre whose half-size starts at twice the largest distance from P to a named leg
    point (the base joints, typically) and doubles until no reachable sample touches
    the square's edge; the grid is then resampled twice on the box of its reachable
    samples (one cell wider each side). Each side of that box is refined by zooming:
    the strip between the outermost reachable column and the one before it, limited
    to the rows reachable near it, is resampled 32 times finer across (sliding
    outwards when the finer rows find reachable poses beyond it), :data:`_ZOOM_LEVELS`
    times. The result is an inner box (its extremes are reachable poses). Against a
    brute-force 1501 x 1501 sweep of the shipped 3-RPR, 3-PRR and 3-RRR at phi = 0 and
    0.3 rad it contains the sweep's box and exceeds it by at most 1.0 sweep step
    (0.12 mm on a ~170 mm box) (tests/test_workspace_bounds.py). A part of the
    workspace narrower than one coarse cell (1 % of the box) and disconnected from the
    rest may be missed. It costs 0.05-0.15 s per orientation, once per design object
    and orientation (the boxes are cached: a design is frozen).

Slices over other coordinates, and spatial designs, are bounded by
:mod:`ppm_stiffness.maps.slices`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError, UnreachablePoseError
from ppm_stiffness.design import Design

#: Sampled bounds: coarse grid points per axis, zoom levels, points across per zoom.
_COARSE = 101
_ZOOM_LEVELS = 6
_ZOOM = 33
#: Sampled bounds: resamplings of the coarse grid on the box of its reachable samples.
_TIGHTEN = 2
#: Sampled bounds: most doublings of the search square before giving up.
_MAX_DOUBLINGS = 12


def reachable_positions(design: Design, x: ArrayLike, y: ArrayLike, phi: float) -> BoolArray:
    """Mask of the positions (x, y) [m] (broadcastable) within every leg's joint
    limits at orientation ``phi`` [rad] (IK solvable, coordinates in range)."""
    xb, yb = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    poses = np.stack([xb, yb, np.full(xb.shape, float(phi))], axis=-1)
    ok = np.ones(xb.shape, dtype=bool)
    for leg in design.legs:
        ok &= np.asarray(leg.reachable(leg.solve(poses)), dtype=bool)
    return ok


def _half_plane_bounds(design: Design, phi: float) -> FloatArray | None:
    """Exact bounding box from the legs' half-planes, None if a leg offers none."""
    normals, offsets = [], []
    for leg in design.legs:
        planes = leg.limit_half_planes(phi)
        if planes is None:
            return None
        normals.append(planes[0])
        offsets.append(planes[1])
    a, b = np.concatenate(normals), np.concatenate(offsets)
    vertices = []
    n = len(b)
    tol = 1e-12 * max(1.0, float(np.max(np.abs(b))))
    for i in range(n):
        for j in range(i + 1, n):
            m = a[[i, j]]
            if abs(np.linalg.det(m)) < 1e-12 * np.linalg.norm(m[0]) * np.linalg.norm(m[1]):
                continue
            p = np.linalg.solve(m, b[[i, j]])
            if np.all(a @ p <= b + tol):
                vertices.append(p)
    if not vertices:
        raise UnreachablePoseError(
            f"no reachable position at phi = {np.degrees(phi):.2f} deg: the joint limits "
            "of the design exclude this orientation"
        )
    v = np.array(vertices)
    return np.array([v[:, 0].min(), v[:, 0].max(), v[:, 1].min(), v[:, 1].max()])


def _search_half_size(design: Design, phi: float) -> float:
    """Largest distance [m] from P to a named leg point at the workspace centre."""
    ws = design.workspace
    centre = np.array([ws.centre_x, ws.centre_y, phi])
    size = 0.0
    for leg in design.legs:
        for point in leg.solve(centre).points.values():
            value = float(np.linalg.norm(point))
            if np.isfinite(value):
                size = max(size, value)
    return size if size > 0 else 1.0


def _zoom_min(
    reach: Callable[[FloatArray, FloatArray], BoolArray],
    us: FloatArray,
    vs: FloatArray,
    mask: BoolArray,
) -> float:
    """Smallest u of the reachable set, refined from a sampled mask (nv, nu) whose
    first column has no reachable sample."""
    level = 0
    while level < _ZOOM_LEVELS:
        i0 = int(np.flatnonzero(mask.any(axis=0))[0])
        if i0 == 0:
            # reachable on the window's first column at rows the coarser grid did not
            # sample: the window slides one width towards smaller u
            width = float(us[-1] - us[0])
            us = np.linspace(us[0] - width, us[0], us.size)
            mask = reach(us[None, :], vs[:, None])
            if not mask.any():
                break
            continue
        level += 1
        near = mask[:, i0] | mask[:, min(i0 + 1, us.size - 1)]
        rows = np.flatnonzero(near)
        r0, r1 = max(int(rows[0]) - 2, 0), min(int(rows[-1]) + 2, vs.size - 1)
        span = r1 - r0
        # keep the previous rows on the new grid: the known reachable sample stays on it
        per = max(1, min(-(-(_ZOOM - 1) // max(span, 1)), 2000 // max(span, 1)))
        vs = np.linspace(vs[r0], vs[r1], span * per + 1) if span > 0 else vs[r0 : r0 + 1]
        us = np.linspace(us[i0 - 1], us[i0], _ZOOM)
        mask = reach(us[None, :], vs[:, None])
    return float(us[int(np.flatnonzero(mask.any(axis=0))[0])])


def _sampled_bounds(design: Design, phi: float) -> FloatArray:
    """Bounding box of the joint-limit workspace by sampling and zooming (module doc)."""
    ws = design.workspace
    cx, cy = ws.centre_x, ws.centre_y
    half = 2.0 * _search_half_size(design, phi)
    for _ in range(_MAX_DOUBLINGS):
        xs = np.linspace(cx - half, cx + half, _COARSE)
        ys = np.linspace(cy - half, cy + half, _COARSE)
        mask = reachable_positions(design, xs[None, :], ys[:, None], phi)
        if not mask.any():
            xs = np.linspace(cx - half, cx + half, 4 * _COARSE)
            ys = np.linspace(cy - half, cy + half, 4 * _COARSE)
            mask = reachable_positions(design, xs[None, :], ys[:, None], phi)
            if not mask.any():
                raise UnreachablePoseError(
                    f"no reachable position at phi = {np.degrees(phi):.2f} deg within "
                    f"{half * 1e3:.4g} mm of the workspace centre: the joint limits of "
                    "the design exclude this orientation"
                )
        if not (mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any()):
            break
        half *= 2.0
    else:
        raise DesignError(
            f"the workspace at phi = {np.degrees(phi):.2f} deg reaches beyond "
            f"{half * 1e3:.4g} mm from its centre: check the joint limits"
        )

    for _ in range(_TIGHTEN):
        # resample the box of the reachable samples, one cell wider on each side
        dx, dy = xs[1] - xs[0], ys[1] - ys[0]
        cols, rows = np.flatnonzero(mask.any(axis=0)), np.flatnonzero(mask.any(axis=1))
        xs = np.linspace(xs[cols[0]] - dx, xs[cols[-1]] + dx, _COARSE)
        ys = np.linspace(ys[rows[0]] - dy, ys[rows[-1]] + dy, _COARSE)
        mask = reachable_positions(design, xs[None, :], ys[:, None], phi)

    def reach_xy(sx: float, sy: float, swap: bool) -> Callable[[FloatArray, FloatArray], BoolArray]:
        def f(u: FloatArray, v: FloatArray) -> BoolArray:
            a, b = (v, u) if swap else (u, v)
            return reachable_positions(design, sx * a, sy * b, phi)

        return f

    x_min = _zoom_min(reach_xy(1.0, 1.0, False), xs, ys, mask)
    x_max = -_zoom_min(reach_xy(-1.0, 1.0, False), -xs[::-1], ys, mask[:, ::-1])
    y_min = _zoom_min(reach_xy(1.0, 1.0, True), ys, xs, mask.T)
    y_max = -_zoom_min(reach_xy(1.0, -1.0, True), -ys[::-1], xs, mask.T[:, ::-1])
    return np.array([x_min, x_max, y_min, y_max])


def workspace_bounds(design: Design, phi: float = 0.0, legs: object = None) -> FloatArray:
    """Bounding box (x_min, x_max, y_min, y_max) [m] of the joint-limit workspace at phi.

    Exact from half-planes when every leg offers them, sampled otherwise (module doc).
    ``legs`` is accepted for compatibility and ignored.

    Raises
    ------
    UnreachablePoseError
        If no position satisfies every joint limit at this orientation.
    """
    del legs
    phi = float(phi)
    if not np.isfinite(phi):
        raise InputDataError("phi must be finite")
    box = _half_plane_bounds(design, phi)
    return _cached_sampled_bounds(design, phi) if box is None else box


#: Sampled bounds already computed: id(design) -> (design, {phi: box}). A design is
#: frozen, so its bounds are design-level work, done once per design object and
#: orientation (the entry keeps the design alive, so its id cannot be reused).
_BOUNDS_CACHE: dict[int, tuple[Design, dict[float, FloatArray]]] = {}
_BOUNDS_CACHE_DESIGNS = 8
_BOUNDS_CACHE_ORIENTATIONS = 64


def _cached_sampled_bounds(design: Design, phi: float) -> FloatArray:
    entry = _BOUNDS_CACHE.get(id(design))
    if entry is None or entry[0] is not design:
        if len(_BOUNDS_CACHE) >= _BOUNDS_CACHE_DESIGNS:
            _BOUNDS_CACHE.pop(next(iter(_BOUNDS_CACHE)))
        entry = (design, {})
        _BOUNDS_CACHE[id(design)] = entry
    boxes = entry[1]
    box = boxes.get(phi)
    if box is None:
        box = _sampled_bounds(design, phi)
        if len(boxes) >= _BOUNDS_CACHE_ORIENTATIONS:
            boxes.pop(next(iter(boxes)))
        boxes[phi] = box
    return box.copy()
