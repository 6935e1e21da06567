"""Numbers printed in the paper, and the rounding box of its matrix (22).

Matrix (22) is printed as 4 decimals x 1e5, so each nonzero entry is known to within
+-5 (N·m/rad, N or N/m). A derived quantity is "consistent with the paper" when the
printed value lies in the range the quantity spans over the matrices that round to
the printed one, widened by half a unit of the derived value's own last printed digit.
The range is taken over all 2^11 corners of the box of the 11 nonzero upper-triangle
entries plus 300 seeded random interior points. Structural zeros stay zero.

The loaded case (33)-(35) and Table 5 is computed from printed inputs as well: the
unloaded (22) and the loaded actuator stiffnesses K_act (section "Actuation compliance
effect", 4 decimals x 1e5 N/m). :func:`loaded_rounding_range` carries both roundings to
a loaded quantity. Where the model's value is compared with its own recorded output
instead (a regression pin), :func:`regression_pin` says so by its name.
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import product
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

EQ22 = np.loadtxt(
    Path(__file__).parents[1] / "src/ppm_stiffness/data/paper_eq22.csv", delimiter=","
)
HALF_UNIT_22 = 5.0  # half of 0.0001e5

#: Matrix (33), the loaded case, reassembled from the fragments the text garbles: the
#: last column [0.0323, -0.0398, 0, 0, 0, 1.4229]e5 printed as "(33)" and the matrix
#: printed a second time as "(32)" (whose planar block differs from (22)'s); the
#: out-of-plane entries are those of (22) (the actuators act in the plane only).
EQ33 = np.array(
    [
        [750, 60, 0, 0, 0, 3230],
        [60, 1430, 0, 0, 0, -3980],
        [0, 0, 30, -420, -520, 0],
        [0, 0, -420, 13850, 0, 0],
        [0, 0, -520, 0, 29540, 0],
        [3230, -3980, 0, 0, 0, 142290],
    ],
    dtype=float,
)

#: Loading case of section "Actuation compliance effect": f = [5, 5, 20] N, m_z = 0.1 N·m,
#: in the library's wrench order (m_x, m_y, m_z, f_x, f_y, f_z).
PAPER_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])


def _box_samples(matrix: np.ndarray, n_random: int = 300, seed: int = 0) -> list[np.ndarray]:
    iu = [(i, j) for i in range(6) for j in range(i, 6) if matrix[i, j] != 0]
    out = []
    for signs in product((-1.0, 1.0), repeat=len(iu)):
        m = matrix.copy()
        for (i, j), s in zip(iu, signs, strict=True):
            m[i, j] += s * HALF_UNIT_22
            m[j, i] = m[i, j]
        out.append(m)
    rng = np.random.default_rng(seed)
    for _ in range(n_random):
        m = matrix.copy()
        for i, j in iu:
            m[i, j] += rng.uniform(-HALF_UNIT_22, HALF_UNIT_22)
            m[j, i] = m[i, j]
        out.append(m)
    return out


_SAMPLES: list[np.ndarray] | None = None


def rounding_range(func: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Elementwise (min, max) of ``func`` over matrices that round to (22)."""
    global _SAMPLES
    if _SAMPLES is None:
        _SAMPLES = _box_samples(EQ22)
    values = np.array([np.asarray(func(m), dtype=float) for m in _SAMPLES])
    return values.min(axis=0), values.max(axis=0)


def assert_in_rounding_range(
    func: Callable[[np.ndarray], np.ndarray], printed: ArrayLike, half_unit: float
) -> None:
    """Assert the printed values lie in the rounding range widened by ``half_unit``."""
    lo, hi = rounding_range(func)
    assert_in_range(printed, lo, hi, half_unit, "printed")


def assert_in_range(
    values: ArrayLike, lo: np.ndarray, hi: np.ndarray, half_unit: ArrayLike, what: str
) -> None:
    """Assert ``lo - half_unit <= values <= hi + half_unit`` elementwise."""
    v = np.asarray(values, dtype=float)
    h = np.broadcast_to(np.asarray(half_unit, dtype=float), v.shape)
    ok = (v >= lo - h) & (v <= hi + h)
    assert np.all(ok), f"{what} {v[~ok]} outside [{lo[~ok]}, {hi[~ok]}] +- {h[~ok]}"


#: The paper's 3-PPR in-plane leg geometry (Table 1, r = 30 mm, D_i = -r(cos psi_i, sin psi_i)):
#: unit in-plane wrench of each leg (m_z, f_x, f_y) = (d_i x u_i, u_i) at the centre.
_PSI = np.array([np.pi / 6, 5 * np.pi / 6, 3 * np.pi / 2])
_U = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
_D = -0.030 * np.stack([np.cos(_PSI), np.sin(_PSI)], axis=1)
LEG_WRENCHES = np.column_stack([_D[:, 0] * _U[:, 1] - _D[:, 1] * _U[:, 0], _U])
LOCKED = 1.1108e5


