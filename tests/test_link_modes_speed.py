"""The fast path of the legs' own modes (issue 30 item 5): the same model, solved with
less work (:mod:`ppm_stiffness.dynamics.legmodes`).

Each check is against an independent computation: SciPy's dense generalised eigensolver
on the leg FE's matrices, the condensation's leg mass matrix, a per-pose generalised
eigensolve of the reduced pair. Residuals measured when the tolerances were set are
given next to each assertion."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.linalg import eigh, null_space

from ppm_stiffness.dynamics.condensation import leg_mass_matrix
from ppm_stiffness.dynamics.legmodes import (
    MECHANISM_TOLERANCE,
    _stiff_basis,
    chain_fe,
    elements_for,
    fixed_interface_modes,
    reduced_frequencies,
)
from ppm_stiffness.model import actuator_stiffness_vector, solve_legs
from ppm_stiffness.poses import full_pose
from test_link_modes import _strut


def _hexapod_chains() -> list[tuple[list[object], float]]:
    from helpers import design_named

    design = design_named("hexapod_6ups")
    p = full_pose(design, None)
    k_act = actuator_stiffness_vector(design, None)
    return [
        (leg.chain(lp), float(k))
        for leg, lp, k in zip(design.legs, solve_legs(design, p), k_act, strict=True)
    ][:2]


def _dense_omega2(chain: list[object], k_act: float, elements: int, count: int) -> np.ndarray:
    """The ``count`` lowest omega^2 of the held leg by SciPy on the dense matrices."""
    fe = chain_fe(chain, k_act, elements)  # type: ignore[arg-type]
    null = null_space(fe.screws[0])
    kz = null.T @ fe.stiffness[0] @ null
    mz = null.T @ fe.mass[0] @ null
    mu = eigh(0.5 * (mz + mz.T), 0.5 * (kz + kz.T), eigvals_only=True)  # mass may be singular
    return 1.0 / mu[::-1][:count]


@pytest.mark.parametrize("elements", [2, 8])
def test_the_modes_are_the_dense_generalised_eigenproblems(elements: int) -> None:
    """Links given as bodies (the hexapod's: fewer mass rows than directions, solved
    through the Gram matrix) and uniform links (a U-P-S strut: more rows, solved
    directly): omega^2 of :func:`fixed_interface_modes` equal SciPy's dense generalised
    eigenvalues of the same FE (measured 4e-12 relative)."""
    cases = [*_hexapod_chains(), (_strut(), 3e7)]
    for chain, k_act in cases:
        got = fixed_interface_modes(chain, k_act, 4, elements).omega2[0]  # type: ignore[arg-type]
        ref = _dense_omega2(chain, k_act, elements, got.size)
        assert got == pytest.approx(ref, rel=1e-10)


def test_the_static_shapes_carry_the_condensed_mass_closely() -> None:
    """Psi^T M_x Psi from the factored mass and the Cholesky path against the
    condensation's leg mass matrix: 1.5e-11 of its largest entry (the eigen path of
    Kz, which it replaced: 1.4e-9)."""
    for chain, k_act in _hexapod_chains():
        fe = fixed_interface_modes(chain, k_act, 2, 8).condensed_mass[0]  # type: ignore[arg-type]
        ref = leg_mass_matrix(chain, k_act)  # type: ignore[arg-type]
        assert np.max(np.abs(fe - ref)) <= 1e-10 * np.max(np.abs(ref))


def test_the_cholesky_path_is_the_eigen_path() -> None:
    """Kz's Cholesky factor (no mechanism) or its eigendecomposition (``general``): the
    same modes to the round-off of the eigen path, eps cond(Kz) (omega^2 measured
    1.8e-9 relative here: the eigen path splits the strut's degenerate pair by that,
    the Cholesky path keeps it within 4e-12; 5.8e-9 on the 6-RUS, cond(Kz) = 7e8) and
    the same coupling up to a rotation within a degenerate pair (C C^T: 6e-10 of its
    largest entry)."""
    for chain, k_act in _hexapod_chains():
        fast = fixed_interface_modes(chain, k_act, 4, 8)  # type: ignore[arg-type]
        slow = fixed_interface_modes(chain, k_act, 4, 8, general=True)  # type: ignore[arg-type]
        assert fast.omega2 == pytest.approx(slow.omega2, rel=5e-9)
        pair = fast.omega2[0, :2]
        assert pair[0] == pytest.approx(pair[1], rel=1e-10)
        cf, cs = fast.coupling[0], slow.coupling[0]
        assert np.max(np.abs(cf @ cf.T - cs @ cs.T)) <= 1e-8 * np.max(np.abs(cs @ cs.T))


def test_the_stiff_basis_uses_cholesky_and_falls_back_on_a_mechanism() -> None:
    """A positive definite Kz: ``B = L^-T`` (upper triangular, ``B^T Kz B = I``); one
    with a mechanism (a zero eigenvalue): the eigen path, the mechanism a zero column
    and ``B^T Kz B = diag(1, .., 1, 0)``."""
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(5, 5)))
    good = q @ np.diag([1.0, 2.0, 5.0, 1e3, 1e6]) @ q.T
    mechanism = q @ np.diag([0.0, 2.0, 5.0, 1e3, 1e6]) @ q.T
    basis = _stiff_basis(np.stack([good, mechanism]))
    assert np.allclose(np.tril(basis[0], -1), 0.0)
    assert basis[0].T @ good @ basis[0] == pytest.approx(np.eye(5), abs=1e-10)  # 8.8e-12
    reduced = basis[1].T @ mechanism @ basis[1]
    assert np.sort(np.diag(reduced)) == pytest.approx([0, 1, 1, 1, 1], abs=1e-9)
    assert np.sum(np.linalg.norm(basis[1], axis=0) == 0.0) == 1
    assert MECHANISM_TOLERANCE * 1e6 < 1.0  # the mechanism is far below the tolerance


def test_reduced_frequencies_batched_are_each_poses_eigenproblem() -> None:
    """Batched over poses, one M_r not positive definite among them: the others are
    SciPy's generalised eigenvalues pose by pose (measured 3e-15), that one NaN."""
    rng = np.random.default_rng(5)
    size, n = 9, 4
    a = rng.normal(size=(n, size, size))
    k = a @ np.swapaxes(a, -1, -2) + np.eye(size)
    b = rng.normal(size=(n, size, size))
    m = b @ np.swapaxes(b, -1, -2) + 0.1 * np.eye(size)
    m[2] = -np.eye(size)
    out = reduced_frequencies(k, m)
    for i in (0, 1, 3):
        lam = eigh(k[i], m[i], eigvals_only=True)[:6]
        assert out[i] == pytest.approx(np.sqrt(lam) / (2 * math.pi), rel=1e-12)
    assert np.all(np.isnan(out[2]))


