"""ppm-stiffness: stiffness of compliant parallel manipulators, planar and spatial.

The package follows the pipeline: ``design`` (schema, TOML) -> ``legs`` (joint chains,
inverse kinematics, virtual springs) -> ``core`` (solver, eigenscrews, decoupling) ->
``statics`` (actuator law, loaded state, deflection) -> ``maps`` and ``fit`` ->
``validation``, ``visuals`` -> ``cli``.

The public API is the names of ``__all__``, importable from here::

    import ppm_stiffness as pps
    design = pps.load_design("examples/3rrr.toml")
    result = pps.analyze(design, pose=[0.01, 0.0, 0.1])   # an Analysis
    print(result.decoupling.rotational_values, result.to_dict()["principal"])

Every function returns an array or one of the result types listed here (each a
dataclass; ``Analysis`` and ``ModalAnalysis`` have ``to_dict()``, the ``--json`` form).
They are loaded on first use, so ``import ppm_stiffness`` stays light (the CLI's
``--help`` imports no numerical library beyond numpy). The names of 0.2 in
:data:`_DEPRECATED` still work with a DeprecationWarning that names the new one
(``docs/compatibility.md``).
"""

from __future__ import annotations

import importlib
import sys
import types
import warnings
from importlib import metadata
from typing import TYPE_CHECKING, Any

from ppm_stiffness import _moved

_moved.install()

try:
    __version__: str = metadata.version("ppm-stiffness")
except metadata.PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

#: Public name -> (module, attribute).
_API: dict[str, tuple[str, str]] = {
    # designs
    "Design": ("ppm_stiffness.design", "Design"),
    "load_design": ("ppm_stiffness.design", "load_design"),
    "default_design": ("ppm_stiffness.design", "default_design"),
    "save_design": ("ppm_stiffness.design", "save_design"),
    # poses (6-D, task coordinates and the parasitic motion)
    "full_pose": ("ppm_stiffness.poses", "full_pose"),
    "home_pose": ("ppm_stiffness.poses", "home_pose"),
    # one pose
    "stiffness_at_pose": ("ppm_stiffness.model", "stiffness_at_pose"),
    "stiffness_at_tool_point": ("ppm_stiffness.model", "stiffness_at_tool_point"),
    "analyze": ("ppm_stiffness.analysis", "analyze_design"),
    "Analysis": ("ppm_stiffness.analysis", "Analysis"),
    "analyze_matrix": ("ppm_stiffness.analysis", "analyze_matrix"),
    "MatrixAnalysis": ("ppm_stiffness.analysis", "MatrixAnalysis"),
    "eigenscrews": ("ppm_stiffness.core.eigenscrews", "eigenscrews"),
    "ScrewSprings": ("ppm_stiffness.core.eigenscrews", "ScrewSprings"),
    "decouple": ("ppm_stiffness.core.decoupling", "decouple"),
    "Decoupling": ("ppm_stiffness.core.decoupling", "Decoupling"),
    "principal_compliance": ("ppm_stiffness.core.principal", "principal_compliance"),
    "PrincipalCompliance": ("ppm_stiffness.core.principal", "PrincipalCompliance"),
    # under load: geometry frozen at the unloaded pose (the paper's model), or moving
    "loaded_state": ("ppm_stiffness.statics.loading", "loaded_state"),
    "LoadedState": ("ppm_stiffness.statics.equilibrium", "LoadedState"),
    "moving_loaded_state": ("ppm_stiffness.statics.moving", "moving_loaded_state"),
    "MovingLoadedState": ("ppm_stiffness.statics.moving", "MovingLoadedState"),
    "deflection_curve": ("ppm_stiffness.statics.deflection", "deflection_curve"),
    "deflection_path": ("ppm_stiffness.statics.deflection", "deflection_path"),
    "DeflectionCurve": ("ppm_stiffness.statics.deflection", "DeflectionCurve"),
    "load_margin": ("ppm_stiffness.statics.margin", "load_margin"),
    "LoadMargin": ("ppm_stiffness.statics.margin", "LoadMargin"),
    "MarginKind": ("ppm_stiffness.statics.margin", "MarginKind"),
    # many poses
    "stiffness_matrix": ("ppm_stiffness.maps.batch", "stiffness_matrix"),
    "evaluate_poses": ("ppm_stiffness.maps.batch", "evaluate_poses"),
    "BatchResult": ("ppm_stiffness.maps.batch", "BatchResult"),
    "stiffness_map": ("ppm_stiffness.maps.workspace", "stiffness_map"),
    "StiffnessMap": ("ppm_stiffness.maps.result", "StiffnessMap"),
    # dynamics (a design with a mass model)
    "mass_matrix": ("ppm_stiffness.dynamics.mass", "mass_matrix"),
    "mass_matrix_at_pose": ("ppm_stiffness.dynamics.mass", "mass_matrix_at_pose"),
    "natural_frequencies": ("ppm_stiffness.dynamics.modes", "natural_frequencies"),
    "mode_shapes": ("ppm_stiffness.dynamics.modes", "mode_shapes"),
    "Modes": ("ppm_stiffness.dynamics.modes", "Modes"),
    "modal_analysis": ("ppm_stiffness.dynamics.analysis", "modal_analysis"),
    "ModalAnalysis": ("ppm_stiffness.dynamics.analysis", "ModalAnalysis"),
    "first_frequencies": ("ppm_stiffness.dynamics.batch", "first_frequencies"),
    # identification and validation
    "calibrate": ("ppm_stiffness.fit.calibration", "calibrate"),
    "CalibrationResult": ("ppm_stiffness.fit.calibration", "CalibrationResult"),
    "compare_poses": ("ppm_stiffness.validation.compare", "compare_poses"),
    "PoseComparison": ("ppm_stiffness.validation.compare", "PoseComparison"),
    # errors
    "PPMStiffnessError": ("ppm_stiffness.core.errors", "PPMStiffnessError"),
    "DesignError": ("ppm_stiffness.core.errors", "DesignError"),
    "UnreachablePoseError": ("ppm_stiffness.core.errors", "UnreachablePoseError"),
    "SingularConfigurationError": ("ppm_stiffness.core.errors", "SingularConfigurationError"),
    "InputDataError": ("ppm_stiffness.core.errors", "InputDataError"),
    "EquilibriumError": ("ppm_stiffness.core.errors", "EquilibriumError"),
}

