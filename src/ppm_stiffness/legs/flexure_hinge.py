"""Notch flexure hinges: a profile ``h(x)``, a width, a material, and its 6x6 compliance.

Conventions (``docs/conventions.md``, "Flexure hinges"): hinge axes with x along the
notch from its base-side end (x = 0) towards the platform (x = L), z the rotation axis
across the width b, y = z x x (across the thickness h). Twists and wrenches are ordered
(phi; v) as everywhere (``core/conventions.py``). :meth:`FlexureHinge.compliance` is the
compliance of the hinge clamped at its base-side end, at its loaded end (x = L, axes
parallel to the hinge axes); with s = L - x measured from that end (Euler-Bernoulli,
no shear deformation)::

    C[phi_z, phi_z] = int 12 / (E b h^3) dx          C[v_x, v_x] = int 1 / (E b h) dx
    C[phi_y, phi_y] = int 12 / (E h b^3) dx          C[phi_x, phi_x] = int 1 / (G J) dx
    C[v_y, v_y] = int 12 s^2 / (E b h^3) ds          C[v_z, v_z] = int 12 s^2 / (E h b^3) ds
    C[v_y, phi_z] = + int 12 s / (E b h^3) ds        C[v_z, phi_y] = - int 12 s / (E h b^3) ds

J(x) is the Saint-Venant torsion constant of the b x h(x) rectangle
(:func:`torsion_constant`, its series summed to round-off). The integrals are composite
Gauss-Legendre rules in each profile segment's natural parameter (the angle of a
circular or elliptical arc, x on a flat or a tabulated piece), ``panels`` equal panels of
``points`` nodes per segment. With the defaults (16 x 24) the circular notch's
rotational compliance matches its closed form to 2.1e-14 relative for R/t from 1 to
1000, 6.6e-8 at R/t = 1e4 (64 panels: 1.3e-13) (``tests/test_flexure_hinge.py``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from ppm_stiffness.core.conventions import FloatArray, twist_b_from_twist_a
from ppm_stiffness.core.object_cache import per_object
from ppm_stiffness.legs.parts import NonNegative, PartModel, Positive

#: Default Gauss-Legendre panels per profile segment and nodes per panel (module doc).
PANELS = 16
POINTS = 24

#: A profile segment: parameter interval (u0, u1) and u -> (x, h, dx/du), vectorised.
ArrayLikeF = float | FloatArray
Segment = tuple[float, float, Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray]]]


class HingeMaterial(PartModel):
    """A hinge's material [Pa, kg/m^3]: E, and G or Poisson's ratio nu (one of them)."""

    UNITS: ClassVar[dict[str, str]] = {
        "young_modulus": "Pa",
        "shear_modulus": "Pa",
        "poisson_ratio": "1",
        "density": "kg/m^3",
        "yield_strength": "Pa",
    }

    young_modulus: Positive
    shear_modulus: Positive | None = None
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5)] | None = None
    density: NonNegative = 0.0
    yield_strength: Positive | None = None

    @model_validator(mode="after")
    def _one_shear_law(self) -> HingeMaterial:
        if (self.shear_modulus is None) == (self.poisson_ratio is None):
            raise ValueError("give exactly one of shear_modulus and poisson_ratio")
        return self

    @property
    def shear(self) -> float:
        """G [Pa]: given, or E / (2 (1 + nu))."""
        if self.shear_modulus is not None:
            return self.shear_modulus
        assert self.poisson_ratio is not None
        return self.young_modulus / (2.0 * (1.0 + self.poisson_ratio))


def _arc(centre: float, half: float, depth: float, t: float, th0: float, th1: float) -> Segment:
    """An elliptical arc cut in both faces: x = centre + half sin(th),
    h = t + 2 depth (1 - cos th)."""

    def shape(u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        return centre + half * np.sin(u), t + 2.0 * depth * (1.0 - np.cos(u)), half * np.cos(u)

    return (th0, th1, shape)


def _flat(x0: float, x1: float, h0: float, h1: float) -> Segment:
    """A straight piece, h linear in x from h0 to h1."""

    def shape(u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        return u, h0 + (h1 - h0) * (u - x0) / (x1 - x0), np.ones_like(u)

    return (x0, x1, shape)


#: Every other field of a profile or a hinge is a length [m] (a design's parameter table).
_LENGTHS: dict[str, str] = {
    key: "m"
    for key in (
        "radius",
        "thickness",
        "semi_length",
        "semi_depth",
        "length",
        "fillet_radius",
        "x",
        "h",
        "width",
    )
}


class CircularNotch(PartModel):
    """Right-circular notch: two cuts of radius R [m], minimum thickness t [m]; L = 2R."""

    UNITS: ClassVar[dict[str, str]] = _LENGTHS

    profile: Literal["circular"]
    radius: Positive
    thickness: Positive

    @property
    def length(self) -> float:
        return 2.0 * self.radius

    def segments(self) -> list[Segment]:
        r, t = self.radius, self.thickness
        half = np.pi / 2
        return [_arc(r, r, r, t, -half, 0.0), _arc(r, r, r, t, 0.0, half)]


class EllipticalNotch(PartModel):
    """Elliptical notch: semi-axis ``semi_length`` along x, ``semi_depth`` across h [m]."""

    UNITS: ClassVar[dict[str, str]] = _LENGTHS

    profile: Literal["elliptical"]
    semi_length: Positive
    semi_depth: Positive
    thickness: Positive

    @property
    def length(self) -> float:
        return 2.0 * self.semi_length

    def segments(self) -> list[Segment]:
        a, c, t = self.semi_length, self.semi_depth, self.thickness
        half = np.pi / 2
        return [_arc(a, a, c, t, -half, 0.0), _arc(a, a, c, t, 0.0, half)]


class FilletedLeaf(PartModel):
    """Corner-filleted leaf: total length L, thickness t, fillets of radius r at both ends."""

    UNITS: ClassVar[dict[str, str]] = _LENGTHS

    profile: Literal["filleted"]
    length: Positive
    fillet_radius: Positive
    thickness: Positive

    @model_validator(mode="after")
    def _fillets_fit(self) -> FilletedLeaf:
        if 2.0 * self.fillet_radius > self.length:
            raise ValueError("two fillet radii exceed the length")
        return self

    def segments(self) -> list[Segment]:
        r, t, L = self.fillet_radius, self.thickness, self.length
        half = np.pi / 2
        out = [_arc(r, r, r, t, -half, 0.0)]
        if L > 2.0 * r:
            out.append(_flat(r, L - r, t, t))
        return [*out, _arc(L - r, r, r, t, 0.0, half)]


class PlainLeaf(PartModel):
    """A prismatic leaf of length L and thickness t [m]."""

    UNITS: ClassVar[dict[str, str]] = _LENGTHS

    profile: Literal["leaf"]
    length: Positive
    thickness: Positive

    def segments(self) -> list[Segment]:
        return [_flat(0.0, self.length, self.thickness, self.thickness)]


class TabulatedProfile(PartModel):
    """Any profile: thickness ``h`` [m] at stations ``x`` [m] (from 0, increasing),
    linear between them."""

    UNITS: ClassVar[dict[str, str]] = _LENGTHS

    profile: Literal["tabulated"]
    x: list[float] = Field(min_length=2)
    h: list[Positive] = Field(min_length=2)

    @model_validator(mode="after")
    def _stations(self) -> TabulatedProfile:
        x = np.asarray(self.x)
        if len(self.x) != len(self.h):
            raise ValueError(f"x has {len(self.x)} stations and h {len(self.h)}")
        if x[0] != 0.0 or np.any(np.diff(x) <= 0.0) or not np.all(np.isfinite(x)):
            raise ValueError("x must start at 0 and increase strictly")
        return self

    @property
    def length(self) -> float:
        return float(self.x[-1])

    def segments(self) -> list[Segment]:
        x, h = self.x, self.h
        return [_flat(x[i], x[i + 1], h[i], h[i + 1]) for i in range(len(x) - 1)]


Profile = Annotated[
    CircularNotch | EllipticalNotch | FilletedLeaf | PlainLeaf | TabulatedProfile,
    Field(discriminator="profile"),
]


def torsion_constant(width: ArrayLikeF, thickness: ArrayLikeF) -> FloatArray:
    """Saint-Venant torsion constant J [m^4] of a solid a x c rectangle (a >= c)::

        J = a c^3 / 3 [1 - 192 c / (pi^5 a) sum_{n odd} tanh(n pi a / (2 c)) / n^5]

    The sum is (31/32) zeta(5) minus sum_{n odd} (1 - tanh(...)) / n^5, whose terms fall
    as exp(-n pi a / c): 40 of them leave it exact to round-off for any a >= c.
    """
    from scipy.special import zeta

    w, t = np.broadcast_arrays(np.asarray(width, float), np.asarray(thickness, float))
    a, c = np.maximum(w, t), np.minimum(w, t)
    n = np.arange(1, 80, 2, dtype=float)
    arg = n * np.pi * (a / c)[..., None] / 2.0
    decay = np.exp(-2.0 * arg)
    tail = np.sum(2.0 * decay / (1.0 + decay) / n**5, axis=-1)  # sum (1 - tanh) / n^5
    series = 31.0 / 32.0 * float(zeta(5.0)) - tail
    return np.asarray(a * c**3 / 3.0 * (1.0 - 192.0 * c / (np.pi**5 * a) * series))


def _nodes(segments: list[Segment], panels: int, points: int) -> tuple[FloatArray, ...]:
    """Stations x, thicknesses h and weights w (sum w f(x) ~ int f dx) of the rule."""
    g, gw = np.polynomial.legendre.leggauss(points)
    xs, hs, ws = [], [], []
    for u0, u1, shape in segments:
        edges = np.linspace(u0, u1, panels + 1)
        mid, half = (edges[1:] + edges[:-1]) / 2, (edges[1:] - edges[:-1]) / 2
        u = (mid[:, None] + half[:, None] * g).ravel()
        x, h, dxdu = shape(u)
        xs.append(x)
        hs.append(h)
        ws.append((half[:, None] * gw).ravel() * dxdu)
    return np.concatenate(xs), np.concatenate(hs), np.concatenate(ws)


class FlexureHinge(PartModel):
    """A notch flexure hinge: its profile, width b [m] (along the rotation axis z),
    material and optional stress concentration factor. Compliances in hinge axes, order
    (phi; v), SI (module doc)."""

    UNITS: ClassVar[dict[str, str]] = {**_LENGTHS, "stress_concentration": "1"}

    profile: Profile
    width: Positive
    material: HingeMaterial
    #: K_t in in-plane bending (>= 1); None: the built-in one of a circular notch or a
    #: leaf (:func:`ppm_stiffness.statics.hinge_stress.stress_concentration`).
    stress_concentration: Annotated[float, Field(ge=1.0, allow_inf_nan=False)] | None = None

    @property
    def length(self) -> float:
        """The notch's length L [m] along x."""
        return float(self.profile.length)

    def compliance(self, panels: int = PANELS, points: int = POINTS) -> FloatArray:
        """6x6 compliance at the loaded end (x = L), clamped at x = 0 (module doc).

        Parameters
        ----------
        panels, points : int
            Gauss-Legendre panels per profile segment and nodes per panel.

        Returns
        -------
        ndarray, shape (6, 6)
            [rad/(N·m), rad/N, m/N], hinge axes at the loaded end. A new array (the
            default quadrature's is computed once per hinge: the hinge is frozen).
        """
        if (panels, points) == (PANELS, POINTS):
            return _default_compliance(self).copy()
        return quadrature_compliance(self, panels, points)

    def compliance_at(self, x: float, panels: int = PANELS, points: int = POINTS) -> FloatArray:
        """The compliance transported to the station x [m] on the hinge's axis (axes
        unchanged): ``T C T^T`` with T the twist map of ``core/conventions.py``."""
        t = twist_b_from_twist_a(np.eye(3), [self.length - x, 0.0, 0.0])
        return np.asarray(t @ self.compliance(panels, points) @ t.T)

    def centre_compliance(self) -> FloatArray:
        """Compliance at the notch's centre x = L / 2 (diagonal for a symmetric notch)."""
        return self.compliance_at(self.length / 2.0)


