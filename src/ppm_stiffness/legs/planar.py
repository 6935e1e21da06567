"""The fast general engine: the stiffness of any planar joint chain at many poses.

The same model as the general path (:func:`ppm_stiffness.legs.chain.leg_springs` and
the bordered inverse of :func:`ppm_stiffness.core.solver.bordered_stiffness`), evaluated
in closed form over arrays of poses ("structure of arrays": one numpy array per scalar
entry, no (n, m, m) temporaries). It rests on two exact facts:

1. **The planar split.** When every joint axis of a chain is along z or in the plane
   z = 0 and every point lies in that plane (every shipped leg type), each virtual
   spring and each passive joint acts either in-plane (twist components phi_z, x, y:
   indices 2, 3, 4) or out of plane (phi_x, phi_y, z: 0, 1, 5). A leg's compliance at
   P, ``J C J^T``, is then block diagonal, and so is its stiffness: two independent
   3x3 problems per leg.
2. **The reduced compliance.** For one block with compliance ``S`` (3x3, without the
   actuator), actuator twist ``a`` and passive twists ``q_1..q_p``, the bordered
   inverse of eq. (1) equals ``K = W (W^T S W + v v^T / k_act)^{-1} W^T`` with ``W``
   (3 x (3 - p)) any basis of the wrenches reciprocal to the passive twists
   (``q_j . w = 0``) and ``v = W^T a``. ``W`` is a cross product for p = 2 (every
   shipped leg in-plane), two for p = 1, the identity for p = 0; K is 0 for p = 3.
   The basis does not change K (``W -> W T`` cancels).

Everything is computed on the chain the leg type builds (``leg.chain``), so the engine
knows no leg type: a chain that is not planar at some pose of a chunk makes
:func:`leg_blocks` return None, and the maps fall back to the general path for that
chunk. Twists and wrenches at P, axes of F_b, SI; arrays have one batch axis (n,).
Python floats stand for entries that are the same at every pose (and exact zeros are
skipped), so constant geometry costs nothing per pose.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.chain import Element, Joint, Link, check_chain
from ppm_stiffness.legs.joint_kinds import joint_kind

#: A scalar entry: an array (n,) or a Python float that holds at every pose.
Scalar = FloatArray | float
Vec3 = tuple[Scalar, Scalar, Scalar]
#: Symmetric 3x3 matrix as its upper triangle (00, 01, 02, 11, 12, 22).
Sym3 = list[Scalar]

PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
#: Twist components of each block, in the order of :mod:`ppm_stiffness.core.conventions`.
IN_PLANE = (2, 3, 4)
OUT_OF_PLANE = (0, 1, 5)
#: |z| below which a point or a unit axis counts as in the plane [m or 1].
PLANAR_ATOL = 1e-12


# -- arithmetic on entries that may be the constant 0.0 ------------------------------
def _is_zero(a: Scalar) -> bool:
    return type(a) is float and a == 0.0


def mul(a: Scalar, b: Scalar) -> Scalar:
    """``a * b`` skipping exact scalar zeros."""
    if (type(a) is float and a == 0.0) or (type(b) is float and b == 0.0):
        return 0.0
    return a * b


def add(a: Scalar, b: Scalar) -> Scalar:
    """``a + b`` skipping exact scalar zeros."""
    if type(a) is float and a == 0.0:
        return b
    if type(b) is float and b == 0.0:
        return a
    return a + b


def sub(a: Scalar, b: Scalar) -> Scalar:
    if type(b) is float and b == 0.0:
        return a
    if type(a) is float and a == 0.0:
        return -b
    return a - b


def div(a: Scalar, b: Scalar) -> Scalar:
    """``a / b`` keeping an exact scalar zero numerator."""
    return 0.0 if _is_zero(a) else a / b


def neg(a: Scalar) -> Scalar:
    return 0.0 if _is_zero(a) else -a


def _floats(*values: Scalar) -> bool:
    for v in values:
        if type(v) is not float:
            return False
    return True


def dot3(a: Vec3, b: Vec3) -> Scalar:
    a0, a1, a2 = a
    b0, b1, b2 = b
    if _floats(a0, a1, a2, b0, b1, b2):
        return a0 * b0 + a1 * b1 + a2 * b2
    return add(add(mul(a0, b0), mul(a1, b1)), mul(a2, b2))


def cross3(a: Vec3, b: Vec3) -> Vec3:
    a0, a1, a2 = a
    b0, b1, b2 = b
    if _floats(a0, a1, a2, b0, b1, b2):
        return (a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0)
    return (
        sub(mul(a1, b2), mul(a2, b1)),
        sub(mul(a2, b0), mul(a0, b2)),
        sub(mul(a0, b1), mul(a1, b0)),
    )


def sum_blocks(legs: Iterable[tuple[Sym3, Sym3]]) -> tuple[Sym3, Sym3]:
    """The platform's (in-plane, out-of-plane) blocks: the sum of the legs' (eq. 4)."""
    total_in: Sym3 = [0.0] * 6
    total_out: Sym3 = [0.0] * 6
    for k_in, k_out in legs:
        total_in = [add(a, b) for a, b in zip(total_in, k_in, strict=True)]
        total_out = [add(a, b) for a, b in zip(total_out, k_out, strict=True)]
    return total_in, total_out


def add_outer(acc: Sym3, c: Scalar, u: Vec3, v: Vec3 | None = None) -> None:
    """``acc += c u u^T`` (or ``c (u v^T + v u^T)`` when v is given), in place."""
    u0, u1, u2 = u
    if (
        type(c) is float
        and type(u0) is float
        and type(u1) is float
        and type(u2) is float
        and (v is None or (type(v[0]) is float and type(v[1]) is float and type(v[2]) is float))
    ):  # one pose (or constant geometry): plain float arithmetic
        cu0, cu1, cu2 = c * u0, c * u1, c * u2
        if v is None:
            terms: tuple[Scalar, ...] = (cu0 * u0, cu0 * u1, cu0 * u2, cu1 * u1, cu1 * u2, cu2 * u2)
        else:
            v0, v1, v2 = v
            terms = (
                2.0 * cu0 * v0,
                cu0 * v1 + cu1 * v0,
                cu0 * v2 + cu2 * v0,
                2.0 * cu1 * v1,
                cu1 * v2 + cu2 * v1,
                2.0 * cu2 * v2,
            )
        acc[0] = acc[0] + terms[0]
        acc[1] = acc[1] + terms[1]
        acc[2] = acc[2] + terms[2]
        acc[3] = acc[3] + terms[3]
        acc[4] = acc[4] + terms[4]
        acc[5] = acc[5] + terms[5]
        return
    cu = (mul(c, u[0]), mul(c, u[1]), mul(c, u[2]))
    for n, (i, j) in enumerate(PAIRS):
        if v is None:
            term = mul(cu[i], u[j])
        else:
            term = add(mul(cu[i], v[j]), mul(cu[j], v[i]))
        acc[n] = add(acc[n], term)


def _components(v: ArrayLike) -> tuple[Scalar, Scalar, Scalar]:
    """x, y, z of points or axes (3,) or (n, 3): floats when constant."""
    if isinstance(v, np.ndarray) and v.shape == (3,):
        x, y, z = v.tolist()
        return float(x), float(y), float(z)
    a = np.asarray(v, dtype=float)
    if a.ndim == 1:
        return float(a[0]), float(a[1]), float(a[2])
    return (
        np.ascontiguousarray(a[..., 0]),
        np.ascontiguousarray(a[..., 1]),
        np.ascontiguousarray(a[..., 2]),
    )


def _all_small(a: Scalar, tol: float) -> bool:
    if isinstance(a, float):
        return abs(a) <= tol
    return bool(np.all(np.abs(a) <= tol))


def _hypot(a: Scalar, b: Scalar) -> Scalar:
    if isinstance(a, float) and isinstance(b, float):
        return math.hypot(a, b)
    return np.asarray(np.hypot(a, b))


@dataclass(frozen=True)
class Direction:
    """A unit direction of the plane model: along ``z * sign`` or in-plane (x, y)."""

    along_z: bool
    x: Scalar = 0.0
    y: Scalar = 0.0
    sign: float = 1.0


def _direction(axis: ArrayLike) -> Direction | None:
    """The direction of an axis (normalised), or None if it is neither along z nor in
    the plane at every pose (a non-planar chain)."""
    ax, ay, az = _components(axis)
    if _all_small(ax, PLANAR_ATOL) and _all_small(ay, PLANAR_ATOL):
        if isinstance(az, float):
            return None if az == 0.0 else Direction(True, sign=math.copysign(1.0, az))
        s = np.sign(az)
        if isinstance(s, np.ndarray):
            if s.size == 0:  # no pose in the batch: any direction along z will do
                return Direction(True, sign=1.0)
            if not (np.all(s == s.flat[0]) and s.flat[0] != 0):
                return None
            s = s.flat[0]
        if s == 0:
            return None
        return Direction(True, sign=float(s))
    if not _all_small(az, PLANAR_ATOL):
        return None
    norm = _hypot(ax, ay)
    if isinstance(norm, float):
        n = norm or 1.0
        return Direction(False, div(ax, n), div(ay, n))
    norm = np.where(norm > 0, norm, 1.0)
    return Direction(False, div(ax, norm), div(ay, norm))


def joint_frame(e1: Direction) -> tuple[Direction, Direction, Direction]:
    """``(e1, e2, e3)`` as :func:`ppm_stiffness.legs.chain.frame_from_axis` builds it."""
    if e1.along_z:
        return e1, Direction(False, 0.0, e1.sign), Direction(False, -1.0, 0.0)
    return e1, Direction(False, neg(e1.y), e1.x), Direction(True, sign=1.0)


def rotation(a: Direction, c: tuple[Scalar, Scalar]) -> tuple[bool, Vec3]:
    """Unit twist of a rotation about ``a`` through ``c`` (x, y): (in-plane?, block vector).

    In-plane block (phi_z, v_x, v_y); out-of-plane block (phi_x, phi_y, v_z).
    """
    if a.along_z:
        if a.sign > 0:
            return True, (1.0, c[1], neg(c[0]))
        return True, (-1.0, neg(c[1]), c[0])
    return False, (a.x, a.y, sub(mul(c[0], a.y), mul(c[1], a.x)))


def translation(a: Direction) -> tuple[bool, Vec3]:
    """Unit twist of a translation along ``a``: (in-plane?, block vector)."""
    if a.along_z:
        return False, (0.0, 0.0, a.sign)
    return True, (0.0, a.x, a.y)


@dataclass
class Block:
    """One block (in-plane or out of plane) of one leg: compliance without the
    actuator, the actuator twist (None if the actuator acts in the other block) and
    the passive twists (block vectors)."""

    compliance: Sym3
    actuator: Vec3 | None
    passive: list[Vec3]


@dataclass(frozen=True)
class ReducedBlock:
    """``W`` (columns, block vectors), ``W^T S W`` (r x r, upper triangle row by row)
    and ``v = W^T a`` (r entries, or None) of one block; r = 3 - p. ``twist`` is the
    actuator's unit twist ``a`` (block vector) when it acts in this block."""

    basis: list[Vec3]
    compliance: list[Scalar]
    actuator: list[Scalar] | None
    twist: Vec3 | None = None


