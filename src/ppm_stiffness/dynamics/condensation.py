"""A leg's moving bodies from the platform's twist, and the leg's mass matrix at P.

The leg's springs (the actuator's among them) and passive joints are those of its
stiffness (:func:`ppm_stiffness.legs.chain.leg_springs`): spring coordinates theta with
unit twists J (6 x m) at P and compliance C, passive joint coordinates q with unit
twists J_q (6 x p). When the platform moves by the twist t (at P, axes of F_b) the
massless leg follows statically (Guyan condensation): the wrench it transmits is
``lambda = K_leg t`` and the coordinates' rates solve the bordered system of its
stiffness (eq. 1)

    [[J C J^T, J_q], [J_q^T, 0]] [lambda; dq] = [t; 0],    d theta = C J^T lambda.

Where the leg's joints can produce t this is its rigid-body kinematics (a motion that
needs the actuator shared between the actuator spring and the structure in series);
where they cannot (the constraint directions of a leg with fewer than six freedoms,
the out-of-plane directions of a planar leg) it is the elastic pattern of its springs.
It is evaluated as the stiffness is (:mod:`ppm_stiffness.core.solver`): with W a basis
of the wrenches reciprocal to J_q and ``G_e = J_e^T W`` for each element e,
``A = sum_e G_e^T C_e G_e``, ``lambda = W A^-1 W^T t`` and ``d theta_e = C_e G_e A^-1
W^T t``; the passive rates are then the least-squares (exact) solution of
``J_q dq = t - J d theta`` in length-balanced units.

A body's twist is the sum of the unit twists of the coordinates upstream of it in the
chain times their rates (a serial chain, twists at P at the current configuration):

- a link's start moves with the chain before it, its end with its own tip springs
  added, and the link between them takes the static shape of a cantilever loaded at
  its tip (:mod:`ppm_stiffness.dynamics.links`: the Euler-Bernoulli cubic; a uniform
  link's consistent mass, a body with a given centre of mass riding on that shape);
  for a rigid motion of the link it is the rigid body's kinetic energy;
- a joint's moving parts (:class:`~ppm_stiffness.legs.chain.JointMass`: an actuator's
  carriage) move with the joint's output, downstream of all its coordinates; a rotor
  turns with the rate of the joint's first coordinate (for the actuated joint: the
  actuator spring's, i.e. the actuator compliance sits between the motor's command and
  its rotor, as a servo's does), with kinetic energy ``rotor * rate^2 / 2``.

The leg's mass matrix at P is ``M_leg = sum_b T_b^T M_b T_b`` with T_b (6 x 6) mapping
the platform twist to body b's and M_b its spatial inertia at P
(:mod:`ppm_stiffness.dynamics.inertia`; a link's term is the same form over its two
ends' twists); the twists of the chain's last element add up to t itself (a check the
tests make). Springs are massless.

Elastic freedoms (``Joint.elastic``, a flexure) are coordinates of the leg with a
stiffness K_e and twists J_e: the bordered form of the stiffness
(:mod:`ppm_stiffness.core.solver`) gives their rates with the wrench,
``[[A, H], [H^T, -K_e]] [y; de] = [W^T t; 0]`` with ``H = W^T J_e`` and
``lambda = W y`` (never ``1/K_e`` in a compliance); the bodies after them move with
``J_e de`` as after a passive joint. A flexure in parallel with the actuator adds to
its stiffness.

Every array has leading batch axes (...): the chain's points and axes (..., 3) or
(3,), the actuator stiffness (...) or a scalar. A pose whose passive twists are
dependent gives NaN.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import TWIST_BALANCE, FloatArray
from ppm_stiffness.dynamics.inertia import spatial_inertia
from ppm_stiffness.dynamics.links import link_mass_matrix
from ppm_stiffness.legs import engine
from ppm_stiffness.legs.chain import (
    CONSTRAINED,
    Element,
    Joint,
    Link,
    check_chain,
    constrained_screws,
    elastic_stiffnesses,
    freedom_count,
    freedom_screws,
    link_screws,
)


@dataclass(frozen=True)
class LegMotion:
    """How a leg's chain follows the platform's twist (module doc).

    Attributes
    ----------
    before, after : list of ndarray (..., 6, 6)
        For each element of the chain, the maps from the platform twist (at P) to the
        twist (at P) of the body just upstream of it (its input) and just downstream
        of it (its output). ``after[-1]`` is the identity.
    first_rates : list of ndarray (..., 6) or None
        For each joint, the map from the platform twist to the rate of its first
        coordinate (the actuator spring for the actuated joint, its first freedom for a
        passive one; None for a rigid joint without freedoms, or a link).
    """

    before: list[FloatArray]
    after: list[FloatArray]
    first_rates: list[FloatArray | None]


def _batch_shape(chain: Sequence[Element], actuator_stiffness: ArrayLike) -> tuple[int, ...]:
    shapes = [
        np.shape(e.point)[:-1] if isinstance(e, Joint) else np.shape(e.end)[:-1] for e in chain
    ]
    return np.broadcast_shapes(*shapes, np.shape(actuator_stiffness))


def _solve(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a^-1 b`` for stacks of symmetric positive definite (n, r, r) and (n, r, k), by
    a Cholesky factorisation vectorised over the stack (r small: a few elementwise
    operations per entry instead of one LAPACK call per matrix); NaN where a is not
    finite or not positive definite."""
    r = a.shape[-1]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        low: list[list[FloatArray]] = []  # L[i][j], j <= i
        inv: list[FloatArray] = []  # 1 / L[j][j]
        for i in range(r):
            row: list[FloatArray] = []
            for j in range(i + 1):
                s = a[:, i, j]
                other = row if j == i else low[j]
                for k in range(j):
                    s = s - row[k] * other[k]
                if j < i:
                    row.append(s * inv[j])
                else:
                    d = np.sqrt(np.where(s > 0.0, s, np.nan))
                    row.append(d)
                    inv.append(1.0 / d)
            low.append(row)
        y: list[FloatArray] = []  # L y = b, rows (n, k)
        for i in range(r):
            s = b[:, i, :]
            for k in range(i):
                s = s - low[i][k][:, None] * y[k]
            y.append(s * inv[i][:, None])
        x: list[FloatArray] = [y[0]] * r  # L^T x = y
        for i in reversed(range(r)):
            s = y[i]
            for k in range(i + 1, r):
                s = s - low[k][i][:, None] * x[k]
            x[i] = s * inv[i][:, None]
        out = np.stack(x, axis=1) if r else np.zeros(b.shape)
    return np.where(np.isfinite(out), out, np.nan)


