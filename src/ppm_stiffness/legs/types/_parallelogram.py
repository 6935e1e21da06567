"""A parallelogram forearm (a Delta robot's): two parallel bars with ball joints at
their four corners, as the last element of a chain leg.

The element (``parallelogram = {bar section}`` or ``"rigid"``) joins the body before
it (the arm) to the platform. At the design's home pose it is given by the centre
``near`` of its near crossbar (on the arm), the centre ``far`` of its far crossbar (on
the platform), the crossbars' direction ``crossbar`` (unit) and their ``width`` w
[m]: the corners are ``near +- (w/2) a`` and ``far +- (w/2) a``, and each bar runs
between the corners on the same side. The crossbars are rigid; the bars are beams
with a spherical joint (``S``) at each end, whose ``springs`` (a ``SphericalModel``
or one number) act at all four corners; their ``max_angle`` limits the angle at each
corner between the bar and its home direction carried by the corner's body (the arm,
or the platform): the leg's coordinate ``<name>_angle`` is the largest of the four.

Kinematics. Each bar keeps its home length: the leg's closure is the two bars' length
errors (:class:`ppm_stiffness.legs.kinematics.Bars`), not the end body's pose. With the
arm's freedoms this leaves the platform's rotation about ``a x n`` (n: the bars'
direction) constrained by each parallelogram: the three of a Delta fix its
orientation.

Stiffness. With ball joints at both ends a bar is a two-force member (its spin and
its bending are mechanisms): its stiffness along its axis is ``k_bar``, with
``1/k_bar = L/EA + 1/k_S,near + 1/k_S,far`` (the corner springs' ``axial``, along the
bar; their ``radial`` springs act in directions the bar already yields in). The two
bars together transmit only a force along n through the far crossbar's centre F
(stiffness ``2 k_bar``) and a couple about the unit ``mu = (a x n)/|a x n|`` (stiffness
``|a x n|^2 k_bar w^2/2``); every other relative motion of the crossbars (the two
translations normal to n, the rotations about a and about n: four freedoms) is free.
That is, exactly, the chain (:mod:`ppm_stiffness.legs.chain`) of two passive prismatic
joints normal to n and a universal joint at F with axes n and ``n x mu`` whose hardware
springs are ``2 k_bar`` along n and ``|a x n|^2 k_bar w^2/2`` about mu, rigid in its
other constrained directions (which the prismatic joints free): the element writes
that chain at each pose (:func:`parallelogram_joints`), so every layer that reads a
leg's chain (the stiffness, the batched engine, the mass model) takes it as it is.
That chain is exact to first order only: its prismatic joints slide without turning
the bars' forces, so the loaded mode's moving geometry, where the bars swing under
their axial loads, takes the bars themselves as two-force members instead
(:meth:`ChainLeg.bar_pair <ppm_stiffness.legs.types.chain_leg.ChainLeg.bar_pair>`,
:mod:`ppm_stiffness.statics.moving_bars`). The bars must be parallel (a
parallelogram): at a pose where they are not (the far crossbar skewed about the
bars by more than :data:`SKEW_TOLERANCE`), the leg refuses the pose.

Masses. A bar moves without spin; half of each bar's mass (the ``mass`` of its
section) is carried at each of its two crossbars' centres: at F with the platform, at
the near centre with the arm's end (the link before the element).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.conventions import FloatArray, cross
from ppm_stiffness.legs.base import check_plausible
from ppm_stiffness.legs.chain import Joint, JointMass, Link, LinkMass, unit
from ppm_stiffness.legs.parts import Finite, PartModel, Positive, SectionModel, SphericalModel
from ppm_stiffness.legs.types._spatial import check_unit

Vector3 = tuple[Finite, Finite, Finite]

#: Largest angle [rad] between a parallelogram's two bars at a pose it can take.
SKEW_TOLERANCE = 1e-9


class ParallelogramElement(PartModel):
    """A parallelogram forearm of a chain leg (module doc); lengths [m]."""

    parallelogram: SectionModel | Literal["rigid"]
    name: str = ""
    near: Vector3
    far: Vector3
    crossbar: Vector3
    width: Positive
    springs: Positive | SphericalModel | None = None

    def model_post_init(self, _context: object) -> None:
        for key in ("near", "far"):
            for v in getattr(self, key):
                check_plausible(key, v, "m")
        check_plausible("width", self.width, "m")
        a = check_unit("crossbar", self.crossbar)
        bar = np.subtract(self.far, self.near)
        length = float(np.linalg.norm(bar))
        if length <= 0.0 or np.linalg.norm(np.cross(a, bar / max(length, 1e-300))) < 1e-6:
            raise ValueError(
                "near and far: the bars (from near to far) must have a length and not "
                "lie along the crossbar"
            )

    @property
    def point(self) -> Vector3:
        """The near crossbar's centre (where the link before the element ends)."""
        return self.near

    def corners(self) -> tuple[FloatArray, FloatArray]:
        """The near and far corners at home (2, 3) each, F_b [m], in bar order."""
        half = 0.5 * self.width * np.asarray(self.crossbar, dtype=float)
        near, far = np.asarray(self.near, dtype=float), np.asarray(self.far, dtype=float)
        return np.stack([near + half, near - half]), np.stack([far + half, far - half])

    def bar_length(self) -> float:
        return float(np.linalg.norm(np.subtract(self.far, self.near)))

    def bar_stiffness(self) -> float:
        """``k_bar`` [N/m] (module doc); ``inf`` for rigid bars without corner springs."""
        compliance = 0.0
        if isinstance(self.parallelogram, SectionModel):
            section = self.parallelogram
            compliance += self.bar_length() / (section.young_modulus * section.area)
        if self.springs is not None:
            axial = self.springs if isinstance(self.springs, (int, float)) else self.springs.axial
            compliance += 2.0 / float(axial)
        return np.inf if compliance == 0.0 else 1.0 / compliance

    def max_angle(self) -> float | None:
        """The corners' angle limit [rad] (their springs' ``max_angle``), or None."""
        return getattr(self.springs, "max_angle", None)

    def bar_mass(self) -> float:
        """Each bar's mass [kg] (0: not given)."""
        section = self.parallelogram
        if isinstance(section, SectionModel) and section.mass is not None:
            return float(section.mass)
        return 0.0


