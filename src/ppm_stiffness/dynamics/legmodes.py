"""The legs' own vibrations (Craig-Bampton): each leg's fixed-interface modes.

The mass model condenses every leg statically (Guyan,
:mod:`ppm_stiffness.dynamics.condensation`): its links move in the static shape the
platform twist t gives them. Where a leg's own first frequency (the platform held) is
near or below the platform's, that misses the legs' dynamics. Here each leg adds its
own lowest modes **with the platform held** (fixed-interface modes, its joints as they
are) as generalised coordinates eta beside t:

    K_r = [[K, 0], [0, diag(omega_k^2)]],   M_r = [[M, C], [C^T, 1]]

with mass-normalised modes phi_k and ``C = Psi^T M_x phi`` (6, n) the kinetic coupling
between the condensed (constraint) shapes Psi of the leg and its modes.

**The leg's FE model** (``chain_fe``): the chain of :mod:`ppm_stiffness.legs.chain`
in relative coordinates x, as the stiffness model builds it, every link split into
``elements`` Euler-Bernoulli elements (each with its six tip springs, the cantilever
compliance of eq. 3c for its length): a joint contributes its constrained directions'
springs and its freedoms (passive: no stiffness; the actuated one: the actuator
spring; elastic: their stiffnesses), a body's twist is the sum of the coordinates
upstream of it times their screws, the platform twist is ``t = J x`` (J: every
coordinate's screw, 6 x N). Masses: each element of a uniform link its consistent mass
(:func:`ppm_stiffness.dynamics.links.link_mass_matrix` on its two nodes' twists); a
link given as a body rides on the Hermite shape of the element holding its centre (a
centre outside the link rigidly on the section of the nearer end), as the condensed
model's body does; carriages, rotors and end masses as there. The static shapes of
this FE are those of the condensed model (a uniform beam's shape under end loads is
cubic, which the elements reproduce exactly), so ``Psi^T M_x Psi`` is the leg's M of
:func:`ppm_stiffness.dynamics.condensation.leg_mass_matrix` (to round-off, a test
checks it).

**The platform held**: ``J x = 0``; x = N z over an orthonormal null-space basis N of
J. Mechanisms with the platform held (zero stiffness: a strut's idle spin between two
spherical joints) are left out (they exert no wrench and move nothing the springs
see); directions without mass have infinite frequency and are left out too. The modes
come from ``N^T M_x N z = mu N^T K_x N z`` (mu = 1 / omega^2), the largest mu first.
A requested count that would split a degenerate pair (both bending planes of a round
strut) is raised to keep the pair whole.

Batched over leading axes (...) as the condensed model: every array of the chain
(..., 3) or (3,).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import BoolArray, FloatArray, hat
from ppm_stiffness.dynamics.links import _node_map, section_motion
from ppm_stiffness.legs.chain import (
    CONSTRAINED,
    Element,
    Joint,
    Link,
    check_chain,
    constrained_screws,
    elastic_stiffnesses,
    frame_from_axis,
    freedom_count,
    freedom_screws,
    link_screws,
    stack_chains,
    structure_groups,
)

IntArray = NDArray[np.int_]

#: Euler-Bernoulli elements per link of a leg's FE model. With 8 a pinned-pinned
#: uniform strut (two links) has its first frequency 1.3e-6 high; the shipped
#: examples' f1..f6 move by at most 8.3e-5 from 8 to 16 (docs/dynamics.md).
ELEMENTS_PER_LINK = 8
#: Fewer elements when few modes are kept (:func:`elements_for`): (modes per leg at
#: most, elements per link). Measured on the shipped examples (docs/dynamics.md):
#: f1 within 3e-5 of 16 elements with 2 (its modes' own truncation is larger).
FEWER_ELEMENTS = ((2, 2), (4, 4))
#: Relative gap of omega^2 under which two fixed-interface modes are one degenerate pair.
DEGENERATE_TOLERANCE = 1e-4
#: A mechanism of the held leg: stiffness below this fraction of its largest.
MECHANISM_TOLERANCE = 1e-13
#: The Cholesky path needs its bound on Kz's condition this far inside the tolerance.
CHOLESKY_MARGIN = 10.0


@dataclass(frozen=True)
class ChainFE:
    """A leg's FE model in relative coordinates x (module doc), flattened batch n.

    Attributes
    ----------
    screws : ndarray (n, 6, N)
        Each coordinate's unit twist at P, axes of F_b (``t = screws @ x``).
    stiffness : ndarray (n, N, N)
        Block diagonal [SI of each coordinate].
    mass_factor : ndarray (n, r, N)
        B with ``M_x = B^T B`` (kinetic energy ``x'^T M_x x' / 2``): each body's
        motions (a point's velocity, a rotor's rate, a link body's section motion, a
        uniform element's nodal motions) weighted by the square roots of its inertias.
    """

    screws: FloatArray
    stiffness: FloatArray
    mass_factor: FloatArray

    @property
    def mass(self) -> FloatArray:
        """M_x (n, N, N)."""
        return np.asarray(np.swapaxes(self.mass_factor, -1, -2) @ self.mass_factor)


@dataclass(frozen=True)
class LegModes:
    """A leg's fixed-interface modes at n poses (module doc).

    Attributes
    ----------
    omega2 : ndarray (n, k) [rad^2/s^2]
        Ascending; NaN with a zero coupling in a slot a pose does not have (another
        pose of the batch keeps more: a degenerate pair kept whole there), NaN with a
        NaN coupling at a pose whose model is not finite.
    coupling : ndarray (n, 6, k)
        ``C = Psi^T M_x phi``: the kinetic coupling of the platform twist at P (axes of
        F_b, order (omega, v)) with each mass-normalised mode.
    condensed_mass : ndarray (n, 6, 6)
        ``Psi^T M_x Psi``: the leg's condensed mass matrix from this FE (a check).
    condensed_stiffness : ndarray (n, 6, 6)
        ``Psi^T K_x Psi``: the leg's stiffness at P from this FE (a check).
    """

    omega2: FloatArray
    coupling: FloatArray
    condensed_mass: FloatArray
    condensed_stiffness: FloatArray

    @property
    def frequencies(self) -> FloatArray:
        """The modes' frequencies (n, k) [Hz]."""
        return np.asarray(np.sqrt(self.omega2) / (2.0 * math.pi))


class _Builder:
    """Accumulates a chain's coordinates and bodies (flattened batch n)."""

    def __init__(self, n: int, batch: tuple[int, ...]) -> None:
        self.n = n
        self.batch = batch
        self.screws: list[FloatArray] = []  # (n, 6, m)
        self.blocks: list[FloatArray] = []  # (n, m, m) stiffness
        self.count = 0
        # bodies, their mass formed once every column is known: a point mass (the
        # column count at its body, mass, point (n, 3)), a rotor (its coordinate's
        # column, reflected inertia), a link (the link, its nodes (n, e + 1, 3), the
        # column count at each node)
        self.points: list[tuple[int, float, FloatArray]] = []
        self.rotors: list[tuple[int, float]] = []
        self.links: list[tuple[Link, FloatArray, list[int]]] = []

    def flat(self, a: ArrayLike, tail: tuple[int, ...]) -> FloatArray:
        b = np.broadcast_to(np.asarray(a, dtype=float), self.batch + tail)
        return b.reshape((self.n,) + tail)

    def add(self, screws: FloatArray, stiffness: FloatArray) -> int:
        """Columns (n, 6, m) with their stiffness (n, m, m); returns the first index."""
        first = self.count
        self.screws.append(screws)
        self.blocks.append(stiffness)
        self.count += screws.shape[-1]
        return first


def _diagonal(k: FloatArray) -> FloatArray:
    """(n, m) -> (n, m, m) diagonal."""
    out = np.zeros(k.shape + (k.shape[-1],))
    idx = np.arange(k.shape[-1])
    out[..., idx, idx] = k
    return out


def _add_joint(b: _Builder, joint: Joint, k_act: FloatArray) -> None:
    free = b.flat(freedom_screws(joint), (6, freedom_count(joint)))
    elastic = elastic_stiffnesses(joint)
    first = b.count
    if joint.actuated:
        k_total = k_act if elastic is None else k_act + elastic[0]
        b.add(free[..., :1], k_total[:, None, None])
    elif elastic is not None:
        b.add(free, _diagonal(b.flat(elastic, (free.shape[-1],))))
    else:
        b.add(free, np.zeros((b.n, free.shape[-1], free.shape[-1])))
    if joint.springs is not None:
        c = CONSTRAINED[joint.kind]
        k = b.flat(joint.springs, (c,))
        keep = ~np.all(np.isinf(k), axis=0)  # rigid directions: no coordinate
        if np.any(np.isinf(k[:, keep])):
            k = np.where(np.isinf(k), 1e6 * np.max(np.where(np.isinf(k), 0.0, k)), k)
        if np.any(keep):
            cols = b.flat(constrained_screws(joint), (6, c))[..., keep]
            b.add(cols, _diagonal(k[:, keep]))
    if joint.mass is not None:
        after = b.count
        if joint.mass.mass > 0.0:
            b.points.append((after, joint.mass.mass, b.flat(joint.point, (3,))))
        if joint.mass.rotor > 0.0:
            b.rotors.append((first, joint.mass.rotor))


def _add_link(b: _Builder, link: Link, elements: int) -> None:
    """A link's ``elements`` Euler-Bernoulli elements, all at once: their tip screws
    (n, e, 6, 6) and stiffnesses (the inverse of their cantilever compliances) as one
    block of 6 e columns, element after element."""
    start, end = b.flat(link.start, (3,)), b.flat(link.end, (3,))
    fractions = np.linspace(0.0, 1.0, elements + 1)
    nodes = start[:, None, :] + fractions[None, :, None] * (end - start)[:, None, :]
    screws, length = link_screws(Link(nodes[:, :-1], nodes[:, 1:], link.section))
    stiff = np.asarray(np.linalg.inv(cantilever_compliance(link.section, length)), dtype=float)
    first = b.add(
        np.swapaxes(screws, 1, 2).reshape(b.n, 6, 6 * elements),
        _block_diagonal(stiff),
    )
    node_cols = [first + 6 * i for i in range(elements + 1)]  # the column count at each node
    b.links.append((link, nodes, node_cols))
    if link.end_mass > 0.0:
        b.points.append((b.count, link.end_mass, end))


def _block_diagonal(blocks: FloatArray) -> FloatArray:
    """(n, e, m, m) -> (n, e m, e m) block diagonal."""
    n, e, m = blocks.shape[:3]
    out = np.zeros((n, e, m, e, m))
    idx = np.arange(e)
    out[:, idx, :, idx, :] = np.moveaxis(blocks, 1, 0)
    return out.reshape(n, e * m, e * m)


def chain_fe(
    chain: Sequence[Element], actuator_stiffness: ArrayLike, elements: int = ELEMENTS_PER_LINK
) -> ChainFE:
    """A leg's FE model (module doc), its batch flattened.

    Parameters
    ----------
    chain : sequence of Joint and Link
        Base to platform, arrays (..., 3) or (3,), relative to P, axes of F_b.
    actuator_stiffness : array_like (...) or scalar [N/m or N·m/rad]
    elements : int
        Euler-Bernoulli elements per link.
    """
    check_chain(chain)
    shapes = [
        np.shape(e.point)[:-1] if isinstance(e, Joint) else np.shape(e.end)[:-1] for e in chain
    ]
    batch = np.broadcast_shapes(*shapes, np.shape(actuator_stiffness))
    n = math.prod(batch)
    b = _Builder(n, batch)
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), batch).reshape(n)
    for element in chain:
        if isinstance(element, Link):
            _add_link(b, element, elements)
        else:
            _add_joint(b, element, k_act)
    screws = np.concatenate(b.screws, axis=-1)
    total = b.count
    stiffness = np.zeros((n, total, total))
    i = 0
    for block in b.blocks:
        m = block.shape[-1]
        stiffness[:, i : i + m, i : i + m] = block
        i += m
    return ChainFE(screws=screws, stiffness=stiffness, mass_factor=_mass_factor(b, screws))


