"""Everything the code knows about a joint kind, in one record per kind.

A joint of a chain (:class:`ppm_stiffness.legs.chain.Joint`) names its kind by a letter:
revolute ``"R"``, prismatic ``"P"``, cylindrical ``"C"`` (a coaxial P + R), universal
``"U"`` (rotations about ``e1`` and a second axis ``e2``) or spherical ``"S"`` (three
rotations about its point). :func:`joint_kind` returns the kind's
:class:`JointKindRecord`; every table and branch of the model, the batched engines,
the FE frame, the mass model and the pictures reads the record, so that no other
module tests a joint's letter (``tests/test_joint_kinds.py`` guards it). Adding a
kind is adding a record here.

Directions are those of the joint frame ``(e1, e2, e3)``
(:meth:`~ppm_stiffness.legs.chain.Joint.frame`): ``("r", k)`` a rotation about
``e_k``, ``("t", k)`` a translation along ``e_k`` (k = 0, 1, 2 for e1, e2, e3).

==== ============ =============================== =====================================
kind name         freedoms                        constrained directions (spring order)
==== ============ =============================== =====================================
R    revolute     rotation e1                     rotation e2, e3; translation e1, e2, e3
P    prismatic    translation e1                  rotation e1, e2, e3; translation e2, e3
C    cylindrical  rotation e1, translation e1     rotation e2, e3; translation e2, e3
U    universal    rotation e1, rotation e2        translation e1, e2, e3; rotation e3
S    spherical    rotation e1, e2, e3             translation e1, e2, e3
==== ============ =============================== =====================================

The FE frame (:mod:`ppm_stiffness.validation.joints`) numbers a joint's six relative
motions 0-2 (rotations about e1, e2, e3) and 3-5 (translations along e1, e2, e3); a
kind's FE releases are the motions it leaves free, the actuated one first.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from pydantic import BaseModel

from ppm_stiffness.core.errors import DesignError

#: The letters of the joint kinds.
JointKind = Literal["R", "P", "C", "U", "S"]

#: A direction of a joint frame: ("r", k) a rotation about e_k, ("t", k) a translation
#: along e_k (k = 0, 1, 2 for e1, e2, e3).
Direction = tuple[Literal["r", "t"], int]


@dataclass(frozen=True)
class AxisBar:
    """Bars drawn along a joint's axes in the mechanism pictures.

    Attributes
    ----------
    colour : str or None
        Matplotlib colour; None: the leg's colour.
    width : float [pt]
    half : float
        Half the bar's length, in the picture's joint unit.
    """

    colour: str | None
    width: float
    half: float


@dataclass(frozen=True)
class JointKindRecord:
    """One joint kind: its motions, its FE releases, how it is drawn and named.

    Attributes
    ----------
    letter : {"R", "P", "C", "U", "S"}
    name : str
        Its name in words (``"revolute"``).
    freedoms : tuple of Direction
        Its freedoms as directions of its frame, in order (an actuated joint's actuated
        freedom is the first; the passive-joint twists follow this order).
    constrained : tuple of Direction
        Its constrained directions, in the order of its hardware springs
        (:mod:`ppm_stiffness.legs.parts`).
    fe_releases : tuple of int
        The relative motions the FE joint leaves free (0-2 rotations about e1, e2, e3;
        3-5 translations along e1, e2, e3), the actuated one first.
    second_axis : bool
        Its second axis ``e2`` is a freedom's axis, given as such and required (a U);
        for the other kinds an optional second axis only orients ``e2`` normal to e1.
    marker : str
        Matplotlib marker of its symbol in the mechanism pictures.
    size_3d : float [pt]
        Marker size in the 3-D view.
    size_2d : float [pt^2]
        Marker area in the planar top view.
    filled : bool
        The symbol is filled with the leg's colour (else white, drawn above the links).
    bar : AxisBar or None
        Bars along its axes (a slider, a sleeve, an axis), or None (a ball).
    legend : str
        What the 3-D view's legend says of its symbol.
    caption : str
        How the report's caption words its symbol (plural).
    spring_part : str
        The class of :mod:`ppm_stiffness.legs.parts` that gives its hardware springs in
        a design file (a chain leg's joint ``springs``).
    hinge_axes : (int, int, int) or None
        The kind may be a notch flexure hinge (:mod:`ppm_stiffness.legs.flexure_hinge`):
        the hinge axis (0, 1, 2 for x, y, z) along e1, e2, e3 of its frame; its freedoms
        are elastic and its springs 1 / C_ii of the hinge along its constrained
        directions. None: no hinge (only an R is one: e1 = z the axis, e2 = x along the
        notch, e3 = y).
    """

    letter: JointKind
    name: str
    freedoms: tuple[Direction, ...]
    constrained: tuple[Direction, ...]
    fe_releases: tuple[int, ...]
    second_axis: bool
    marker: str
    size_3d: float
    size_2d: float
    filled: bool
    bar: AxisBar | None
    legend: str
    caption: str
    spring_part: str
    hinge_axes: tuple[int, int, int] | None = None

    def springs_model(self) -> type[BaseModel]:
        """The part (:mod:`ppm_stiffness.legs.parts`) that gives this kind's hardware
        springs in a design file, by the class named in ``spring_part``."""
        from ppm_stiffness.legs import parts

        model: type[BaseModel] = getattr(parts, self.spring_part)
        return model

    @property
    def freedom_count(self) -> int:
        """Number of freedoms."""
        return len(self.freedoms)

    @property
    def constrained_count(self) -> int:
        """Number of constrained directions (hardware springs)."""
        return len(self.constrained)

    @property
    def rotations(self) -> int:
        """Number of rotational freedoms."""
        return sum(d == "r" for d, _ in self.freedoms)

    @property
    def spherical(self) -> bool:
        """Its freedoms are the three rotations about its point."""
        return self.rotations == 3 and self.freedom_count == 3

    @property
    def planar(self) -> bool:
        """It may keep a planar mechanism planar: at most one rotation (about the
        plane's normal) among its freedoms."""
        return self.rotations <= 1

    @property
    def linear(self) -> bool:
        """Every freedom is a translation (a guide: a rail when it is a leg's base
        joint, a linear actuator when actuated)."""
        return self.rotations == 0

    @property
    def slides(self) -> bool:
        """It has a translational freedom (drawn with a slider or a sleeve). Its point
        (where its springs act) then lies on one of its two bodies, not on both: a
        bushing on the body before it, or a carriage on the body after it (a chain
        joint's ``carried_by``); a kind that does not slide has its point on its axes,
        the same point of both bodies."""
        return self.rotations < self.freedom_count

    @property
    def first_rotates(self) -> bool:
        """Its first freedom (an actuated joint's actuated one, where a rotor reflects
        its inertia) is a rotation."""
        return self.freedoms[0][0] == "r"

    @property
    def label(self) -> str:
        """Its name in a legend (``"revolute joint R"``)."""
        return f"{self.name} joint {self.letter}"

    def actuator_units(self) -> tuple[str, str, str]:
        """SI units of an actuator along its first freedom: force, displacement and
        stiffness (a rotary actuator: N·m, rad, N·m/rad; a linear one: N, m, N/m)."""
        if self.first_rotates:
            return "N·m", "rad", "N·m/rad"
        return "N", "m", "N/m"


_AXIS = AxisBar("k", 2.5, 0.8)
_SLIDER = AxisBar(None, 7.0, 0.45)
_SLEEVE = AxisBar("k", 7.0, 0.45)

#: Every joint kind, by its letter.
JOINT_KINDS: dict[str, JointKindRecord] = {
    record.letter: record
    for record in (
        JointKindRecord(
            letter="R",
            name="revolute",
            freedoms=(("r", 0),),
            constrained=(("r", 1), ("r", 2), ("t", 0), ("t", 1), ("t", 2)),
            fe_releases=(0,),
            second_axis=False,
            marker="o",
            size_3d=5.5,
            size_2d=45.0,
            filled=False,
            bar=_AXIS,
            legend="revolute joint R (bar: its axis)",
            caption="revolute joints R: a circle with a bar along the axis",
            spring_part="RevoluteModel",
            hinge_axes=(2, 0, 1),
        ),
        JointKindRecord(
            letter="P",
            name="prismatic",
            freedoms=(("t", 0),),
            constrained=(("r", 0), ("r", 1), ("r", 2), ("t", 1), ("t", 2)),
            fe_releases=(3,),
            second_axis=False,
            marker="s",
            size_3d=8.0,
            size_2d=70.0,
            filled=True,
            bar=_SLIDER,
            legend="prismatic joint (type letter P; bar: its slider)",
            caption="prismatic joints (type letter P): a square with the slider",
            spring_part="GuideModel",
        ),
        JointKindRecord(
            letter="C",
            name="cylindrical",
            freedoms=(("r", 0), ("t", 0)),
            constrained=(("r", 1), ("r", 2), ("t", 1), ("t", 2)),
            fe_releases=(0, 3),
            second_axis=False,
            marker="D",
            size_3d=7.5,
            size_2d=55.0,
            filled=True,
            bar=_SLEEVE,
            legend="cylindrical joint C (sleeve: its axis)",
            caption="cylindrical joints C: a diamond with the sleeve",
            spring_part="BearingModel",
        ),
        JointKindRecord(
            letter="U",
            name="universal",
            freedoms=(("r", 0), ("r", 1)),
            constrained=(("t", 0), ("t", 1), ("t", 2), ("r", 2)),
            fe_releases=(0, 1),
            second_axis=True,
            marker="P",
            size_3d=7.0,
            size_2d=55.0,
            filled=False,
            bar=_AXIS,
            legend="universal joint U (bars: its two axes)",
            caption="universal joints U: a cross with bars along their two axes",
            spring_part="UniversalModel",
        ),
        JointKindRecord(
            letter="S",
            name="spherical",
            freedoms=(("r", 0), ("r", 1), ("r", 2)),
            constrained=(("t", 0), ("t", 1), ("t", 2)),
            fe_releases=(0, 1, 2),
            second_axis=False,
            marker="o",
            size_3d=10.0,
            size_2d=90.0,
            filled=True,
            bar=None,
            legend="spherical joint S",
            caption="spherical joints S: a ball",
            spring_part="SphericalModel",
        ),
    )
}


def joint_kind(letter: str) -> JointKindRecord:
    """The record of the joint kind ``letter``.

    Raises
    ------
    DesignError
        ``letter`` is not a joint kind.
    """
    record = JOINT_KINDS.get(letter)
    if record is None:
        raise DesignError(
            f"unknown joint kind {letter!r}: valid kinds are {', '.join(JOINT_KINDS)}"
        )
    return record


__all__ = [
    "JOINT_KINDS",
    "AxisBar",
    "Direction",
    "JointKind",
    "JointKindRecord",
    "joint_kind",
]