@dataclass(frozen=True)
class LegBlocks:
    """A leg at n poses, reduced: its in-plane and out-of-plane blocks."""

    inplane: ReducedBlock
    outplane: ReducedBlock


def _link(element: Link, blocks: dict[bool, Block]) -> bool:
    """Add a link's cantilever compliance (eq. 3c) at P; False if not planar."""
    sx, sy, sz = _components(element.start)
    ex_, ey_, ez_ = _components(element.end)
    if not (_all_small(sz, PLANAR_ATOL) and _all_small(ez_, PLANAR_ATOL)):
        return False
    dx, dy = sub(ex_, sx), sub(ey_, sy)
    length = _hypot(dx, dy)
    if isinstance(length, float):
        safe: Scalar = length if length > 0 else 1.0
    else:
        safe = np.where(length > 0, length, 1.0)
    ux, uy = div(dx, safe), div(dy, safe)  # local x; local y = (-uy, ux); local z = +z
    sec = element.section
    ei_z = sec.young_modulus * sec.inertia_z
    ei_y = sec.young_modulus * sec.inertia_y
    l2 = length * length
    l3 = l2 * length
    end = (ex_, ey_)
    # in-plane: local (rot z, u_x, u_y) at the end
    r_z = (1.0, ey_, neg(ex_))
    t_x = (0.0, ux, uy)
    t_y = (0.0, -uy, ux)
    acc = blocks[True].compliance
    add_outer(acc, length / ei_z, r_z)
    add_outer(acc, length / (sec.young_modulus * sec.area), t_x)
    add_outer(acc, l3 / (3.0 * ei_z), t_y)
    add_outer(acc, l2 / (2.0 * ei_z), r_z, t_y)
    # out of plane: local (rot x, rot y, u_z) at the end
    _, r_x = rotation(Direction(False, ux, uy), end)
    _, r_y = rotation(Direction(False, -uy, ux), end)
    acc = blocks[False].compliance
    add_outer(acc, length / (sec.shear_modulus * sec.torsion_constant), r_x)
    add_outer(acc, length / ei_y, r_y)
    add_outer(acc, l3 / (3.0 * ei_y), (0.0, 0.0, 1.0))
    add_outer(acc, -l2 / (2.0 * ei_y), r_y, (0.0, 0.0, 1.0))
    return True


