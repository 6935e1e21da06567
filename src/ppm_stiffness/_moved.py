"""Old import paths of modules that moved into the pipeline's subpackages.

``import ppm_stiffness.eigenscrews`` (the layout before 0.2) still works: a finder
on ``sys.meta_path`` serves the module from its new home and emits a
DeprecationWarning that names it. One table, one finder; nothing else in the package
uses the old paths.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from types import ModuleType
from typing import Any

#: Old dotted path -> new dotted path.
MOVED: dict[str, str] = {
    f"ppm_stiffness.{old}": f"ppm_stiffness.{new}"
    for old, new in {
        "conventions": "core.conventions",
        "beam": "core.beam",
        "solver": "core.solver",
        "eigenscrews": "core.eigenscrews",
        "decoupling": "core.decoupling",
        "errors": "core.errors",
        "ppr": "legs.types.ppr",
        "actuator": "statics.actuator",
        "actuator_fit": "statics.actuator_fit",
        "loading": "statics.loading",
        "deflection": "statics.deflection",
        "measurements": "statics.measurements",
        "batch": "maps.batch",
        "reduced_leg": "maps.reduced_leg",
        "workspace": "maps.workspace",
        "calibration": "fit.calibration",
    }.items()
}


class _Loader(importlib.abc.Loader):
    def __init__(self, new_name: str) -> None:
        self._new = new_name
        self._spec: importlib.machinery.ModuleSpec | None = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        warnings.warn(
            f"{spec.name} moved to {self._new}; the old path will be removed in 1.0",
            DeprecationWarning,
            stacklevel=4,
        )
        module = importlib.import_module(self._new)
        self._spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        """The module ran under its new name already; give it back its own spec
        (the import system overwrote it with the alias's)."""
        module.__spec__ = self._spec


class MovedModuleFinder(importlib.abc.MetaPathFinder):
    """Serves the modules of :data:`MOVED` under their old names."""

    def find_spec(
        self, fullname: str, path: Any = None, target: ModuleType | None = None
    ) -> importlib.machinery.ModuleSpec | None:
        new = MOVED.get(fullname)
        if new is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _Loader(new))


def install() -> None:
    """Put the finder on ``sys.meta_path`` once."""
    if not any(isinstance(f, MovedModuleFinder) for f in sys.meta_path):
        sys.meta_path.append(MovedModuleFinder())
