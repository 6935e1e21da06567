"""The loaded state under a wrench at many poses (batched :mod:`ppm_stiffness.statics`).

:func:`loaded_poses` gives, at every pose, the equilibrium that
:func:`ppm_stiffness.statics.equilibrium.equilibrium` (and so
:func:`ppm_stiffness.statics.loading.loaded_state`) computes: the nonlinear actuator
law with the secant load sharing of redundant designs, the platform twist at P, the
actuator forces, displacements ``delta(G)`` and tangent stiffnesses, and the tangent
K of the loaded state with its principal stiffnesses. The algebra is that of the
statics module (its docstring): per leg the stiffness with a rigid actuator ``K_i^S``
and ``b_i = K_i^S a_i``; ``C^S = (sum K_i^S)^-1``; ``g0 = B^T C^S w``,
``M = diag(a_i . b_i) - B^T C^S B``; Newton's method with the same backtracking line
search, tolerance and iteration limit on ``G - g0 + M delta(G) = 0`` for every pose
at once (a 3-leg design's forces are statically determinate: ``G = g0``); then
``t = C^S (w + B delta)``. The leg terms come from the planar engine
(:mod:`ppm_stiffness.legs.planar`); a chunk whose chains are not planar is solved pose
by pose with the statics module itself.

Where the single-pose call raises, the batch masks instead (:class:`LoadedBatch`).
Wrenches and twists at P, axes of F_b, SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import LENGTH_SCALE, BoolArray, FloatArray
from ppm_stiffness.core.errors import (
    EquilibriumError,
    InputDataError,
    SingularConfigurationError,
)
from ppm_stiffness.design import Design
from ppm_stiffness.legs import planar as engine
from ppm_stiffness.maps.batch import (
    PLANAR_CHUNK,
    PlanarEntries,
    Principal,
    _masked,
    _take,
    assemble,
    nonsingular_from_entries,
    principal_from_entries,
)
from ppm_stiffness.model import transmission_blocks
from ppm_stiffness.statics.equilibrium import (
    FORCE_TOLERANCE,
    MAX_ITERATIONS,
    MAX_ROTATION,
    displacements,
    tangent_stiffnesses,
)


@dataclass(frozen=True)
class LoadedBatch:
    """The loaded state at many poses (SI). Arrays have the batch shape of the poses.

    Masks (each implies the one before):

    reachable
        every leg's IK solvable and its joint coordinates within limits;
    singular
        reachable, but the manipulator with rigid actuators is singular (where
        ``loaded_state`` raises :class:`SingularConfigurationError` before solving);
    solved
        reachable, the manipulator with rigid actuators is not singular
        (:func:`ppm_stiffness.model.check_nonsingular`) and Newton's method converged:
        the equilibrium exists and its values below are given;
    valid
        solved, within the small-displacement model (no actuator beyond its whole
        stroke, a platform rotation of at most
        :data:`~ppm_stiffness.statics.equilibrium.MAX_ROTATION`) and a positive
        definite loaded K: exactly where ``loaded_state`` returns without raising.

    Attributes
    ----------
    twist : numpy.ma.MaskedArray (..., 6)
        Platform twist (phi_x, phi_y, phi_z [rad], x, y, z [m]) at P, axes of F_b;
        masked where not ``solved``.
    actuator_forces, actuator_displacements, actuator_stiffness : numpy.ma.MaskedArray
        (..., n_legs): G_i [N or N·m], delta_i(G_i) [m or rad], the tangent stiffness
        of eq. (21) [N/m or N·m/rad]; masked where not ``solved``.
    k_phi, k_x, k_y : numpy.ma.MaskedArray (...)
        Principal stiffnesses of the loaded tangent K (paper decoupling), masked where
        not ``valid``.
    stiffness : ndarray (..., 6, 6) or None
        The loaded tangent K (zero where not valid), when asked for.
    iterations : ndarray of int (...)
        Newton iterations (0 for statically determinate forces; -1 where not solved).
    """

    reachable: BoolArray
    singular: BoolArray
    solved: BoolArray
    valid: BoolArray
    twist: np.ma.MaskedArray
    actuator_forces: np.ma.MaskedArray
    actuator_displacements: np.ma.MaskedArray
    actuator_stiffness: np.ma.MaskedArray
    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    stiffness: FloatArray | None
    iterations: np.ndarray


@dataclass
class _Chunk:
    """Results of one chunk (flat, n poses)."""

    reachable: BoolArray
    singular: BoolArray
    solved: BoolArray
    valid: BoolArray
    twist: FloatArray
    forces: FloatArray
    delta: FloatArray
    k_tan: FloatArray
    principal: Principal
    stiffness: FloatArray
    iterations: np.ndarray


def _vec6(inp: engine.Vec3 | None, out: engine.Vec3 | None, m: int) -> FloatArray:
    """A twist or wrench (m, 6) from its in-plane and out-of-plane block vectors."""
    v = np.zeros((m, 6))
    for block, idx in ((inp, engine.IN_PLANE), (out, engine.OUT_OF_PLANE)):
        if block is not None:
            for k in range(3):
                v[:, idx[k]] = block[k]
    return v


def _stroke_spans(design: Design) -> FloatArray:
    spans = []
    for leg in design.legs:
        lo, hi = leg.limits()[leg.ACTUATED_COORDINATE]
        spans.append(float(hi - lo))
    return np.array(spans)


def _pd_3x3(
    a: FloatArray, b: FloatArray, c: FloatArray, d: FloatArray, e: FloatArray, f: FloatArray
) -> BoolArray:
    """Sylvester's criterion for symmetric [[a, b, c], [b, d, e], [c, e, f]]."""
    det = a * (d * f - e * e) - b * (b * f - e * c) + c * (b * e - d * c)
    return np.asarray((a > 0) & (a * d - b * b > 0) & (det > 0))


