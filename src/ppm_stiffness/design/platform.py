"""The platform's mass properties, ``[platform]`` in a design file (optional).

Either an explicit rigid body::

    [platform]
    mass = 2.5                          # kg
    centre_of_mass = [0.0, 0.0, 0.01]   # m, platform frame F_p (from P)
    inertia = [[0.004, 0.0, 0.0],       # kg·m^2, about the centre of mass, axes of F_p
               [0.0, 0.004, 0.0],
               [0.0, 0.0, 0.0075]]

or a simple solid from which the inertia is computed (about its centre, which is the
centre of mass; :mod:`ppm_stiffness.dynamics.inertia`)::

    [platform]
    mass = 2.5
    shape = "cylinder"                  # axis along z of F_p
    radius = 0.08                       # m
    height = 0.02                       # m
    centre_of_mass = [0.0, 0.0, 0.0]    # the cylinder's centre

    shape = "box"                       # edges along x, y, z of F_p
    size = [0.2, 0.15, 0.02]            # m

The mass is in kg (beyond :data:`~ppm_stiffness.legs.parts.MAX_MASS` grams are named as
the likely mistake), inertias in kg·m^2 (a radius of gyration beyond 10 m names
kg·mm^2). A solid whose density ``mass / volume`` exceeds :data:`MAX_DENSITY` (denser
than any material) is refused as a mass in grams
(:func:`~ppm_stiffness.legs.parts.check_density`, which checks each link's body too).
An explicit inertia must be symmetric with positive principal moments that satisfy the
triangle inequality (those of a real body).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import field_validator, model_validator

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.dynamics.inertia import box_inertia, cylinder_inertia
from ppm_stiffness.legs.base import check_plausible
from ppm_stiffness.legs.parts import (
    MAX_DENSITY,
    Finite,
    PartModel,
    Positive,
    check_density,
    check_gyration,
    check_mass,
)

Vector3 = tuple[Finite, Finite, Finite]

#: Relative tolerance of the symmetry and the triangle inequality of an inertia tensor.
INERTIA_TOLERANCE = 1e-9


class PlatformModel(PartModel):
    """The platform's mass properties (module doc); SI, platform frame F_p."""

    mass: Positive
    centre_of_mass: Vector3 = (0.0, 0.0, 0.0)
    inertia: tuple[Vector3, Vector3, Vector3] | None = None
    shape: Literal["cylinder", "box"] | None = None
    radius: Positive | None = None
    height: Positive | None = None
    size: tuple[Positive, Positive, Positive] | None = None

    @field_validator("mass")
    @classmethod
    def _mass_in_kg(cls, v: float) -> float:
        return check_mass("mass", v)

    @field_validator("centre_of_mass")
    @classmethod
    def _centre_in_m(cls, v: tuple[float, float, float]) -> tuple[float, float, float]:
        for x in v:
            check_plausible("centre_of_mass", x, "m")
        return v

    @field_validator("radius", "height")
    @classmethod
    def _length_in_m(cls, v: float | None, info: object) -> float | None:
        if v is not None:
            check_plausible(str(getattr(info, "field_name", "length")), v, "m")
        return v

    @field_validator("size")
    @classmethod
    def _size_in_m(cls, v: tuple[float, float, float] | None) -> tuple[float, float, float] | None:
        for x in v or ():
            check_plausible("size", x, "m")
        return v

    @model_validator(mode="after")
    def _one_description(self) -> PlatformModel:
        """An inertia or a solid (with its dimensions), not both; a real body."""
        dims = {"radius": self.radius, "height": self.height, "size": self.size}
        given = [k for k, v in dims.items() if v is not None]
        if self.inertia is not None:
            if self.shape is not None or given:
                extra = ", ".join(["shape"] * (self.shape is not None) + given)
                raise ValueError(
                    f"give the inertia or a shape with its dimensions, not both ({extra} "
                    "given with inertia)"
                )
            self._check_tensor(np.array(self.inertia, dtype=float))
            return self
        if self.shape is None:
            raise ValueError(
                'give the inertia [kg·m^2] about the centre of mass, or shape = "cylinder" '
                '(radius, height) or "box" (size)'
            )
        need = ("radius", "height") if self.shape == "cylinder" else ("size",)
        missing = [k for k in need if dims[k] is None]
        wrong = [k for k in given if k not in need]
        if missing or wrong:
            raise ValueError(
                f"a {self.shape} has {' and '.join(need)}"
                + (f"; missing {', '.join(missing)}" if missing else "")
                + (f"; {', '.join(wrong)} is not one of its dimensions" if wrong else "")
            )
        volume = (
            math.pi * self.radius**2 * self.height
            if self.radius is not None and self.height is not None
            else math.prod(self.size or (1.0,))
        )
        check_density(
            "mass",
            self.mass,
            volume,
            f"a {self.shape} of {volume:.4g} m^3",
            MAX_DENSITY,
            "denser than any material",
        )
        return self

    def _check_tensor(self, tensor: FloatArray) -> None:
        scale = float(np.max(np.abs(tensor)))
        if scale == 0.0 or np.max(np.abs(tensor - tensor.T)) > INERTIA_TOLERANCE * scale:
            raise ValueError("inertia must be a symmetric, nonzero 3x3 tensor [kg·m^2]")
        moments = np.linalg.eigvalsh(tensor)
        if moments[0] <= 0.0:
            raise ValueError(
                f"inertia: principal moments {moments.tolist()} must be positive (a real body's)"
            )
        if moments[0] + moments[1] < moments[2] * (1.0 - INERTIA_TOLERANCE):
            raise ValueError(
                f"inertia: principal moments {moments.tolist()} break the triangle "
                "inequality I1 + I2 >= I3 that every body's satisfy"
            )
        check_gyration("inertia", float(moments[2]), self.mass)

    def centre(self) -> FloatArray:
        """The centre of mass (3,) in the platform frame [m]."""
        return np.array(self.centre_of_mass, dtype=float)

    def inertia_tensor(self) -> FloatArray:
        """The inertia tensor (3, 3) about the centre of mass, axes of F_p [kg·m^2]."""
        if self.inertia is not None:
            t = np.array(self.inertia, dtype=float)
            return 0.5 * (t + t.T)
        if self.shape == "cylinder":
            assert self.radius is not None and self.height is not None
            return cylinder_inertia(self.mass, self.radius, self.height)
        assert self.size is not None
        return box_inertia(self.mass, self.size)


#: SI unit of each field of :class:`PlatformModel`.
PLATFORM_UNITS = {
    "mass": "kg",
    "centre_of_mass": "m",
    "inertia": "kg·m^2",
    "radius": "m",
    "height": "m",
    "size": "m",
}