def _mass_factor(b: _Builder, screws: FloatArray) -> FloatArray:
    """B (n, r, N) with ``M_x = B^T B`` (:class:`ChainFE`)."""
    n, total = b.n, screws.shape[-1]

    def upto(rows: FloatArray, c: int) -> FloatArray:
        """Rows (n, q, 6) over the twist of a body after the first c coordinates."""
        out = np.zeros(rows.shape[:-1] + (total,))
        out[..., :c] = rows @ screws[..., :c]
        return out

    parts: list[FloatArray] = [np.zeros((n, 0, total))]
    for col, mass, point in b.points:  # its velocity v - hat(p) omega, times sqrt(m)
        rows = np.concatenate([-hat(point), np.broadcast_to(np.eye(3), (n, 3, 3))], axis=-1)
        parts.append(math.sqrt(mass) * upto(rows, col))
    for col, rotor in b.rotors:
        row = np.zeros((n, 1, total))
        row[:, 0, col] = math.sqrt(rotor)
        parts.append(row)
    for link, nodes, cols in b.links:
        parts.append(_link_factor(link, nodes, cols, upto))
    return np.concatenate(parts, axis=1)


@functools.lru_cache(maxsize=256)
def _unit_factor(mass: float, axial: float) -> FloatArray:
    """R (q, 12) with ``R^T R`` the consistent mass of a uniform element of length 1
    (:func:`ppm_stiffness.dynamics.links.link_mass_matrix`), its null rows dropped
    (kept per element mass: a design's links call it pose after pose; read only)."""
    from ppm_stiffness.dynamics.links import _UNIT_TRANS, _UNIT_TWIST

    lam, w = np.linalg.eigh(mass * _UNIT_TRANS + axial * _UNIT_TWIST)
    keep = lam > 1e-14 * max(float(lam[-1]), 0.0)
    out = np.asarray(np.sqrt(lam[keep])[:, None] * w[:, keep].T)
    out.flags.writeable = False
    return out


