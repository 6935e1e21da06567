"""The report's "Loaded geometry" section (:mod:`ppm_stiffness.visuals.report`), when a
wrench is given.

Under the report's wrench the equilibrium with moving geometry (docs/statics.md):

- the displaced pose and the figures of ``analyze --geometry moving``: ``||K_F - K|| /
  ||K||``, the geometric term against K_F, K_F's antisymmetric part (a couple of fixed
  direction), the load steps;
- the **load margin** and its buckling mode (a twist at the displaced tool point);
- K_F, K_F - K (K the frozen model's loaded tangent under the same load) and the
  geometric term, 6x6 at the tool point;
- the deflection of the tool point as the wrench grows from zero to its full value, the
  frozen and the moving curves in one picture (a curve that stops says where and why).

Every number cell carries ``data-path`` into the analysis embedded as
``<script type="application/json" id="analysis-moving">`` (the document ``analyze
--wrench ... --geometry moving --json`` prints), as in the rest of the report.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.design import Design
from ppm_stiffness.visuals.html import (
    cell,
    esc,
    figure_block,
    figure_data_uri,
    json_block,
    vector_cells,
)
from ppm_stiffness.visuals.html import matrix as html_matrix
from ppm_stiffness.visuals.html import table as html_table

#: The section's id and title.
SECTION_ID = "loaded-geometry"
SECTION_TITLE = "Loaded geometry"
#: The embedded analysis' block id, and the key of its data paths.
BLOCK_ID = "analysis-moving"
KEY = "moving"
#: Scales of the wrench along the deflection picture (0 to the full wrench).
SCALES = np.linspace(0.0, 1.0, 21)

_TWIST = ("φx", "φy", "φz", "x", "y", "z")


def loaded_geometry_section(
    design: Design, pose: ArrayLike, wrench: ArrayLike
) -> tuple[str, str, str]:
    """The section (id, title, html) under ``wrench`` (6,) [N·m, N] at the tool point
    at the full pose ``pose`` (6,) (module doc)."""
    from ppm_stiffness.analysis import analyze_design
    from ppm_stiffness.statics.moving_deflection import moving_deflection
    from ppm_stiffness.visuals.deflection import plot_deflection_curves

    p = np.asarray(pose, dtype=float)
    w = np.asarray(wrench, dtype=float)
    # as `analyze --json` prints it (ppm_stiffness.leading)
    doc = analyze_design(design, p, w, geometry="moving").to_dict()
    curves = moving_deflection(design, w, SCALES, p, "integrate", "wrench")
    uri = figure_data_uri(plot_deflection_curves([curves.frozen, curves.moving]))
    mg = doc["moving_geometry"]
    base = f"{KEY}/moving_geometry"
    margin = mg["load_margin"]
    rows = [
        [
            "‖K_F − K‖ / ‖K‖ (length-balanced)",
            cell(mg["relative_difference"], f"{base}/relative_difference", 100, 3),
            "%",
        ],
        [
            "geometric term / K_F",
            cell(mg["relative_geometric"], f"{base}/relative_geometric", 100, 3),
            "%",
        ],
        ["antisymmetric part / K_F", cell(mg["asymmetry"], f"{base}/asymmetry", 100, 3), "%"],
        ["load steps", cell(mg["load_steps"], f"{base}/load_steps", sig=3), ""],
    ]
    if margin["factor"] is not None:
        rows.append(
            ["load margin λ", cell(margin["factor"], f"{base}/load_margin/factor", sig=6), "×"]
        )
    pose_cells = [
        cell(mg["displaced_pose"][n], f"{base}/displaced_pose/{n}", s, 6)
        for n, s in zip(
            ("x", "y", "z", "rx", "ry", "rz"), (1e3,) * 3 + (180 / np.pi,) * 3, strict=True
        )
    ]
    parts = [
        "<p>The equilibrium with <b>moving geometry</b> (docs/statics.md): the platform "
        "and every leg move under the wrench, each leg's chain closing at the displaced "
        "platform; K<sub>F</sub> = dw/dt is the loaded tangent at the displaced tool "
        "point (axes of F<sub>b</sub>), K the frozen model's (the paper's: the unloaded "
        "geometry, the tables above).</p>",
        html_table(
            ["x [mm]", "y [mm]", "z [mm]", "rx [°]", "ry [°]", "rz [°]"],
            [pose_cells],
            "Displaced pose of P under the wrench",
        ),
        html_table(["", "value", ""], rows, "K<sub>F</sub> against the frozen K"),
        f"<p>Load margin: {esc(margin['description'])}.</p>",
    ]
    if margin["mode"] is not None:
        parts.append(
            html_table(
                [f"{t} [{u}]" for t, u in zip(_TWIST, ("rad",) * 3 + ("m",) * 3, strict=True)],
                [vector_cells(margin["mode"], f"{base}/load_margin/mode")],
                f"Buckling mode ({esc(margin['mode_direction'])}), a unit twist at the "
                "displaced tool point (length-balanced)",
            )
        )
    for key, caption in (
        ("stiffness_matrix", "K<sub>F</sub> [SI] at the displaced tool point"),
        ("difference", "K<sub>F</sub> − K [SI]"),
        ("geometric_stiffness", "The geometric term of K<sub>F</sub> [SI]"),
    ):
        parts.append(html_matrix(mg[key], f"{base}/{key}", _TWIST, _TWIST, caption=caption))
    stops = "".join(f"<p class='note'>{esc(s)}.</p>" for s in curves.stops())
    parts.append(
        figure_block(
            uri,
            "Deflection of the tool point as the wrench grows from zero to its full value "
            "(the load axis is its scale): the frozen geometry (solid; the actuators' law "
            "in the loop) and the moving geometry (dashed).",
            "fig-deflection-moving",
        )
        + stops
    )
    parts.append(json_block(BLOCK_ID, doc))
    return SECTION_ID, SECTION_TITLE, "".join(parts)


def embedded_blocks(page: str) -> dict[str, Any]:
    """The section's embedded analysis of a report page, by its data-path key."""
    from ppm_stiffness.visuals.report import embedded_json

    return {KEY: embedded_json(page, BLOCK_ID)}


__all__ = ["BLOCK_ID", "SECTION_ID", "embedded_blocks", "loaded_geometry_section"]
