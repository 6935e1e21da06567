"""Natural frequencies and mode shapes: the mass model, the 6x6 mass matrix at P, and
the generalised eigenproblem ``K v = omega^2 M v`` (docs/dynamics.md).

- :mod:`.inertia`: spatial inertias of rigid bodies at P, the inertia of simple solids;
- :mod:`.condensation`: a leg's bodies' twists from the platform twist (static, i.e.
  Guyan, condensation of its springs and passive joints) and its mass matrix;
- :mod:`.mass`: the design's mass matrix at one pose or many;
- :mod:`.legmodes`: each leg's own modes with the platform held (Craig-Bampton: a beam
  FE of the whole leg) beside the condensed twist;
- :mod:`.modes`: frequencies and mode shapes from (K, M) stacks;
- :mod:`.analysis`: one modal analysis of a design at a pose, as plain data.

The package imports nothing at its top level, so that the design schema can use
:mod:`.inertia` without a cycle.
"""
