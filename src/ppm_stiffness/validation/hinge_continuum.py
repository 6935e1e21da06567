"""A notch hinge's in-plane stiffness by a 2-D plane-stress finite-element model.

An independent check of the Euler-Bernoulli integrals of
:class:`~ppm_stiffness.legs.flexure_hinge.FlexureHinge` (issue 29 item 5), with
scikit-fem (the optional extra ``validate``; imported when called).

Model (hinge axes: x along the notch, y across its thickness, z the rotation axis)
---------------------------------------------------------------------------------
* Domain: the notch's profile, x in [0, L], |y| <= h(x) / 2, plus a prismatic stub of
  the end thickness and of length equal to it at each end (x in [-s0, 0] and
  [L, L + s1], s = h at that end): the clamp and the load act on the stubs, so that
  their local disturbance (the clamp's hold on the Poisson contraction, a traction not
  exactly the elastic one) has decayed at the notch's end sections (Saint-Venant's
  principle: over about one section depth).
* Plane stress (the Euler-Bernoulli integrals' E), unit thickness; the stiffnesses
  scale with the width b. ``state="strain"`` gives the plane-strain bound
  (E / (1 - nu^2)), which a hinge much wider than thick approaches at its waist.
* Boundary conditions: the face x = -s0 clamped (u = 0); on the face x = L + s1 a pure
  moment (traction t_x = -12 M y / h^3, the linear bending stress, no net force) or a
  pure axial force (uniform t_x = N / h).
* What is measured: the notch's end sections x = 0 and x = L are mesh lines; the
  rotation of each is the least-squares rotation of its points, theta =
  -int y u_x dy / int y^2 dy (Simpson's rule, exact on the quadratic elements), and its
  axial displacement the mean of u_x. K_phiz = M / (theta(L) - theta(0)), K_x = N /
  (mean u_x(L) - mean u_x(0)): the stiffness of the notch alone between its end
  sections, the quantity the beam integrals give.
* Mesh: a structured grid of quadratic triangles (``ElementTriP2``), the columns
  equidistributed in int dx / h (columns about as far apart as the section is deep
  over ``ny`` rows; ``aspect`` scales that), the nodes on the exact profile, straight
  edges between them. Richardson extrapolation over meshes refined by 2 in both
  directions gives the limit and the observed order of convergence.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import ValidationError

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.legs.flexure_hinge import FlexureHinge
from ppm_stiffness.validation import MissingExtraError

#: Rows across the section of the coarsest mesh, and the number of meshes (each twice
#: as fine as the one before) of :func:`continuum_stiffness`.
COARSEST_ROWS = 4
LEVELS = 3
#: Parameter samples per profile segment of the table that places the columns.
_TABLE = 2001


def require_skfem() -> Any:
    """The ``skfem`` package, or :class:`MissingExtraError` with the install hint."""
    try:
        import skfem
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise MissingExtraError(
            "the hinge continuum check needs scikit-fem: pip install 'ppm-stiffness[validate]'"
        ) from exc
    return skfem


@dataclass(frozen=True)
class MeshResult:
    """One mesh's figures: rows across the section, unknowns, K_phiz [N·m/rad] and
    K_x [N/m] for the hinge's width."""

    rows: int
    dofs: int
    rotational: float
    axial: float


@dataclass(frozen=True)
class ContinuumResult:
    """The continuum model's stiffnesses beside the beam integrals'.

    Attributes
    ----------
    meshes : list of MeshResult
        Coarsest first.
    rotational, axial : float
        Richardson limits [N·m/rad, N/m] (the finest mesh's value when the increments
        do not shrink monotonically: ``order`` is then None).
    order_rotational, order_axial : float or None
        Observed orders of convergence, log2 of the ratio of the last two increments.
    rotational_eb, axial_eb : float
        1 / C_phiz_phiz and 1 / C_xx of :meth:`FlexureHinge.compliance`.
    """

    meshes: list[MeshResult]
    rotational: float
    axial: float
    order_rotational: float | None
    order_axial: float | None
    rotational_eb: float
    axial_eb: float


