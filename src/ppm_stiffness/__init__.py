"""ppm-stiffness: stiffness of compliant planar parallel manipulators.

The package follows the pipeline: ``design`` (schema, TOML) -> ``legs`` (joint chains,
inverse kinematics, virtual springs) -> ``core`` (solver, eigenscrews, decoupling) ->
``statics`` (actuator law, loaded state, deflection) -> ``maps`` and ``fit`` ->
``validation``, ``visuals`` -> ``cli``.
"""

from ppm_stiffness import _moved

_moved.install()
