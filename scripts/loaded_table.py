"""The measured table of docs/statics.md, "When the difference matters": every shipped
design at its home pose under the paper's load and a handling load B, frozen against
moving geometry.

Columns (the same definitions as the page):

- ``K_F vs K``: ``||K_F - K_frozen|| / ||K_frozen||`` (length-balanced Frobenius norms,
  ``statics.moving.relative_difference``);
- ``geometric``: the geometric term ``K_F - K_elastic`` against K_F;
- ``deflection``: ``|t_moving - t_frozen| / |t_frozen|`` of the length-balanced twists of
  P (the moving solution's rotation vector and displacement against the frozen twist);
- ``moved``: P's displacement under the moving model [mm];
- ``load margin``: :func:`ppm_stiffness.statics.margin.load_margin` of the load.

Loads (the CLI's FX,FY,FZ,MX,MY,MZ at P): the paper's ``5,5,20,0,0,0.1`` and B
``200,200,-500,2,2,5``. A design that cannot carry a load says why (the refusal).
Run: .venv/bin/python scripts/loaded_table.py [--designs NAME,...]
(about a minute: most of it the load margins). The same numbers, one design and load at
a time: ``ppm-stiffness analyze --design FILE --wrench ... --geometry moving``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from ppm_stiffness.core.conventions import BALANCE
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.equilibrium import equilibrium
from ppm_stiffness.statics.margin import load_margin
from ppm_stiffness.statics.moving import (
    moving_states,
    relative_difference,
    relative_size,
    state_of,
)

ROOT = Path(__file__).parents[1]
#: (name, file or None for the built-in design).
DESIGNS = (
    ("paper 3-PPR (built-in)", None),
    ("symmetric 3-PPR", "symmetric_3ppr.toml"),
    ("redundant 4-PPR", "redundant_4ppr.toml"),
    ("3-RPR", "3rpr.toml"),
    ("3-PRR", "3prr.toml"),
    ("3-RRR", "3rrr.toml"),
    ("hexapod 6-UPS", "hexapod_6ups.toml"),
    ("3-PRS", "3prs.toml"),
    ("3-RPS", "3rps.toml"),
)
#: The loads as the library's (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P.
LOADS = {
    "paper": np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0]),
    "B": np.array([2.0, 2.0, 5.0, 200.0, 200.0, -500.0]),
}


def row(design: Design, wrench: np.ndarray) -> list[str]:
    """The table's cells for one design and load (module doc)."""
    batch = moving_states(design, home_pose(design)[None], wrench)
    code = Refusal(int(batch.refusal[0]))
    if code != Refusal.NONE:
        return [f"refused: {code.reason}, from {batch.factor[0]:.3g} times the load", *[""] * 4]
    state = state_of(batch, 0)
    frozen = equilibrium(design, wrench, state.pose).twist  # the frozen equilibrium
    k_f = state.stiffness_matrix
    moved = np.linalg.norm(state.twist[3:]) * 1e3
    gap = np.linalg.norm((state.twist - frozen) / BALANCE) / np.linalg.norm(frozen / BALANCE)
    margin = load_margin(design, wrench)
    return [
        f"{100 * relative_difference(k_f, state.frozen_stiffness):.3g} %",
        f"{100 * relative_size(state.geometric_stiffness, k_f):.3g} %",
        f"{100 * gap:.2g} %",
        f"{moved:.3g} mm",
        margin.describe().replace(" times the load", ""),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", help="comma-separated names of DESIGNS (default all)")
    args = parser.parse_args()
    chosen = None if args.designs is None else set(args.designs.split(","))
    print("| design | load | K_F vs K | geometric | deflection | moved | load margin |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, file in DESIGNS:
        if chosen is not None and name not in chosen and str(file) not in chosen:
            continue
        design = default_design() if file is None else load_design(ROOT / "examples" / file)
        for load, wrench in LOADS.items():
            print(f"| {name} | {load} | " + " | ".join(row(design, wrench)) + " |", flush=True)


if __name__ == "__main__":
    main()