def _springs(
    chain: Sequence[Element], batch: tuple[int, ...], k_act: FloatArray
) -> tuple[
    list[tuple[FloatArray, FloatArray, bool] | None],
    list[FloatArray | None],
    list[tuple[FloatArray, FloatArray] | None],
]:
    """Each element's springs ``(J_e (n, 6, m), C_e, diagonal)`` (C_e (n, m) diagonal
    for a joint, (n, 6, 6) for a link) and passive twists (n, 6, p_e), or None."""
    n = math.prod(batch)

    def flat(a: ArrayLike, tail: tuple[int, ...]) -> FloatArray:
        return np.broadcast_to(np.asarray(a, dtype=float), batch + tail).reshape((n,) + tail)

    springs: list[tuple[FloatArray, FloatArray, bool] | None] = []
    passive: list[FloatArray | None] = []
    elastic_out: list[tuple[FloatArray, FloatArray] | None] = []
    for element in chain:
        if isinstance(element, Link):
            screws, length = link_screws(element)
            compliance = cantilever_compliance(element.section, length)
            springs.append((flat(screws, (6, 6)), flat(compliance, (6, 6)), False))
            passive.append(None)
            elastic_out.append(None)
            continue
        free = flat(freedom_screws(element), (6, freedom_count(element)))
        cols: list[FloatArray] = []
        comp: list[FloatArray] = []
        elastic = elastic_stiffnesses(element)
        if element.actuated:
            cols.append(free[..., :1])
            k_total = k_act if elastic is None else k_act + elastic[0]
            comp.append((1.0 / k_total)[:, None])
            passive.append(None)
            elastic_out.append(None)
        elif elastic is not None:  # elastic freedoms: kept by the bordered solve
            elastic_out.append((free, elastic))
            passive.append(None)
        else:
            passive.append(free)
            elastic_out.append(None)
        if element.springs is not None:
            c = CONSTRAINED[element.kind]
            cols.append(flat(constrained_screws(element), (6, c)))
            comp.append(flat(1.0 / np.asarray(element.springs, dtype=float), (c,)))
        springs.append(
            (np.concatenate(cols, axis=-1), np.concatenate(comp, axis=-1), True) if cols else None
        )
    return springs, passive, elastic_out


