"""The report's "Uncertainty" section (``report --tolerances``): bands of the principal
stiffnesses at the pose, the sensitivity ranking, the planar-force deflection curve
with its band, and maps of the lower band and relative spread.

Every design: the principal stiffnesses are the paper's k_phi, k_x, k_y for a planar
design and the spatial principal stiffnesses (k_rot_1..3, k_trans_1..3, ascending, at
the tool point) for others (:func:`~ppm_stiffness.fit.band_outputs.pose_labels`); the
maps are the design's default slice and quantities (:func:`~ppm_stiffness.maps.workspace
.stiffness_map`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.design import Design
from ppm_stiffness.visuals.html import esc, figure_block, figure_data_uri, format_number, table

#: Display names of the paper's principal stiffnesses.
_SYMBOLS = {"k_phi": "k_φ"}

#: The deflection curve drawn with its band: planar force at 45 deg up to 10 N.
CURVE_LOADS = np.linspace(0.0, 10.0, 21)


def uncertainty_section(
    design: Design,
    variables: list[Any],
    pose: ArrayLike,
    grid: int,
    method: str = "first-order",
    samples: int = 64,
) -> tuple[str, str, str]:
    """``(id, title, html)`` of the section (see the module docstring), any design."""
    from ppm_stiffness.fit.band_outputs import (
        deflection_output,
        map_output,
        pose_output,
        principal_quantities,
    )
    from ppm_stiffness.fit.uncertainty import propagate
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.statics.deflection import deflection_curve
    from ppm_stiffness.visuals.bands import plot_map_bands
    from ppm_stiffness.visuals.deflection import plot_deflection_curves

    p = np.asarray(pose, dtype=float)
    tool = np.asarray(design.tool_point, dtype=float)
    at_pose = propagate(design, variables, pose_output(p, tool), method, samples)
    rows = []
    for i, (name, unit) in enumerate(principal_quantities(design)):
        ranking = ", ".join(
            f"{esc(n)} {100 * s:.0f} %" for n, s in at_pose.ranking(i)[:3] if s > 0.005
        )
        rows.append(
            [
                _SYMBOLS.get(name, name),
                format_number(at_pose.nominal[i]),
                format_number(at_pose.lower[i]),
                format_number(at_pose.upper[i]),
                unit,
                ranking,
            ]
        )
    html = (
        f"<p>Tolerances on {len(variables)} parameters ({esc(', '.join(at_pose.labels[:6]))}"
        f"{', ...' if len(variables) > 6 else ''}); bands: {esc(at_pose.label)}"
        + (
            f"; {at_pose.failed} of {at_pose.samples} samples unreachable or singular, "
            f"{at_pose.redrawn} values redrawn (a stiffness &le; 0)"
            if method == "qmc"
            else ""
        )
        + ". Sensitivity: share of each tolerance in the first-order variance.</p>"
        + table(
            ["", "nominal", "lower", "upper", "unit", "largest contributions"],
            rows,
            "Principal stiffnesses at the pose",
        )
    )
    curve = deflection_curve(design, "planar-force", CURVE_LOADS, p, math.pi / 4, "closed-form")
    curve_bands = propagate(
        design,
        variables,
        deflection_output(curve.unit_wrench, curve.loads, curve.pose, curve.tool_point),
        method,
        samples,
    )
    html += figure_block(
        figure_data_uri(plot_deflection_curves([curve], bands=[curve_bands])),
        f"Deflection under a planar force at 45°, shaded: {esc(curve_bands.label)}.",
        "fig-deflection-bands",
    )
    smap = stiffness_map(design, grid=grid)
    if np.any(smap.reachable):
        map_bands = propagate(
            design, variables, map_output(**smap.grid_arguments()), method, samples
        )
        html += figure_block(
            figure_data_uri(plot_map_bands(smap, map_bands)),
            f"Stiffness maps (actuators locked): nominal, lower band ({esc(map_bands.label)})"
            " and relative spread.",
            "fig-map-bands",
        )
    return "uncertainty", "Uncertainty from the tolerances", html


__all__ = ["uncertainty_section"]