def richardson(values: list[float]) -> tuple[float, float | None]:
    """Limit and observed order of a sequence on meshes refined by 2.

    With increments d1 = v[-2] - v[-3], d2 = v[-1] - v[-2] of the same sign and
    shrinking, the order is p = log2(d1 / d2) and the limit v[-1] + d2 / (2^p - 1);
    otherwise (fewer than three values, or no monotone convergence) the last value and
    None.
    """
    if len(values) < 3:
        return values[-1], None
    d1, d2 = values[-2] - values[-3], values[-1] - values[-2]
    if d2 == 0.0:
        return values[-1], None
    if d1 / d2 <= 1.0:
        return values[-1], None
    p = math.log2(d1 / d2)
    return values[-1] + d2 / (2.0**p - 1.0), p


def _segment_table(hinge: FlexureHinge) -> list[tuple[FloatArray, FloatArray, FloatArray, Any]]:
    """Per profile segment: parameter samples u, x(u), h(u) and the shape function."""
    out = []
    for u0, u1, shape in hinge.profile.segments():
        u = np.linspace(u0, u1, _TABLE)
        x, h, _ = shape(u)
        out.append((u, np.asarray(x, float), np.asarray(h, float), shape))
    return out


def _stations(hinge: FlexureHinge, rows: int, aspect: float) -> tuple[FloatArray, FloatArray]:
    """Column stations x [m] and thicknesses h [m] over the notch, on the exact
    profile: per segment, columns equidistributed in int dx / h, their number
    ``rows * aspect * int dx / h`` (at least one), segment ends included."""
    xs: list[float] = [0.0]
    hs: list[float] = []
    for k, (u, x, h, shape) in enumerate(_segment_table(hinge)):
        if k == 0:
            hs.append(float(h[0]))
        depth = np.concatenate([[0.0], np.cumsum(np.diff(x) * 0.5 * (1 / h[1:] + 1 / h[:-1]))])
        count = max(1, math.ceil(rows * aspect * depth[-1]))
        targets = np.linspace(0.0, depth[-1], count + 1)[1:]
        u_at = np.interp(targets, depth, u)
        u_at[-1] = u[-1]
        x_at, h_at, _ = shape(u_at)
        xs.extend(np.asarray(x_at, float).tolist())
        hs.extend(np.asarray(h_at, float).tolist())
    return np.array(xs), np.array(hs)


def _grid(hinge: FlexureHinge, rows: int, aspect: float) -> tuple[FloatArray, FloatArray, int, int]:
    """The columns (x, h) of the whole domain, stubs included, and the indices of the
    notch's end columns."""
    x, h = _stations(hinge, rows, aspect)
    x[-1] = hinge.length
    h0, h1 = h[0], h[-1]
    n0 = max(1, math.ceil(rows * aspect))
    left = np.linspace(-h0, 0.0, n0 + 1)[:-1]
    right = np.linspace(hinge.length, hinge.length + h1, n0 + 1)[1:]
    columns = np.concatenate([left, x, right])
    depths = np.concatenate([np.full(n0, h0), h, np.full(n0, h1)])
    return columns, depths, n0, n0 + len(x) - 1


def _mesh(columns: FloatArray, depths: FloatArray, rows: int) -> Any:
    """A structured mesh of triangles: node (i, j) at (x_i, (j / rows - 1/2) h_i)."""
    skfem = require_skfem()
    nx = len(columns)
    eta = np.linspace(-0.5, 0.5, rows + 1)
    px = np.repeat(columns, rows + 1)
    py = (depths[:, None] * eta[None, :]).ravel()
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(rows), indexing="ij")
    a = (i * (rows + 1) + j).ravel()
    b, c, d = a + rows + 1, a + rows + 2, a + 1
    t = np.hstack([np.vstack([a, b, c]), np.vstack([a, c, d])])
    return skfem.MeshTri(np.vstack([px, py]), t)


def _section(basis: Any, x0: float, u: FloatArray) -> tuple[float, float]:
    """Least-squares rotation and mean axial displacement of the section x = x0."""
    locs = basis.doflocs
    nodal = basis.nodal_dofs  # (2, n_vertices): x and y components at the vertices
    facet = basis.facet_dofs if basis.facet_dofs.size else np.zeros((2, 0), int)
    dofs_x = np.concatenate([nodal[0], facet[0]])
    on = dofs_x[np.abs(locs[0, dofs_x] - x0) <= 1e-9 * max(1.0, abs(x0)) + 1e-15]
    order = np.argsort(locs[1, on])
    y, ux = locs[1, on][order], u[on][order]
    if len(y) < 3 or len(y) % 2 == 0:  # pragma: no cover - the grid's construction
        raise InputDataError(f"continuum model: section x = {x0:g} m is not a mesh line")
    dy = (y[-1] - y[0]) / (len(y) - 1)
    w = np.ones(len(y))
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    w *= dy / 3.0  # composite Simpson over the quadratic elements' nodes
    depth = float(np.sum(w))
    ybar = float(np.sum(w * y)) / depth
    yc = y - ybar
    theta = -float(np.sum(w * yc * ux)) / float(np.sum(w * yc**2))
    return theta, float(np.sum(w * ux)) / depth


