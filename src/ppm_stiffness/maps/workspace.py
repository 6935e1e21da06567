"""Constant-orientation workspace and stiffness maps (paper Figures 6-7), any architecture.

The workspace at orientation phi is the set of platform positions (x, y) where every
leg's inverse kinematics has a solution with its joint coordinates inside their limits
(:meth:`ppm_stiffness.legs.base.LegModel.reachable`: strokes, rod ranges, actuator
angles), and that are not (nearly) singular (the transmission index of
:mod:`ppm_stiffness.core.singularity`). The map grid spans the bounding box of the
joint-limit workspace (:func:`workspace_bounds`) and masks what lies outside.

Workspace bounds, two methods:

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

Actuator states of a map (``actuators``), each leg with its own actuator law
(``design.legs[i].actuator``: linear [N/m] or rotary [N·m/rad]):

``"max"``
    every actuator locked: ``leg.actuator.locked_stiffness`` (eq. 21, small loads).
``"min"``
    every actuator at the tangent stiffness of eq. (20)-(21) of its own law under the
    reference load ``reference_force`` (default :data:`DEFAULT_REFERENCE_FORCE` = 10, in
    N for a linear actuator and N·m for a rotary one). The paper does not state its
    minimum; see docs/maps.md.
``"wrench"``
    the loaded state under ``wrench`` (m_x, m_y, m_z, f_x, f_y, f_z, axes of F_b, at
    the tool point: P by default) at each pose, as
    :func:`ppm_stiffness.statics.loading.loaded_state` computes it and by the same code
    (:func:`ppm_stiffness.maps.loaded.loaded_poses`: the equilibrium of the nonlinear
    actuator law, Newton's method run on all poses at once, for every design); the
    principal stiffnesses are those of the loaded tangent K. The legs' linear parts come
    from the planar engine (or the general springs for chains out of the plane),
    whatever ``path``.

Masks. A grid pose is masked exactly where the single-pose API raises
(:func:`ppm_stiffness.model.stiffness_at_pose`, and ``loaded_state`` under a wrench),
and :attr:`StiffnessMap.refusal` says why (:class:`ppm_stiffness.core.refusals.Refusal`:
outside the joint limits, singular, no equilibrium, a load beyond the
small-displacement model: an actuator beyond its whole stroke or a rotation beyond
:data:`~ppm_stiffness.statics.equilibrium.MAX_ROTATION`, a loaded K not positive
definite). A map never raises for a pose: a load too large for some poses masks them.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray, hat
from ppm_stiffness.core.errors import (
    DesignError,
    InputDataError,
    UnreachablePoseError,
)
from ppm_stiffness.core.refusals import Refusal, RefusalArray, first_refusal, refusal_counts
from ppm_stiffness.design import Design
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.loaded import loaded_poses
from ppm_stiffness.model import locked_actuator_stiffness, tool_offset
from ppm_stiffness.statics import actuator as act

#: Reference actuator load [N, or N·m for a rotary actuator] that defines "min".
DEFAULT_REFERENCE_FORCE = 10.0
#: Relative inward margin of the grid so that no grid point lies on a joint limit.
_EDGE_MARGIN = 1e-9
#: Sampled bounds: coarse grid points per axis, zoom levels, points across per zoom.
_COARSE = 101
_ZOOM_LEVELS = 6
_ZOOM = 33
#: Sampled bounds: resamplings of the coarse grid on the box of its reachable samples.
_TIGHTEN = 2
#: Sampled bounds: most doublings of the search square before giving up.
_MAX_DOUBLINGS = 12

ACTUATOR_STATES = ("max", "min", "wrench")


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


def workspace_grid(
    design: Design,
    phi: float = 0.0,
    grid: int | tuple[int, int] = 200,
    bounds: ArrayLike | None = None,
    legs: object = None,
) -> tuple[FloatArray, FloatArray]:
    """Grid axes x (nx,), y (ny,) [m] over ``bounds`` or the workspace bounding box.

    The box is shrunk by a relative 1e-9 so that no grid point sits exactly on a limit.
    ``legs`` is accepted for compatibility and ignored.
    """
    nx, ny = (grid, grid) if isinstance(grid, (int, np.integer)) else grid
    if int(nx) < 2 or int(ny) < 2:
        raise InputDataError(f"a map grid needs at least 2 x 2 points, got {nx} x {ny}")
    if bounds is None:
        box = workspace_bounds(design, phi)
        margin = _EDGE_MARGIN * max(box[1] - box[0], box[3] - box[2], 1e-6)
        box = box + np.array([margin, -margin, margin, -margin])
    else:
        box = np.asarray(bounds, dtype=float)
        if box.shape != (4,) or not np.all(np.isfinite(box)):
            raise InputDataError("bounds must be 4 finite numbers x_min, x_max, y_min, y_max")
        if not (box[0] < box[1] and box[2] < box[3]):
            raise InputDataError("bounds must have x_min < x_max and y_min < y_max")
    return np.linspace(box[0], box[1], int(nx)), np.linspace(box[2], box[3], int(ny))


def minimum_actuator_stiffness(design: Design, reference_force: float) -> FloatArray:
    """The "min" actuator stiffness of each leg (n_legs,) [N/m or N·m/rad]: eq.
    (20)-(21) of the leg's own law under ``reference_force`` [N or N·m]."""
    if not np.isfinite(reference_force) or reference_force <= 0:
        raise InputDataError(f"reference force must be finite and > 0 N, got {reference_force}")
    return np.array(
        [float(act.stiffness_from_force(leg.actuator, reference_force)) for leg in design.legs]
    )