def _link_factor(
    link: Link,
    nodes: FloatArray,
    cols: list[int],
    upto: Callable[[FloatArray, int], FloatArray],
) -> FloatArray:
    """A link's rows of B (n, q, N) from its nodes (n, e + 1, 3) and the coordinates
    upstream of each (module doc of :mod:`ppm_stiffness.dynamics.links`)."""
    from ppm_stiffness.dynamics.links import _BENDING_ROTATIONS

    body = link.mass
    n = nodes.shape[0]
    if body is None:
        return upto(np.zeros((n, 0, 6)), 0)
    elements = nodes.shape[1] - 1
    d = nodes[:, -1] - nodes[:, 0]
    length = np.linalg.norm(d, axis=-1)
    axes = np.stack(frame_from_axis(d), axis=-1)

    # every node's (displacement, rotation), local axes, over x: (n, e + 1, 6, N)
    stack = _node_rows(nodes, axes, cols, upto)
    if body.centre is None and body.transverse is None:  # uniform: each element's share
        unit = _unit_factor(body.mass / elements, body.axial / elements)
        scale = np.ones((n, 12))
        scale[:, _BENDING_ROTATIONS] = (length / elements)[:, None]
        g = np.concatenate([stack[:, :-1], stack[:, 1:]], axis=-2)  # (n, e, 12, N)
        parts = unit @ (scale[:, None, :, None] * g)  # (n, e, q, N)
        return parts.reshape(n, -1, parts.shape[-1])
    # a body: on the Hermite shape of the element holding its centre
    if body.centre is None:
        s = 0.5 * length
    elif body.from_end:
        s = length - body.centre
    else:
        s = np.full(n, body.centre)
    xi = s / length * elements
    k = np.clip(np.floor(xi).astype(int), 0, elements - 1)
    local = xi - k
    rows = np.arange(n)
    g = np.concatenate([stack[rows, k], stack[rows, k + 1]], axis=-2)  # (n, 12, N)
    transverse = body.mass * length**2 / 12.0 if body.transverse is None else body.transverse
    weights = np.zeros((n, 6))
    weights[:, :3] = body.mass
    weights[:, 3] = body.axial
    weights[:, 4] = weights[:, 5] = transverse
    motion = section_motion(local, length / elements) @ g  # (n, 6, N)
    return np.asarray(np.sqrt(weights)[:, :, None] * motion)


