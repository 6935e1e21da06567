"""A leg ending in two two-force bars (a parallelogram forearm) in the moving geometry.

The frozen model writes a parallelogram with ball joints at its corners as an
equivalent chain (two passive P joints normal to the bars and a U,
:mod:`ppm_stiffness.legs.types._parallelogram`): exact at the pose it is written at, to
first order. Under load the bars swing: a bar's axial force N turns with it, which the
chain's prismatic joints (sliding without turning the force) do not do. The geometric
stiffness of a bar of length l under N, ``(N/l)(I - n n^T)`` on the difference of its
ends' translations, is missing there. So in the moving geometry the bars are
themselves: two two-force members, each an axial spring of compliance c (``1/k_bar``,
0 for rigid bars) between a near end E_j carried by the chain's last body (the arm)
and a far end F_j carried by the platform. Their forces N_j (tension positive) are
two more coordinates of the leg; with ``d_j = F_j - E_j``, ``l_j = |d_j|``,
``n_j = d_j / l_j`` and the rest lengths L_j (their lengths at the reference
configuration), a leg is in equilibrium when

    bars        l_j - L_j - c N_j = 0,
    springs     x_s = delta_s(tau_s),   passive  tau_q = 0,   elastic  tau_e = k x_e,

with ``tau = J_A(x)^T w0`` the arm chain's generalised forces under the bars' wrench
on it, ``w0 = sum_j N_j (E_j x n_j ; n_j)`` (about c0; the same on the platform:
a bar's two end forces are opposite and on one line). The leg's wrench about the
displaced load point c' is ``(m0 - p_t x f, f)``.

Linearisation (notation of :mod:`ppm_stiffness.statics.moving_core`): the arm moves
E_j by ``V_j dx`` (``V_j = v + w x E_j`` of the spatial Jacobian's columns), a
platform twist dt = (dphi, dv) at c' moves F_j by ``dphi x (F_j - p_t) + dv``;
``dl_j = n_j . (dF_j - dE_j)``, ``dn_j = (I - n_j n_j^T)(dF_j - dE_j) / l_j`` and

    dw0 = sum_j [ (E_j x n_j ; n_j) dN_j + N_j (dE_j x n_j + E_j x dn_j ; dn_j) ],

whose ``dn_j`` terms are the bars' geometric stiffness; ``dtau = H^x dx + J^T dw0``.
The leg's (n + 2)-square system in (dx, dN) is solved for each column of
(1, dt), giving ``dw = dw0 + dw_t dt`` as for every other leg; the leg's wrench in
the state is kept equal to the one its coordinates give (its difference enters dw0
and the residual), so the platform's Newton step is the same. At zero load this is
the frozen K exactly (two axial springs k_bar at the corners are the chain's
``2 k_bar`` along n and ``|a x n|^2 k_bar w^2/2`` about mu).
"""

from __future__ import annotations

import numpy as np

from ppm_stiffness.core.conventions import FloatArray, hat
from ppm_stiffness.legs.screw_chain import (
    BarPair,
    ScrewChain,
    cross,
    forward,
)