@dataclass(frozen=True)
class StiffnessMap:
    """Principal stiffnesses over a constant-orientation grid (SI).

    Attributes
    ----------
    x : ndarray (nx,) [m]
    y : ndarray (ny,) [m]
    phi : float [rad]
    k_phi : numpy.ma.MaskedArray (ny, nx) [N·m/rad]
        ``f_rr[2]`` after the paper's decoupling (eq. 19).
    k_x, k_y : numpy.ma.MaskedArray (ny, nx) [N/m]
        ``f_tt[0]``, ``f_tt[1]``.
    reachable : ndarray (ny, nx) of bool
        True where the map has values: inside the workspace (strokes, rod ranges,
        not singular) and, under a wrench, where the loaded state exists within the
        small-displacement model. The k arrays are masked exactly where this is False
        (``mask == ~reachable``): where the single-pose API raises.
    actuators : str
        "max", "min" or "wrench".
    actuator_stiffness : ndarray (2, n_legs) [N/m, or N·m/rad for a rotary actuator]
        Smallest and largest actuator stiffness of each leg over the workspace (equal
        rows when uniform, always so for "max" and "min").
    wrench : ndarray (6,) or None
        The applied wrench (m_x, m_y, m_z, f_x, f_y, f_z) for "wrench".
    reference_force : float or None
        [N] for "min".
    design_name : str
    refusal : ndarray (ny, nx) of int8, optional
        Why each masked point is masked (:class:`ppm_stiffness.core.refusals.Refusal`;
        0 where ``reachable``); None for a map read from an older file.
    """

    x: FloatArray
    y: FloatArray
    phi: float
    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    reachable: BoolArray
    actuators: str
    actuator_stiffness: FloatArray
    wrench: FloatArray | None = None
    reference_force: float | None = None
    design_name: str = ""
    refusal: RefusalArray | None = None

    @property
    def mask(self) -> BoolArray:
        """True where the maps are masked (outside the workspace), numpy convention."""
        return np.asarray(~self.reachable)

    def refusal_counts(self) -> dict[str, int]:
        """Masked points by reason (:func:`ppm_stiffness.core.refusals.refusal_counts`);
        ``{"masked": n}`` for a map read from an older file."""
        if self.refusal is None:
            masked = int(np.count_nonzero(~self.reachable))
            return {"masked": masked} if masked else {}
        return refusal_counts(self.refusal)

    def masked_text(self) -> str:
        """``"12 of 25 poses masked (12 outside the joint limits)"``, for messages."""
        counts = self.refusal_counts()
        parts = "; ".join(f"{n} {reason}" for reason, n in counts.items())
        total = sum(counts.values())
        return f"{total} of {self.reachable.size} poses masked" + (f" ({parts})" if parts else "")

    def fields(self) -> dict[str, np.ma.MaskedArray]:
        """The three maps by name."""
        return {"k_phi": self.k_phi, "k_x": self.k_x, "k_y": self.k_y}

    def summary(self) -> dict[str, dict[str, float]]:
        """min, max, max/min and their positions [m] of each map over the workspace."""
        out: dict[str, dict[str, float]] = {}
        for name, values in self.fields().items():
            if not np.any(self.reachable):
                continue
            data = np.where(self.reachable, values.filled(np.nan), np.nan)
            jmin, imin = np.unravel_index(np.nanargmin(data), data.shape)
            jmax, imax = np.unravel_index(np.nanargmax(data), data.shape)
            vmin, vmax = float(data[jmin, imin]), float(data[jmax, imax])
            out[name] = {
                "min": vmin,
                "max": vmax,
                "ratio": vmax / vmin if vmin > 0 else float("inf"),
                "x_at_min": float(self.x[imin]),
                "y_at_min": float(self.y[jmin]),
                "x_at_max": float(self.x[imax]),
                "y_at_max": float(self.y[jmax]),
            }
        return out

    def to_npz(self, path: str | Path) -> Path:
        """Write the map as NPZ: x, y, phi, k_phi, k_x, k_y (NaN outside the workspace),
        reachable, actuators, actuator_stiffness, wrench, reference_force (SI), and
        refusal (why each masked point is masked, :class:`~ppm_stiffness.core.refusals.Refusal`)."""
        arrays: dict[str, Any] = {
            "x": self.x,
            "y": self.y,
            "phi": np.float64(self.phi),
            "k_phi": self.k_phi.filled(np.nan),
            "k_x": self.k_x.filled(np.nan),
            "k_y": self.k_y.filled(np.nan),
            "reachable": self.reachable,
            "actuators": np.str_(self.actuators),
            "actuator_stiffness": self.actuator_stiffness,
            "wrench": np.full(6, np.nan) if self.wrench is None else self.wrench,
            "reference_force": np.float64(
                np.nan if self.reference_force is None else self.reference_force
            ),
            "design_name": np.str_(self.design_name),
        }
        if self.refusal is not None:
            arrays["refusal"] = self.refusal
        p = Path(path)
        with p.open("wb") as fh:
            np.savez(fh, **arrays)
        return p

    def to_csv(self, path: str | Path, progress: Callable[[int], None] | None = None) -> Path:
        """Write the map as CSV, one row per grid point (x fastest), SI columns
        ``x_m, y_m, reachable, k_phi_Nm_per_rad, k_x_N_per_m, k_y_N_per_m``; the k cells
        are empty outside the workspace. ``#`` lines give phi and the actuator state.
        ``progress(rows)`` is called with the number of rows written since its last call."""
        p = Path(path)
        xx, yy = np.meshgrid(self.x, self.y)
        flat = [a.ravel() for a in (xx, yy)]
        values = [v.filled(np.nan).ravel() for v in self.fields().values()]
        ok = self.reachable.ravel()
        with p.open("w", newline="", encoding="utf-8") as fh:
            fh.write(f"# design: {self.design_name}\n")
            fh.write(f"# phi_rad: {self.phi!r}\n# actuators: {self.actuators}\n")
            if self.wrench is not None:
                fh.write(f"# wrench (m_x,m_y,m_z,f_x,f_y,f_z): {self.wrench.tolist()}\n")
            if self.reference_force is not None:
                fh.write(f"# reference_force_N: {self.reference_force!r}\n")
            fh.write(f"# actuator_stiffness_N_per_m min/max: {self.actuator_stiffness.tolist()}\n")
            writer = csv.writer(fh)
            writer.writerow(
                ["x_m", "y_m", "reachable", "k_phi_Nm_per_rad", "k_x_N_per_m", "k_y_N_per_m"]
            )
            step = 100_000
            for n in range(ok.size):
                ks = [f"{v[n]:.12g}" if ok[n] else "" for v in values]
                writer.writerow([f"{flat[0][n]:.12g}", f"{flat[1][n]:.12g}", int(ok[n]), *ks])
                if progress is not None and (n + 1) % step == 0:
                    progress(step)
            if progress is not None:
                progress(ok.size % step)
        return p