def _joint(element: Joint, blocks: dict[bool, Block]) -> bool:
    """Add a joint's springs, its actuator twist or its passive twists; False if not
    planar (a kind with two or three rotations, a U or an S, is never planar: its
    freedoms leave the plane)."""
    record = joint_kind(element.kind)
    if not record.planar or element.axis2 is not None:
        return False  # the plane model's frames come from the axis alone
    e1 = _direction(element.axis)
    cx, cy, cz = _components(element.point)
    if e1 is None or not _all_small(cz, PLANAR_ATOL):
        return False
    frame = joint_frame(e1)
    c = (cx, cy)

    def screw(kind: str, axis: int) -> tuple[bool, Vec3]:
        return rotation(frame[axis], c) if kind == "r" else translation(frame[axis])

    free = [screw(k, i) for k, i in record.freedoms]
    if element.actuated:
        inplane, vec = free[0]
        blocks[inplane].actuator = vec
    else:
        for inplane, vec in free:
            blocks[inplane].passive.append(vec)
    if element.springs is not None:
        k = np.asarray(element.springs, dtype=float).tolist()
        directions = record.constrained
        for stiffness, (kind, axis) in zip(k, directions, strict=True):
            if math.isinf(stiffness):
                continue
            inplane, vec = screw(kind, axis)
            add_outer(blocks[inplane].compliance, 1.0 / float(stiffness), vec)
    return True


