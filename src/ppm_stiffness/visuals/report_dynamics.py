"""The report's "Natural frequencies" section, for a design with a mass model.

At the report's pose (the workspace centre unless one is given), locked actuators:

- the masses of the model and the six natural frequencies with each mode's dominant
  direction and its share (:func:`ppm_stiffness.dynamics.analysis.modal_analysis`, the
  function behind ``ppm-stiffness modes --json``, at P: the mode shapes are P's
  twists), embedded verbatim as ``<script type="application/json"
  id="analysis-modes">`` with every printed number traced to it (``data-path``
  ``modes/frequencies/0``, as the other tables of the report);
- the mode-shape picture (:func:`ppm_stiffness.visuals.modes.plot_modes`);
- the map of the first natural frequency f1 over the design's default slice
  (:func:`ppm_stiffness.maps.workspace.stiffness_map` with ``quantities=["f1"]``: x-y,
  or the first two task coordinates, at the pose's other coordinates), with its range.

Both with each leg's own modes (the default number per leg,
:data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`, Craig-Bampton: the same
model in the table and the map).

A design without a mass model gets no section (:func:`dynamics_sections` returns none).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.design import Design
from ppm_stiffness.visuals.html import cell, esc, figure_block, figure_data_uri, table

#: The section's id, its figures' ids and its JSON block's id.
SECTION_ID = "dynamics"
FIGURE_MODES = "fig-modes"
FIGURE_F1_MAP = "fig-f1-map"
JSON_ID = "analysis-modes"


def modes_json_block(result: dict[str, Any]) -> str:
    """The modal analysis embedded as the document ``ppm-stiffness modes --json``
    prints."""
    from ppm_stiffness.analysis import json_document
    from ppm_stiffness.dynamics.analysis import MODES_UNITS

    text = json_document("modes", result, MODES_UNITS)
    text = text.replace("</", "<\\/").replace("<!--", "<\\!--")
    return f'<script type="application/json" id="{JSON_ID}">{text}</script>'


def _tables(result: dict[str, Any]) -> str:
    m = result["masses"]
    masses = table(
        ["platform [kg]", "links [kg]", "carriages [kg]", "total [kg]"],
        [[cell(m[k], f"modes/masses/{k}") for k in ("platform", "links", "carriages", "total")]],
        "Moving masses of the mass model",
    )
    rows = [
        [
            str(j + 1),
            cell(mode["frequency"], f"modes/frequencies/{j}"),
            esc(mode["direction"]),
            cell(mode["share"], f"modes/modes/{j}/share", 100.0, 3),
        ]
        for j, mode in enumerate(result["modes"])
    ]
    freqs = table(
        ["mode", "f [Hz]", "dominant direction", "share [%]"],
        rows,
        "Natural frequencies, K v = ω² M v (locked actuators)",
    )
    groups = result.get("modes_repeated") or []
    note = (
        '<p class="note">Repeated frequencies (modes '
        + "; ".join(", ".join(str(i + 1) for i in g) for g in groups)
        + "): their mode shapes are not unique; those closest to the coordinate axes are "
        "shown.</p>"
        if groups
        else ""
    )
    return f'<div class="cols">{masses}{freqs}</div>{note}'


def _f1_map(design: Design, pose: np.ndarray, grid: int) -> str:
    """The f1 map's figure and range, or a note where the slice has no valid pose."""
    from ppm_stiffness.core.errors import UnreachablePoseError
    from ppm_stiffness.core.pose import POSE_INDEX
    from ppm_stiffness.maps.slices import map_slice
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.visuals.maps import plot_stiffness_maps, slice_label

    axes = map_slice(design).axes
    fixed = {n: float(pose[POSE_INDEX[n]]) for n in design.task_coordinates if n not in axes}
    try:
        smap = stiffness_map(design, grid=grid, axes=axes, fixed=fixed, quantities=["f1"])
    except UnreachablePoseError as exc:
        return f'<p class="note">no f<sub>1</sub> map: {esc(exc)}</p>'
    if not np.any(smap.reachable):
        return f'<p class="note">no f<sub>1</sub> map: {esc(smap.masked_text())}</p>'
    fig = plot_stiffness_maps(smap, title="First natural frequency f1, locked actuators")
    s = smap.summary()["f1"]
    caption = (
        f"f<sub>1</sub> [Hz] over the {esc(axes[0])}-{esc(axes[1])} slice "
        f"({esc(slice_label(smap))}), {grid} × {grid} grid, locked actuators, "
        f"{smap.link_modes} link modes per leg: "
        f"{s['min']:.4g} Hz to {s['max']:.4g} Hz ({esc(smap.masked_text())})."
    )
    return figure_block(figure_data_uri(fig), caption, FIGURE_F1_MAP)


def dynamics_sections(design: Design, pose: ArrayLike, grid: int) -> list[tuple[str, str, str]]:
    """The "Natural frequencies" section ``(id, title, html)`` of the report at a full
    pose (6,), or none for a design without a mass model (module doc)."""
    if not design.has_mass_model:
        return []
    from ppm_stiffness.dynamics.analysis import modal_analysis
    from ppm_stiffness.visuals.modes import plot_modes

    p = np.asarray(pose, dtype=float)
    result = modal_analysis(design, p, tool_point=np.zeros(3)).to_dict()
    fig = plot_modes(
        design,
        p,
        result["frequencies"],
        [m["shape"] for m in result["modes"]],
        [m["direction"] for m in result["modes"]],
        title=f"{design.name}: vibration modes (locked actuators)",
    )
    f1 = result["frequencies"][0]
    html = (
        "<p>Undamped free vibrations of the machine about the pose: K v = ω² M v with K "
        "the locked actuators' stiffness and M the 6 × 6 mass matrix at P (the platform "
        "and the legs following it statically), with each leg's own lowest "
        f"{result.get('link_modes', 0)} modes with the platform held added (Craig-Bampton; "
        'docs/dynamics.md, "Link modes"), f = ω / 2π. '
        f"First natural frequency f<sub>1</sub> = {f1:.4g} Hz "
        f"({esc(result['modes'][0]['direction'])}).</p>"
        + _tables(result)
        + figure_block(
            figure_data_uri(fig),
            "The platform displaced along each mode (exaggerated; mode shapes as twists of "
            "P), at rest in grey.",
            FIGURE_MODES,
        )
        + _f1_map(design, p, grid)
        + modes_json_block(result)
    )
    return [(SECTION_ID, f"Natural frequencies (f<sub>1</sub> = {f1:.4g} Hz)", html)]