def quadrature_compliance(hinge: FlexureHinge, panels: int, points: int) -> FloatArray:
    """:meth:`FlexureHinge.compliance` by Gauss-Legendre quadrature of the profile's
    Euler-Bernoulli integrals (module doc), computed afresh."""
    x, h, w = _nodes(hinge.profile.segments(), panels, points)
    e, b = hinge.material.young_modulus, hinge.width
    s = hinge.length - x
    in_plane = w * 12.0 / (e * b * h**3)
    out_plane = w * 12.0 / (e * h * b**3)
    c = np.zeros((6, 6))
    c[0, 0] = np.sum(w / (hinge.material.shear * torsion_constant(b, h)))
    c[1, 1] = np.sum(out_plane)
    c[2, 2] = np.sum(in_plane)
    c[3, 3] = np.sum(w / (e * b * h))
    c[4, 4] = np.sum(in_plane * s**2)
    c[5, 5] = np.sum(out_plane * s**2)
    c[4, 2] = c[2, 4] = np.sum(in_plane * s)
    c[5, 1] = c[1, 5] = -np.sum(out_plane * s)
    return c


@per_object
def _default_compliance(hinge: FlexureHinge) -> FloatArray:
    """The default quadrature's compliance, once per hinge (shared: never changed)."""
    return quadrature_compliance(hinge, PANELS, POINTS)


