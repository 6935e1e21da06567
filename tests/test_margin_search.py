"""The load margin's continuation (statics/margin.py): a step is at most the one that
moves the platform :data:`MOTION_AIM` of the most a step may move, judged from the last
step's motion, so that fewer steps are taken again shorter. The margins equal those of
the search without that cap (8ed1dfb: a step doubled after each stable step, quartered
when it moved too far), pinned below, to a few times 1e-9 relative (the searches stop
at a relative bracket of 1e-9), with about a third fewer Newton solves at a limit point.

Regression pins: the factor and the Newton solves of ``margin_batch`` at 8ed1dfb.
"""

from __future__ import annotations

import numpy as np
import pytest
from tests.helpers import design_named
from tests.paper import PAPER_WRENCH

from ppm_stiffness.statics.margin import MOTION_AIM, MarginKind, margin_batch

#: name: (design, task pose, wrench, at the tool point, kind, factor and solves at 8ed1dfb)
CASES = {
    "paper": ("paper", [0.0, 0.0, 0.0], PAPER_WRENCH, False, MarginKind.LIMIT_POINT,
              3.2618141136261727, 83),
    "3rps": ("3rps", [0.35, 0.0, 0.0], [2.0, 2.0, 5.0, 200.0, 200.0, -500.0], True,
             MarginKind.LIMIT_POINT, 35.283023974916546, 80),
    "3rps-buckling": ("3rps", [0.35, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0, -2e4], False,
                      MarginKind.BIFURCATION, 1.522077042571769, 13),
}  # fmt: skip


@pytest.mark.parametrize("case", CASES)
def test_the_margin_is_the_uncapped_searchs_in_fewer_solves(case: str) -> None:
    name, pose, wrench, at_tool, kind, factor, solves = CASES[case]
    design = design_named(name)
    tool = design.tool_point if at_tool else None
    batch = margin_batch(design, np.array([pose]), np.asarray(wrench, dtype=float), tool)
    assert batch.kind[0] == kind
    # measured 2.9e-10 (paper), 7.0e-10 (3-RPS), 0 (the bifurcation: the same steps)
    assert batch.factor[0] == pytest.approx(factor, rel=3e-9)
    # measured 54 of 83 and 56 of 80 solves at the limit points; 13 of 13
    limit = 0.75 * solves if kind == MarginKind.LIMIT_POINT else solves
    assert batch.steps[0] <= limit
    assert 0 < MOTION_AIM < 1