def _bordered_rates(
    a: FloatArray, h_e: FloatArray, k_e: FloatArray, w: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """``y`` (n, r, 6) and the elastic rates (n, e, 6) from
    ``[[A, H], [H^T, -K_e]] [y; de] = [W^T; 0]`` (the bordered form of
    :mod:`ppm_stiffness.core.solver`); NaN where it is singular or not finite."""
    n, r, e = a.shape[0], a.shape[-1], h_e.shape[-1]
    m = np.zeros((n, r + e, r + e))
    m[:, :r, :r] = 0.5 * (a + np.swapaxes(a, -1, -2))
    m[:, :r, r:] = h_e
    m[:, r:, :r] = np.swapaxes(h_e, -1, -2)
    idx = np.arange(r, r + e)
    m[:, idx, idx] = -k_e
    rhs = np.zeros((n, r + e, 6))
    rhs[:, :r, :] = np.swapaxes(w, -1, -2)
    out = np.full((n, r + e, 6), np.nan)
    good = np.isfinite(m).all(axis=(1, 2)) & np.isfinite(rhs).all(axis=(1, 2))
    for i in np.flatnonzero(good):
        try:
            out[i] = np.linalg.solve(m[i], rhs[i])
        except np.linalg.LinAlgError:
            continue
    return out[:, :r, :], out[:, r:, :]


def leg_motion(
    chain: Sequence[Element],
    actuator_stiffness: ArrayLike,
    elements: Sequence[int] | None = None,
) -> LegMotion:
    """The twists of a leg's bodies per unit platform twist (module doc).

    Parameters
    ----------
    chain : sequence of Joint and Link
        Base to platform; points and axes (..., 3) or (3,), relative to P, axes of F_b.
    actuator_stiffness : array_like (...) or scalar
        [N/m or N·m/rad]: the locked actuator's, or the tangent one of a loaded state.
    elements : sequence of int, optional
        The elements whose maps are wanted (the others are left as zeros); all if None.

    Returns
    -------
    LegMotion

    Notes
    -----
    With ``X_e = J_e C_e G_e`` (6 x r) the spring twists of the elements up to e add up
    to ``(sum X) A^-1 W^T``: the running sum stays in the r-dimensional space of the
    transmitted wrenches, and only the wanted elements' maps are formed.
    """
    check_chain(chain)
    batch = _batch_shape(chain, actuator_stiffness)
    n = math.prod(batch)
    wanted = set(range(len(chain)) if elements is None else elements)
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), batch).reshape(n)
    springs, passive, elastic = _springs(chain, batch, k_act)
    q_all = [q[:, :, j] for q in passive if q is not None for j in range(q.shape[-1])]
    w = engine.reciprocal_basis(q_all, n)  # (n, 6, r)
    r = w.shape[-1]
    a = np.zeros((n, r, r))
    xs: list[FloatArray | None] = []  # X_e = J_e C_e G_e, (n, 6, r)
    cgs: list[FloatArray | None] = []  # C_e G_e, (n, m, r)
    with np.errstate(invalid="ignore", over="ignore"):
        for block in springs:
            if block is None:
                xs.append(None)
                cgs.append(None)
                continue
            j_e, c_e, diagonal = block
            g = np.swapaxes(j_e, -1, -2) @ w  # (n, m, r)
            cg = c_e[:, :, None] * g if diagonal else c_e @ g
            a += np.swapaxes(g, -1, -2) @ cg
            cgs.append(cg)
            xs.append(j_e @ cg)
        elastic_rates: list[FloatArray | None] = [None] * len(chain)
        elastic_sum = np.zeros((n, 6, 6))  # sum of J_e de over the elastic freedoms
        if any(x is not None for x in elastic):
            j_all = np.concatenate([f[0] for f in elastic if f is not None], axis=-1)
            k_all = np.concatenate(
                [np.broadcast_to(f[1], (n, f[1].size)) for f in elastic if f is not None], axis=-1
            )
            h, de = _bordered_rates(a, np.swapaxes(w, -1, -2) @ j_all, k_all, w)
            i = 0
            for e, found in enumerate(elastic):
                if found is not None:
                    elastic_rates[e] = de[:, i : i + found[1].size, :]
                    i += found[1].size
            elastic_sum = j_all @ de
        else:
            h = _solve(0.5 * (a + np.swapaxes(a, -1, -2)), np.swapaxes(w, -1, -2))  # (n, r, 6)
        total = np.zeros((n, 6, r))
        for x in xs:
            if x is not None:
                total = total + x
        passive_rates: list[FloatArray | None] = [None] * len(chain)
        if q_all:
            residual = np.eye(6) - total @ h - elastic_sum
            jb = TWIST_BALANCE[:, None] * np.stack(q_all, axis=-1)  # (n, 6, p), (omega L, v)
            jbt = np.swapaxes(jb, -1, -2)
            dq = _solve(jbt @ jb, jbt @ (TWIST_BALANCE[:, None] * residual))  # (n, p, 6)
            i = 0
            for e, q in enumerate(passive):
                if q is not None:
                    passive_rates[e] = dq[:, i : i + q.shape[-1], :]
                    i += q.shape[-1]

        zero = np.zeros(batch + (6, 6))
        before: list[FloatArray] = []
        after: list[FloatArray] = []
        first: list[FloatArray | None] = []
        springs_sum = np.zeros((n, 6, r))
        passive_sum = np.zeros((n, 6, 6))
        for e, element in enumerate(chain):
            if e in wanted:
                before.append((springs_sum @ h + passive_sum).reshape(batch + (6, 6)))
            x_e, q, dq_e = xs[e], passive[e], passive_rates[e]
            if x_e is not None:
                springs_sum = springs_sum + x_e
            if q is not None and dq_e is not None:
                passive_sum = passive_sum + q @ dq_e
            flexure, de_e = elastic[e], elastic_rates[e]
            if flexure is not None and de_e is not None:
                passive_sum = passive_sum + flexure[0] @ de_e
            if e in wanted:
                after.append((springs_sum @ h + passive_sum).reshape(batch + (6, 6)))
            else:
                before.append(zero)
                after.append(zero)
            rate: FloatArray | None = None
            cg_e = cgs[e]
            if isinstance(element, Joint) and e in wanted:
                if element.actuated and cg_e is not None:
                    rate = (cg_e[:, :1, :] @ h)[:, 0, :].reshape(batch + (6,))
                elif de_e is not None:
                    rate = de_e[:, 0, :].reshape(batch + (6,))
                elif dq_e is not None:
                    rate = dq_e[:, 0, :].reshape(batch + (6,))
            first.append(rate)
    return LegMotion(before=before, after=after, first_rates=first)