def _node_rows(
    nodes: FloatArray,
    axes: FloatArray,
    cols: list[int],
    upto: Callable[[FloatArray, int], FloatArray],
) -> FloatArray:
    """Every node's map (n, e + 1, 6, N) from x to its (displacement, rotation) in the
    link's local axes ``axes`` (n, 3, 3): node i moves with the first ``cols[i]``
    coordinates (``upto`` of the node map over the whole chain, its later columns
    zero)."""
    n, nodes_count = nodes.shape[:2]
    maps = _node_map(nodes, axes[:, None])  # (n, e + 1, 6, 6)
    full = upto(maps.reshape(n, nodes_count * 6, 6), cols[-1])
    full = full.reshape(n, nodes_count, 6, full.shape[-1])  # (n, e + 1, 6, N)
    cut = np.arange(full.shape[-1])[None, :] < np.asarray(cols)[:, None]  # (e + 1, N)
    return np.asarray(np.where(cut[None, :, None, :], full, 0.0))


def elements_for(count: int) -> int:
    """Euler-Bernoulli elements per link for ``count`` modes per leg: 2 up to 2 modes,
    4 up to 4, else :data:`ELEMENTS_PER_LINK` (:data:`FEWER_ELEMENTS`; nested meshes,
    so the frequencies still fall as modes are added)."""
    for most, elements in FEWER_ELEMENTS:
        if count <= most:
            return elements
    return ELEMENTS_PER_LINK