#: Largest off-diagonal entry of a notch's centre compliance, relative to the geometric
#: mean of its diagonal pair, for the notch to be a joint (symmetric profiles give 1e-16).
SYMMETRY_TOLERANCE = 1e-9


def asymmetry(hinge: FlexureHinge) -> float:
    """max |C_ij| / sqrt(C_ii C_jj), i != j, of the compliance at the notch's centre."""
    c = hinge.centre_compliance()
    d = np.sqrt(np.diag(c))
    return float(np.max(np.abs(c - np.diag(np.diag(c))) / np.outer(d, d)))


def joint_stiffnesses(
    hinge: FlexureHinge,
    directions: tuple[tuple[str, int], ...],
    hinge_axes: tuple[int, int, int],
) -> FloatArray:
    """1 / C_ii at the notch's centre along directions of a joint frame.

    Parameters
    ----------
    hinge : FlexureHinge
        A symmetric notch (its centre compliance diagonal, :func:`asymmetry`).
    directions : tuple of ("r" | "t", k)
        Directions of the joint frame (e1, e2, e3) (:mod:`ppm_stiffness.legs.joint_kinds`).
    hinge_axes : (int, int, int)
        The hinge axis (0, 1, 2 for x, y, z) along e1, e2, e3 (the kind's record).

    Returns
    -------
    ndarray, shape (len(directions),)
        [N·m/rad for a rotation, N/m for a translation].
    """
    c = np.diag(hinge.centre_compliance())
    index = [hinge_axes[k] + (3 if kind == "t" else 0) for kind, k in directions]
    return np.asarray(1.0 / c[index])