def point_inertia(mass: float, point: ArrayLike) -> FloatArray:
    """The spatial inertia (..., 6, 6) at P of a point mass at ``point`` (..., 3)."""
    p = np.asarray(point, dtype=float)
    return spatial_inertia(mass, p, np.zeros(p.shape[:-1] + (3, 3)))


def _carries(element: Element) -> bool:
    return element.mass is not None or (isinstance(element, Link) and element.end_mass > 0.0)


def has_masses(chain: Sequence[Element]) -> bool:
    """True if an element of the chain carries a mass or a rotor."""
    return any(_carries(e) for e in chain)


def _congruence(t: FloatArray, m: FloatArray) -> FloatArray:
    """``T^T M T`` for stacks (..., 6, 6)."""
    return np.asarray(np.swapaxes(t, -1, -2) @ m @ t)


def leg_mass_matrix(chain: Sequence[Element], actuator_stiffness: ArrayLike) -> FloatArray:
    """The leg's mass matrix (..., 6, 6) at P, axes of F_b, order (omega, v) [kg·m^2,
    kg·m, kg] (module doc); zeros for a leg without masses.

    Parameters
    ----------
    chain : sequence of Joint and Link
    actuator_stiffness : array_like (...) or scalar [N/m or N·m/rad]
    """
    batch = _batch_shape(chain, actuator_stiffness)
    total = np.zeros(batch + (6, 6))
    if not has_masses(chain):
        return total
    carrying = [e for e, element in enumerate(chain) if _carries(element)]
    motion = leg_motion(chain, actuator_stiffness, carrying)
    for e, element in enumerate(chain):
        if isinstance(element, Link):
            if element.mass is not None:
                total = total + link_mass_matrix(element, motion.before[e], motion.after[e])
            if element.end_mass > 0.0:
                end = point_inertia(element.end_mass, element.end)
                total = total + _congruence(motion.after[e], end)
            continue
        parts = element.mass
        if parts is None:
            continue
        if parts.mass > 0.0:
            total = total + _congruence(motion.after[e], point_inertia(parts.mass, element.point))
        rate = motion.first_rates[e]
        if parts.rotor > 0.0 and rate is not None:
            total = total + parts.rotor * rate[..., :, None] * rate[..., None, :]
    return np.asarray(0.5 * (total + np.swapaxes(total, -1, -2)))