def fixed_interface_modes(
    chain: Sequence[Element],
    actuator_stiffness: ArrayLike,
    count: int,
    elements: int | None = None,
    checks: bool = True,
    general: bool = False,
) -> LegModes:
    """The leg's ``count`` lowest modes with the platform held (module doc), more if
    the last would split a degenerate pair; fewer if the leg has fewer with mass.

    Parameters
    ----------
    chain : sequence of Joint and Link
    actuator_stiffness : array_like (...) or scalar [N/m or N·m/rad]
    count : int
        Modes wanted (0: none; the coupling is then (n, 6, 0)).
    elements : int, optional
        Euler-Bernoulli elements per link; :func:`elements_for` ``count`` if None.
    checks : bool
        Also ``condensed_mass`` and ``condensed_stiffness`` (NaN if False).
    general : bool
        Every pose by the eigendecomposition of Kz (:func:`_stiff_basis`; a check of
        the Cholesky path).

    Returns
    -------
    LegModes
        Flattened batch n; NaN at a pose whose model is not finite.
    """
    fe = chain_fe(chain, actuator_stiffness, elements_for(count) if elements is None else elements)
    j, k_x, b_x = fe.screws, fe.stiffness, fe.mass_factor
    n, total = j.shape[0], j.shape[-1]
    good = np.asarray(
        np.isfinite(j).all(axis=(1, 2))
        & np.isfinite(k_x).all(axis=(1, 2))
        & np.isfinite(b_x).all(axis=(1, 2)),
        dtype=bool,
    )
    j = np.where(good[:, None, None], j, 0.0)
    j[~good, :, :6] = np.eye(6)
    k_x = np.where(good[:, None, None], k_x, np.eye(total))
    b_x = np.where(good[:, None, None], b_x, 0.0)
    u, sv, vh = np.linalg.svd(j)  # J = U S Vh, (n, 6, N)
    v = np.swapaxes(vh, -1, -2)
    null = v[:, :, 6:]  # (n, N, N - 6)
    particular = v[:, :, :6] @ (np.swapaxes(u, -1, -2) / sv[:, :, None])  # J^+ (n, N, 6)
    null_t = np.swapaxes(null, -1, -2)
    kz = null_t @ k_x @ null
    basis = _stiff_basis(0.5 * (kz + np.swapaxes(kz, -1, -2)), general)  # (n, m, m)
    basis_t = np.swapaxes(basis, -1, -2)
    # the static (constraint) shapes: Psi = J^+ - N Kz^+ N^T K J^+, Kz^+ = basis basis^T
    psi = particular - null @ (basis @ (basis_t @ (null_t @ (k_x @ particular))))
    mu, y, present = _mass_modes((b_x @ null) @ basis, count)
    phi = null @ (basis @ y)  # (n, N, k), zero in a slot the pose does not have
    bp = b_x @ psi
    coupling = np.swapaxes(bp, -1, -2) @ (b_x @ phi)
    bad = ~good[:, None, None]
    if checks:
        cm = np.where(bad, np.nan, np.swapaxes(bp, -1, -2) @ bp)
        ck = np.swapaxes(psi, -1, -2) @ k_x @ psi
        ck = np.where(bad, np.nan, 0.5 * (ck + np.swapaxes(ck, -1, -2)))
    else:
        cm = ck = np.full((n, 6, 6), np.nan)
    return LegModes(
        omega2=np.where(good[:, None] & present, 1.0 / mu, np.nan),
        coupling=np.where(bad, np.nan, coupling),
        condensed_mass=cm,
        condensed_stiffness=ck,
    )