def loaded_positive_definite(e: PlanarEntries) -> BoolArray:
    """Mask: K finite and positive definite (length-balanced; the test of
    :func:`~ppm_stiffness.statics.equilibrium.equilibrium` on the loaded K)."""
    s1, s2 = LENGTH_SCALE, LENGTH_SCALE * LENGTH_SCALE
    finite = np.ones(np.shape(e.k22), dtype=bool)
    for value in e:
        finite &= np.isfinite(value)
    with np.errstate(all="ignore"):
        ok = _pd_3x3(e.k22 / s2, e.k23 / s1, e.k24 / s1, e.k33, e.k34, e.k44) & _pd_3x3(
            e.k00 / s2, e.k01 / s2, e.k05 / s1, e.k11 / s2, e.k15 / s1, e.k55
        )
    return np.asarray(finite & ok)


def solve_forces_batch(
    design: Design, g0: FloatArray, m: FloatArray, leg_scale: FloatArray
) -> tuple[FloatArray, BoolArray, np.ndarray]:
    """Actuator forces (k, n) at equilibrium for k poses at once.

    :func:`ppm_stiffness.statics.equilibrium.solve_forces` vectorised: the same
    determinacy test, residual, Jacobian, line search, tolerance and iteration limit.
    Returns the forces, a mask of the poses that converged and the iterations (-1 where
    Newton's method did not converge).
    """
    k, n = g0.shape
    g = g0.copy()
    iterations = np.zeros(k, dtype=int)
    determinate = np.max(np.abs(m), axis=(1, 2)) <= 1e-9 * np.maximum(leg_scale, 1e-300)
    converged = determinate.copy()
    active = np.flatnonzero(~determinate)
    if active.size == 0:
        return g, converged, iterations
    scale = np.maximum(np.max(np.abs(g0), axis=1), 1.0)

    def residual(gs: FloatArray, rows: np.ndarray) -> FloatArray:
        return np.asarray(
            gs - g0[rows] + np.einsum("kij,kj->ki", m[rows], displacements(design, gs))
        )

    ga = g[active]
    f = residual(ga, active)
    eye = np.eye(n)
    for iteration in range(1, MAX_ITERATIONS + 1):
        done = np.max(np.abs(f), axis=1) <= FORCE_TOLERANCE * scale[active]
        if np.any(done):
            rows = active[done]
            g[rows] = ga[done]
            converged[rows] = True
            iterations[rows] = iteration - 1
            keep = ~done
            active, ga, f = active[keep], ga[keep], f[keep]
        if active.size == 0:
            break
        jac = eye + m[active] / tangent_stiffnesses(design, ga)[:, None, :]
        step = np.linalg.solve(jac, -f[..., None])[..., 0]
        norm0 = np.linalg.norm(f, axis=1)
        alpha = np.ones(active.size)
        trial = ga + step
        f_trial = residual(trial, active)
        while True:
            ok = (np.linalg.norm(f_trial, axis=1) < (1 - 1e-4 * alpha) * norm0) | (alpha < 1e-6)
            if np.all(ok):
                break
            redo = np.flatnonzero(~ok)
            alpha[redo] *= 0.5
            trial[redo] = ga[redo] + alpha[redo, None] * step[redo]
            f_trial[redo] = residual(trial[redo], active[redo])
        ga, f = trial, f_trial
    g[active] = ga  # not converged: left as the last iterate, masked by the caller
    iterations[active] = -1
    return g, converged, iterations


