"""Reduced forms of a design's legs, through the legs' own capability.

The exact P-P-R reduced form lives beside its leg type
(:mod:`ppm_stiffness.legs.types._ppr_reduced`); this module only asks each leg for its
reduced form (:meth:`ppm_stiffness.legs.base.LegModel.reduced_form`) and re-exports
the names the maps use, so that old imports keep working. A leg's reduced form is
computed once per leg object (legs are frozen; :mod:`ppm_stiffness.core.object_cache`)
and shared by every map, sweep and optimisation step that uses it: its arrays are
read-only.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.object_cache import per_object
from ppm_stiffness.design import Design
from ppm_stiffness.legs.types._ppr_reduced import IN_PLANE, OUT_OF_PLANE, ReducedLeg

__all__ = [
    "IN_PLANE",
    "OUT_OF_PLANE",
    "ReducedLeg",
    "reduce_design",
    "reduce_leg",
    "reduced_design",
]


@per_object
def leg_reduced_form(leg: Any) -> Any | None:
    """``leg.reduced_form()``, computed once per leg object (arrays read-only)."""
    form = leg.reduced_form()
    if dataclasses.is_dataclass(form):
        for field in dataclasses.fields(form):
            value = getattr(form, field.name)
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
    return form


def reduce_leg(design: Design, index: int) -> ReducedLeg:
    """Reduced form of leg ``index`` (0-based) of ``design``.

    Raises
    ------
    DesignError
        If that leg offers no reduced form the batched path can evaluate.
    """
    form = leg_reduced_form(design.legs[index])
    if not isinstance(form, ReducedLeg):
        raise DesignError(
            f"leg {index + 1} ({design.legs[index].type}) has no exact reduced form; "
            "use the general batched path"
        )
    return form


def reduced_design(design: Design) -> tuple[ReducedLeg, ...] | None:
    """Reduced form of every leg, or None unless every leg offers one."""
    forms = []
    for leg in design.legs:
        form = leg_reduced_form(leg)
        if not isinstance(form, ReducedLeg):
            return None
        forms.append(form)
    return tuple(forms)


def reduce_design(design: Design) -> tuple[ReducedLeg, ...]:
    """Reduced form of every leg (a few milliseconds; reuse it for many batches).

    Raises
    ------
    DesignError
        If a leg offers none (:func:`reduced_design` returns None instead).
    """
    return tuple(reduce_leg(design, i) for i in range(len(design.legs)))
