"""The load margin (statics/margin.py): the buckling of a straight chain of rigid links
and torsion springs (the discrete Euler column, exact), and on the shipped designs the
factor at which the moving-geometry equilibrium ends, "no instability up to" a range,
and the stop at an actuator's stroke."""

from __future__ import annotations

import numpy as np
import pytest
from tests.helpers import design_named
from tests.paper import PAPER_WRENCH
from tests.test_moving_geometry import _straight_chain

from ppm_stiffness.core.conventions import BALANCE
from ppm_stiffness.core.errors import EquilibriumError
from ppm_stiffness.design import Design
from ppm_stiffness.poses import home_pose, task_values
from ppm_stiffness.statics.margin import (
    MarginKind,
    chains_margin,
    load_margin,
    margin_batch,
    margin_of,
)
from ppm_stiffness.statics.moving import moving_equilibrium, moving_load_states


@pytest.mark.parametrize(("n", "exact"), [(1, 1.0), (2, 0.381966), (3, 0.198062), (4, 0.120615)])
def test_straight_chain_buckles_at_the_discrete_euler_load(n: int, exact: float) -> None:
    """n rigid links of length L in a line, torsion springs k (the first at the base),
    an axial compressive force P at the tip: the first instability is at
    P L / k = 4 sin^2(pi / (2 (2n + 1))) (issue 23: 1, 0.381966, 0.198062, 0.120615),
    found to 1e-8 (measured within 2.8e-9: the tip's other springs, 1e8 times stiffer,
    shift it by about that). The buckling mode is the chain's first mode: the joints'
    rotations are the eigenvector of T^T T (T the lower triangle of ones: absolute link
    angles from joint rotations) of its largest eigenvalue, to 2e-11 (measured 4.4e-12), and
    the platform's twist is named for its dominant direction, the tip's sideways motion."""
    length, k = 0.2, 50.0
    wrench = np.array([[0.0, 0.0, 0.0, -k / length, 0.0, 0.0]])
    margin = chains_margin(_straight_chain(n, length, k), wrench, 100.0)
    formula = 4 * np.sin(np.pi / (2 * (2 * n + 1))) ** 2
    assert abs(formula - exact) < 5e-7  # the printed values
    assert margin.kind[0] == MarginKind.BIFURCATION
    assert abs(margin.factor[0] / formula - 1) < 1e-8  # measured 2.8e-9 (n = 1)
    tri = np.tril(np.ones((n, n)))
    first = np.linalg.eigh(tri.T @ tri)[1][:, -1]
    mode = margin.coordinate_modes[0][0, :n]
    mode = mode / np.linalg.norm(mode) * np.sign(mode @ first)
    np.testing.assert_allclose(mode, first, rtol=0, atol=2e-11)  # measured 4.4e-12 (n = 2)
    assert margin.mode_name(0) == "y translation"
    # measured 0 exactly (the mode's other entries are 0.9 to 4.5)
    np.testing.assert_allclose(margin.mode[0, [0, 1, 3, 5]], 0.0, rtol=0, atol=1e-15)


#: Load factors just below the paper load's limit point, where the fold's square-root law
#: holds (mu^2 of the balanced K_F is linear in the factor to 2 % over [3.26, 3.2618]).
FOLD_SCAN = (3.2615, 3.2617)


def _smallest_eigenvalues(design: Design, factors: tuple[float, ...]) -> np.ndarray:
    """The smallest real part of the eigenvalues of the length-balanced loaded tangent
    S K_F S at the exact equilibria under ``factors`` times the paper's load (row i of
    the batch is moving_equilibrium's; K_F is the finite-difference derivative of that
    equilibrium, tests/test_moving_geometry.py)."""
    batch = moving_load_states(design, np.outer(factors, PAPER_WRENCH))
    assert np.all(batch.refusal == 0)
    balanced = BALANCE[:, None] * batch.stiffness * BALANCE[None, :]
    return np.min(np.linalg.eigvals(balanced).real, axis=1)


def test_the_margin_is_where_the_equilibrium_path_ends() -> None:
    """The built-in design under the paper's load: the path turns back at 3.2618 times
    the load, the platform turned by about 57 deg about z (a limit point: the soft
    powered actuators, eq. 21, and the moving geometry). Independently of the margin's
    continuation: at a fold the smallest eigenvalue mu of K_F along the path goes as
    sqrt(lambda_c - lambda), so mu^2 at two stable equilibria just below extrapolates
    linearly to lambda_c (3.2618136 from 3.2615 and 3.2617, measured 5e-7 from the
    margin). Just above the margin no equilibrium is found."""
    design = design_named("paper")
    margin = load_margin(design, PAPER_WRENCH)
    assert margin.kind == MarginKind.LIMIT_POINT
    assert margin.mode_name == "rotation about z"
    assert margin.factor is not None
    assert "3.26181 times the load (limit point; mode: rotation about z)" in margin.describe()
    (lo, hi), (mu_lo, mu_hi) = FOLD_SCAN, _smallest_eigenvalues(design, FOLD_SCAN)
    assert mu_lo > mu_hi > 0  # stable, and softening towards the fold
    fold = hi + mu_hi**2 * (hi - lo) / (mu_lo**2 - mu_hi**2)
    assert hi < margin.factor
    assert abs(margin.factor - fold) < 3e-6  # measured 5e-7
    with pytest.raises(EquilibriumError, match="no equilibrium with moving geometry found"):
        moving_equilibrium(design, 1.005 * margin.factor * PAPER_WRENCH)


def test_no_instability_in_the_range_searched() -> None:
    design = design_named("3rpr")
    margin = load_margin(design, PAPER_WRENCH, max_factor=100.0)
    assert margin.kind == MarginKind.NONE and margin.factor is None
    assert margin.searched_up_to == 100.0
    assert margin.describe() == "no instability up to 100 times the load"


def test_the_search_stops_at_an_actuators_stroke() -> None:
    """The symmetric 3-PPR's soft actuators (the paper's law) leave their 50 mm stroke
    at about 3.9 times the paper's load, before any instability."""
    design = design_named("symmetric_3ppr")
    margin = load_margin(design, PAPER_WRENCH)
    assert margin.kind == MarginKind.STROKE and margin.factor is None
    assert 3.0 < margin.searched_up_to < 4.0
    assert margin.describe().endswith("where an actuator reaches its whole stroke")


def test_many_poses_are_the_single_poses() -> None:
    design = design_named("3rpr")
    wrench = np.array([0.0, 0.0, 0.0, 100.0, 0.0, 0.0])
    home = task_values(design, home_pose(design))  # x, y, phi
    poses = np.array([home, home + [0.005, -0.003, 0.02]])
    batch = margin_batch(design, poses, wrench)
    for i, pose in enumerate(poses):
        single = load_margin(design, wrench, pose)
        assert margin_of(batch, i).factor == pytest.approx(single.factor, rel=1e-9)
        assert margin_of(batch, i).kind == single.kind
