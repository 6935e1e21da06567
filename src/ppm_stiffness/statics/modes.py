"""Names of the deflection curves' loading modes and methods, defined once here (no
numpy, no design schema), so that ``ppm-stiffness deflect --help`` can list them without
importing :mod:`ppm_stiffness.statics.deflection`, which re-exports them."""

from __future__ import annotations

#: The loading modes of the paper's Fig. 9 (wrenches at the tool point, axes of F_b:
#: they mean the same for a planar and a spatial design).
MODES = ("planar-force", "moment", "vertical-force")
#: The mode of a load along any wrench direction
#: (:func:`ppm_stiffness.statics.deflection.direction_wrench`).
DIRECTION = "direction"
#: Every mode a curve may have: Fig. 9's, a direction, and multiples of a wrench.
CURVE_MODES = MODES + (DIRECTION, "wrench")
#: Ways to compute the path (:mod:`ppm_stiffness.statics.deflection`).
METHODS = ("integrate", "closed-form", "linear")