#: Names of 0.2 -> (module, attribute, the name to use). They work, with a
#: DeprecationWarning, until 0.4; they are not in ``__all__``.
_DEPRECATED: dict[str, tuple[str, str, str]] = {
    "equilibrium": ("ppm_stiffness.statics.equilibrium", "equilibrium", "loaded_state"),
    "moving_equilibrium": (
        "ppm_stiffness.statics.moving",
        "moving_loaded_state",
        "moving_loaded_state",
    ),
    "MovingEquilibrium": (
        "ppm_stiffness.statics.moving",
        "MovingLoadedState",
        "MovingLoadedState",
    ),
}

__all__ = [
    "__version__",
    "Design",
    "load_design",
    "default_design",
    "save_design",
    "full_pose",
    "home_pose",
    "stiffness_at_pose",
    "stiffness_at_tool_point",
    "analyze",
    "Analysis",
    "analyze_matrix",
    "MatrixAnalysis",
    "eigenscrews",
    "ScrewSprings",
    "decouple",
    "Decoupling",
    "principal_compliance",
    "PrincipalCompliance",
    "loaded_state",
    "LoadedState",
    "moving_loaded_state",
    "MovingLoadedState",
    "deflection_curve",
    "deflection_path",
    "DeflectionCurve",
    "load_margin",
    "LoadMargin",
    "MarginKind",
    "stiffness_matrix",
    "evaluate_poses",
    "BatchResult",
    "stiffness_map",
    "StiffnessMap",
    "mass_matrix",
    "mass_matrix_at_pose",
    "natural_frequencies",
    "mode_shapes",
    "Modes",
    "modal_analysis",
    "ModalAnalysis",
    "first_frequencies",
    "calibrate",
    "CalibrationResult",
    "compare_poses",
    "PoseComparison",
    "PPMStiffnessError",
    "DesignError",
    "UnreachablePoseError",
    "SingularConfigurationError",
    "InputDataError",
    "EquilibriumError",
]


def __getattr__(name: str) -> Any:
    """Load a public name on first use (PEP 562); a name of 0.2 (:data:`_DEPRECATED`)
    with a DeprecationWarning, each time (never cached)."""
    if name in _DEPRECATED:
        module, attr, new = _DEPRECATED[name]
        warnings.warn(
            f"ppm_stiffness.{name} is deprecated since 0.3: use ppm_stiffness.{new}; "
            "removed in 0.4",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(importlib.import_module(module), attr)
    try:
        module, attr = _API[name]
    except KeyError:
        raise AttributeError(f"module 'ppm_stiffness' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_API))


class _Package(types.ModuleType):
    """The package module: importing a deprecated submodule path of 0.1
    (``ppm_stiffness.eigenscrews``) must not replace the public function of that name
    (the import system sets the submodule as an attribute of its parent)."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _API and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs
    from ppm_stiffness.analysis import Analysis, MatrixAnalysis, analyze_matrix
    from ppm_stiffness.analysis import analyze_design as analyze
    from ppm_stiffness.core.decoupling import Decoupling, decouple
    from ppm_stiffness.core.eigenscrews import ScrewSprings, eigenscrews
    from ppm_stiffness.core.errors import (
        DesignError,
        EquilibriumError,
        InputDataError,
        PPMStiffnessError,
        SingularConfigurationError,
        UnreachablePoseError,
    )
    from ppm_stiffness.core.principal import PrincipalCompliance, principal_compliance
    from ppm_stiffness.design import Design, default_design, load_design, save_design
    from ppm_stiffness.dynamics.analysis import ModalAnalysis, modal_analysis
    from ppm_stiffness.dynamics.batch import first_frequencies
    from ppm_stiffness.dynamics.mass import mass_matrix, mass_matrix_at_pose
    from ppm_stiffness.dynamics.modes import Modes, mode_shapes, natural_frequencies
    from ppm_stiffness.fit.calibration import CalibrationResult, calibrate
    from ppm_stiffness.maps.batch import BatchResult, evaluate_poses, stiffness_matrix
    from ppm_stiffness.maps.result import StiffnessMap
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.model import stiffness_at_pose, stiffness_at_tool_point
    from ppm_stiffness.poses import full_pose, home_pose
    from ppm_stiffness.statics.deflection import (
        DeflectionCurve,
        deflection_curve,
        deflection_path,
    )
    from ppm_stiffness.statics.equilibrium import LoadedState
    from ppm_stiffness.statics.loading import loaded_state
    from ppm_stiffness.statics.margin import LoadMargin, MarginKind, load_margin
    from ppm_stiffness.statics.moving import MovingLoadedState, moving_loaded_state
    from ppm_stiffness.validation.compare import PoseComparison, compare_poses
