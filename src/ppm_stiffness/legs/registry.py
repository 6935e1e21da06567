"""The leg types: every :class:`~ppm_stiffness.legs.base.LegModel` subclass defined in
a module of :mod:`ppm_stiffness.legs.types`, found by walking that package once."""

from __future__ import annotations

import importlib
import pkgutil
from functools import cache

from ppm_stiffness.legs import types as _types
from ppm_stiffness.legs.base import LegModel


@cache
def leg_types() -> dict[str, type[LegModel]]:
    """Leg type name (the ``type`` key of a design's leg) -> its model class."""
    found: dict[str, type[LegModel]] = {}
    for info in sorted(pkgutil.iter_modules(_types.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{_types.__name__}.{info.name}")
        for obj in vars(module).values():
            if (
                isinstance(obj, type)
                and issubclass(obj, LegModel)
                and obj is not LegModel
                and obj.__module__ == module.__name__
            ):
                name = obj.model_fields["type"].default
                found[name] = obj
    return found
