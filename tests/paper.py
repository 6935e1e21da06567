"""Numbers printed in the paper, and the rounding box of its matrix (22).

Matrix (22) is printed as 4 decimals x 1e5, so each nonzero entry is known to within
+-5 (N·m/rad, N or N/m). A derived quantity is "consistent with the paper" when the
printed value lies in the range the quantity spans over the matrices that round to
the printed one, widened by half a unit of the derived value's own last printed digit.
The range is taken over all 2^10 corners of the box of the 10 nonzero upper-triangle
entries plus seeded random interior points. Structural zeros stay zero.
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

#: Matrix (33), the loaded case, reassembled from the garbled fragments (NOTES.md):
#: out-of-plane entries unchanged from (22), planar block from the fragment "(32)".
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
    printed = np.asarray(printed, dtype=float)
    ok = (printed >= lo - half_unit) & (printed <= hi + half_unit)
    assert np.all(ok), f"printed {printed[~ok]} outside [{lo[~ok]}, {hi[~ok]}] +- {half_unit}"


#: The paper's 3-PPR in-plane leg geometry (Table 1, r = 30 mm, D_i = -r(cos psi_i, sin psi_i)):
#: unit in-plane wrench of each leg (m_z, f_x, f_y) = (d_i x u_i, u_i) at the centre.
_PSI = np.array([np.pi / 6, 5 * np.pi / 6, 3 * np.pi / 2])
_U = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
_D = -0.030 * np.stack([np.cos(_PSI), np.sin(_PSI)], axis=1)
LEG_WRENCHES = np.column_stack([_D[:, 0] * _U[:, 1] - _D[:, 1] * _U[:, 0], _U])
LOCKED = 1.1108e5


def loaded_from_unloaded(k_unloaded: np.ndarray, k_act: np.ndarray) -> np.ndarray:
    """Model-free route from an unloaded 3-PPR matrix to the loaded one (NOTES.md).

    Each leg transmits one in-plane force along u_i through D_i, so the planar block
    (phi_z, x, y) is ``sum_i k_i s_i s_i^T``; solve the leg stiffnesses k_i in least
    squares from the six planar entries, strip the locked actuator in series, put the
    loaded actuator back, and keep the out-of-plane block.
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
#: the diagonal of K_act under the wrench of eq. 33).
PAPER_K_ACT_LOADED = np.array([1.1108e5, 0.0516e5, 0.1912e5])
#: Their printed half-unit [N/m]: 4 decimals of 1e5. The model's 111080, 5164.98 and
#: 19119.5 N/m are within it (residuals 0, 4.98 and 0.47 N/m).
PAPER_K_ACT_HALF_UNIT = 5.0


def paper_tolerance(printed: np.ndarray, half_unit: float, residual: np.ndarray) -> np.ndarray:
    """Per-entry tolerance of a comparison with a printed paper value: the larger of the
    printed half-unit and twice the documented residual of that quantity (docs/model.md,
    "The real test: the loaded case")."""
    return np.maximum(half_unit, 2.0 * np.abs(np.asarray(residual, dtype=float)))