def _lame(hinge: FlexureHinge, state: Literal["stress", "strain"]) -> tuple[float, float]:
    """Lame parameters (lambda, mu) [Pa] of plane stress or plane strain."""
    e, g = hinge.material.young_modulus, hinge.material.shear
    nu = e / (2.0 * g) - 1.0
    if not -1.0 < nu < 0.5:
        raise InputDataError(
            f"continuum model: E = {e:g} Pa and G = {g:g} Pa give Poisson's ratio {nu:g}, "
            "outside (-1, 0.5)"
        )
    if state == "stress":
        return e * nu / (1.0 - nu**2), g
    return e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), g


def _solve(
    hinge: FlexureHinge, rows: int, aspect: float, state: Literal["stress", "strain"]
) -> tuple[Any, FloatArray, FloatArray, int, int, FloatArray]:
    """The mesh's basis, its columns (x, h), the notch's end columns and the
    displacements (N, 2) under a unit end moment and a unit axial force per unit width
    (module doc)."""
    skfem = require_skfem()
    from skfem.helpers import dot
    from skfem.models.elasticity import linear_elasticity

    columns, depths, i0, i1 = _grid(hinge, rows, aspect)
    mesh = _mesh(columns, depths, rows)
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
    lam, mu = _lame(hinge, state)
    stiffness = skfem.asm(linear_elasticity(lam, mu), basis)
    x_end, h_end = float(columns[-1]), float(depths[-1])
    loaded = mesh.facets_satisfying(lambda p: np.abs(p[0] - x_end) < 1e-12 * (1.0 + abs(x_end)))
    face = skfem.FacetBasis(mesh, basis.elem, facets=loaded)

    @skfem.LinearForm
    def moment(v: Any, w: Any) -> Any:  # unit moment: t_x = -12 y / h^3
        return -12.0 * w.x[1] / h_end**3 * v[0]

    @skfem.LinearForm
    def force(v: Any, w: Any) -> Any:  # unit axial force: t_x = 1 / h
        return dot(np.array([1.0 / h_end, 0.0])[:, None, None] + 0.0 * w.x, v)

    x_start = float(columns[0])
    clamped = basis.get_dofs(lambda p: np.abs(p[0] - x_start) < 1e-12 * (1.0 + abs(x_start)))
    loads = np.column_stack([skfem.asm(moment, face), skfem.asm(force, face)])
    displacement = np.zeros_like(loads)
    for k in range(2):
        displacement[:, k] = skfem.solve(*skfem.condense(stiffness, loads[:, k], D=clamped))
    return basis, columns, depths, i0, i1, displacement


def mesh_stiffness(
    hinge: FlexureHinge,
    rows: int,
    aspect: float = 1.0,
    state: Literal["stress", "strain"] = "stress",
) -> MeshResult:
    """K_phiz and K_x of ``hinge`` on one mesh of ``rows`` rows (module doc)."""
    basis, columns, _, i0, i1, displacement = _solve(hinge, rows, aspect, state)
    a, b = float(columns[i0]), float(columns[i1])
    rot = _section(basis, b, displacement[:, 0])[0] - _section(basis, a, displacement[:, 0])[0]
    ext = _section(basis, b, displacement[:, 1])[1] - _section(basis, a, displacement[:, 1])[1]
    width = hinge.width
    return MeshResult(rows, int(basis.N), width / rot, width / ext)


def waist_stress_factor(hinge: FlexureHinge, rows: int = 16, aspect: float = 1.0) -> float:
    """The in-plane bending stress at a symmetric notch's waist surface under a pure
    moment, over the beam value 6 M / (b t^2): the stress concentration factor K_t by
    the plane-stress model (the axial strain's central difference along the waist's
    surface, where the surface is parallel to x, times E: a free surface carries
    sigma_xx alone)."""
    thickness = getattr(hinge.profile, "thickness", None)
    if thickness is None:
        raise InputDataError("continuum model: the waist stress needs a profile's thickness")
    basis, _, _, _, _, displacement = _solve(hinge, rows, aspect, "stress")
    ux_basis = basis.split_bases()[0]
    ux = displacement[basis.split_indices()[0], 0]
    centre, t = hinge.length / 2.0, float(thickness)
    step = 1e-3 * t
    y = 0.5 * t * (1.0 - 1e-9)  # just inside the surface
    probes = ux_basis.probes(np.array([[centre - step, centre + step], [y, y]]))
    strain = float(np.diff(probes @ ux)[0]) / (2.0 * step)
    return abs(hinge.material.young_modulus * strain) / (6.0 / t**2)