def _basis(passive: list[Vec3]) -> list[Vec3] | None:
    """Basis of the block wrenches reciprocal to the passive twists (module doc);
    None when p = 3 (the block transmits nothing)."""
    if not passive:
        return [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
    if len(passive) == 2:
        return [cross3(passive[0], passive[1])]
    if len(passive) == 1:
        q = passive[0]
        # q x e_k for the axis e_k along which q is smallest, then q x (q x e_k)
        if all(isinstance(v, float) for v in q):
            qf = [abs(float(v)) for v in q]
            k = 0 if qf[0] <= qf[1] and qf[0] <= qf[2] else 1 if qf[1] <= qf[2] else 2
            w1 = cross3(q, ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))[k])
            return [w1, cross3(q, w1)]
        qa = [np.abs(np.asarray(v, dtype=float)) for v in q]
        pick0 = (qa[0] <= qa[1]) & (qa[0] <= qa[2])
        pick1 = ~pick0 & (qa[1] <= qa[2])
        cand = [cross3(q, e) for e in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))]
        if np.ndim(pick0) == 0:
            w1 = cand[0] if pick0 else cand[1] if pick1 else cand[2]
        else:
            c0, c1, c2 = (
                np.where(pick0, cand[0][i], np.where(pick1, cand[1][i], cand[2][i]))
                for i in range(3)
            )
            w1 = (c0, c1, c2)
        return [w1, cross3(q, w1)]
    return None


def sym_get(s: Sym3, i: int, j: int) -> Scalar:
    a, b = (i, j) if i <= j else (j, i)
    return s[PAIRS.index((a, b))]


