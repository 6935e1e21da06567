"""A stiffness map: quantities over a 2-D slice, with its axes, fixed coordinates and
masks, and its files (NPZ, CSV).

The quantities (:data:`QUANTITIES`), each a masked array (nv, nu) over the grid of the
slice's two axes:

- the paper's (planar designs): ``k_phi`` [N·m/rad] = f_rr[2] after the decoupling of
  eq. (19), ``k_x``, ``k_y`` [N/m] = f_tt[0], f_tt[1];
- the spatial principal stiffnesses (any design, :mod:`ppm_stiffness.core.principal`):
  ``rotational_min``, ``rotational_mid``, ``rotational_max`` [N·m/rad], the eigenvalues
  of C_rr^-1 in ascending order (``rotational_min`` is the worst-direction rotational
  stiffness), and ``translational_min``, ``..._mid``, ``..._max`` [N/m], those of
  C_tt^-1 at the tool point;
- the first natural frequency ``f1`` [Hz] (a design with a mass model,
  :mod:`ppm_stiffness.dynamics.batch`): the lowest natural frequency at P with each
  leg's own modes (``link_modes`` per leg, as ``modes`` and ``analyze``:
  docs/dynamics.md, "Link modes"), or of ``K v = omega^2 M v`` with the legs
  condensed (``link_modes`` 0).
- ``hinge_range`` [rad for rotary drives, m for linear ones] (a design with notch hinges
  whose materials give their yield strength): the smallest over the drives of each
  drive's range alone, its free displacement at which the first hinge yields
  (:func:`ppm_stiffness.statics.hinge_stress.drive_range`, the frozen hinge model at
  each pose, safety factor 1; docs/flexures.md).
- under a wrench, on request: ``load_margin`` (dimensionless), the load factor up to
  which the path ``lambda * wrench`` is stable with moving geometry
  (:func:`ppm_stiffness.maps.loaded.margin_column`).

A map carries its axis names and their SI units, the fixed task coordinates, for a
design with dependent coordinates their values at each grid point (a tripod's parasitic
x, y, rz), the actuator state and the refusal codes, so that pictures, CSV and JSON are
written from the map alone.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.refusals import RefusalArray, refusal_counts
from ppm_stiffness.maps.slices import unit_of

#: name -> (unit, CSV column suffix, plot symbol) of every map quantity.
QUANTITIES: dict[str, tuple[str, str, str]] = {
    "k_phi": ("N·m/rad", "Nm_per_rad", r"$k_\phi$"),
    "k_x": ("N/m", "N_per_m", r"$k_x$"),
    "k_y": ("N/m", "N_per_m", r"$k_y$"),
    "rotational_min": ("N·m/rad", "Nm_per_rad", r"$k_{r,\min}$"),
    "rotational_mid": ("N·m/rad", "Nm_per_rad", r"$k_{r,\mathrm{mid}}$"),
    "rotational_max": ("N·m/rad", "Nm_per_rad", r"$k_{r,\max}$"),
    "translational_min": ("N/m", "N_per_m", r"$k_{t,\min}$"),
    "translational_mid": ("N/m", "N_per_m", r"$k_{t,\mathrm{mid}}$"),
    "translational_max": ("N/m", "N_per_m", r"$k_{t,\max}$"),
    "load_margin": ("1", "factor", r"$\lambda$"),
    "f1": ("Hz", "Hz", r"$f_1$"),
    "hinge_range": ("rad or m", "drive_unit", r"$\Delta q_{\max}$"),
}
#: Quantities under a wrench only, never in a set ("load-margin" is accepted too):
#: the load margin of the map's wrench (:func:`ppm_stiffness.maps.loaded.margin_column`).
EXTRA = ("load_margin",)
#: The quantity sets: the paper's (planar designs) and the spatial principal ones.
PAPER = ("k_phi", "k_x", "k_y")
PRINCIPAL = (
    "rotational_min",
    "rotational_mid",
    "rotational_max",
    "translational_min",
    "translational_mid",
    "translational_max",
)


@dataclass(frozen=True)
class StiffnessMap:
    """Quantities over a 2-D slice of the task space (SI).

    Attributes
    ----------
    axes : (str, str)
        The task coordinates along the grid (``("x", "y")`` for the paper's maps).
    u, v : ndarray (nu,), (nv,) [m or rad]
        The grid values of ``axes[0]`` and ``axes[1]``; arrays are (nv, nu).
    fixed : dict of str to float
        The other task coordinates [m or rad] (``{"rz": phi}`` for a planar x-y map).
    quantities : dict of str to numpy.ma.MaskedArray (nv, nu)
        :data:`QUANTITIES` by name (module doc), masked (NaN data) where not
        ``reachable``.
    reachable : ndarray (nv, nu) of bool
        True where the map has values: reachable (completed, strokes, rod ranges,
        joint angles), not singular and, under a wrench, where the loaded state exists
        within the small-displacement model; the quantities are masked exactly where
        this is False, where the single-pose API raises.
    actuators : str
        "max", "min" or "wrench".
    actuator_stiffness : ndarray (2, n_legs) [N/m, or N·m/rad for a rotary actuator]
        Smallest and largest actuator stiffness of each leg over the map (equal rows
        when uniform, always so for "max" and "min").
    wrench : ndarray (6,) or None
        The applied wrench (m_x, m_y, m_z, f_x, f_y, f_z) at the tool point, "wrench".
    reference_force : float or None
        [N or N·m] for "min".
    design_name : str
    refusal : ndarray (nv, nu) of int8, optional
        Why each masked point is masked (:class:`ppm_stiffness.core.refusals.Refusal`;
        0 where ``reachable``); None for a map read from an older file.
    dependent : dict of str to ndarray (nv, nu)
        The dependent coordinates [m or rad] of a design that has them (not planar),
        NaN where not ``reachable``; empty for a planar design (z = rx = ry = 0).
    tool_point : ndarray (3,)
        Where the quantities are taken [m, platform frame] (translational ones depend
        on it).
    geometry : str
        Under a wrench, the statics: "frozen" (the unloaded geometry, the paper's) or
        "moving" (the equilibrium with moving geometry, K_F's symmetric part).
    link_modes : int or None
        f1's fixed-interface modes per leg (0: the legs condensed); None without f1.
    """

    axes: tuple[str, str]
    u: FloatArray
    v: FloatArray
    fixed: dict[str, float]
    quantities: dict[str, np.ma.MaskedArray]
    reachable: BoolArray
    actuators: str
    actuator_stiffness: FloatArray
    wrench: FloatArray | None = None
    reference_force: float | None = None
    design_name: str = ""
    refusal: RefusalArray | None = None
    dependent: dict[str, FloatArray] = field(default_factory=dict)
    tool_point: FloatArray = field(default_factory=lambda: np.zeros(3))
    geometry: str = "frozen"
    drive_unit: str = ""
    link_modes: int | None = None

    def _column_suffix(self, name: str) -> str:
        """The CSV column's unit suffix of quantity ``name`` (hinge_range: rad or m)."""
        if name == "hinge_range" and self.drive_unit:
            return self.drive_unit
        return QUANTITIES[name][1]

    def unit(self, name: str) -> str:
        """The SI unit of quantity ``name`` on this map: :data:`QUANTITIES`'s, the
        design's drive unit (rad for rotary drives, m for linear ones) for
        ``hinge_range``."""
        if name == "hinge_range" and self.drive_unit:
            return self.drive_unit
        return QUANTITIES[name][0]

    # -- the names of the paper's x-y maps ---------------------------------------------
    def values_of(self, name: str) -> FloatArray:
        """The grid values of axis ``name`` [m or rad]."""
        if name not in self.axes:
            raise AttributeError(
                f"{name} is not an axis of this map (its axes: {', '.join(self.axes)})"
            )
        return self.u if self.axes[0] == name else self.v

    @property
    def x(self) -> FloatArray:
        """Grid values along x [m] (a map with an x axis)."""
        return self.values_of("x")

    @property
    def y(self) -> FloatArray:
        """Grid values along y [m] (a map with a y axis)."""
        return self.values_of("y")

    @property
    def phi(self) -> float:
        """The fixed rz [rad] (a map at constant rz, every planar x-y map)."""
        if "rz" not in self.fixed:
            raise AttributeError("rz is not fixed on this map")
        return self.fixed["rz"]

    def _quantity(self, name: str) -> np.ma.MaskedArray:
        if name not in self.quantities:
            raise AttributeError(
                f"this map has no {name} (its quantities: {', '.join(self.quantities)})"
            )
        return self.quantities[name]

    @property
    def k_phi(self) -> np.ma.MaskedArray:
        return self._quantity("k_phi")

    @property
    def k_x(self) -> np.ma.MaskedArray:
        return self._quantity("k_x")

    @property
    def k_y(self) -> np.ma.MaskedArray:
        return self._quantity("k_y")

    # -- masks and summaries -----------------------------------------------------------
    @property
    def mask(self) -> BoolArray:
        """True where the maps are masked (outside the workspace), numpy convention."""
        return np.asarray(~self.reachable)

    def units(self) -> tuple[str, str]:
        """The SI units of the two axes ("m" or "rad")."""
        return unit_of(self.axes[0]), unit_of(self.axes[1])

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

    def grid_arguments(self) -> dict[str, Any]:
        """Keyword arguments of :func:`ppm_stiffness.maps.workspace.stiffness_map` that
        give this map's grid, slice, state and quantities again (for another design:
        tolerance bands, comparisons)."""
        out: dict[str, Any] = {
            "axes": self.axes,
            "fixed": dict(self.fixed),
            "grid": (self.u.size, self.v.size),
            "bounds": (float(self.u[0]), float(self.u[-1]), float(self.v[0]), float(self.v[-1])),
            "actuators": self.actuators,
            "wrench": self.wrench,
            "tool_point": np.asarray(self.tool_point, dtype=float),
            "quantities": list(self.quantities),
        }
        if self.geometry != "frozen":
            out["geometry"] = self.geometry
        if self.reference_force is not None:
            out["reference_force"] = self.reference_force
        if self.link_modes is not None:
            out["link_modes"] = self.link_modes
        return out

    def fields(self) -> dict[str, np.ma.MaskedArray]:
        """The quantities by name."""
        return dict(self.quantities)

    def summary(self) -> dict[str, dict[str, float]]:
        """min, max, max/min of each quantity over the map, and where they are: keys
        ``<axis>_at_min`` and ``<axis>_at_max`` for both axes [m or rad]."""
        out: dict[str, dict[str, float]] = {}
        a, b = self.axes
        for name, values in self.quantities.items():
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
                f"{a}_at_min": float(self.u[imin]),
                f"{b}_at_min": float(self.v[jmin]),
                f"{a}_at_max": float(self.u[imax]),
                f"{b}_at_max": float(self.v[jmax]),
            }
        return out

    # -- files -------------------------------------------------------------------------
    def to_npz(self, path: str | Path) -> Path:
        """Write the map as NPZ (SI; docs/maps.md "Files"): ``axes``, the grid of each
        axis under its name (``x``, ``y``, ``rx``, ...), ``fixed_names`` and
        ``fixed_values``, ``phi`` when rz is fixed, ``quantities`` and each quantity
        under its name (NaN where masked), ``reachable``, ``refusal``, ``actuators``,
        ``actuator_stiffness``, ``wrench``, ``reference_force`` (NaN if none),
        ``design_name``, ``tool_point``, ``dependent_names`` and each dependent
        coordinate as ``pose_<name>``."""
        arrays: dict[str, Any] = {
            "axes": np.array(self.axes),
            self.axes[0]: self.u,
            self.axes[1]: self.v,
            "fixed_names": np.array(list(self.fixed), dtype=str),
            "fixed_values": np.array(list(self.fixed.values()), dtype=float),
            "quantities": np.array(list(self.quantities), dtype=str),
            "reachable": self.reachable,
            "actuators": np.str_(self.actuators),
            "actuator_stiffness": self.actuator_stiffness,
            "wrench": np.full(6, np.nan) if self.wrench is None else self.wrench,
            "reference_force": np.float64(
                np.nan if self.reference_force is None else self.reference_force
            ),
            "design_name": np.str_(self.design_name),
            "tool_point": np.asarray(self.tool_point, dtype=float),
            "dependent_names": np.array(list(self.dependent), dtype=str),
            "geometry": np.str_(self.geometry),
            "drive_unit": np.str_(self.drive_unit),
        }
        if "rz" in self.fixed:
            arrays["phi"] = np.float64(self.fixed["rz"])
        for name, quantity in self.quantities.items():
            arrays[name] = quantity.filled(np.nan)
        for name, coordinate in self.dependent.items():
            arrays[f"pose_{name}"] = coordinate
        if self.refusal is not None:
            arrays["refusal"] = self.refusal
        p = Path(path)
        with p.open("wb") as fh:
            np.savez(fh, **arrays)
        return p

    def to_csv(self, path: str | Path, progress: Callable[[int], None] | None = None) -> Path:
        """Write the map as CSV, one row per grid point (the first axis fastest), SI
        columns: the two axes (``x_m, y_m`` for an x-y map, ``rx_rad``, ...),
        ``reachable``, the dependent coordinates (``x_m``, ... of a tripod), then each
        quantity with its unit (``k_phi_Nm_per_rad, k_x_N_per_m, k_y_N_per_m``,
        ``rotational_min_Nm_per_rad``, ...); value cells are empty where masked. ``#``
        lines give the fixed coordinates (rz as ``phi_rad``), the actuator state and the
        tool point. ``progress(rows)`` is called with the rows written since its last
        call."""
        p = Path(path)
        uu, vv = np.meshgrid(self.u, self.v)
        flat = [a.ravel() for a in (uu, vv)]
        dependent = [v.ravel() for v in self.dependent.values()]
        values = [v.filled(np.nan).ravel() for v in self.quantities.values()]
        ok = self.reachable.ravel()
        header = [f"{name}_{unit_of(name)}" for name in self.axes] + ["reachable"]
        header += [f"{name}_{unit_of(name)}" for name in self.dependent]
        header += [f"{name}_{self._column_suffix(name)}" for name in self.quantities]
        with p.open("w", newline="", encoding="utf-8") as fh:
            fh.write(f"# design: {self.design_name}\n")
            for name, value in self.fixed.items():
                label = "phi" if name == "rz" else name
                fh.write(f"# {label}_{unit_of(name)}: {value!r}\n")
            fh.write(f"# actuators: {self.actuators}\n")
            if self.wrench is not None:
                fh.write(f"# wrench (m_x,m_y,m_z,f_x,f_y,f_z): {self.wrench.tolist()}\n")
                fh.write(f"# geometry: {self.geometry}\n")
            if self.reference_force is not None:
                fh.write(f"# reference_force_N: {self.reference_force!r}\n")
            fh.write(f"# actuator_stiffness_N_per_m min/max: {self.actuator_stiffness.tolist()}\n")
            if np.any(self.tool_point):
                fh.write(f"# tool_point_m: {np.asarray(self.tool_point).tolist()}\n")
            writer = csv.writer(fh)
            writer.writerow(header)
            step = 100_000
            for n in range(ok.size):
                cells = [f"{flat[0][n]:.12g}", f"{flat[1][n]:.12g}", int(ok[n])]
                cells += [f"{v[n]:.12g}" if ok[n] else "" for v in dependent]
                cells += [f"{v[n]:.12g}" if ok[n] else "" for v in values]
                writer.writerow(cells)
                if progress is not None and (n + 1) % step == 0:
                    progress(step)
            if progress is not None:
                progress(ok.size % step)
        return p


def load_npz(path: str | Path) -> StiffnessMap:
    """Read a map written by :meth:`StiffnessMap.to_npz` (also by versions before the
    map carried its axes: an x-y map at ``phi`` with k_phi, k_x, k_y)."""
    with np.load(Path(path), allow_pickle=False) as data:
        files = set(data.files)
        ok = data["reachable"].astype(bool)

        def masked(name: str) -> np.ma.MaskedArray:
            return np.ma.MaskedArray(data[name], mask=~ok, fill_value=np.nan)

        if "axes" in files:
            axes = (str(data["axes"][0]), str(data["axes"][1]))
            fixed = {
                str(k): float(v)
                for k, v in zip(data["fixed_names"], data["fixed_values"], strict=True)
            }
            names = [str(n) for n in data["quantities"]]
            dependent = {str(n): data[f"pose_{n}"] for n in data["dependent_names"]}
            tool = data["tool_point"]
        else:  # an older file: the paper's x-y map at phi
            axes, fixed, names, dependent = ("x", "y"), {"rz": float(data["phi"])}, list(PAPER), {}
            tool = np.zeros(3)
        wrench = data["wrench"]
        ref = float(data["reference_force"])
        return StiffnessMap(
            axes=axes,
            u=data[axes[0]],
            v=data[axes[1]],
            fixed=fixed,
            quantities={name: masked(name) for name in names},
            reachable=ok,
            actuators=str(data["actuators"]),
            actuator_stiffness=data["actuator_stiffness"],
            wrench=None if np.all(np.isnan(wrench)) else wrench,
            reference_force=None if np.isnan(ref) else ref,
            design_name=str(data["design_name"]),
            refusal=data["refusal"].astype(np.int8) if "refusal" in files else None,
            dependent=dependent,
            tool_point=tool,
            geometry=str(data["geometry"]) if "geometry" in files else "frozen",
            drive_unit=str(data["drive_unit"]) if "drive_unit" in files else "",
        )