def continuum_stiffness(
    hinge: FlexureHinge,
    coarsest: int = COARSEST_ROWS,
    levels: int = LEVELS,
    aspect: float = 1.0,
    state: Literal["stress", "strain"] = "stress",
) -> ContinuumResult:
    """K_phiz and K_x of ``hinge`` by the continuum model on ``levels`` meshes of
    ``coarsest * 2^k`` rows, Richardson-extrapolated, beside the beam integrals.

    Parameters
    ----------
    hinge : FlexureHinge
    coarsest : int
        Rows across the section of the coarsest mesh (>= 2).
    levels : int
        Number of meshes (>= 1; 3 for an extrapolation with its observed order).
    aspect : float
        Column density: columns ``aspect * rows`` per section depth (> 0).
    state : {"stress", "strain"}
        Plane stress (the beam integrals' E) or plane strain.

    Returns
    -------
    ContinuumResult
        Stiffnesses [N·m/rad, N/m] for the hinge's width b.

    Raises
    ------
    InputDataError
        Bad mesh parameters.
    """
    if coarsest < 2 or levels < 1 or not aspect > 0.0 or not math.isfinite(aspect):
        raise InputDataError(
            f"continuum model: coarsest >= 2 rows, levels >= 1 and aspect > 0, got "
            f"{coarsest}, {levels}, {aspect}"
        )
    meshes = [mesh_stiffness(hinge, coarsest * 2**k, aspect, state) for k in range(levels)]
    rot, p_rot = richardson([m.rotational for m in meshes])
    ax, p_ax = richardson([m.axial for m in meshes])
    c = hinge.compliance()
    return ContinuumResult(meshes, rot, ax, p_rot, p_ax, 1.0 / c[2, 2], 1.0 / c[3, 3])


def hinges_in_file(path: str | Path) -> list[tuple[str, FlexureHinge]]:
    """The distinct notch hinges of a TOML file: a design's (its chain legs' R joints
    with a ``hinge`` table; equal hinges once, labelled by the first joint and their
    count) or one hinge (``profile``, ``width``, ``material`` at the top level or in a
    ``[hinge]`` table).

    Raises
    ------
    DesignError
        Not a readable TOML file, not a valid design or hinge, or a design without a
        hinge.
    """
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise DesignError(f"{p}: cannot read it as TOML: {exc}") from None
    if "legs" not in data:
        raw = data.get("hinge", data)
        try:
            return [("hinge", FlexureHinge.model_validate(raw))]
        except ValidationError as exc:
            first = exc.errors()[0]
            where = ".".join(str(k) for k in first["loc"]) or "(top level)"
            raise DesignError(
                f"{p}: neither a design (no [[legs]]) nor a hinge (profile, width, "
                f"material): {where}: {first['msg']}"
            ) from None
    from ppm_stiffness.design import load_design
    from ppm_stiffness.legs.types.chain_leg import ChainLeg, JointElement

    design = load_design(p)
    found: list[tuple[list[str], FlexureHinge]] = []
    for i, leg in enumerate(design.legs):
        if not isinstance(leg, ChainLeg):
            continue
        for k, element in enumerate(leg.elements):
            if isinstance(element, JointElement) and element.hinge is not None:
                name = f"leg{i + 1}.{leg.element_name(k)}"
                same = next((g for g in found if g[1] == element.hinge), None)
                if same is None:
                    found.append(([name], element.hinge))
                else:
                    same[0].append(name)
    if not found:
        raise DesignError(f"{p}: the design has no notch hinge (an R joint's hinge table)")
    return [
        (names[0] if len(names) == 1 else f"{names[0]} (+{len(names) - 1} equal)", hinge)
        for names, hinge in found
    ]


__all__ = [
    "ContinuumResult",
    "hinges_in_file",
    "MeshResult",
    "continuum_stiffness",
    "mesh_stiffness",
    "require_skfem",
    "richardson",
]