def _reduce(block: Block) -> ReducedBlock:
    basis = _basis(block.passive)
    if basis is None:
        return ReducedBlock([], [], None, block.actuator)
    s = block.compliance
    sw = [
        (
            dot3((sym_get(s, 0, 0), sym_get(s, 0, 1), sym_get(s, 0, 2)), w),
            dot3((sym_get(s, 1, 0), sym_get(s, 1, 1), sym_get(s, 1, 2)), w),
            dot3((sym_get(s, 2, 0), sym_get(s, 2, 1), sym_get(s, 2, 2)), w),
        )
        for w in basis
    ]
    r = len(basis)
    m = [dot3(basis[a], sw[b]) for a in range(r) for b in range(a, r)]
    v = None if block.actuator is None else [dot3(w, block.actuator) for w in basis]
    return ReducedBlock(basis, m, v, block.actuator)


def leg_blocks(chain: Sequence[Element]) -> LegBlocks | None:
    """A leg's chain at n poses (arrays (n, 3) or constant (3,)) reduced per block, or
    None if the chain is not planar at every pose (then use the general path)."""
    check_chain(chain)
    if any(isinstance(e, Joint) and e.elastic is not None for e in chain):
        return None  # elastic freedoms: the general path's bordered solve
    blocks = {True: Block([0.0] * 6, None, []), False: Block([0.0] * 6, None, [])}
    for element in chain:
        ok = _link(element, blocks) if isinstance(element, Link) else _joint(element, blocks)
        if not ok:
            return None
    return LegBlocks(_reduce(blocks[True]), _reduce(blocks[False]))


def block_stiffness(block: ReducedBlock, actuator_stiffness: Scalar | None) -> Sym3:
    """The block's stiffness (upper triangle, SI) with the given actuator stiffness
    (None: a rigid actuator, or an actuator in the other block)."""
    r = len(block.basis)
    if r == 0:
        return [0.0] * 6
    m = list(block.compliance)
    if block.actuator is not None and actuator_stiffness is not None:
        c = 1.0 / actuator_stiffness
        v = block.actuator
        n = 0
        for a in range(r):
            for b in range(a, r):
                m[n] = add(m[n], mul(c, mul(v[a], v[b])))
                n += 1
    w = block.basis
    out: Sym3 = [0.0] * 6
    if r == 1:
        add_outer(out, 1.0 / m[0], w[0])
        return out
    if r == 2:
        det = sub(mul(m[0], m[2]), mul(m[1], m[1]))
        add_outer(out, m[2] / det, w[0])
        add_outer(out, -m[1] / det, w[0], w[1])
        add_outer(out, m[0] / det, w[1])
        return out
    return sym3_inverse(m)


def sym3_inverse(m: Sym3) -> Sym3:
    """Inverse of a symmetric 3x3 matrix by its adjugate (upper triangles)."""
    a, b, c, d, e, f = m
    c00 = sub(mul(d, f), mul(e, e))
    c01 = sub(mul(c, e), mul(b, f))
    c02 = sub(mul(b, e), mul(c, d))
    c11 = sub(mul(a, f), mul(c, c))
    c12 = sub(mul(b, c), mul(a, e))
    c22 = sub(mul(a, d), mul(b, b))
    det = add(add(mul(a, c00), mul(b, c01)), mul(c, c02))
    inv = 1.0 / det
    return [mul(x, inv) for x in (c00, c01, c02, c11, c12, c22)]


def sym3_apply(m: Sym3, v: Vec3) -> Vec3:
    """``m @ v`` for a symmetric 3x3 ``m`` (upper triangle)."""
    a, b, c, d, e, f = m
    return (
        dot3((a, b, c), v),
        dot3((b, d, e), v),
        dot3((c, e, f), v),
    )


def leg_stiffness_blocks(leg: LegBlocks, actuator_stiffness: Scalar | None) -> tuple[Sym3, Sym3]:
    """In-plane and out-of-plane stiffness of one leg (upper triangles)."""
    return (
        block_stiffness(leg.inplane, actuator_stiffness),
        block_stiffness(leg.outplane, actuator_stiffness),
    )