def bar_ends(
    bars: BarPair,
    arm_rotation: FloatArray,
    arm_translation: FloatArray,
    rotation: FloatArray,
    translation: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """The bars' near and far ends (k, 2, 3) relative to c0 [m], the arm displaced by
    (R_A, p_A) and the platform by (R_t, p_t) from the reference configuration."""
    near = np.einsum("kij,kbj->kbi", arm_rotation, bars.near) + arm_translation[:, None]
    far = np.einsum("kij,kbj->kbi", rotation, bars.far) + translation[:, None]
    return near, far


def bar_wrench(near: FloatArray, direction: FloatArray, force: FloatArray) -> FloatArray:
    """The bars' wrench on the arm (and the leg's on the platform) about c0 (k, 6):
    ``sum_j N_j (E_j x n_j ; n_j)``."""
    lines = np.concatenate([cross(near, direction), direction], axis=-1)  # (k, 2, 6)
    return np.asarray(np.einsum("kbi,kb->ki", lines, force))


def bar_terms(
    chain: ScrewChain,
    coordinates: FloatArray,
    rotation: FloatArray,
    translation: FloatArray,
    geometric: bool,
) -> dict[str, FloatArray]:
    """Everything the leg's linearisation needs at a state (module doc): the arm's
    Jacobian, the bars' ends, lengths, directions and forces, the wrench about c0 and
    its derivatives ``w_x`` (k, 6, n), ``w_n`` (k, 6, 2), ``w_t`` (k, 6, 6) and the
    bars' length derivatives ``l_x`` (k, 2, n), ``l_t`` (k, 2, 6)."""
    bars = chain.bars
    assert bars is not None
    n = chain.screws.shape[-1]
    x, force = coordinates[:, :n], coordinates[:, n:]
    kin = forward(chain.screws, x)
    jac = kin.jacobian
    near, far = bar_ends(bars, kin.rotation, kin.translation, rotation, translation)
    d = far - near
    length = np.linalg.norm(d, axis=-1)
    u = d / length[..., None]
    lines = np.concatenate([cross(near, u), u], axis=-1)  # (k, 2, 6)
    w0 = np.einsum("kbi,kb->ki", lines, force)
    om = np.swapaxes(jac[:, :3, :], 1, 2)  # (k, n, 3)
    vel = np.swapaxes(jac[:, 3:, :], 1, 2)
    v_near = vel[:, None] + cross(om[:, None], near[:, :, None, :])  # (k, 2, n, 3)
    d_far = np.zeros(far.shape + (6,))  # (k, 2, 3, 6): dF/dt
    d_far[..., :3] = -hat(far - translation[:, None])
    d_far[..., 3:] = np.eye(3)
    l_x = -np.einsum("kbi,kbni->kbn", u, v_near)
    l_t = np.einsum("kbi,kbic->kbc", u, d_far)
    w_x = np.zeros((x.shape[0], 6, n))
    w_t = np.zeros((x.shape[0], 6, 6))
    if geometric:
        eye = np.eye(3)
        proj = (eye - u[..., :, None] * u[..., None, :]) / length[..., None, None]
        # dw0 / dd_j through dn_j: N_j ([E_j]x ; I) P_j / l_j  (k, 2, 6, 3)
        g_u = np.concatenate([hat(near), np.broadcast_to(eye, near.shape + (3,))], axis=-2)
        m_u = force[..., None, None] * (g_u @ proj)
        # dw0 / dE_j at fixed n_j: N_j (-[n_j]x ; 0)
        g_e = np.zeros(near.shape[:2] + (6, 3))
        g_e[..., :3, :] = -force[..., None, None] * hat(u)
        w_x = np.einsum("kbic,kbnc->kin", g_e - m_u, v_near)
        w_t = np.einsum("kbic,kbcs->kis", m_u, d_far)
    return {
        "jac": jac,
        "w0": w0,
        "w_x": w_x,
        "w_n": np.swapaxes(lines, 1, 2),
        "w_t": w_t,
        "l_x": l_x,
        "l_t": l_t,
        "length": length,
        "force": force,
        "x": x,
    }


def bar_closure(chain: ScrewChain, terms: dict[str, FloatArray]) -> FloatArray:
    """The bars' length errors ``l - L - c N`` (k, 2) [m]."""
    assert chain.bars is not None
    return np.asarray(terms["length"] - chain.bars.rest - chain.bars.compliance * terms["force"])


def about_displaced(w0: FloatArray, translation: FloatArray) -> FloatArray:
    """A wrench (k, 6) about c0 taken about c' = c0 + p_t: ``(m0 - p_t x f, f)``."""
    out = w0.copy()
    out[:, :3] -= cross(translation, w0[:, 3:])
    return out


__all__ = [
    "about_displaced",
    "bar_closure",
    "bar_ends",
    "bar_terms",
    "bar_wrench",
]