def _loaded_chunk(design: Design, poses: FloatArray, wrench: FloatArray) -> _Chunk | None:
    """One chunk by the planar engine, or None if a chain is not planar."""
    n = poses.shape[0]
    n_legs = len(design.legs)
    leg_poses = [leg.solve(poses) for leg in design.legs]
    reach = np.ones(n, dtype=bool)
    for leg, lp in zip(design.legs, leg_poses, strict=True):
        reach &= np.asarray(leg.reachable(lp), dtype=bool)
    index = np.flatnonzero(reach)
    k = index.size
    sub_poses = [_take(lp, index) for lp in leg_poses]
    blocks = []
    for leg, lp in zip(design.legs, sub_poses, strict=True):
        found = engine.leg_blocks(leg.chain(lp))
        if found is None:
            return None
        blocks.append(found)
    with np.errstate(all="ignore"):
        rigid = [engine.leg_stiffness_blocks(lb, None) for lb in blocks]
        ks_in, ks_out = engine.sum_blocks(rigid)
        entries_s = PlanarEntries(
            *(np.broadcast_to(np.asarray(v, dtype=float), (k,)) for v in ks_in + ks_out)
        )
        pi_in, pi_out = transmission_blocks(blocks)
        pi = PlanarEntries(
            *(np.broadcast_to(np.asarray(v, dtype=float), (k,)) for v in pi_in + pi_out)
        )
        nonsingular = nonsingular_from_entries(entries_s, pi)
        c_in, c_out = engine.sym3_inverse(ks_in), engine.sym3_inverse(ks_out)
        # b_i = K_i^S a_i and C^S b_i, by block
        a6, b6, cb6 = [], [], []
        for blk, (k_in, k_out) in zip(blocks, rigid, strict=True):
            a_in, a_out = blk.inplane.twist, blk.outplane.twist
            b_in = None if a_in is None else engine.sym3_apply(k_in, a_in)
            b_out = None if a_out is None else engine.sym3_apply(k_out, a_out)
            a6.append(_vec6(a_in, a_out, k))
            b6.append(_vec6(b_in, b_out, k))
            cb6.append(
                _vec6(
                    None if b_in is None else engine.sym3_apply(c_in, b_in),
                    None if b_out is None else engine.sym3_apply(c_out, b_out),
                    k,
                )
            )
        a = np.stack(a6, axis=1)  # (k, n_legs, 6)
        b = np.stack(b6, axis=1)
        cb = np.stack(cb6, axis=1)
        w_in = (wrench[2], wrench[3], wrench[4])
        w_out = (wrench[0], wrench[1], wrench[5])
        u = _vec6(engine.sym3_apply(c_in, w_in), engine.sym3_apply(c_out, w_out), k)
        g0 = np.einsum("kli,ki->kl", b, u)
        ab = np.einsum("kli,kli->kl", a, b)
        m = -np.einsum("kli,kji->klj", b, cb)
        m[:, np.arange(n_legs), np.arange(n_legs)] += ab
        m = 0.5 * (m + np.swapaxes(m, 1, 2))
        good = np.flatnonzero(nonsingular)
        forces = np.zeros((k, n_legs))
        converged = np.zeros(k, dtype=bool)
        iters = np.full(k, -1)
        if good.size:
            forces[good], converged[good], iters[good] = solve_forces_batch(
                design, g0[good], m[good], np.max(np.abs(ab[good]), axis=1)
            )
        solved = nonsingular & converged
        safe_forces = np.where(solved[:, None], forces, 0.0)
        delta = displacements(design, safe_forces)
        k_tan = tangent_stiffnesses(design, safe_forces)
        twist = u + np.einsum("kli,kl->ki", cb, delta)
        loaded = [engine.leg_stiffness_blocks(blk, k_tan[:, i]) for i, blk in enumerate(blocks)]
        kl_in, kl_out = engine.sum_blocks(loaded)
        entries = PlanarEntries(
            *(np.broadcast_to(np.asarray(v, dtype=float), (k,)) for v in kl_in + kl_out)
        )
        principal = principal_from_entries(entries)
        within = np.all(np.abs(delta) <= _stroke_spans(design), axis=1) & (
            np.linalg.norm(twist[:, :3], axis=1) <= MAX_ROTATION
        )
        valid = solved & within & loaded_positive_definite(entries)

    def spread(values: np.ndarray, fill: float = 0.0) -> np.ndarray:
        out = np.full((n,) + values.shape[1:], fill, dtype=values.dtype)
        out[index] = values
        return out

    return _Chunk(
        reachable=reach,
        singular=spread(~nonsingular, False),
        solved=spread(solved, False),
        valid=spread(valid, False),
        twist=spread(twist),
        forces=spread(forces),
        delta=spread(delta),
        k_tan=spread(k_tan),
        principal=Principal(*(spread(np.asarray(v)) for v in principal)),
        stiffness=spread(assemble(entries)),
        iterations=spread(iters, -1),
    )


