"""Workspace bounds of every architecture against a brute-force reachability sweep."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from helpers import example_designs, is_planar, wide_design
from ppm_stiffness.core.errors import UnreachablePoseError
from ppm_stiffness.design import Design, default_design, design_from_dict, load_design
from ppm_stiffness.maps import workspace
from ppm_stiffness.maps.workspace import reachable_positions, workspace_bounds

ROOT = Path(__file__).parents[1]


def half_planes(design: Design) -> bool:
    """A planar design whose legs' limits are half-planes in (x, y) (exact bounds)."""
    return design.planar and all(leg.limit_half_planes(0.0) is not None for leg in design.legs)


#: Brute-force sweep points per axis, and the stride of the coarse pass.
N_SWEEP = 1201
COARSE = 8


def _first_reachable(mask_of: Callable[[np.ndarray], np.ndarray], start: int, step: int) -> int:
    """Index of the first fine line (column or row) with a reachable point, scanning
    from the last empty coarse line ``start`` in direction ``step`` (+-1): the strip
    between it and the first reachable coarse line, widened while its outer line is
    reachable (a reach beyond the coarse pass)."""
    lo = start
    while True:
        idx = np.arange(lo, lo + step * (COARSE + 1), step)
        hit = mask_of(idx).any(axis=1)
        if not hit[0] or lo in (0, N_SWEEP - 1):
            return int(idx[np.argmax(hit)])
        lo -= step * COARSE


def brute_box(design: Design, phi: float, around: np.ndarray) -> tuple[np.ndarray, float]:
    """Box of the reachable points of an N_SWEEP x N_SWEEP sweep over ``around`` padded
    by 10 %, and the step. A coarse pass (every COARSE-th line) finds each side; fine
    strips between the last empty and the first reachable coarse line find it to the
    fine step (1/40 of the points of the full sweep; equal to the full sweep's box on
    every case of this module when it was written)."""
    pad = 0.1 * max(around[1] - around[0], around[3] - around[2])
    xs = np.linspace(around[0] - pad, around[1] + pad, N_SWEEP)
    ys = np.linspace(around[2] - pad, around[3] + pad, N_SWEEP)
    border = np.concatenate(
        [
            reachable_positions(design, xs[[0, -1]][None, :], ys[:, None], phi).ravel(),
            reachable_positions(design, xs[None, :], ys[[0, -1]][:, None], phi).ravel(),
        ]
    )
    assert not border.any()
    coarse = reachable_positions(design, xs[None, ::COARSE], ys[::COARSE, None], phi)
    cols, rows = np.flatnonzero(coarse.any(axis=0)), np.flatnonzero(coarse.any(axis=1))

    def columns(idx: np.ndarray) -> np.ndarray:  # (len(idx), N_SWEEP)
        return reachable_positions(design, xs[idx][:, None], ys[None, :], phi)

    def lines(idx: np.ndarray) -> np.ndarray:
        return reachable_positions(design, xs[None, :], ys[idx][:, None], phi)

    box = np.array(
        [
            xs[_first_reachable(columns, COARSE * (cols[0] - 1), 1)],
            xs[_first_reachable(columns, COARSE * (cols[-1] + 1), -1)],
            ys[_first_reachable(lines, COARSE * (rows[0] - 1), 1)],
            ys[_first_reachable(lines, COARSE * (rows[-1] + 1), -1)],
        ]
    )
    return box, float(max(xs[1] - xs[0], ys[1] - ys[0]))


def assert_matches_sweep(design: Design, phi: float, box: np.ndarray, steps: float) -> None:
    ref, step = brute_box(design, phi, box)
    outward = np.array([-1.0, 1.0, -1.0, 1.0]) * (box - ref)
    # the box contains every reachable sweep point, and exceeds the sweep's box by less
    # than ``steps`` sweep steps (what a sweep can miss near the extremes)
    assert np.all(outward >= -1e-12), outward / step
    assert np.all(outward <= steps * step), outward / step


@pytest.mark.parametrize("name", example_designs(lambda d: is_planar(d) and not half_planes(d)))
@pytest.mark.parametrize("phi", [0.0, 0.3])
def test_sampled_bounds_match_a_brute_force_sweep(name: str, phi: float) -> None:
    """Measured: 0.12-1.0 sweep steps outward; 1.5 steps allowed."""
    design = load_design(ROOT / "examples" / f"{name}.toml")
    assert all(leg.limit_half_planes(phi) is None for leg in design.legs)
    box = workspace_bounds(design, phi)
    assert_matches_sweep(design, phi, box, 1.5)
    # each side is touched: reachable poses within 1e-4 of the box size inside it
    inward = 1e-4 * np.ptp(box)
    for side, value in enumerate(box):
        at = value + (inward if side % 2 == 0 else -inward)
        lo, hi = (box[2], box[3]) if side < 2 else (box[0], box[1])
        line = np.linspace(lo, hi, 100001)
        xx, yy = (np.full_like(line, at), line) if side < 2 else (line, np.full_like(line, at))
        assert reachable_positions(design, xx, yy, phi).any()


@pytest.mark.parametrize("name", example_designs(half_planes, paper=True))
def test_exact_half_plane_bounds_match_a_brute_force_sweep(name: str) -> None:
    design = (
        default_design() if name == "paper" else load_design(ROOT / "examples" / f"{name}.toml")
    )
    for phi in (0.0, 0.3):
        assert_matches_sweep(design, phi, workspace_bounds(design, phi), 2.0)


def test_half_planes_hold_for_a_rod_oblique_to_its_rail() -> None:
    """beta != 90 deg: the stroke's half-plane normal is not the rail direction; the
    exact box must equal the one the sampling method finds (to its resolution)."""
    data = wide_design().model_dump()
    data["legs"][2]["beta"] = -1.2
    design = design_from_dict(data)
    box = workspace_bounds(design, 0.0)
    sampled = workspace._sampled_bounds(design, 0.0)
    np.testing.assert_allclose(sampled, box, atol=1e-9 * np.ptp(box))
    assert_matches_sweep(design, 0.0, box, 2.0)


def test_no_reachable_orientation_raises_for_sampled_bounds() -> None:
    design = load_design(ROOT / "examples" / "3prr.toml")
    with pytest.raises(UnreachablePoseError, match="no reachable position at phi = 170.00 deg"):
        workspace_bounds(design, np.radians(170.0))