def _mass_modes(h: FloatArray, count: int) -> tuple[FloatArray, FloatArray, BoolArray]:
    """The largest mu (n, k) of ``A y = mu y`` with ``A = H^T H`` (n, m, m) (``H = B
    N basis`` (n, r, m): the mass in the K-orthonormal basis), ``y / sqrt(mu)`` (n, m,
    k) (the mass-normalised modes over that basis) and which of the k slots each pose
    has (n, k): its ``count`` modes with mass, more where the last would split a
    degenerate pair (:func:`_whole_pairs`), pose by pose (k: the most of any pose; a
    slot a pose does not have: mu 1, a zero mode).

    With fewer mass rows than directions (r < m: links given as bodies, a few rows
    each, against every coordinate of the FE) the same nonzero mu come from the Gram
    matrix ``H H^T`` (n, r, r), ``y = H^T u / sqrt(mu)``."""
    n, r, m = h.shape
    gram = 0 < r < m
    ht = np.swapaxes(h, -1, -2)
    a = h @ ht if gram else ht @ h
    mu, y = np.linalg.eigh(0.5 * (a + np.swapaxes(a, -1, -2)))  # ascending
    mu, y = mu[:, ::-1], y[:, :, ::-1]  # descending: the lowest frequencies first
    top = mu[:, :1] if mu.shape[-1] else np.zeros((n, 1))
    available = np.sum(mu > 1e-12 * top, axis=-1)  # a prefix: those with mass
    want = _whole_pairs(mu, np.minimum(count, available), available)
    k = int(np.max(want)) if n else 0
    present = np.arange(k)[None, :] < want[:, None]
    mu_k = np.where(present, mu[:, :k], 1.0)
    y_k = y[:, :, :k]
    if gram:
        y_k = ht @ y_k / np.sqrt(mu_k)[:, None, :]
    return mu_k, np.where(present[:, None, :], y_k / np.sqrt(mu_k)[:, None, :], 0.0), present


def _stiff_basis(kz: FloatArray, general: bool = False) -> FloatArray:
    """A Kz-orthonormal basis B (n, m, m) of Kz's stiff directions (its mechanisms,
    eigenvalues below :data:`MECHANISM_TOLERANCE` of its largest, left out: zero
    columns; the pseudo-inverse ``Kz^+ = B B^T``), of symmetric Kz (n, m, m).

    Where Kz has a Cholesky factor L and no mechanism by the bound ``lambda_min >=
    1 / ||L^-1||_F^2`` against ``lambda_max <= trace Kz`` (:data:`CHOLESKY_MARGIN`
    below the tolerance), ``B = L^-T``; elsewhere (or every pose with ``general``)
    ``B = W Lambda^-1/2`` over its stiff eigenpairs. The two differ by an orthogonal
    factor, which the modes do not see."""
    n, m = kz.shape[0], kz.shape[-1]
    basis = np.zeros((n, m, m))
    fast = np.zeros(n, dtype=bool)
    if not general and n and m:
        low, fast = _batched_cholesky(kz)
        if fast.any():
            idx = np.flatnonzero(fast)
            inv = np.linalg.inv(low[idx])  # L^-1
            bound = np.trace(kz[idx], axis1=-2, axis2=-1) * np.sum(inv**2, axis=(1, 2))
            sure = bound < MECHANISM_TOLERANCE**-1 / CHOLESKY_MARGIN
            fast[idx[~sure]] = False
            basis[idx[sure]] = np.swapaxes(inv[sure], -1, -2)
    slow = np.flatnonzero(~fast)
    if slow.size:
        lam, w = np.linalg.eigh(kz[slow])
        scale = np.max(np.abs(lam), axis=-1, keepdims=True)
        stiff = lam > MECHANISM_TOLERANCE * scale
        inv_sqrt = np.where(stiff, 1.0 / np.sqrt(np.where(stiff, lam, 1.0)), 0.0)
        basis[slow] = w * inv_sqrt[:, None, :]
    return basis


def _batched_cholesky(a: FloatArray) -> tuple[FloatArray, BoolArray]:
    """Lower Cholesky factors of a stack (n, m, m) and where they exist (n,) (one
    matrix at a time only when the batched factorisation fails)."""
    try:
        return np.asarray(np.linalg.cholesky(a), dtype=float), np.ones(a.shape[0], dtype=bool)
    except np.linalg.LinAlgError:
        pass
    low = np.zeros_like(a)
    ok = np.zeros(a.shape[0], dtype=bool)
    for i in range(a.shape[0]):
        try:
            low[i] = np.linalg.cholesky(a[i])
            ok[i] = True
        except np.linalg.LinAlgError:
            continue
    return low, ok


def _whole_pairs(mu: FloatArray, count: IntArray, available: IntArray) -> IntArray:
    """Each pose's ``count`` (n,) raised while its next mode (``mu`` (n, s) descending)
    repeats its last one, up to its ``available`` (n,)."""
    k = np.array(count, dtype=int)
    rows = np.arange(mu.shape[0])
    for _ in range(mu.shape[-1]):
        grow = (k > 0) & (k < available)
        if not np.any(grow):
            break
        last = mu[rows, np.maximum(k - 1, 0)]
        nxt = mu[rows, np.minimum(k, mu.shape[-1] - 1)]
        grow &= np.abs(last - nxt) <= DEGENERATE_TOLERANCE * np.abs(last)
        if not np.any(grow):
            break
        k = k + grow
    return k


