"""Independent validation of the virtual-joint model by a finite-element frame model.

The manipulator is rebuilt at a full pose (x, y, z, rx, ry, rz) as a 3D frame in
PyNite (``pynitefea``, the optional extra ``validate``) from each leg's joint chain
(:meth:`LegModel.chain`, any leg type, joints R, P, C, U, S with any axes): links are
Euler-Bernoulli frame members, joint springs and actuators are spring elements between
coincident nodes, passive joint freedoms are missing spring components or member-end
releases, the platform is a stiff frame joining the legs' platform points and P, and
the stiffness at P comes from six unit-load cases. Only the chain (points, axes, joint
kinds, springs, sections) and the design's numbers are shared with the virtual-joint
model; :mod:`ppm_stiffness.core.solver`, :mod:`ppm_stiffness.legs.engine`,
:func:`ppm_stiffness.core.beam.cantilever_compliance` and
:func:`ppm_stiffness.legs.chain.leg_springs` are not used to build the FE model.

Modules
-------
frame
    PyNite building blocks: members (sections oriented in space), moment-only members,
    springs, unit-load compliance.
joints
    A joint of any kind and orientation between two coincident nodes; where
    auxiliary nodes go.
fe_model
    The manipulator as a PyNite frame at a pose; K at P, one leg's K, a cantilever.
compare
    Per-block and per-direction comparison of the two matrices, seeded reachable
    poses over the task coordinates, timings.
hinge_continuum
    One notch hinge's in-plane stiffnesses by a 2-D plane-stress (or plane-strain)
    finite-element model in scikit-fem, beside the beam integrals (``validate --hinge``).

Importing this package does not import PyNite (nor scikit-fem); :func:`frame.require_pynite`
raises :class:`MissingExtraError` with an installation hint when it is absent.
"""

from __future__ import annotations

from ppm_stiffness.core.errors import PPMStiffnessError


class MissingExtraError(PPMStiffnessError):
    """The optional FE library (extra ``validate``) is not installed."""


__all__ = ["MissingExtraError"]