def load_npz(path: str | Path) -> StiffnessMap:
    """Read a map written by :meth:`StiffnessMap.to_npz`."""
    with np.load(Path(path), allow_pickle=False) as data:
        ok = data["reachable"].astype(bool)

        def masked(name: str) -> np.ma.MaskedArray:
            return np.ma.MaskedArray(data[name], mask=~ok, fill_value=np.nan)

        wrench = data["wrench"]
        ref = float(data["reference_force"])
        return StiffnessMap(
            x=data["x"],
            y=data["y"],
            phi=float(data["phi"]),
            k_phi=masked("k_phi"),
            k_x=masked("k_x"),
            k_y=masked("k_y"),
            reachable=ok,
            actuators=str(data["actuators"]),
            actuator_stiffness=data["actuator_stiffness"],
            wrench=None if np.all(np.isnan(wrench)) else wrench,
            reference_force=None if np.isnan(ref) else ref,
            design_name=str(data["design_name"]),
            refusal=data["refusal"].astype(np.int8) if "refusal" in data.files else None,
        )


class _Fields(NamedTuple):
    """k_phi, k_x, k_y of one chunk (the part of a Principal the map uses)."""

    k_phi: FloatArray
    k_x: FloatArray
    k_y: FloatArray


def stiffness_map(
    design: Design,
    phi: float = 0.0,
    actuators: str = "max",
    grid: int | tuple[int, int] = 200,
    wrench: ArrayLike | None = None,
    progress: Callable[[int, int], None] | None = None,
    *,
    bounds: ArrayLike | None = None,
    reference_force: float = DEFAULT_REFERENCE_FORCE,
    chunk_size: int | None = None,
    path: batch.Path = "auto",
    tool_point: ArrayLike | None = None,
) -> StiffnessMap:
    """Maps of k_phi, k_x, k_y over the workspace at constant orientation, any design.

    Parameters
    ----------
    design : Design
    phi : float
        Platform orientation [rad].
    actuators : {"max", "min", "wrench"}
        Actuator state (module docstring); each leg uses its own actuator law.
    grid : int or (nx, ny)
        Grid points along x and y.
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N], axes of F_b, acting at the tool point
        (P by default); for "wrench" only. The loaded state of every grid pose comes
        from :func:`ppm_stiffness.maps.loaded.loaded_poses`.
    progress : callable(done, total), optional
        Called after each chunk with the number of poses done and the total.
    bounds : array_like (4,), optional
        (x_min, x_max, y_min, y_max) [m]; default the workspace bounding box.
    reference_force : float
        [N, or N·m for a rotary actuator], defines the "min" state.
    chunk_size : int, optional
        Poses per chunk (memory bound: about 1 kB per pose on the reduced path, 2 kB
        on the planar engine, 6 kB per pose and leg on the general path); default
        :func:`~ppm_stiffness.maps.batch.default_chunk`.
    path : {"auto", "reduced", "planar", "general"}
        :func:`ppm_stiffness.maps.batch.select_path`: the reduced P-P-R form when every
        leg offers it, else the planar engine ("auto"); or the general path (the
        reference) for any leg type.
    tool_point : array_like (3,), optional
        Platform frame [m]; ``design.tool_point`` if None. The principal stiffnesses are
        those of K at that point (a wrench of the "wrench" state acts there too); the
        grid and the mask are still those of P.

    Returns
    -------
    StiffnessMap

    Raises
    ------
    InputDataError
        Unknown actuator state, wrench missing or given for another state, bad grid.
        (A load too large at some poses masks them: :attr:`StiffnessMap.refusal`.)
    UnreachablePoseError
        No reachable position at this orientation (and no ``bounds`` given).
    """
    from ppm_stiffness.statics.loading import validate_wrench

    if actuators not in ACTUATOR_STATES:
        raise InputDataError(f"actuators must be one of {ACTUATOR_STATES}, got {actuators!r}")
    if (actuators == "wrench") != (wrench is not None):
        raise InputDataError('a wrench is needed for actuators="wrench" and only for it')
    phi = float(phi)
    if not np.isfinite(phi):
        raise InputDataError("phi must be finite")
    legs = batch.select_path(design, path)
    tool = np.asarray(design.tool_point if tool_point is None else tool_point, dtype=float)
    if tool.shape != (3,) or not np.all(np.isfinite(tool)):
        raise InputDataError("the tool point has 3 finite coordinates [m, platform frame]")
    # at fixed phi the tool point sits at the same offset from P at every grid pose:
    # K_T = A K A^T and w_P = A^-1 w_T with A = [[1, hat(P - T)], [0, 1]] (eq. 16)
    at_tool = bool(np.any(tool))
    shift = np.eye(6)
    shift[:3, 3:] = hat(-tool_offset(np.array([0.0, 0.0, phi]), tool))
    x, y = workspace_grid(design, phi, grid, bounds)
    n_legs = len(design.legs)
    k_locked = locked_actuator_stiffness(design)
    w = (
        None
        if wrench is None
        else np.asarray(np.linalg.solve(shift, validate_wrench(wrench)), dtype=float)
    )
    ref: float | None = None
    if actuators == "max":
        k_const: FloatArray | None = k_locked
    elif actuators == "min":
        ref = float(reference_force)
        k_const = minimum_actuator_stiffness(design, ref)
    else:
        k_const = None
    planar = path != "general"
    if chunk_size is None:
        chunk_size = batch.default_chunk(legs, planar)
    ny, nx = y.size, x.size
    rows = max(1, int(chunk_size) // nx)
    k_phi, k_x, k_y = (np.empty((ny, nx)) for _ in range(3))
    valid = np.zeros((ny, nx), dtype=bool)
    refusal = np.zeros((ny, nx), dtype=np.int8)
    k_lo = np.full(n_legs, np.inf)
    k_hi = np.full(n_legs, -np.inf)
    xr = x[None, :]
    for j0 in range(0, ny, rows):
        j1 = min(j0 + rows, ny)
        yc = y[j0:j1, None]
        shape = (j1 - j0, nx)
        poses = np.stack(
            [np.broadcast_to(xr, shape), np.broadcast_to(yc, shape), np.full(shape, phi)],
            axis=-1,
        ).reshape(-1, 3)
        k_act: FloatArray
        pr: _Fields | batch.Principal
        if k_const is None:  # the loaded state under the wrench: as loaded_state
            assert w is not None
            res = loaded_poses(design, poses, w, matrices=at_tool)
            codes, ok = res.refusal, res.valid
            k_act = np.ma.getdata(res.actuator_stiffness)
            pr = _Fields(res.k_phi.filled(np.nan), res.k_x.filled(np.nan), res.k_y.filled(np.nan))
            if at_tool:
                assert res.stiffness is not None
                k_t = shift @ np.where(ok[:, None, None], res.stiffness, np.eye(6)) @ shift.T
                pr = batch.principal_from_matrices(k_t)
        elif legs is not None and not at_tool:
            # the reduced form broadcasts over the grid axes (no per-pose copies)
            k_act = np.broadcast_to(k_const, (poses.shape[0], n_legs))
            with np.errstate(all="ignore"):
                entries, reach_g = batch.planar_entries(legs, xr, yc, phi, k_const)
                pr = batch.principal_from_entries(entries)
                pi = batch.reduced_projector(legs, phi)
            reach = reach_g.reshape(-1)
            ok = (reach_g & batch.nonsingular_from_entries(entries, pi)).reshape(-1)
            codes = first_refusal(ok.shape, [(Refusal.UNREACHABLE, reach), (Refusal.SINGULAR, ok)])
        else:
            k_act = np.broadcast_to(k_const, (poses.shape[0], n_legs))
            k_p, reach, ok, pr, _ = batch.chunk_result(
                design, legs, poses, k_act, planar, matrices=at_tool
            )
            codes = first_refusal(ok.shape, [(Refusal.UNREACHABLE, reach), (Refusal.SINGULAR, ok)])
            if at_tool:
                assert k_p is not None
                k_t = shift @ np.where(ok[:, None, None], k_p, np.eye(6)) @ shift.T
                pr = batch.principal_from_matrices(k_t)
        refusal[j0:j1] = codes.reshape(shape)
        valid[j0:j1] = ok.reshape(shape)
        k_phi[j0:j1] = np.reshape(pr.k_phi, shape)
        k_x[j0:j1] = np.reshape(pr.k_x, shape)
        k_y[j0:j1] = np.reshape(pr.k_y, shape)
        if k_const is None and np.any(ok):
            ka = k_act[ok]
            k_lo = np.minimum(k_lo, ka.min(axis=0))
            k_hi = np.maximum(k_hi, ka.max(axis=0))
        if progress is not None:
            progress(j1 * nx, ny * nx)
    if k_const is not None:
        k_lo = k_hi = np.asarray(k_const, dtype=float)
    if not np.any(valid):
        k_lo = k_hi = np.full(n_legs, np.nan)

    def masked(values: FloatArray) -> np.ma.MaskedArray:
        values[~valid] = np.nan
        return np.ma.MaskedArray(values, mask=~valid, fill_value=np.nan)

    return StiffnessMap(
        x=x,
        y=y,
        phi=phi,
        k_phi=masked(k_phi),
        k_x=masked(k_x),
        k_y=masked(k_y),
        reachable=valid,
        actuators=actuators,
        actuator_stiffness=np.stack([k_lo, k_hi]),
        wrench=None if wrench is None else validate_wrench(wrench),
        reference_force=ref,
        design_name=design.name,
        refusal=refusal,
    )
