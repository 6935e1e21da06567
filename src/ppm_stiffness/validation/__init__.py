"""Independent validation of the virtual-joint model by a finite-element frame model.

The manipulator is rebuilt at a pose as a 3D frame in PyNite (``pynitefea``, the
optional extra ``validate``) from each leg's joint chain (:meth:`LegModel.chain`, any
leg type): links are Euler-Bernoulli frame members, joint springs and actuators are
spring elements between coincident nodes, passive joint freedoms are missing spring
components or member-end releases, and the stiffness at P comes from six unit-load
cases. Only the chain (points, axes, springs, sections) and the design's numbers are
shared with the virtual-joint model; :mod:`ppm_stiffness.core.solver`,
:func:`ppm_stiffness.core.beam.cantilever_compliance` and
:func:`ppm_stiffness.legs.chain.leg_springs` are not used to build the FE model.

Modules
-------
frame
    PyNite building blocks: members, moment-only members, springs, unit-load compliance.
fe_model
    The manipulator as a PyNite frame at a pose; K at P, one leg's K, a cantilever.
compare
    Per-block comparison of the two matrices, seeded reachable poses, timings.

Importing this package does not import PyNite; :func:`frame.require_pynite`
raises :class:`MissingExtraError` with an installation hint when it is absent.
"""

from __future__ import annotations

from ppm_stiffness.core.errors import PPMStiffnessError


class MissingExtraError(PPMStiffnessError):
    """The optional FE library (extra ``validate``) is not installed."""


__all__ = ["MissingExtraError"]
