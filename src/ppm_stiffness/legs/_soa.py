"""Structure-of-arrays arithmetic and geometry for the batched engine
(:mod:`ppm_stiffness.legs.engine`).

Every scalar entry of a vector or a small matrix is its own contiguous array (n,), or a
Python float when it holds at every pose (constant geometry, and every entry at a
single pose), so that each numpy call is an elementwise operation on (n,) arrays and
exact float zeros cost nothing (the helpers of :mod:`ppm_stiffness.legs.planar`).
Vectors are lists of such entries: 3 for points and axes, 6 for twists and wrenches
(rotation or moment first, :mod:`ppm_stiffness.core.conventions`).

The complement of a set of twists is found by Householder reflections (a QR of the
twists): the last ``6 - p`` columns of Q are an orthonormal basis of it, with no
per-pose choice of pivot, and each diagonal entry of R is the norm of a twist's
remainder after the ones before it (the test of dependence).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.chain import Element, Link
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.legs.planar import Scalar, add, mul, sub

Vec = list[Scalar]
#: A boolean entry: an array (n,) or a Python bool.
Mask = np.ndarray | bool


def sqrt(a: Scalar) -> Scalar:
    return math.sqrt(a) if type(a) is float else np.sqrt(a)


def recip(a: Scalar) -> Scalar:
    """``1 / a`` (a float zero gives inf, as an array's would)."""
    if type(a) is float:
        return math.inf if a == 0.0 else 1.0 / a
    return 1.0 / a


def where(mask: Mask, a: Scalar, b: Scalar) -> Scalar:
    if type(mask) is bool:
        return a if mask else b
    return np.where(mask, a, b)


def copysign(a: Scalar, b: Scalar) -> Scalar:
    if type(a) is float and type(b) is float:
        return math.copysign(a, b)
    return np.copysign(a, b)


def or_not(bad: Mask, ok: Mask | np.bool_) -> Mask:
    """``bad or not ok`` for masks (``ok`` a bool when it comes from floats)."""
    if not isinstance(ok, np.ndarray):
        return bool(bad) or not ok if type(bad) is bool else bad | (not ok)
    return np.logical_or(bad, ~ok)


def any_true(mask: Mask) -> bool:
    return bool(mask) if type(mask) is bool else bool(np.any(mask))


def is_zero(values: Sequence[Scalar]) -> bool:
    """Every entry is an exact float zero."""
    return all(type(x) is float and x == 0.0 for x in values)


def dot(a: Sequence[Scalar], b: Sequence[Scalar]) -> Scalar:
    """``a . b`` for vectors of any (equal) length, skipping exact float zeros."""
    acc: Scalar = 0.0
    for x, y in zip(a, b, strict=True):
        if (type(x) is float and x == 0.0) or (type(y) is float and y == 0.0):
            continue
        acc = add(acc, x * y)
    return acc


def axpy(y: Sequence[Scalar], s: Scalar, x: Sequence[Scalar]) -> Vec:
    """``y - s x`` (entrywise), skipping exact float zeros."""
    return [sub(yi, mul(s, xi)) for yi, xi in zip(y, x, strict=True)]


def cross(a: Sequence[Scalar], b: Sequence[Scalar]) -> Vec:
    a0, a1, a2 = a
    b0, b1, b2 = b
    return [
        sub(mul(a1, b2), mul(a2, b1)),
        sub(mul(a2, b0), mul(a0, b2)),
        sub(mul(a0, b1), mul(a1, b0)),
    ]


def components(value: ArrayLike, lo: int, hi: int, scalar: bool) -> Vec:
    """x, y, z of a point or axis (3,) or (n, 3) at poses lo:hi: floats when constant
    (or when ``scalar``: one pose), else contiguous arrays."""
    a = np.asarray(value, dtype=float)
    if a.ndim == 1:
        x, y, z = a.tolist()
        return [float(x), float(y), float(z)]
    if scalar:
        x, y, z = a.reshape(-1, 3)[lo if a.shape[0] > 1 else 0].tolist()
        return [float(x), float(y), float(z)]
    part = a[lo:hi] if a.shape[0] > 1 else np.broadcast_to(a, (hi - lo, 3))
    rows = part.T.copy()
    return [rows[0], rows[1], rows[2]]


def unit(v: Sequence[Scalar]) -> tuple[Vec, Scalar]:
    """``v / |v|`` and ``|v|`` (zero vectors stay zero, as :func:`chain.unit`)."""
    norm = sqrt(dot(v, v))
    inv: Scalar
    if type(norm) is float:
        inv = 1.0 / norm if norm > 0 else 1.0
    else:
        inv = 1.0 / np.where(norm > 0, norm, 1.0)
    return [mul(x, inv) for x in v], norm


def frame_from_unit(e1: Vec) -> tuple[Vec, Vec, Vec]:
    """``(e1, e2, e3)`` from a unit e1 as :func:`ppm_stiffness.legs.chain.frame_from_axis`
    builds it: ``e2 = unit(z x e1)``, or ``unit(e1 x x)`` where e1 is along z."""
    x, y, z = e1
    h = sqrt(add(mul(x, x), mul(y, y)))  # |z x e1|
    along_z: Mask = h < 1e-12
    if not any_true(along_z):
        inv = recip(h)
        e2: Vec = [-mul(y, inv), mul(x, inv), 0.0]
    else:
        zero = mul(0.0, h) if type(h) is float else np.zeros_like(h)
        e2, _ = unit([where(along_z, zero, -y), where(along_z, z, x), where(along_z, -y, zero)])
    return e1, e2, cross(e1, e2)


def _householder(
    cols: list[Vec], sizes: Sequence[Scalar], tolerance: float, d: int
) -> tuple[list[Vec], Mask]:
    """Householder QR of p vectors of d entries: the last d - p columns of Q and the
    mask of poses where a remainder (a diagonal entry of R) is at most ``tolerance``
    times the vector's size."""
    p = len(cols)
    reflectors: list[tuple[int, Vec, Scalar]] = []
    bad: Mask = False
    for k in range(p):
        x = cols[k][k:]
        norm = sqrt(dot(x, x))
        bad = or_not(bad, norm > tolerance * sizes[k])
        x0 = x[0]
        # v = x + sign(x0) |x| e_0, H = I - beta v v^T with beta = 2 / (v . v)
        v = [add(x0, copysign(norm, x0)), *x[1:]]
        beta = recip(norm * add(norm, abs(x0)))  # type: ignore[arg-type]
        reflectors.append((k, v, beta))
        for j in range(k + 1, p):
            y = cols[j][k:]
            cols[j][k:] = axpy(y, beta * dot(v, y), v)
    basis = []
    for j in range(p, d):
        q: Vec = [0.0] * d  # Q e_j = H_0 ... H_{p-1} e_j
        q[j] = 1.0
        for k, v, beta in reversed(reflectors):
            s = dot(v, q[k:])
            if not (type(s) is float and s == 0.0):
                q[k:] = axpy(q[k:], beta * s, v)
        basis.append(q)
    return basis, bad


def householder_complement(
    passive: Sequence[Sequence[Scalar]], tolerance: float, all_rotations: Mask | None = None
) -> tuple[list[Vec], Mask]:
    """An orthonormal basis (6 - p vectors) of the complement of p vectors (each 6
    entries), and the mask of poses where they are dependent: a remainder norm at most
    ``tolerance`` times the vector's norm (module doc).

    ``all_rotations``: the vectors also include, first, the three rotations about the
    reference point (entries 0-2 only, a spherical joint there), independent where the
    mask is True. Their reflections touch entries 0-2 only and the complement is zero
    there: the QR runs on entries 3-5 of the others (the same complement, the same
    remainders).
    """
    cols = [list(q) for q in passive]
    sizes = [sqrt(dot(q, q)) for q in cols]
    if all_rotations is None:
        return _householder(cols, sizes, tolerance, 6)
    rest, bad = _householder([q[3:] for q in cols], sizes, tolerance, 3)
    return [[0.0, 0.0, 0.0, *y] for y in rest], or_not(bad, all_rotations)


def stack(values: Sequence[Scalar], out: FloatArray) -> None:
    """Write entries into the last axis of ``out`` (n, len(values))."""
    for i, value in enumerate(values):
        out[:, i] = value


def twist(kind: str, point: Vec, axis: Vec, balance: float = 1.0) -> Vec:
    """Unit twist (6 entries) of a rotation about (``"r"``) or a translation along
    (``"t"``) ``axis`` through ``point``; rotation entries times ``balance``."""
    if kind == "r":
        return [mul(balance, e) for e in axis] + cross(point, axis)
    return [0.0, 0.0, 0.0, *axis]


class Frame:
    """An element's point, axis e1 and (computed when asked) e2 and e3.

    ``orthonormal``: built from e1 alone (:func:`frame_from_unit`) or from e1 and the
    part of a given second axis normal to it, orthonormal by construction; not so for a
    U joint's two given axes.
    """

    def __init__(
        self,
        point: Vec,
        e1: Vec,
        rest: tuple[Vec, Vec] | None = None,
        orthonormal: bool | None = None,
    ) -> None:
        self.point, self.e1, self._rest = point, e1, rest
        self.orthonormal = rest is None if orthonormal is None else orthonormal

    def axes(self) -> list[Vec]:
        if self._rest is None:
            _, e2, e3 = frame_from_unit(self.e1)
            self._rest = (e2, e3)
        return [self.e1, *self._rest]


class Geometry:
    """A chain's points and axes at poses lo:hi as entries, each array read once (the
    same array object in several elements is one entry)."""

    def __init__(self, lo: int, hi: int) -> None:
        self.lo, self.hi, self.scalar = lo, hi, hi - lo == 1
        self._vectors: dict[int, Vec] = {}
        self._units: dict[int, tuple[Vec, Scalar]] = {}

    def vector(self, value: ArrayLike) -> Vec:
        key = id(value)
        if key not in self._vectors:
            self._vectors[key] = components(value, self.lo, self.hi, self.scalar)
        return self._vectors[key]

    def unit(self, value: ArrayLike) -> tuple[Vec, Scalar]:
        """``value / |value|`` and ``|value|``."""
        key = id(value)
        if key not in self._units:
            self._units[key] = unit(self.vector(value))
        return self._units[key]

    def frame(self, element: Element) -> tuple[Frame, Scalar]:
        """The frame of a joint (:meth:`Joint.frame`) or of a link's tip, and the length
        of its axis as given (a link's length)."""
        if isinstance(element, Link):
            start, end = self.vector(element.start), self.vector(element.end)
            e1, length = unit([sub(b, a) for a, b in zip(start, end, strict=True)])
            return Frame(end, e1), length
        point = self.vector(element.point)
        e1, norm = self.unit(element.axis)
        second_axis = joint_kind(element.kind).second_axis
        if element.axis2 is None:
            if second_axis:
                element.frame()  # the error naming the joint
            return Frame(point, e1), norm
        if not second_axis:  # e2 along the part of axis2 normal to e1
            given = self.vector(element.axis2)
            e2, _ = unit(axpy(given, dot(given, e1), e1))
            return Frame(point, e1, (e2, cross(e1, e2)), orthonormal=True), norm
        e2, _ = self.unit(np.asarray(element.axis2))
        return Frame(point, e1, (e2, cross(e1, e2))), norm


__all__ = [
    "Frame",
    "Geometry",
    "Mask",
    "Scalar",
    "Vec",
    "add",
    "any_true",
    "axpy",
    "components",
    "copysign",
    "cross",
    "dot",
    "frame_from_unit",
    "householder_complement",
    "is_zero",
    "mul",
    "or_not",
    "recip",
    "sqrt",
    "stack",
    "sub",
    "twist",
    "unit",
    "where",
]
