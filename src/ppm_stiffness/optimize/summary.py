"""Summary figures of one design over its required region (one function for
``compare``, ``sweep`` and ``optimize``).

:func:`summarize` evaluates every grid pose of the region
(:func:`ppm_stiffness.optimize.region.region_poses`) with the batched model
(:func:`ppm_stiffness.maps.batch.evaluate_poses`, actuators locked) and reduces them
to a handful of numbers (:class:`RegionSummary`):

- ``covered_fraction``: the share of grid poses that are reachable and not singular;
  the design *covers* the region when it is 1;
- the minimum, mean and 5th percentile (linear interpolation between order statistics,
  ``numpy.percentile``) of k_x, k_y [N/m] and k_phi [N·m/rad], the principal
  stiffnesses of the paper's decoupling (eq. 19) as ``analyze`` prints them, at the
  design's tool point (P unless it sets one), over the covered poses;
- under a wrench (m_x, m_y, m_z, f_x, f_y, f_z [N·m, N], axes of F_b, acting at the
  tool point), from the loaded equilibrium at every covered pose
  (:func:`ppm_stiffness.optimize.loaded.loaded_twists`): ``max_displacement``, the
  largest |(dx, dy)| of the tool point [m], and ``max_rotation``, the largest |phi_z|
  [rad]. Where the loaded state cannot be solved at a covered pose (a load beyond the
  small-displacement model, no equilibrium, a singular loaded K) the worst case is
  unknown: both are +inf and ``loaded_failures`` counts those poses.

A figure that has no value (no covered pose; no wrench) is NaN in the record and
``None`` in :meth:`RegionSummary.figures`, never a number.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray, hat, rotation_z
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.loaded import loaded_twists
from ppm_stiffness.optimize.region import region_poses

#: Percentile of the stiffness figures named ``*_p5``.
PERCENTILE = 5.0

#: Every figure of a summary, in table order: name -> SI unit.
FIGURE_UNITS: dict[str, str] = {
    "covered_fraction": "1",
    **{
        f"{k}_{stat}": unit
        for k, unit in (("k_x", "N/m"), ("k_y", "N/m"), ("k_phi", "N·m/rad"))
        for stat in ("min", "mean", "p5")
    },
    "max_displacement": "m",
    "max_rotation": "rad",
}

#: Short descriptions of the figures, for tables and docs.
FIGURE_LABELS: dict[str, str] = {
    "covered_fraction": "covered fraction",
    **{
        f"{k}_{stat}": f"{k} {text}"
        for k in ("k_x", "k_y", "k_phi")
        for stat, text in (("min", "min"), ("mean", "mean"), ("p5", "5th pct"))
    },
    "max_displacement": "max |(dx, dy)|",
    "max_rotation": "max |phi_z|",
}


@dataclass(frozen=True)
class RegionSummary:
    """Summary figures of one design over a region (SI, module doc).

    Attributes
    ----------
    values : dict
        Figure name (:data:`FIGURE_UNITS`) -> value; NaN where there is none.
    poses : int
        Grid poses of the region.
    covered : int
        Poses reachable and not singular.
    loaded_failures : int
        Covered poses whose loaded state could not be solved (0 without a wrench).
    error : str or None
        Why the design could not be evaluated at all (e.g. parameter values the design
        schema refuses); then nothing is covered.
    """

    values: dict[str, float]
    poses: int
    covered: int
    loaded_failures: int = 0
    error: str | None = None
    first_loaded_failure: tuple[float, float, float] | None = field(default=None)

    @property
    def covers(self) -> bool:
        """Every grid pose reachable and not singular (and no evaluation error)."""
        return self.error is None and self.poses > 0 and self.covered == self.poses

    @property
    def covered_fraction(self) -> float:
        return self.values["covered_fraction"]

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def figures(self) -> dict[str, float | None]:
        """The figures for JSON and CSV: NaN as None (a missing value, never a number)."""
        return {k: (None if math.isnan(v) else v) for k, v in self.values.items()}

    @classmethod
    def failed(cls, poses: int, error: str) -> RegionSummary:
        """The record of a design that could not be evaluated (``error`` says why)."""
        values = {name: math.nan for name in FIGURE_UNITS}
        values["covered_fraction"] = 0.0
        return cls(values=values, poses=poses, covered=0, error=error)


def _statistics(values: FloatArray, prefix: str) -> dict[str, float]:
    if values.size == 0:
        return {f"{prefix}_{s}": math.nan for s in ("min", "mean", "p5")}
    return {
        f"{prefix}_min": float(np.min(values)),
        f"{prefix}_mean": float(np.mean(values)),
        f"{prefix}_p5": float(np.percentile(values, PERCENTILE)),
    }


def _shift(offsets: FloatArray) -> FloatArray:
    """Per pose ``A = [[1, hat(-r)], [0, 1]]`` (n, 6, 6): ``K_T = A K A^T``,
    ``w_P = A^-1 w_T``, for tool offsets ``r = T - P`` (n, 3) [m, F_b]."""
    a = np.tile(np.eye(6), (offsets.shape[0], 1, 1))
    a[:, :3, 3:] = hat(-offsets)
    return a


def _tool_offsets(poses: FloatArray, tool_point: FloatArray) -> FloatArray:
    """``T - P`` at each pose (n, 3) [m, F_b]: :func:`ppm_stiffness.model.tool_offset`
    for many poses."""
    return np.asarray(rotation_z(poses[:, 2]) @ np.asarray(tool_point, dtype=float))


def _principal(design: Design, poses: FloatArray) -> tuple[BoolArray, FloatArray]:
    """Covered mask (n,) and (k_x, k_y, k_phi) (3, n) at the tool point."""
    from ppm_stiffness.maps import batch

    tool = np.asarray(design.tool_point, dtype=float)
    at_tool = bool(np.any(tool))
    res = batch.evaluate_poses(design, poses, matrices=at_tool)
    valid = np.asarray(res.valid, dtype=bool)
    k = np.stack([np.asarray(res.k_x.filled(np.nan)), np.asarray(res.k_y.filled(np.nan))])
    k = np.concatenate([k, np.asarray(res.k_phi.filled(np.nan))[None]])
    if at_tool and np.any(valid):
        assert res.stiffness is not None
        a = _shift(_tool_offsets(poses[valid], tool))
        k_t = a @ res.stiffness[valid] @ np.swapaxes(a, -1, -2)
        pr = batch.principal_from_matrices(k_t)
        k[:, valid] = np.stack([pr.k_x, pr.k_y, pr.k_phi])
    return valid, k


def _loaded(
    design: Design, poses: FloatArray, wrench: FloatArray
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """|(dx, dy)| [m] and |phi_z| [rad] of the tool point under ``wrench`` (at the tool
    point) at poses (n, 3), and the solved mask."""
    tool = np.asarray(design.tool_point, dtype=float)
    if not np.any(tool):
        twists, solved = loaded_twists(design, poses, wrench)
        return np.hypot(twists[:, 3], twists[:, 4]), np.abs(twists[:, 2]), solved
    offsets = _tool_offsets(poses, tool)
    twists = np.full((poses.shape[0], 6), np.nan)
    solved = np.zeros(poses.shape[0], dtype=bool)
    for phi in np.unique(poses[:, 2]):  # the offset, so the wrench at P, depends on phi
        rows = np.flatnonzero(poses[:, 2] == phi)
        w_p = np.linalg.solve(_shift(offsets[rows[:1]])[0], wrench)
        twists[rows], solved[rows] = loaded_twists(design, poses[rows], w_p)
    v = twists[:, 3:] + np.cross(twists[:, :3], offsets)
    return np.hypot(v[:, 0], v[:, 1]), np.abs(twists[:, 2]), solved


def summarize(
    design: Design, region: RequiredRegionModel, wrench: ArrayLike | None = None
) -> RegionSummary:
    """The summary figures of ``design`` over ``region`` (module doc).

    Parameters
    ----------
    design : Design
        Any architecture.
    region : RequiredRegionModel
        The grid of poses (:func:`ppm_stiffness.optimize.region.region_of`).
    wrench : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N], axes of F_b, at the tool point; adds
        ``max_displacement`` and ``max_rotation`` (NaN without it).

    Returns
    -------
    RegionSummary
    """
    from ppm_stiffness.statics.loading import validate_wrench

    w = None if wrench is None else validate_wrench(wrench)
    poses = region_poses(region).reshape(-1, 3)
    covered, k = _principal(design, poses)
    values: dict[str, float] = {"covered_fraction": float(np.mean(covered))}
    for row, name in enumerate(("k_x", "k_y", "k_phi")):
        values.update(_statistics(k[row, covered], name))
    values["max_displacement"] = values["max_rotation"] = math.nan
    failures = 0
    first: tuple[float, float, float] | None = None
    if w is not None and np.any(covered):
        disp, rot, solved = _loaded(design, poses[covered], w)
        failures = int(np.count_nonzero(~solved))
        if failures:
            values["max_displacement"] = values["max_rotation"] = math.inf
            bad = poses[covered][~solved][0]
            first = (float(bad[0]), float(bad[1]), float(bad[2]))
        else:
            values["max_displacement"] = float(np.max(disp))
            values["max_rotation"] = float(np.max(rot))
    return RegionSummary(
        values=values,
        poses=int(poses.shape[0]),
        covered=int(np.count_nonzero(covered)),
        loaded_failures=failures,
        first_loaded_failure=first,
    )


def summarize_candidate(
    design: Design,
    values: Mapping[str, float] | None,
    region: RequiredRegionModel,
    wrench: ArrayLike | None = None,
) -> RegionSummary:
    """:func:`summarize` of ``design`` with parameters ``values`` (name or glob -> SI
    value) set: the task one worker runs for one design (the design travels, not the
    maps). Parameter values the design schema refuses give a :meth:`RegionSummary.failed`
    record (nothing covered) instead of an error, so that an optimiser can step over
    them.
    """
    from ppm_stiffness.optimize.executors import limit_threads

    limit_threads()
    if values:
        try:
            design = design.with_parameters(dict(values))
        except DesignError as exc:
            return RegionSummary.failed(math.prod(region.grid), str(exc))
    return summarize(design, region, wrench)
