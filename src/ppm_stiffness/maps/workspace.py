"""Constant-orientation workspace and stiffness maps (paper Figures 6-7).

The workspace at orientation phi is the set of platform positions (x, y) whose inverse
kinematics keeps every actuator coordinate inside its ``stroke`` and every rod free
length inside its ``rod_length_range`` (design file, per leg), and whose stiffness
matrix is not (nearly) singular by the criterion of
:func:`ppm_stiffness.model.check_nonsingular`. For P-P-R legs both joint values are
affine in (x, y) at fixed phi, so the workspace is a convex polygon; the map grid spans
its bounding box and masks what lies outside.

Actuator states of a map (``actuators``):

``"max"``
    every actuator locked: ``design.actuator.locked_stiffness`` (eq. 21, small loads).
``"min"``
    every actuator at the tangent stiffness of eq. (20)-(21) under the reference force
    ``reference_force`` (default :data:`DEFAULT_REFERENCE_FORCE` = 10 N). The paper
    does not state its minimum; see docs/maps.md.
``"wrench"``
    the loaded state under ``wrench`` (m_x, m_y, m_z, f_x, f_y, f_z at P, F_b) at each
    pose, as :func:`ppm_stiffness.statics.loading.loaded_state`: actuator forces from the
    statics of the locked manipulator, then eq. (20)-(21).
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError, UnreachablePoseError
from ppm_stiffness.design import Design
from ppm_stiffness.maps import batch
from ppm_stiffness.statics import actuator as act

#: Reference actuator force [N] that defines the "min" actuator state.
DEFAULT_REFERENCE_FORCE = 10.0
#: Poses evaluated at once by :func:`stiffness_map` (bounds the temporary memory).
DEFAULT_CHUNK = 65536
#: Relative inward margin of the grid so that no grid point lies on a joint limit.
_EDGE_MARGIN = 1e-9

ACTUATOR_STATES = ("max", "min", "wrench")


def _half_planes(
    legs: tuple[batch.ReducedLeg, ...], phi: float
) -> tuple[FloatArray, FloatArray]:
    """Joint limits at ``phi`` as half-planes ``normals @ (x, y) <= offsets``."""
    normals, offsets = [], []
    for leg in legs:
        dx, dy, rho0, rod0 = batch.leg_kinematics(leg, 0.0, 0.0, phi)
        for direction, value0, (lo, hi) in (
            (leg.u, rho0, leg.stroke),
            (leg.w, rod0, leg.rod_length_range),
        ):
            normals += [direction, -direction]
            offsets += [hi - float(value0), float(value0) - lo]
    return np.array(normals), np.array(offsets)


def workspace_bounds(
    design: Design, phi: float = 0.0, legs: tuple[batch.ReducedLeg, ...] | None = None
) -> FloatArray:
    """Bounding box (x_min, x_max, y_min, y_max) [m] of the joint-limit workspace at phi.

    ``legs`` (from :func:`ppm_stiffness.maps.batch.reduce_design`) saves recomputing them.

    Raises
    ------
    UnreachablePoseError
        If no position satisfies every stroke and rod-length limit at this orientation.
    """
    a, b = _half_planes(batch.reduce_design(design) if legs is None else legs, float(phi))
    vertices = []
    n = len(b)
    for i in range(n):
        for j in range(i + 1, n):
            m = a[[i, j]]
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            p = np.linalg.solve(m, b[[i, j]])
            if np.all(a @ p <= b + 1e-12):
                vertices.append(p)
    if not vertices:
        raise UnreachablePoseError(
            f"no reachable position at phi = {np.degrees(phi):.2f} deg: the strokes and "
            "rod length ranges of the design exclude this orientation"
        )
    v = np.array(vertices)
    return np.array([v[:, 0].min(), v[:, 0].max(), v[:, 1].min(), v[:, 1].max()])


def workspace_grid(
    design: Design,
    phi: float = 0.0,
    grid: int | tuple[int, int] = 200,
    bounds: ArrayLike | None = None,
    legs: tuple[batch.ReducedLeg, ...] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Grid axes x (nx,), y (ny,) [m] over ``bounds`` or the workspace bounding box.

    The box is shrunk by a relative 1e-9 so that no grid point sits exactly on a limit.
    """
    nx, ny = (grid, grid) if isinstance(grid, (int, np.integer)) else grid
    if int(nx) < 2 or int(ny) < 2:
        raise InputDataError(f"a map grid needs at least 2 x 2 points, got {nx} x {ny}")
    if bounds is None:
        box = workspace_bounds(design, phi, legs)
        margin = _EDGE_MARGIN * max(box[1] - box[0], box[3] - box[2], 1e-6)
        box = box + np.array([margin, -margin, margin, -margin])
    else:
        box = np.asarray(bounds, dtype=float)
        if box.shape != (4,) or not np.all(np.isfinite(box)):
            raise InputDataError("bounds must be 4 finite numbers x_min, x_max, y_min, y_max")
        if not (box[0] < box[1] and box[2] < box[3]):
            raise InputDataError("bounds must have x_min < x_max and y_min < y_max")
    return np.linspace(box[0], box[1], int(nx)), np.linspace(box[2], box[3], int(ny))


