"""One module per leg type; each defines a :class:`~ppm_stiffness.legs.base.LegModel`
subclass. :func:`ppm_stiffness.legs.registry.leg_types` finds them: adding a leg type
is adding a module here (and its tests)."""
