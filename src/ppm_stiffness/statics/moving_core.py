"""Newton's method for the equilibrium with moving geometry, and the loaded tangent K_F.

The platform is carried by legs, each a chain of coordinates x (its virtual springs'
deflections and its passive joints' displacements, :mod:`ppm_stiffness.legs.screw_chain`)
whose last body is displaced by ``g(x) = (R_x, p_x)`` from the reference configuration.
Everything is about the **load point** c, the platform point where the external wrench
acts (P, or the tool point): the twists of the chains about its reference position c0,
the platform's displacement ``(R_t, p_t)`` (the rotation and the displacement of c), the
leg wrenches ``w_i = (m_i, f_i)`` about the displaced load point c' = c0 + p_t, axes of
F_b. A leg is in equilibrium when

    closure     g(x) = (R_t, p_t),
    springs     x_s = delta_s(tau_s)   (each spring follows its law),
    passive     tau_q = 0              (passive joints carry no load),

with ``tau = J(x)^T w0`` the generalised forces, ``J(x)`` the chain's spatial Jacobian
about c0 and ``w0 = (m + p_t x f, f)`` the leg's wrench about c0; the platform is in
equilibrium when ``sum_i w_i = w``, the applied wrench (a force of fixed direction at
c and a couple of fixed direction, axes of F_b: constant in these coordinates).

Linearisation. With ``H^x_kl = w0 . [J_l, J_k]`` for l < k (0 otherwise: the derivative
of ``J_k^T w0`` along x_l at fixed w0) and ``dtau_k / dp_t = f x w_k`` (the moment arm of
c' moving), a platform twist dt = (dphi, dv) at c' (``R_t -> exp(dphi) R_t``,
``p_t -> p_t + dv``) and the increments dx, dw satisfy, per leg,

    dx_s - C_s (H^x_s dx + J'^T_s dw + P_s dt) = -(x_s - delta_s),
    H^x_q dx + J'^T_q dw + P_q dt = -tau_q,
    J'_x dx - dt = e,

C the springs' tangent compliance (``1/K_act`` of eq. 21 for the actuator, 0 for a rigid
spring: no stiffness is ever inverted), J' the twists about c' and e the closure error
(``log(R_t R_x^T)``, ``p_t - p_x``). Solved per leg (one (n + 6)-square system with the
rows and columns equilibrated) for ``dw = b + B dt``; the platform's row
``sum_i B_i dt = w - sum_i (w_i + b_i)`` gives dt. At an equilibrium (b = 0) B is the
leg's loaded tangent stiffness and

    K_F = sum_i B_i,   dw = K_F dt,

at the displaced load point c', axes of F_b; eliminating dx from the leg's rows gives the
top-left 6x6 block of the inverse of
``[[J_s A^-1 J_s^T, J_q + J_s A^-1 H_sq], [J_q^T + H_qs A^-1 J_s^T, H_qq + H_qs A^-1 H_sq]]``
with ``A = K_s - H_ss`` (the Klimchik-Pashkevich-Chablat "loaded mode", with the moving
reference point's term folded into H: ``H_kl = H^x_kl + (f x w_k) . v'_l``). At w = 0,
H = 0 and it is the bordered inverse of eq. (1): today's K.

Symmetry: ``H_kl - H_lk = m . (w_l x w_k)`` (l < k): H, and K_F, are symmetric when the
wrench at the load point is a pure force; a couple m adds ``-m^ / 2`` to K_F's rotation
block (a couple of fixed direction is not conservative under finite rotations; with the
twist update ``R -> exp(dphi) R`` this is the whole antisymmetric part).

Every array has one leading batch axis (k,): k independent problems, solved together;
each converges (or fails) on its own.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, LENGTH_SCALE, BoolArray, FloatArray, hat
from ppm_stiffness.core.pose import rotation_exp
from ppm_stiffness.legs.screw_chain import (
    ScrewChain,
    bracket_form,
    cross,
    forward,
    moving_point_jacobian,
    rotation_log,
)
from ppm_stiffness.statics import actuator as act
from ppm_stiffness.statics.moving_bars import about_displaced, bar_closure, bar_terms

#: Newton's method has converged when the relative residual (:func:`linearize`) is at
#: most this; one more step is then taken (quadratic convergence: to round-off).
RESIDUAL_TOLERANCE = 1e-10
#: Newton iterations at most, per solve (from a good start it converges in a few: the
#: tests' solves take 1 to 5).
MAX_ITERATIONS = 15
#: A relative residual above this is a diverging iteration: stopped.
DIVERGED = 1e8
#: An iteration still above this relative residual after ``SLOW_AFTER`` steps is not
#: converging (quadratically it would be far below): stopped, the step is shortened.
SLOW_RESIDUAL = 1e-6
SLOW_AFTER = 8
#: Largest platform motion of one load step along a path (rotation [rad], and
#: translation in units of :data:`~ppm_stiffness.core.conventions.LENGTH_SCALE`): a step
#: that moves more is taken again shorter, so that Newton's method cannot jump to a
#: distant equilibrium (past a limit point, to another branch) unnoticed.
MAX_STEP_MOTION = 0.05
#: A continuation step of the load margin's search is at most the one that moves the
#: platform this fraction of :data:`MAX_STEP_MOTION`, from the motion of the last step
#: scaled linearly: longer ones would mostly be taken again shorter. (The load path of
#: statics/moving_path.py keeps its halving: with this cap, the 3-RPS under 50 kN at
#: +-0.05 rad tilts, past a limit point, lands on unstable states beyond it and is
#: refused as UNSTABLE instead of NO_EQUILIBRIUM.)
MOTION_AIM = 0.8


@dataclass(frozen=True)
class PlatformChains:
    """The legs of a platform at k reference configurations.

    Attributes
    ----------
    chains : tuple of ScrewChain
        One per leg, every twist about the load point's reference position c0.
    strokes : ndarray (n_legs,) or None
        Each actuator's whole stroke [m or rad] (the displacement beyond which the
        model does not hold); None: no limit.
    """

    chains: tuple[ScrewChain, ...]
    strokes: FloatArray | None = None

    @property
    def size(self) -> int:
        return self.chains[0].size

    def take(self, index: np.ndarray) -> PlatformChains:
        """The problems ``index``."""
        return PlatformChains(
            tuple(
                replace(
                    c,
                    screws=c.screws[index],
                    compliance=c.compliance[index],
                    bars=None if c.bars is None else c.bars.take(index),
                )
                for c in self.chains
            ),
            self.strokes,
        )


@dataclass(frozen=True)
class ChainState:
    """Platform and legs at k problems (SI; module doc).

    Attributes
    ----------
    rotation : ndarray (k, 3, 3)
        R_t, the platform's rotation from its reference orientation (axes of F_b).
    translation : ndarray (k, 3) [m]
        p_t, the displacement of the load point.
    coordinates : tuple of ndarray (k, n_i)
        Each leg's coordinates [m or rad].
    wrenches : ndarray (k, n_legs, 6)
        Each leg's wrench about the displaced load point [N·m, N].
    """

    rotation: FloatArray
    translation: FloatArray
    coordinates: tuple[FloatArray, ...]
    wrenches: FloatArray

    def take(self, index: np.ndarray) -> ChainState:
        return ChainState(
            self.rotation[index],
            self.translation[index],
            tuple(x[index] for x in self.coordinates),
            self.wrenches[index],
        )

    def put(self, index: np.ndarray, other: ChainState) -> None:
        """Write ``other`` (len(index) problems) into rows ``index``, in place."""
        self.rotation[index] = other.rotation
        self.translation[index] = other.translation
        for mine, theirs in zip(self.coordinates, other.coordinates, strict=True):
            mine[index] = theirs
        self.wrenches[index] = other.wrenches

    def copy(self) -> ChainState:
        return ChainState(
            self.rotation.copy(),
            self.translation.copy(),
            tuple(x.copy() for x in self.coordinates),
            self.wrenches.copy(),
        )

    def twist(self) -> FloatArray:
        """The platform's finite displacement (k, 6): rotation vector of R_t [rad] and p_t
        [m] (the load point's displacement)."""
        return np.concatenate([rotation_log(self.rotation), self.translation], axis=1)


def zero_state(system: PlatformChains) -> ChainState:
    """The unloaded reference configuration: every coordinate and wrench 0."""
    k = system.size
    return ChainState(
        np.broadcast_to(np.eye(3), (k, 3, 3)).copy(),
        np.zeros((k, 3)),
        tuple(np.zeros((k, c.n)) for c in system.chains),
        np.zeros((k, len(system.chains), 6)),
    )


def spring_law(chain: ScrewChain, tau: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Deflections (k, n) of the chain's springs under generalised forces ``tau`` (k, n)
    and their tangent compliance (k, n, n): the linear springs' compliance, the
    actuator's ``delta(G)`` and ``1/K_act(G)`` (eq. 20-21); 0 for passive coordinates.
    A drive in parallel with a flexure k_h: the drive's share G of the column's force
    (:func:`ppm_stiffness.statics.actuator.drive_force`), ``delta(G)`` and
    ``1/(K_act(G) + k_h)``."""
    defl = np.einsum("kij,kj->ki", chain.compliance, tau)
    c_tan = chain.compliance.copy()
    if chain.elastic is not None:  # an elastic coordinate's deflection tau / k
        e = np.flatnonzero(chain.elastic)
        defl[:, e] = tau[:, e] / chain.elastic[e]
    if chain.actuator is not None:
        a = chain.actuator
        if chain.law is None:  # pragma: no cover - a ScrewChain is built with its law
            raise ValueError("an actuator column needs its law")
        g = act.drive_force(chain.law, chain.parallel, tau[:, a])
        defl[:, a] = act.actuator_displacement(chain.law, g)
        c_tan[:, a, a] = 1.0 / (act.stiffness_from_force(chain.law, g) + chain.parallel)
    return defl, c_tan


@dataclass(frozen=True)
class LegLinearization:
    """One leg's Newton step (module doc): ``dx = dx0 + dx_t dt``, ``dw = dw0 + dw_t dt``.

    Attributes
    ----------
    dx0 : (k, n), dx_t : (k, n, 6), dw0 : (k, 6), dw_t : (k, 6, 6)
    residual : (k,)
        The leg's relative residual (closure, springs, passive joints).
    forces : (k, n)
        The generalised forces tau [N·m or N].
    ok : (k,) bool
        The leg's system was solved (finite).
    """

    dx0: FloatArray
    dx_t: FloatArray
    dw0: FloatArray
    dw_t: FloatArray
    residual: FloatArray
    forces: FloatArray
    ok: BoolArray


def _solve_equilibrated(a: FloatArray, rhs: FloatArray) -> tuple[FloatArray, BoolArray]:
    """``a z = rhs`` (k, N, N), (k, N, c) with rows then columns scaled to unit maximum;
    NaN and False where a problem's matrix is singular."""
    with np.errstate(divide="ignore", invalid="ignore"):
        row = np.max(np.abs(a), axis=2, keepdims=True)
        row = np.where(row > 0, row, 1.0)
        a1 = a / row
        col = np.max(np.abs(a1), axis=1, keepdims=True)
        col = np.where(col > 0, col, 1.0)
        a2 = a1 / col
        b = rhs / row
    ok = np.all(np.isfinite(a2), axis=(1, 2)) & np.all(np.isfinite(b), axis=(1, 2))
    out = _solve_all(a2, b) if ok.all() else None  # the usual case: one batched solve
    if out is None:
        out = np.full(rhs.shape, np.nan)
        idx = np.flatnonzero(ok)
        if idx.size:
            try:
                out[idx] = np.linalg.solve(a2[idx], b[idx])
            except np.linalg.LinAlgError:
                for i in idx:
                    try:
                        out[i] = np.linalg.solve(a2[i], b[i])
                    except np.linalg.LinAlgError:
                        ok[i] = False
    out = out / np.swapaxes(col, 1, 2)
    ok &= np.all(np.isfinite(out), axis=(1, 2))
    return out, ok


def _solve_all(a: FloatArray, rhs: FloatArray) -> FloatArray | None:
    """``np.linalg.solve`` of every problem at once (each is solved on its own: the same
    numbers as one problem at a time), None if one of them is singular."""
    try:
        return np.asarray(np.linalg.solve(a, rhs), dtype=float)
    except np.linalg.LinAlgError:
        return None


def _balanced_norm(w: FloatArray) -> FloatArray:
    """``max |(m / L, f)|`` of wrenches (..., 6) [N]."""
    return np.asarray(np.max(np.abs(w * BALANCE), axis=-1))


#: ``BALANCE ** -1`` (L, L, L, 1, 1, 1): a twist (rotation, displacement) in metres.
_TWIST_SCALE = BALANCE[None, :] ** -1


def _displacement_size(rotation: FloatArray, translation: FloatArray) -> FloatArray:
    """The platform's displacement (k,) [m] against which a leg's closure error is
    measured: ``max |(log(R_t) L, p_t)|``, at least 1e-6 L."""
    return np.asarray(
        np.maximum(
            np.max(
                np.abs(np.concatenate([rotation_log(rotation) * LENGTH_SCALE, translation], 1)), 1
            ),
            1e-6 * LENGTH_SCALE,
        )
    )


def linearize_leg(
    chain: ScrewChain,
    coordinates: FloatArray,
    wrench: FloatArray,
    rotation: FloatArray,
    translation: FloatArray,
    geometric: bool = True,
    displacement_size: FloatArray | None = None,
) -> LegLinearization:
    """One leg's Newton step at a state (module doc).

    Parameters
    ----------
    chain : ScrewChain
    coordinates : (k, n)
    wrench : (k, 6)
        The leg's wrench about the displaced load point.
    rotation, translation : (k, 3, 3), (k, 3)
        The platform's displacement (R_t, p_t).
    geometric : bool
        False: without the second-derivative terms (H = 0, P = 0): the tangent of the
        springs alone at the displaced geometry (K_F's elastic part).
    displacement_size : (k,), optional
        :func:`_displacement_size` of (rotation, translation), the same for every leg
        (:func:`linearize` computes it once); computed here if None.
    """
    k, n = coordinates.shape
    kin = forward(chain.screws, coordinates)
    jac = kin.jacobian
    f = wrench[:, 3:]
    w0 = wrench.copy()
    w0[:, :3] += cross(translation, f)
    tau = np.einsum("kin,ki->kn", jac, w0)
    defl, c_tan = spring_law(chain, tau)
    if geometric:
        hx = np.tril(np.swapaxes(bracket_form(jac, w0), 1, 2), -1)
        pt = np.zeros((k, n, 6))
        pt[:, :, 3:] = cross(f[:, None, :], np.swapaxes(jac[:, :3, :], 1, 2))
    else:
        hx = np.zeros((k, n, n))
        pt = np.zeros((k, n, 6))
    jt = np.swapaxes(moving_point_jacobian(jac, translation), 1, 2)  # (k, n, 6): dtau/dw
    jx = moving_point_jacobian(jac, kin.translation)
    closure = np.concatenate(
        [rotation_log(rotation @ np.swapaxes(kin.rotation, 1, 2)), translation - kin.translation],
        axis=1,
    )
    size = n + 6
    a = np.zeros((k, size, size))
    rhs = np.zeros((k, size, 7))
    a[:, :n, :n] = np.eye(n) - c_tan @ hx
    a[:, :n, n:] = -c_tan @ jt
    rhs[:, :n, 0] = defl - coordinates
    rhs[:, :n, 1:] = c_tan @ pt
    q = np.flatnonzero(chain.passive)
    a[:, q, :n] = hx[:, q, :]
    a[:, q, n:] = jt[:, q, :]
    rhs[:, q, 0] = -tau[:, q]
    rhs[:, q, 1:] = -pt[:, q, :]
    if chain.elastic is not None:  # stiffness form: H dx - k dx_e + ... = -(tau_e - k x_e)
        e = np.flatnonzero(chain.elastic)
        k_e = chain.elastic[e]
        a[:, e, :n] = hx[:, e, :]
        a[:, e, e] -= k_e
        a[:, e, n:] = jt[:, e, :]
        rhs[:, e, 0] = -(tau[:, e] - k_e * coordinates[:, e])
        rhs[:, e, 1:] = -pt[:, e, :]
    a[:, n:, :n] = jx
    rhs[:, n:, 0] = closure
    rhs[:, n:, 1:] = np.eye(6)
    sol, ok = _solve_equilibrated(a, rhs)
    # Relative residual: closure against the size of the displacement (at least
    # 1e-6 L), spring deflections against the largest deflection, passive forces
    # against the leg's load (generalised forces of rotations divided by L).
    scale = np.where(chain.rotational, LENGTH_SCALE, 1.0)
    if displacement_size is None:
        displacement_size = _displacement_size(rotation, translation)
    r_closure = np.max(np.abs(closure * _TWIST_SCALE), axis=1) / displacement_size
    x_scaled = coordinates * scale
    r_spring = np.abs((coordinates - defl) * scale)
    held = chain.passive if chain.elastic is None else chain.passive | (chain.elastic > 0)
    r_spring = np.where(held, 0.0, r_spring)
    x_size = np.max(np.abs(np.where(chain.passive, 0.0, x_scaled)), axis=1)
    r_springs = np.max(r_spring, axis=1) / np.where(x_size > 0, x_size, 1.0)
    load = np.maximum(_balanced_norm(w0), np.max(np.abs(tau / scale), axis=1))
    unbalanced = tau if chain.elastic is None else tau - chain.elastic * coordinates
    r_passive = np.max(np.abs(np.where(held, unbalanced / scale, 0.0)), axis=1, initial=0.0)
    r_passive = r_passive / np.where(load > 0, load, 1.0)
    residual = np.maximum(np.maximum(r_closure, r_springs), r_passive)
    return LegLinearization(
        dx0=sol[:, :n, 0],
        dx_t=sol[:, :n, 1:],
        dw0=sol[:, n:, 0],
        dw_t=sol[:, n:, 1:],
        residual=np.where(ok, residual, np.inf),
        forces=tau,
        ok=ok,
    )


def linearize_bar_leg(
    chain: ScrewChain,
    coordinates: FloatArray,
    wrench: FloatArray,
    rotation: FloatArray,
    translation: FloatArray,
    geometric: bool,
    displacement_size: FloatArray,
) -> LegLinearization:
    """:func:`linearize_leg` of a leg ending in two two-force bars (``chain.bars``;
    :mod:`ppm_stiffness.statics.moving_bars`, where the equations are): coordinates
    (k, n + 2), the arm's then the bars' axial forces [N]. ``geometric=False``: without
    the arm's brackets and the bars' turning (K_F's elastic part)."""
    k, size = coordinates.shape
    n = size - 2
    t = bar_terms(chain, coordinates, rotation, translation, geometric)
    jac, w0 = t["jac"], t["w0"]
    tau = np.einsum("kin,ki->kn", jac, w0)
    defl, c_tan = spring_law(chain, tau)
    hx = np.zeros((k, n, n))
    if geometric:
        hx = np.tril(np.swapaxes(bracket_form(jac, w0), 1, 2), -1)
    jt = np.swapaxes(jac, 1, 2)
    t_x = hx + jt @ t["w_x"]  # dtau / dx, dN, dt
    t_n = jt @ t["w_n"]
    t_t = jt @ t["w_t"]
    a = np.zeros((k, size, size))
    rhs = np.zeros((k, size, 7))
    a[:, :n, :n] = np.eye(n) - c_tan @ t_x
    a[:, :n, n:] = -c_tan @ t_n
    rhs[:, :n, 0] = defl - t["x"]
    rhs[:, :n, 1:] = c_tan @ t_t
    held = chain.passive.copy()
    if chain.elastic is not None:
        held |= chain.elastic > 0
    h = np.flatnonzero(held)
    k_e = np.zeros(n) if chain.elastic is None else chain.elastic
    a[:, h, :n] = t_x[:, h, :] - np.diag(k_e)[h]
    a[:, h, n:] = t_n[:, h, :]
    unbalanced = tau - k_e * t["x"]
    rhs[:, h, 0] = -unbalanced[:, h]
    rhs[:, h, 1:] = -t_t[:, h, :]
    assert chain.bars is not None
    closure = bar_closure(chain, t)
    a[:, n:, :n] = t["l_x"]
    a[:, n:, n:] = -chain.bars.compliance * np.eye(2)
    rhs[:, n:, 0] = -closure
    rhs[:, n:, 1:] = -t["l_t"]
    sol, ok = _solve_equilibrated(a, rhs)
    dz0, dz_t = sol[:, :, 0], sol[:, :, 1:]
    w_z = np.concatenate([t["w_x"], t["w_n"]], axis=2)  # (k, 6, n + 2)
    now = about_displaced(w0, translation)
    dw0 = now - wrench + _about_displaced_increment(w_z @ dz0[..., None], translation)[..., 0]
    dw_t = _about_displaced_increment(w_z @ dz_t + t["w_t"], translation)
    if geometric:  # the moment arm of c' moving: -dv x f
        dw_t[:, :3, 3:] += hat(w0[:, 3:])
    scale = np.where(chain.rotational, LENGTH_SCALE, 1.0)
    x_scaled = t["x"] * scale
    r_spring = np.where(held, 0.0, np.abs((t["x"] - defl) * scale))
    x_size = np.max(np.abs(np.where(chain.passive, 0.0, x_scaled)), axis=1, initial=0.0)
    r_springs = np.max(r_spring, axis=1, initial=0.0) / np.where(x_size > 0, x_size, 1.0)
    load = np.maximum(_balanced_norm(w0), np.max(np.abs(tau / scale), axis=1, initial=0.0))
    load = np.where(load > 0, load, 1.0)
    r_passive = np.max(np.abs(np.where(held, unbalanced / scale, 0.0)), axis=1, initial=0.0)
    r_bars = np.max(np.abs(closure), axis=1) / displacement_size
    r_wrench = _balanced_norm(now - wrench) / load
    residual = np.max([r_springs, r_passive / load, r_bars, r_wrench], axis=0)
    return LegLinearization(
        dx0=dz0,
        dx_t=dz_t,
        dw0=dw0,
        dw_t=dw_t,
        residual=np.where(ok, residual, np.inf),
        forces=np.concatenate([tau, t["force"]], axis=1),
        ok=ok,
    )


def _about_displaced_increment(dw: FloatArray, translation: FloatArray) -> FloatArray:
    """Wrench increments (k, 6, c) about c0 taken about c' = c0 + p_t:
    ``dm - p_t x df``."""
    out = dw.copy()
    out[:, :3, :] -= cross(translation[:, None, :], np.swapaxes(dw[:, 3:, :], 1, 2)).swapaxes(1, 2)
    return out


@dataclass(frozen=True)
class Linearization:
    """All legs' steps at k problems: the platform's tangent K (k, 6, 6) = sum B_i, the
    right-hand side and the relative residual (k,) (legs' and the platform's force
    balance)."""

    legs: tuple[LegLinearization, ...]
    stiffness: FloatArray
    unbalance: FloatArray
    residual: FloatArray
    leg_residual: FloatArray
    ok: BoolArray


def linearize(
    system: PlatformChains, state: ChainState, wrench: FloatArray, geometric: bool = True
) -> Linearization:
    """Every leg's step and the platform's row at a state, under ``wrench`` (k, 6) at
    the load point."""
    disp = _displacement_size(state.rotation, state.translation)
    out: list[LegLinearization | None] = [None] * len(system.chains)
    for group in _stackable(system.chains, system.size):
        if len(group) == 1:
            i = group[0]
            c = system.chains[i]
            out[i] = (linearize_leg if c.bars is None else linearize_bar_leg)(
                c,
                state.coordinates[i],
                state.wrenches[:, i],
                state.rotation,
                state.translation,
                geometric,
                disp,
            )
            continue
        stacked = _linearize_stacked(system, state, group, geometric, disp)
        for i, leg in zip(group, stacked, strict=True):
            out[i] = leg
    legs = tuple(leg for leg in out if leg is not None)
    stiffness = np.sum([leg.dw_t for leg in legs], axis=0)
    total = state.wrenches.sum(axis=1)
    unbalance = wrench - total - np.sum([leg.dw0 for leg in legs], axis=0)
    size = np.maximum(_balanced_norm(wrench), np.max(_balanced_norm(state.wrenches), axis=1))
    r_force = _balanced_norm(wrench - total) / np.where(size > 0, size, 1.0)
    residual = np.max([leg.residual for leg in legs], axis=0)
    ok = np.all([leg.ok for leg in legs], axis=0) & np.all(np.isfinite(stiffness), axis=(1, 2))
    return Linearization(legs, stiffness, unbalance, np.maximum(residual, r_force), residual, ok)


#: Problems solved as one batch by :func:`linearize` at most (legs of one structure
#: stacked): larger batches of (n + 6)-square systems leave the cache (the hexapod's
#: 10 x 10 margin map, 62 poses: every leg stacked was no faster than leg by leg; two
#: legs at a time 14-16 s of CPU against 16-17 s, load 4.5-6.9, noisy).
STACKED_PROBLEMS = 128


def _same_structure(a: ScrewChain, b: ScrewChain) -> bool:
    """Whether two legs' chains differ only in their screws and compliances (their
    steps can be solved as one batch: the same numbers as each on its own)."""
    if a.bars is not None or b.bars is not None or a.screws.shape != b.screws.shape:
        return False
    if a.actuator != b.actuator or a.law != b.law or a.parallel != b.parallel:
        return False
    if a.elastic is None or b.elastic is None:
        if a.elastic is not b.elastic:
            return False
    elif not np.array_equal(a.elastic, b.elastic):
        return False
    return bool(np.array_equal(a.passive, b.passive) and np.array_equal(a.rotational, b.rotational))


def _stackable(chains: tuple[ScrewChain, ...], size: int = 1) -> list[list[int]]:
    """The legs in groups of the same structure (:func:`_same_structure`), in order of
    their first leg, each group of at most :data:`STACKED_PROBLEMS` problems at ``size``
    problems per leg (at least one leg)."""
    most = max(STACKED_PROBLEMS // max(size, 1), 1)
    groups: list[list[int]] = []
    for i, c in enumerate(chains):
        for g in groups:
            if len(g) < most and _same_structure(chains[g[0]], c):
                g.append(i)
                break
        else:
            groups.append([i])
    return groups


def _linearize_stacked(
    system: PlatformChains,
    state: ChainState,
    group: list[int],
    geometric: bool,
    disp: FloatArray,
) -> list[LegLinearization]:
    """:func:`linearize_leg` of the legs ``group`` (of one structure) as one batch of
    ``len(group) * k`` problems (leg-major), split back per leg: every problem is
    solved on its own, so each leg's numbers are those of its own call."""
    k = system.size
    g = len(group)
    first = system.chains[group[0]]
    chain = replace(
        first,
        screws=np.concatenate([system.chains[i].screws for i in group]),
        compliance=np.concatenate([system.chains[i].compliance for i in group]),
    )
    lin = linearize_leg(
        chain,
        np.concatenate([state.coordinates[i] for i in group]),
        np.concatenate([state.wrenches[:, i] for i in group]),
        np.concatenate([state.rotation] * g),
        np.concatenate([state.translation] * g),
        geometric,
        np.concatenate([disp] * g),
    )
    return [
        LegLinearization(
            dx0=lin.dx0[j * k : (j + 1) * k],
            dx_t=lin.dx_t[j * k : (j + 1) * k],
            dw0=lin.dw0[j * k : (j + 1) * k],
            dw_t=lin.dw_t[j * k : (j + 1) * k],
            residual=lin.residual[j * k : (j + 1) * k],
            forces=lin.forces[j * k : (j + 1) * k],
            ok=lin.ok[j * k : (j + 1) * k],
        )
        for j in range(g)
    ]


def platform_step(lin: Linearization, fixed: bool = False) -> FloatArray:
    """The platform twist dt (k, 6) of a Newton step: ``K dt = unbalance`` (solved in
    length-balanced units; least squares where K is exactly singular); 0 with ``fixed``
    (the platform held)."""
    k = lin.stiffness.shape[0]
    if fixed:
        return np.zeros((k, 6))
    kb = lin.stiffness / BALANCE[None, :, None] / BALANCE[None, None, :]
    rhs = lin.unbalance / BALANCE
    out = np.full((k, 6), np.nan)
    idx = np.flatnonzero(lin.ok)
    try:
        out[idx] = np.linalg.solve(kb[idx], rhs[idx][..., None])[..., 0]
    except np.linalg.LinAlgError:  # a K exactly singular (at a bifurcation point)
        for i in idx:
            out[i] = np.linalg.lstsq(kb[i], rhs[i], rcond=None)[0]
    return np.asarray(out / BALANCE)


def apply_step(state: ChainState, lin: Linearization, dt: FloatArray) -> ChainState:
    """The state after a Newton step with platform twist dt (k, 6)."""
    rot = rotation_exp(dt[:, :3]) @ state.rotation
    coords = tuple(
        x + leg.dx0 + np.einsum("knj,kj->kn", leg.dx_t, dt)
        for x, leg in zip(state.coordinates, lin.legs, strict=True)
    )
    dw = np.stack([leg.dw0 + np.einsum("kij,kj->ki", leg.dw_t, dt) for leg in lin.legs], axis=1)
    return ChainState(rot, state.translation + dt[:, 3:], coords, state.wrenches + dw)


@dataclass(frozen=True)
class NewtonResult:
    """:func:`newton` at k problems.

    Attributes
    ----------
    state : ChainState
        The solution where converged (the last iterate elsewhere).
    converged : (k,) bool
    stiffness : (k, 6, 6)
        K_F at the solution (NaN where not converged).
    forces : tuple of (k, n_i)
        Each leg's generalised forces at the solution.
    iterations : (k,) int
    """

    state: ChainState
    converged: BoolArray
    stiffness: FloatArray
    forces: tuple[FloatArray, ...]
    iterations: np.ndarray


def newton(
    system: PlatformChains, start: ChainState, wrench: FloatArray, fixed: bool = False
) -> NewtonResult:
    """Newton's method from ``start`` under ``wrench`` (k, 6) at the load point, every
    problem on its own (module doc); with ``fixed`` the platform stays where ``start``
    has it and only the legs are solved (the wrench the legs then carry is the one
    that holds the platform there).

    Converged: the relative residual at most :data:`RESIDUAL_TOLERANCE`, after which
    one more step is taken and K_F is evaluated there.
    """
    k = system.size
    state = start.copy()
    stiffness = np.full((k, 6, 6), np.nan)
    forces = tuple(np.zeros((k, c.n)) for c in system.chains)
    converged = np.zeros(k, dtype=bool)
    failed = np.zeros(k, dtype=bool)
    polished = np.zeros(k, dtype=bool)
    iterations = np.zeros(k, dtype=int)
    for _ in range(MAX_ITERATIONS + 2):
        idx = np.flatnonzero(~converged & ~failed)
        if idx.size == 0:
            break
        sub_sys = system if idx.size == k else system.take(idx)  # take copies: skipped
        sub = state.take(idx)
        lin = linearize(sub_sys, sub, wrench[idx])
        residual = lin.leg_residual if fixed else lin.residual
        finish = polished[idx] & lin.ok
        if np.any(finish):
            rows = idx[finish]
            stiffness[rows] = lin.stiffness[finish]
            for mine, leg in zip(forces, lin.legs, strict=True):
                mine[rows] = leg.forces[finish]
            converged[rows] = True
        slow = (iterations[idx] >= SLOW_AFTER) & (residual > SLOW_RESIDUAL)
        bad = ~lin.ok | ~(residual <= DIVERGED) | slow | (iterations[idx] >= MAX_ITERATIONS)
        failed[idx[bad & ~finish]] = True
        go = ~finish & ~bad
        polished[idx[go & (residual <= RESIDUAL_TOLERANCE)]] = True
        if not np.any(go):
            continue
        rows = idx[go]
        sel = np.flatnonzero(go)
        every = sel.size == go.size
        sub_lin = (
            lin
            if every
            else Linearization(
                tuple(
                    replace(
                        leg,
                        dx0=leg.dx0[sel],
                        dx_t=leg.dx_t[sel],
                        dw0=leg.dw0[sel],
                        dw_t=leg.dw_t[sel],
                        residual=leg.residual[sel],
                        forces=leg.forces[sel],
                        ok=leg.ok[sel],
                    )
                    for leg in lin.legs
                ),
                lin.stiffness[sel],
                lin.unbalance[sel],
                lin.residual[sel],
                lin.leg_residual[sel],
                lin.ok[sel],
            )
        )
        dt = platform_step(sub_lin, fixed)
        stepped = apply_step(sub if every else sub.take(sel), sub_lin, dt)
        finite = np.isfinite(stepped.wrenches).all(axis=(1, 2)) & np.isfinite(dt).all(axis=1)
        state.put(rows[finite], stepped if finite.all() else stepped.take(np.flatnonzero(finite)))
        failed[rows[~finite]] = True
        iterations[rows] += 1
    return NewtonResult(state, converged, stiffness, forces, np.where(converged, iterations, -1))


def motion(a: ChainState, b: ChainState) -> FloatArray:
    """How far the platform moves from state a to state b (k,): the largest of the
    rotation [rad] and the load point's displacement divided by L."""
    rot = rotation_log(b.rotation @ np.swapaxes(a.rotation, 1, 2))
    disp = (b.translation - a.translation) / LENGTH_SCALE
    return np.asarray(np.max(np.abs(np.concatenate([rot, disp], axis=1)), axis=1))


def step_per_motion(step: FloatArray, moved: FloatArray) -> FloatArray:
    """Load steps (k,) over the platform motion (:func:`motion`) they gave: inf where the
    platform did not move (no cap on the next step), NaN where the motion is NaN."""
    out = np.full(np.shape(step), np.inf)
    np.divide(step, moved, out=out, where=moved > 0)
    return np.where(np.isnan(moved), np.nan, out)


def stability_index(stiffness: FloatArray) -> FloatArray:
    """The smallest real part of the eigenvalues of the length-balanced K_F (k,) [N/m]:
    positive where the state is stable; it reaches 0 where det K_F does (a limit or a
    bifurcation point; for a symmetric K_F its smallest eigenvalue). NaN where K_F is
    not finite."""
    kb = stiffness * BALANCE[None, :, None] * BALANCE[None, None, :]
    good = np.all(np.isfinite(kb), axis=(1, 2))
    out = np.full(kb.shape[0], np.nan)
    if np.any(good):
        out[good] = np.min(np.linalg.eigvals(kb[good]).real, axis=1)
    return out


def relative_size(a: ArrayLike, reference: ArrayLike) -> float:
    """``||S a S|| / ||S reference S||`` of 6x6 stiffness matrices (Frobenius norms of
    the length-balanced matrices, :data:`~ppm_stiffness.core.conventions.BALANCE`)."""
    s = BALANCE[:, None] * BALANCE[None, :]
    return float(np.linalg.norm(np.asarray(a) * s) / np.linalg.norm(np.asarray(reference) * s))


def relative_difference(a: ArrayLike, b: ArrayLike) -> float:
    """``||S (a - b) S|| / ||S b S||`` (:func:`relative_size` of the difference)."""
    return relative_size(np.asarray(a) - np.asarray(b), b)