def minimum_actuator_stiffness(design: Design, reference_force: float) -> float:
    """The "min" actuator stiffness [N/m]: eq. (20)-(21) under ``reference_force`` [N]."""
    if not np.isfinite(reference_force) or reference_force <= 0:
        raise InputDataError(f"reference force must be finite and > 0 N, got {reference_force}")
    return float(act.stiffness_from_force(design.actuator, reference_force))


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
        True inside the workspace: strokes, rod ranges and non-singularity respected.
        The k arrays are masked exactly where this is False (``mask == ~reachable``).
    actuators : str
        "max", "min" or "wrench".
    actuator_stiffness : ndarray (2, n_legs) [N/m]
        Smallest and largest actuator stiffness of each leg over the workspace (equal
        rows when uniform, always so for "max" and "min").
    wrench : ndarray (6,) or None
        The applied wrench (m_x, m_y, m_z, f_x, f_y, f_z) for "wrench".
    reference_force : float or None
        [N] for "min".
    design_name : str
    """

    x: FloatArray
    y: FloatArray
    phi: float
    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    reachable: FloatArray
    actuators: str
    actuator_stiffness: FloatArray
    wrench: FloatArray | None = None
    reference_force: float | None = None
    design_name: str = ""

    @property
    def mask(self) -> FloatArray:
        """True where the maps are masked (outside the workspace), numpy convention."""
        return np.asarray(~self.reachable)

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
        reachable, actuators, actuator_stiffness, wrench, reference_force (SI)."""
        p = Path(path)
        with p.open("wb") as fh:
            np.savez(
                fh,
                x=self.x,
                y=self.y,
                phi=np.float64(self.phi),
                k_phi=self.k_phi.filled(np.nan),
                k_x=self.k_x.filled(np.nan),
                k_y=self.k_y.filled(np.nan),
                reachable=self.reachable,
                actuators=np.str_(self.actuators),
                actuator_stiffness=self.actuator_stiffness,
                wrench=np.full(6, np.nan) if self.wrench is None else self.wrench,
                reference_force=np.float64(
                    np.nan if self.reference_force is None else self.reference_force
                ),
                design_name=np.str_(self.design_name),
            )
        return p

    def to_csv(self, path: str | Path) -> Path:
        """Write the map as CSV, one row per grid point (x fastest), SI columns
        ``x_m, y_m, reachable, k_phi_Nm_per_rad, k_x_N_per_m, k_y_N_per_m``; the k cells
        are empty outside the workspace. ``#`` lines give phi and the actuator state."""
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
            for n in range(ok.size):
                ks = [f"{v[n]:.12g}" if ok[n] else "" for v in values]
                writer.writerow([f"{flat[0][n]:.12g}", f"{flat[1][n]:.12g}", int(ok[n]), *ks])
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
        )


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
    chunk_size: int = DEFAULT_CHUNK,
) -> StiffnessMap:
    """Maps of k_phi, k_x, k_y over the workspace at constant orientation.

    Parameters
    ----------
    design : Design
    phi : float
        Platform orientation [rad].
    actuators : {"max", "min", "wrench"}
        Actuator state (module docstring).
    grid : int or (nx, ny)
        Grid points along x and y.
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P, axes of F_b; for "wrench" only.
    progress : callable(done, total), optional
        Called after each chunk with the number of poses done and the total.
    bounds : array_like (4,), optional
        (x_min, x_max, y_min, y_max) [m]; default the workspace bounding box.
    reference_force : float
        [N], defines the "min" state.
    chunk_size : int
        Poses per chunk (memory bound: about 1 kB per pose of chunk).

    Returns
    -------
    StiffnessMap

    Raises
    ------
    InputDataError
        Unknown actuator state, wrench missing or given for another state, bad grid.
    UnreachablePoseError
        No reachable position at this orientation (and no ``bounds`` given).
    """
    from ppm_stiffness.statics.loading import check_actuator_travel, validate_wrench

    if actuators not in ACTUATOR_STATES:
        raise InputDataError(f"actuators must be one of {ACTUATOR_STATES}, got {actuators!r}")
    if (actuators == "wrench") != (wrench is not None):
        raise InputDataError('a wrench is needed for actuators="wrench" and only for it')
    phi = float(phi)
    if not np.isfinite(phi):
        raise InputDataError("phi must be finite")
    legs = batch.reduce_design(design)
    x, y = workspace_grid(design, phi, grid, bounds, legs)
    n_legs = len(legs)
    law = design.actuator
    w = None if wrench is None else validate_wrench(wrench)
    ref: float | None = None
    if actuators == "max":
        k_const: FloatArray | None = np.full(n_legs, law.locked_stiffness)
    elif actuators == "min":
        ref = float(reference_force)
        k_const = np.full(n_legs, minimum_actuator_stiffness(design, ref))
    else:
        k_const = None
    ny, nx = y.size, x.size
    rows = max(1, int(chunk_size) // nx)
    k_phi, k_x, k_y = (np.empty((ny, nx)) for _ in range(3))
    valid = np.zeros((ny, nx), dtype=bool)
    k_lo = np.full(n_legs, np.inf)
    k_hi = np.full(n_legs, -np.inf)
    xr = x[None, :]
    for j0 in range(0, ny, rows):
        j1 = min(j0 + rows, ny)
        yc = y[j0:j1, None]
        with np.errstate(all="ignore"):
            if k_const is None:
                assert w is not None
                forces = batch.actuator_forces_batch(
                    legs, xr, yc, phi, w, law.locked_stiffness
                )
                check_actuator_travel(design, act.displacement_from_force(law, forces))
                k_act = act.stiffness_from_force(law, forces)
            else:
                k_act = k_const
            entries, reach = batch.planar_entries(legs, xr, yc, phi, k_act)
            pr = batch.principal_from_entries(entries)
        ok = reach & batch.nonsingular_from_entries(entries)
        valid[j0:j1] = ok
        k_phi[j0:j1], k_x[j0:j1], k_y[j0:j1] = pr.k_phi, pr.k_x, pr.k_y
        if k_const is None and np.any(ok):
            ka = np.broadcast_to(k_act, ok.shape + (n_legs,))[ok]
            k_lo = np.minimum(k_lo, ka.min(axis=0))
            k_hi = np.maximum(k_hi, ka.max(axis=0))
        if progress is not None:
            progress(j1 * nx, ny * nx)
    if k_const is not None:
        k_lo = k_hi = k_const
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
        wrench=w,
        reference_force=ref,
        design_name=design.name,
    )