def _loaded_pose_by_pose(design: Design, poses: FloatArray, wrench: FloatArray) -> _Chunk:
    """The statics module pose by pose (chains that are not planar)."""
    from ppm_stiffness.core.decoupling import decouple
    from ppm_stiffness.statics.equilibrium import equilibrium

    n, n_legs = poses.shape[0], len(design.legs)
    reach = np.ones(n, dtype=bool)
    for leg in design.legs:
        reach &= np.asarray(leg.reachable(leg.solve(poses)), dtype=bool)
    solved = np.zeros(n, dtype=bool)
    singular = np.zeros(n, dtype=bool)
    valid = np.zeros(n, dtype=bool)
    twist = np.zeros((n, 6))
    forces, delta, k_tan = (np.zeros((n, n_legs)) for _ in range(3))
    fields = np.zeros((6, n))
    stiffness = np.zeros((n, 6, 6))
    iterations = np.full(n, -1)
    for i in np.flatnonzero(reach):
        try:
            st = equilibrium(design, wrench, poses[i])
        except SingularConfigurationError:
            singular[i] = True  # (or a loaded K not positive definite)
            continue
        except (EquilibriumError, InputDataError):
            continue  # the rare non-planar chain: values only where fully valid
        solved[i] = valid[i] = True
        twist[i], forces[i] = st.twist, st.actuator_forces
        delta[i], k_tan[i] = st.actuator_displacements, st.actuator_stiffness
        stiffness[i], iterations[i] = st.stiffness_matrix, st.iterations
        dec = decouple(st.stiffness_matrix, "paper")
        fields[:, i] = (
            dec.d[0],
            dec.d[1],
            dec.rotational_values[2],
            *dec.translational_values,
        )
    return _Chunk(
        reach,
        singular,
        solved,
        valid,
        twist,
        forces,
        delta,
        k_tan,
        Principal(*fields),
        stiffness,
        iterations,
    )


