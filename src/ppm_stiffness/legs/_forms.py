"""The compliance of one block of springs against the transmitted wrenches, for the
batched engine (:mod:`ppm_stiffness.legs.engine`): ``A += G^T C G`` with G the wrenches
W in the block's frame, evaluated entry by entry (:mod:`ppm_stiffness.legs._soa`).

A block's compliance C (6 x 6 in its frame: rotations about e1, e2, e3, then
translations along them) is a list of upper-triangle :data:`Term` s ``(i, j, c, p)``:
``C_ij = c L^p`` with L the block's length (a link's cantilever, eq. 3c), or p = 0 (a
joint's springs). In an orthonormal frame, exact identities skip the projections on e2
and e3 when compliances are equal, with every term kept positive (no cancellation):

- c about (or along) all three axes: ``sum_k c (e_k . x)^2 = c |x|^2``;
- c on the two axes normal to e_k (and d on e_k, or no spring there):
  ``c |x - (e_k . x) e_k|^2 (+ d (e_k . x)^2)``;
- a cantilever of equal bending stiffnesses (``C_15 = -C_24``, a round tube):
  ``C_24 ((e3 . m)(e2 . f) - (e2 . m)(e3 . f)) = -C_24 e1 . (m x f)``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import lru_cache

import numpy as np

from ppm_stiffness.core.beam import BeamSection, cantilever_compliance
from ppm_stiffness.legs import _soa as soa
from ppm_stiffness.legs._soa import Scalar, Vec

#: One upper-triangle entry ``(i, j, c, p)`` of a block's compliance: ``c L^p`` (c an
#: array when the entries are not monomials, then p = 0).
Term = tuple[int, int, Scalar, int]


@lru_cache(maxsize=256)
def cantilever_terms(section: BeamSection) -> tuple[Term, ...] | None:
    """The nonzero upper-triangle entries of a section's cantilever compliance as
    monomials in the length, read off :func:`cantilever_compliance` at L = 1, 2, 3;
    None if they are not monomials."""
    c1, c2, c3 = (cantilever_compliance(section, length) for length in (1.0, 2.0, 3.0))
    terms: list[Term] = []
    for i in range(6):
        for j in range(i, 6):
            if c1[i, j] == 0.0 and c2[i, j] == 0.0:
                continue
            power = round(math.log2(c2[i, j] / c1[i, j])) if c1[i, j] * c2[i, j] > 0 else -1
            if not (0 <= power <= 4 and math.isclose(c3[i, j], c1[i, j] * 3.0**power)):
                return None
            terms.append((i, j, float(c1[i, j]), power))
    return tuple(terms)


def full_terms(compliance: np.ndarray) -> list[Term]:
    """Nonzero upper-triangle entries of (..., 6, 6) compliances as terms (p = 0)."""
    return [
        (i, j, compliance[..., i, j] if compliance.ndim > 2 else float(compliance[i, j]), 0)
        for i in range(6)
        for j in range(i, 6)
        if np.any(compliance[..., i, j] != 0.0)
    ]


def spring_terms(springs: Sequence[Scalar], directions: Sequence[tuple[str, int]]) -> list[Term]:
    """A joint's hardware springs (stiffnesses in its constrained directions, a float or
    one per pose; inf is rigid) as compliance terms."""
    return [
        (k + (0 if kind == "r" else 3), k + (0 if kind == "r" else 3), soa.recip(s), 0)
        for s, (kind, k) in zip(springs, directions, strict=True)
        if not isinstance(s, float) or math.isfinite(s)
    ]


def add_outer(acc: list[Scalar], c: Scalar, g: Vec, h: Vec | None = None) -> None:
    """``acc += c g g^T`` (or ``c (g h^T + h g^T)``), acc the upper triangle row by row."""
    cg = [soa.mul(c, x) for x in g]
    ch = None if h is None else [soa.mul(c, x) for x in h]
    r, k = len(g), 0
    for a in range(r):
        for b in range(a, r):
            if ch is None or h is None:
                term = soa.mul(cg[a], g[b])
            else:
                term = soa.add(soa.mul(cg[a], h[b]), soa.mul(ch[a], g[b]))
            acc[k] = soa.add(acc[k], term)
            k += 1


def add_matrix(acc: list[Scalar], c: Scalar, m: list[Scalar]) -> None:
    """``acc += c m`` (upper triangles)."""
    for k, x in enumerate(m):
        acc[k] = soa.add(acc[k], soa.mul(c, x))


class Projections:
    """Components of the columns of W (moments about a point, or forces: r vectors)
    along axes and normal to them, and their Gram matrices, each computed once (keys:
    the identities of the lists)."""

    def __init__(self) -> None:
        self._along: dict[tuple[int, int], Vec] = {}
        self._normal: dict[tuple[int, int], list[Vec]] = {}
        self._gram: dict[int, list[Scalar]] = {}
        self._keep: list[object] = []  # the keyed lists stay alive (their ids unique)

    def along(self, e: Vec, xs: list[Vec]) -> Vec:
        """``e . x_a``."""
        key = (id(e), id(xs))
        if key not in self._along:
            self._keep += [e, xs]
            self._along[key] = [soa.dot(e, x) for x in xs]
        return self._along[key]

    def normal(self, e: Vec, xs: list[Vec]) -> list[Vec]:
        """``x_a - (e . x_a) e`` for a unit e."""
        key = (id(e), id(xs))
        if key not in self._normal:
            self._normal[key] = [
                soa.axpy(x, g, e) for x, g in zip(xs, self.along(e, xs), strict=True)
            ]
        return self._normal[key]

    def gram(self, xs: list[Vec]) -> list[Scalar]:
        """``x_a . x_b`` (upper triangle)."""
        if id(xs) not in self._gram:
            self._keep.append(xs)
            r = len(xs)
            self._gram[id(xs)] = [soa.dot(xs[a], xs[b]) for a in range(r) for b in range(a, r)]
        return self._gram[id(xs)]


def _add_twisted(
    acc: list[Scalar], c: Scalar, c2: Scalar, e1: Vec, m: list[Vec], f: list[Vec]
) -> None:
    """``acc += c (e1 . (m_a x f_b) + e1 . (m_b x f_a))``, c2 = 2 c."""
    r, k = len(m), 0
    for a in range(r):
        for b in range(a, r):
            t = soa.dot(e1, soa.cross(m[a], f[b]))
            if a == b:
                term = soa.mul(c2, t)
            else:
                term = soa.mul(c, soa.add(t, soa.dot(e1, soa.cross(m[b], f[a]))))
            acc[k] = soa.add(acc[k], term)
            k += 1


def _identity(keys: list[tuple[Scalar, int] | None]) -> tuple[int | None, int | None] | None:
    """For the compliances about (or along) the three axes of a frame (None: no spring),
    ``(k, odd)`` when those normal to e_k are equal floats: all three equal (k None),
    two equal and ``odd`` = k with its own, or two equal and none on e_k (odd None);
    None otherwise."""
    given = [k for k in range(3) if keys[k] is not None]
    if len(given) < 2 or any(type(keys[k][0]) is not float for k in given):  # type: ignore[index]
        return None
    if len(given) == 2:
        i, j = given
        return (3 - i - j, None) if keys[i] == keys[j] else None
    if keys[0] == keys[1] == keys[2]:
        return None, None
    odd = [k for k in range(3) if keys.count(keys[k]) == 1]
    return (odd[0], odd[0]) if len(odd) == 1 else None


def add_block(
    acc: list[Scalar],
    terms: Sequence[Term],
    length: Scalar,
    frame: soa.Frame,
    x: tuple[list[Vec], list[Vec]],
    cache: Projections,
) -> None:
    """``acc += G^T C G`` for a block's compliance terms (module doc): its frame, the
    columns of W as (moments about its point, forces)."""
    powers: list[Scalar] = [1.0, length]

    def value(c: Scalar, p: int) -> Scalar:
        if p == 0:
            return c
        while len(powers) <= p:
            powers.append(soa.mul(powers[-1], length))
        return soa.mul(c, powers[p])

    def axis(k: int) -> Vec:
        return frame.e1 if k == 0 else frame.axes()[k]

    diagonal = {i: (c, p) for i, j, c, p in terms if i == j}
    coupling = {(i, j): (c, p) for i, j, c, p in terms if i != j}
    for first in (0, 3) if frame.orthonormal else ():
        keys = [diagonal.get(first + k) for k in range(3)]
        found = _identity(keys)
        if found is None:
            continue
        for a in range(3):
            diagonal.pop(first + a, None)
        xs = x[first // 3]
        if soa.is_zero([v for col in xs for v in col]):
            continue
        normal_to, odd = found
        common = keys[0 if normal_to is None else (normal_to + 1) % 3]  # normal to e_k
        assert common is not None
        if normal_to is None:
            add_matrix(acc, value(*common), cache.gram(xs))
            continue
        add_matrix(acc, value(*common), cache.gram(cache.normal(axis(normal_to), xs)))
        if odd is not None:
            add_outer(acc, value(*keys[odd]), cache.along(axis(odd), xs))  # type: ignore[misc]
    for i, (c, p) in diagonal.items():
        g = cache.along(axis(i % 3), x[i // 3])
        if not soa.is_zero(g):
            add_outer(acc, value(c, p), g)
    if frame.orthonormal and set(coupling) == {(1, 5), (2, 4)}:
        (c15, p15), (c24, p24) = coupling[(1, 5)], coupling[(2, 4)]
        if type(c24) is float and c15 == -c24 and p15 == p24:
            coupling = {}
            if not soa.is_zero([v for col in x[0] for v in col]):
                c = value(-c24, p24) if len(x[0]) > 1 else 0.0
                _add_twisted(acc, c, value(-2.0 * c24, p24), frame.e1, *x)
    for (i, j), (c, p) in coupling.items():
        g, h = cache.along(axis(i % 3), x[i // 3]), cache.along(axis(j % 3), x[j // 3])
        if not soa.is_zero(g + h):
            add_outer(acc, value(c, p), g, h)


__all__ = [
    "Projections",
    "Term",
    "add_block",
    "add_matrix",
    "add_outer",
    "cantilever_terms",
    "full_terms",
    "spring_terms",
]