def skew(near: FloatArray, far: FloatArray) -> FloatArray:
    """Angle [rad] between the two bars, (...) from corners (..., 2, 3)."""
    d = far - near
    n = d / np.linalg.norm(d, axis=-1, keepdims=True)
    s = np.linalg.norm(cross(n[..., 0, :], n[..., 1, :]), axis=-1)
    c = np.einsum("...i,...i->...", n[..., 0, :], n[..., 1, :])
    return np.asarray(np.arctan2(s, c))


def parallelogram_joints(
    element: ParallelogramElement, near: FloatArray, far: FloatArray, name: str
) -> list[Joint]:
    """The element's chain at poses (module doc): corners (..., 2, 3) relative to P,
    axes of F_b [m]; two passive P joints and a U at the far crossbar's centre."""
    bar = far[..., 0, :] - near[..., 0, :]
    n = unit(bar)
    a = unit(far[..., 0, :] - far[..., 1, :])
    normal = cross(a, n)
    sine = np.linalg.norm(normal, axis=-1)
    mu = unit(normal)
    m = cross(mu, n)
    centre = 0.5 * (far[..., 0, :] + far[..., 1, :])
    k_bar = element.bar_stiffness()
    springs = None
    if np.isfinite(k_bar):  # per pose: the couple's lever w |a x n| follows the angle
        rotation = sine**2 * k_bar * element.width**2 / 2.0
        springs = np.stack(np.broadcast_arrays(2.0 * k_bar, np.inf, np.inf, rotation), axis=-1)
    mass = element.bar_mass()
    return [
        Joint("P", m, centre, None, name=f"{name}.translation_1", equivalent=True),
        Joint("P", mu, centre, None, name=f"{name}.translation_2", equivalent=True),
        Joint(
            "U",
            n,
            centre,
            springs,
            name=name,
            axis2=m,
            mass=JointMass(mass=mass) if mass > 0.0 else None,
            equivalent=True,
        ),
    ]


def parallelogram_members(
    element: ParallelogramElement, near: FloatArray, far: FloatArray, name: str
) -> tuple[list[Link], list[Joint]]:
    """The element's parts as pictures draw them and the FE frame builds them, from its
    corners (2, 3) at one pose (relative to P) [m]: links: the near crossbar, the two
    bars (their section; :data:`RIGID_PART` for rigid bars), the far crossbar as two
    halves ending at its centre (where the leg meets the platform); each bar with its
    own mass as a uniform rod without spin (the frame's consistent beam mass; the
    mass model lumps its halves instead, module doc); joints: a ball
    joint with the corner springs at each corner, in pairs (near, far) per bar."""
    section = (
        element.parallelogram.section()
        if isinstance(element.parallelogram, SectionModel)
        else RIGID_PART
    )
    centre = far.mean(axis=0)
    bar_mass = element.bar_mass()
    mass = LinkMass(mass=bar_mass) if bar_mass > 0.0 else None  # uniform, no spin
    links = [
        Link(near[0], near[1], RIGID_PART, name=f"{name}.crossbar"),
        Link(near[0], far[0], section, name=name, mass=mass),
        Link(near[1], far[1], section, name=name, mass=mass),
        Link(far[0], centre, RIGID_PART, name=f"{name}.crossbar"),
        Link(far[1], centre, RIGID_PART, name=f"{name}.crossbar"),
    ]
    springs = None
    if element.springs is not None:
        springs = (
            np.full(3, float(element.springs))
            if isinstance(element.springs, (int, float))
            else element.springs.stiffnesses()
        )
    joints = []
    for k in range(2):
        bar = unit(far[k] - near[k])
        joints += [
            Joint("S", bar, near[k], springs, name=f"{name}.corner"),
            Joint("S", bar, far[k], springs, name=f"{name}.corner"),
        ]
    return links, joints


#: The stand-in section of a rigid part (the crossbars, rigid bars): never a beam.
RIGID_PART = BeamSection(1.0, 1.0, 1.0, 1.0, 1.0, 1.0)


__all__ = [
    "RIGID_PART",
    "SKEW_TOLERANCE",
    "ParallelogramElement",
    "parallelogram_joints",
    "parallelogram_members",
    "skew",
]