#: Fixed-interface modes per leg by default (``modes --link-modes``, ``map``,
#: ``optimize``): measured to put f1..f6 of every shipped example at home within 3.9e-5
#: of their values with all the legs' modes, f1 within 1.8e-5 (4 modes: f1 within
#: 7.5e-5, f1..f6 within 1.1e-3; 2 modes: f1 within 3.2e-3 of 8; docs/dynamics.md).
DEFAULT_LINK_MODES = 8
#: A warning when a leg's first fixed-interface frequency is below this multiple of
#: the condensed f1 and its modes are left out (the error of f1 is of the order
#: (f1 / f_leg)^2: 1 % at 10).
LINK_MODE_WARNING_RATIO = 10.0


def resolve_link_modes(link_modes: int | None) -> int:
    """The number of fixed-interface modes per leg: ``link_modes``, or the default.

    Raises
    ------
    InputDataError
        Not a non-negative integer.
    """
    from ppm_stiffness.core.errors import InputDataError

    if link_modes is None:
        return DEFAULT_LINK_MODES
    if isinstance(link_modes, bool) or not isinstance(link_modes, (int, np.integer)):
        raise InputDataError(f"link modes: a non-negative integer, got {link_modes!r}")
    if link_modes < 0:
        raise InputDataError(f"link modes: a non-negative integer, got {link_modes}")
    return int(link_modes)


def design_leg_modes(
    design: object,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike,
    count: int,
    elements: int | None = None,
    checks: bool = True,
) -> list[LegModes]:
    """Every leg's fixed-interface modes at full poses (..., 6) (flattened to n).

    Parameters
    ----------
    design : Design
    poses : array_like (..., 6) [m, rad]
    actuator_stiffness : array_like (..., n_legs) or (n_legs,) [N/m or N·m/rad]
    count : int
        Modes per leg (:func:`fixed_interface_modes`).
    elements : int, optional
        Euler-Bernoulli elements per link; :func:`elements_for` ``count`` if None.
    checks : bool
        :func:`fixed_interface_modes`.
    """
    legs = design.legs  # type: ignore[attr-defined]
    q = np.asarray(poses, dtype=float)
    k = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), q.shape[:-1] + (len(legs),))
    chains = [leg.chain(leg.solve(q)) for leg in legs]
    if q.ndim > 1:
        return [
            fixed_interface_modes(chain, k[..., i], count, elements, checks)
            for i, chain in enumerate(chains)
        ]
    # one pose: the legs of one structure in one batched call
    out: list[LegModes | None] = [None] * len(chains)
    for group in structure_groups(chains):
        stacked = stack_chains([chains[i] for i in group])
        assert stacked is not None
        both = fixed_interface_modes(stacked, k[group], count, elements, checks)
        for i, modes in zip(group, split_leg_modes(both, len(group)), strict=True):
            out[i] = modes
    return [m for m in out if m is not None]


def split_leg_modes(modes: LegModes, legs: int) -> list[LegModes]:
    """The legs' modes (:class:`LegModes`) of chains stacked along their first axis
    (:func:`~ppm_stiffness.legs.chain.stack_chains`; batch ``legs * n``), one per leg,
    each with its own slots (those any of its poses has: as computed alone)."""
    n = modes.omega2.shape[0] // legs
    out = []
    for i in range(legs):
        rows = slice(i * n, (i + 1) * n)
        omega2 = modes.omega2[rows]
        k = int(np.max(np.sum(np.isfinite(omega2), axis=-1), initial=0))
        out.append(
            LegModes(
                omega2=omega2[:, :k],
                coupling=modes.coupling[rows, :, :k],
                condensed_mass=modes.condensed_mass[rows],
                condensed_stiffness=modes.condensed_stiffness[rows],
            )
        )
    return out


def stack_leg_modes(legs: Sequence[LegModes]) -> tuple[FloatArray, FloatArray]:
    """Every leg's omega^2 (n, k) and coupling (n, 6, k) side by side."""
    omega2 = np.concatenate([leg.omega2 for leg in legs], axis=-1)
    coupling = np.concatenate([leg.coupling for leg in legs], axis=-1)
    return omega2, coupling


