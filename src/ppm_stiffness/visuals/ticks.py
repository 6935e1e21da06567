"""Colour-bar scales without an offset text (the "1e5" above a bar is easily missed).

:func:`scaled_unit` puts the scale in the unit (N/m -> MN/m, N·m/rad -> kN·m/rad, a
"×10^e" factor for other units) and :func:`plain_formatter` writes each tick as its
value in that unit with the decimals its spacing needs: no offset, no multiplier.
:func:`variation` is the relative variation a map's note states when it is small
(:data:`SMALL_VARIATION`), so that a 3 % variation drawn over the full colour range is
not read as a strong gradient.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

#: SI prefixes of the powers of a thousand used in the units.
_PREFIXES = {-9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G", 12: "T"}
#: A map whose variation (max - min) / max |value| is below this gets a note.
SMALL_VARIATION = 0.05


def scaled_unit(largest: float, unit: str) -> tuple[float, str]:
    """The factor and unit text of values up to ``largest`` in magnitude.

    Returns
    -------
    factor : float
        Shown value = value / factor (a power of 1000).
    text : str
        The unit with its SI prefix (``"MN/m"``) when it starts with N or Hz, or is rad
        or m below 1 (``"mrad"``, ``"µm"``), else
        ``"×10^e unit"``; the unit unchanged when the factor is 1.
    """
    if not math.isfinite(largest) or largest <= 0:
        return 1.0, unit
    e = 3 * math.floor(math.log10(largest) / 3)
    e = min(max(e, -9), 12)
    if e == 0:
        return 1.0, unit
    if unit.startswith(("N", "Hz")) or (unit in ("rad", "m") and e < 0):
        return 10.0**e, _PREFIXES[e] + unit
    return 10.0**e, f"×10^{e} {unit}".strip()


def plain_formatter(factor: float, step: float) -> Any:
    """A tick formatter writing value / ``factor`` with the decimals that tell apart
    ticks ``step`` apart (in the values' units): no offset or multiplier text."""
    from matplotlib.ticker import FuncFormatter

    shown = abs(step) / factor if step else 0.0
    decimals = max(0, 1 - math.floor(math.log10(shown))) if shown > 0 else 0
    decimals = min(decimals, 8)
    return FuncFormatter(lambda x, _pos: f"{x / factor:.{decimals}f}")


def variation(values: ArrayLike) -> float:
    """(max - min) / max |value| of the finite, unmasked values (0 when none)."""
    v: np.ndarray = np.ma.masked_invalid(np.ma.asarray(values, dtype=float)).compressed()
    if v.size == 0:
        return 0.0
    top = float(np.max(np.abs(v)))
    return float((v.max() - v.min()) / top) if top > 0 else 0.0


__all__ = ["SMALL_VARIATION", "plain_formatter", "scaled_unit", "variation"]