def test_few_modes_use_few_elements_within_the_stated_error() -> None:
    """2 modes per leg: 2 elements per link, 4 modes: 4, more: 8 (``elements_for``);
    the hexapod leg's first own frequency with 2 elements within 5e-5 of 8 (measured
    3.6e-5 on the shipped hexapod's legs)."""
    assert [elements_for(c) for c in (1, 2, 3, 4, 5, 8, 12)] == [2, 2, 4, 4, 8, 8, 8]
    for chain, k_act in _hexapod_chains():
        coarse = fixed_interface_modes(chain, k_act, 2).frequencies[0]  # type: ignore[arg-type]
        fine = fixed_interface_modes(chain, k_act, 2, 8).frequencies[0]  # type: ignore[arg-type]
        assert coarse == pytest.approx(fine, rel=5e-5)
        assert np.all(coarse >= fine)  # a coarser mesh is stiffer


def test_each_pose_keeps_its_own_modes_in_a_batch() -> None:
    """A batch of three strut poses (the base moved sideways), the middle one not
    finite: the others keep their modes, each as alone (measured equal to 1e-15;
    before, the non-finite pose left every pose of the batch without modes), the
    middle one NaN; the reduced problem of a pose leaves out a slot it does not have."""
    from ppm_stiffness.dynamics.legmodes import reduced_matrices

    good = _strut()
    shift = np.array([[0.0, 0.0, 0.0], [np.nan, 0.0, 0.0], [0.03, -0.02, 0.0]])
    base, guide = good[1].start + shift, good[1].end + shift
    chain = [
        replace(good[0], point=base),
        replace(good[1], start=base, end=guide),
        replace(good[2], point=guide),
        replace(good[3], start=guide),
        good[4],
    ]
    batch = fixed_interface_modes(chain, 3e7, 2, 4)
    assert np.all(np.isnan(batch.omega2[1])) and np.all(np.isnan(batch.coupling[1]))
    for i in (0, 2):
        alone = [
            replace(e, **{f: getattr(e, f)[i] for f in ("point", "start", "end") if _batched(e, f)})
            for e in chain
        ]
        ref = fixed_interface_modes(alone, 3e7, 2, 4)
        assert batch.omega2[i] == pytest.approx(ref.omega2[0], rel=1e-12)
    k = np.stack([np.diag([1.0, 2, 3, 4, 5, 6])] * 2)
    m = np.stack([np.eye(6)] * 2)
    omega2 = np.array([[9.0, np.nan], [9.0, 16.0]])
    coupling = np.zeros((2, 6, 2))
    coupling[1, 0, 1] = 0.1
    f = reduced_frequencies(*reduced_matrices(k, m, omega2, coupling))
    assert f[0] == pytest.approx(np.sqrt([1, 2, 3, 4, 5, 6]) / (2 * math.pi), rel=1e-14)
    assert np.all(np.isfinite(f[1]))


def _batched(element: object, name: str) -> bool:
    return np.ndim(getattr(element, name, None)) == 2