def reduced_matrices(
    stiffness: ArrayLike, mass: ArrayLike, omega2: FloatArray, coupling: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The Craig-Bampton K_r and M_r (n, 6 + k, 6 + k) (module doc) from the condensed
    K and M (n, 6, 6) or (6, 6), the modes' omega^2 (n, k) and their coupling (n, 6,
    k), all at one reference point (:func:`stack_leg_modes`)."""
    n, k = omega2.shape
    size = 6 + k
    kr = np.zeros((n, size, size))
    mr = np.zeros((n, size, size))
    kr[:, :6, :6] = stiffness
    mr[:, :6, :6] = mass
    idx = np.arange(6, size)
    kr[:, idx, idx] = omega2
    mr[:, idx, idx] = 1.0
    mr[:, :6, 6:] = coupling
    mr[:, 6:, :6] = np.swapaxes(coupling, -1, -2)
    return kr, mr


def reduced_frequencies(stiffness: FloatArray, mass: FloatArray) -> FloatArray:
    """The six lowest frequencies (n, 6) [Hz] of stacks of K_r, M_r (n, s, s); NaN where
    they are not finite or M_r is not positive definite.

    A mode slot a pose does not have (:class:`LegModes`: omega^2 NaN, a zero coupling;
    :func:`reduced_matrices` puts it on the diagonal) is left out of that pose's
    problem; the poses are solved in groups with the same slots, each batched."""
    n, size = stiffness.shape[0], stiffness.shape[-1]
    out = np.full((n, 6), np.nan)
    idx = np.arange(size)
    off = mass.copy()
    off[:, idx, idx] = 0.0
    absent = np.isnan(stiffness[:, idx, idx]) & np.all(off == 0.0, axis=-1)
    absent[:, :6] = False
    patterns, which = np.unique(absent, axis=0, return_inverse=True)
    for g, pattern in enumerate(patterns):
        poses = np.flatnonzero(np.ravel(which) == g)
        keep = np.flatnonzero(~pattern)
        sub = np.ix_(poses, keep, keep)
        out[poses] = _lowest_six(stiffness[sub], mass[sub])
    return out


def _lowest_six(stiffness: FloatArray, mass: FloatArray) -> FloatArray:
    """:func:`reduced_frequencies` of stacks without absent slots: one Cholesky
    factorisation of every M_r (one pose at a time only where the batched one fails),
    one eigvalsh of every ``L^-1 K_r L^-T``."""
    n = stiffness.shape[0]
    out = np.full((n, 6), np.nan)
    good = np.isfinite(stiffness).all(axis=(1, 2)) & np.isfinite(mass).all(axis=(1, 2))
    idx = np.flatnonzero(good)
    if not idx.size:
        return out
    m = mass[idx]
    low, ok = _batched_cholesky(0.5 * (m + np.swapaxes(m, -1, -2)))
    idx = idx[ok]
    if not idx.size:
        return out
    inv = np.linalg.inv(low[ok])
    a = inv @ stiffness[idx] @ np.swapaxes(inv, -1, -2)
    lam = np.linalg.eigvalsh(0.5 * (a + np.swapaxes(a, -1, -2)))[:, :6]
    scale = np.max(np.abs(lam), axis=-1, keepdims=True)
    lam = np.where(np.abs(lam) <= 1e-12 * scale, 0.0, lam)
    real = np.all(lam >= 0.0, axis=-1)
    out[idx[real]] = np.sqrt(lam[real]) / (2.0 * math.pi)
    return out


class LinkModeWarning(UserWarning):
    """A leg's own first frequency is near the machine's f1 and its modes are left out
    (``link_modes`` 0): the condensed f1 is too high (module doc)."""


def warn_slow_legs(
    design: object, pose: ArrayLike, actuator_stiffness: ArrayLike, f1: float
) -> None:
    """Warn (:class:`LinkModeWarning`) where a leg's first fixed-interface frequency
    is below :data:`LINK_MODE_WARNING_RATIO` times the condensed ``f1`` [Hz] (one
    pose (6,))."""
    import warnings

    legs = design_leg_modes(design, pose, actuator_stiffness, 1, ELEMENTS_PER_LINK, False)
    lowest = [float(leg.frequencies[0, 0]) for leg in legs if leg.omega2.shape[-1]]
    if not lowest or not math.isfinite(f1):
        return
    f_leg = min(lowest)
    if f_leg < LINK_MODE_WARNING_RATIO * f1:
        warnings.warn(
            f"a leg's own first frequency (platform held) is {f_leg:.4g} Hz, "
            f"{f_leg / f1:.3g} times the condensed f1 = {f1:.4g} Hz (below "
            f"{LINK_MODE_WARNING_RATIO:g}): without link modes f1 is too high by up to "
            f"about (f1 / f_leg)^2; use link modes (--link-modes, default "
            f"{DEFAULT_LINK_MODES})",
            LinkModeWarning,
            stacklevel=3,
        )