def loaded_from_unloaded(k_unloaded: np.ndarray, k_act: np.ndarray) -> np.ndarray:
    """Model-free route from an unloaded 3-PPR matrix to the loaded one.

    The paper's reasoning after (33): the actuators act only on the planar entries.
    Each leg transmits one in-plane force along u_i through D_i, so the planar block
    (phi_z, x, y) is ``sum_i k_i s_i s_i^T`` (eq. 1 with the legs' wrenches); solve the
    leg stiffnesses k_i in least squares from the six planar entries, strip the locked
    actuator in series, put the loaded actuator back, and keep the out-of-plane block.
    docs/model.md ("The real test: the loaded case") uses this route.
    """
    idx = [2, 3, 4]
    planar = k_unloaded[np.ix_(idx, idx)]
    iu = np.triu_indices(3)
    basis = np.stack([np.outer(s, s)[iu] for s in LEG_WRENCHES], axis=1)
    k_leg = np.linalg.lstsq(basis, planar[iu], rcond=None)[0]
    structural = 1.0 / (1.0 / k_leg - 1.0 / LOCKED)
    k_new = 1.0 / (1.0 / structural + 1.0 / np.asarray(k_act))
    out = k_unloaded.copy()
    pairs = zip(k_new, LEG_WRENCHES, strict=True)
    out[np.ix_(idx, idx)] = sum(k * np.outer(s, s) for k, s in pairs)
    return out


#: The paper's loaded actuator stiffnesses [N/m] (section "Actuation compliance effect",
#: under the wrench that gives (33)).
PAPER_K_ACT_LOADED = np.array([1.1108e5, 0.0516e5, 0.1912e5])
#: Their printed half-unit [N/m]: 4 decimals of 1e5. The model's 111080, 5164.98 and
#: 19119.5 N/m are within it (residuals 0, 4.98 and 0.47 N/m).
PAPER_K_ACT_HALF_UNIT = 5.0


def loaded_rounding_range(
    func: Callable[[np.ndarray], np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """Elementwise (min, max) of ``func(K_loaded)`` over the printed inputs' rounding.

    ``K_loaded = loaded_from_unloaded(K, K_act)`` for K in the rounding box of (22)
    (:func:`rounding_range`) and K_act = the printed loaded actuator stiffnesses. The
    rounding of K_act (+-5 N/m each) is added to first order: each of the three enters
    with the change of ``func`` over its half-unit, measured at (22). Measured against
    the 2^14 corners of the joint box (2^11 of (22) times 2^3 of K_act) on the
    quantities of tests/test_model_paper.py: this range falls short of the corners' by
    at most 6e-4 of its width (0.0018 N on kappa, 0.007 N/m on a spring constant),
    far below the half-units a printed value is allowed.
    """
    lo, hi = rounding_range(lambda k: func(loaded_from_unloaded(k, PAPER_K_ACT_LOADED)))
    widen = np.zeros_like(lo)
    for j in range(PAPER_K_ACT_LOADED.size):
        step = np.zeros(PAPER_K_ACT_LOADED.size)
        step[j] = PAPER_K_ACT_HALF_UNIT
        up = np.asarray(func(loaded_from_unloaded(EQ22, PAPER_K_ACT_LOADED + step)), dtype=float)
        down = np.asarray(func(loaded_from_unloaded(EQ22, PAPER_K_ACT_LOADED - step)), dtype=float)
        widen += 0.5 * np.abs(up - down)
    return lo - widen, hi + widen


#: Relative tolerance of a regression pin: the model's outputs of the loaded case agree
#: to at most 4e-15 relative between three numerical routes (the full model, the
#: model-free route of :func:`loaded_from_unloaded` applied to the model's own unloaded
#: K, and a symmetric-definite eigen-solver in place of ``numpy.linalg.eig``); 1e-13
#: leaves room for other BLAS/LAPACK builds and nothing for a change of the model.
PIN_RTOL = 1e-13


def regression_pin(
    actual: ArrayLike, pinned: ArrayLike, *, paper: ArrayLike, why: str, rtol: float = PIN_RTOL
) -> None:
    """Assert that ``actual`` still equals ``pinned``, the model's own output recorded
    when the pin was written. This is not a comparison with the paper: ``paper`` (the
    printed value) and ``why`` (why the model differs from it) are shown next to it, so
    that a failing pin is read against the paper. Update a pin only for an understood
    change of the model, and docs/model.md's table with it."""
    a = np.asarray(actual, dtype=float)
    p = np.asarray(pinned, dtype=float)
    bad = np.abs(a - p) > rtol * np.abs(p)
    assert not bad.any(), (
        f"regression pin moved: model {a[bad]} against pinned {p[bad]} (rtol {rtol:g}); "
        f"paper prints {np.asarray(paper)}; the model differs from the paper because {why}"
    )