def loaded_poses(
    design: Design,
    poses: ArrayLike,
    wrench: ArrayLike,
    *,
    matrices: bool = False,
    chunk_size: int | None = None,
) -> LoadedBatch:
    """The loaded state under ``wrench`` at many poses (module doc).

    Parameters
    ----------
    design : Design
        Any architecture, redundant designs included.
    poses : array_like, shape (..., 3)
        (x [m], y [m], phi [rad]) of P in F_b.
    wrench : array_like, shape (6,)
        (m_x, m_y, m_z [N·m], f_x, f_y, f_z [N]) at P, axes of F_b, the same at every
        pose (move a wrench given at a tool point with
        :func:`ppm_stiffness.core.conventions.wrench_b_from_wrench_a`).
    matrices : bool
        Also return the loaded tangent K (288 bytes per pose).
    chunk_size : int, optional
        Poses evaluated at once; default :data:`~ppm_stiffness.maps.batch.PLANAR_CHUNK`.

    Returns
    -------
    LoadedBatch
        At every ``valid`` pose the numbers of
        :func:`ppm_stiffness.statics.loading.loaded_state` (to rounding).

    Raises
    ------
    InputDataError
        Poses not of shape (..., 3) or not finite; a wrench not of 6 finite values.
    """
    from ppm_stiffness.statics.loading import validate_wrench

    w = validate_wrench(wrench)
    p = np.asarray(poses, dtype=float)
    if p.shape[-1:] != (3,):
        raise InputDataError(f"poses must have shape (..., 3), got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InputDataError("poses must be finite")
    batch = p.shape[:-1]
    flat = p.reshape(-1, 3)
    n, n_legs = flat.shape[0], len(design.legs)
    step = max(int(chunk_size or PLANAR_CHUNK), 1)
    masks = np.zeros((4, n), dtype=bool)
    twist = np.zeros((n, 6))
    per_leg = np.zeros((3, n, n_legs))
    fields = np.zeros((3, n))
    iterations = np.full(n, -1)
    mats = np.zeros((n, 6, 6)) if matrices else None
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        c = _loaded_chunk(design, flat[sl], w)
        if c is None:
            c = _loaded_pose_by_pose(design, flat[sl], w)
        masks[:, sl] = (c.reachable, c.solved, c.valid, c.singular)
        twist[sl] = c.twist
        per_leg[0, sl], per_leg[1, sl], per_leg[2, sl] = c.forces, c.delta, c.k_tan
        fields[:, sl] = (c.principal.k_phi, c.principal.k_x, c.principal.k_y)
        iterations[sl] = c.iterations
        if mats is not None:
            mats[sl] = np.where(c.valid[:, None, None], c.stiffness, 0.0)
    solved, valid = masks[1], masks[2]

    def by_solved(values: FloatArray) -> np.ma.MaskedArray:
        mask = np.broadcast_to(~solved.reshape((n,) + (1,) * (values.ndim - 1)), values.shape)
        data = np.where(mask, np.nan, values)
        out = np.ma.MaskedArray(data, mask=mask.copy(), fill_value=np.nan)
        return out.reshape(batch + values.shape[1:])

    return LoadedBatch(
        reachable=masks[0].reshape(batch),
        singular=masks[3].reshape(batch),
        solved=solved.reshape(batch),
        valid=valid.reshape(batch),
        twist=by_solved(twist),
        actuator_forces=by_solved(per_leg[0]),
        actuator_displacements=by_solved(per_leg[1]),
        actuator_stiffness=by_solved(per_leg[2]),
        k_phi=_masked(fields[0], valid).reshape(batch),
        k_x=_masked(fields[1], valid).reshape(batch),
        k_y=_masked(fields[2], valid).reshape(batch),
        stiffness=None if mats is None else mats.reshape(batch + (6, 6)),
        iterations=iterations.reshape(batch),
    )
