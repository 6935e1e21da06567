"""The report's "Notch hinges" section, for a design with notch hinges (issue 29 item 3).

At the report's pose, the frozen linear hinge model
(:func:`ppm_stiffness.statics.hinge_stress.hinge_summary`, the figures
``ppm-stiffness analyze --wrench --json`` gives under ``hinge_stress``, safety factor 1):

- the range of motion along each input direction (each drive alone, then the platform
  along each task coordinate) and the hinge that limits it;
- each hinge's allowed stress, its smallest range over the drives and, under the
  report's loaded case (its wrench moved to P), its peak stress and utilisation;

embedded verbatim as ``<script type="application/json" id="analysis-hinges">`` with every
printed number traced to it (``data-path`` ``hinges/directions/0/range``). A design
without hinges, or with a hinge whose material has no yield strength, gets no section.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.design import Design
from ppm_stiffness.visuals.html import cell, esc, table

#: The section's id and its JSON block's id.
SECTION_ID = "hinges"
JSON_ID = "analysis-hinges"


def hinge_document(
    design: Design, pose: ArrayLike, wrench: ArrayLike, tool_point: ArrayLike
) -> dict[str, Any] | None:
    """The hinge figures at a full pose under ``wrench`` (6,) [N·m, N] at the tool point
    (platform frame [m]), as ``analyze --json`` gives them; None without hinges or
    yield strengths."""
    from ppm_stiffness.model import tool_offset
    from ppm_stiffness.statics.hinge_stress import has_hinges, has_yield_strengths, hinge_summary

    if not has_hinges(design) or not has_yield_strengths(design):
        return None
    p = np.asarray(pose, dtype=float)
    w = np.asarray(wrench, dtype=float)
    offset = tool_offset(p, np.asarray(tool_point, dtype=float))
    at_p = np.concatenate([w[:3] + np.cross(offset, w[3:]), w[3:]])
    return hinge_summary(design, p, at_p, 1.0)


def _json_block(doc: dict[str, Any]) -> str:
    from ppm_stiffness.analysis import dump_json

    text = dump_json(doc).replace("</", "<\\/").replace("<!--", "<\\!--")
    return f'<script type="application/json" id="{JSON_ID}">{text}</script>'


def _range_cell(value: float, path: str, unit: str) -> str:
    """A range in µrad or µm (a flexure stage's ranges), inf as text."""
    if not np.isfinite(value):
        return "<td>unloaded</td>"
    return cell(value, path, 1e6, 4)


def hinge_sections(
    design: Design, pose: ArrayLike, wrench: ArrayLike, tool_point: ArrayLike, wrench_text: str
) -> list[tuple[str, str, str]]:
    """The "Notch hinges" section ``(id, title, html)`` (module doc), or none."""
    doc = hinge_document(design, pose, wrench, tool_point)
    if doc is None:
        return []
    dirs = [
        [
            esc(d["name"]),
            _range_cell(d["range"], f"hinges/directions/{j}/range", d["unit"]),
            f"µ{esc(d['unit'])}",
            esc(d["limiting_hinge"]),
        ]
        for j, d in enumerate(doc["directions"])
    ]
    ranges = table(
        ["input", "range (±)", "unit", "limiting hinge"],
        dirs,
        "Range of motion: the input at which the first hinge reaches its yield strength",
    )
    drives = [d["name"] for d in doc["directions"] if d["name"].startswith("drive ")]
    unit = next((d["unit"] for d in doc["directions"] if d["name"] in drives), "rad")
    rows = []
    for j, h in enumerate(doc["hinges"]):
        smallest = min((h["range"][d] for d in drives), default=float("inf"))
        key = min(drives, key=lambda d: h["range"][d]) if drives else ""
        rows.append(
            [
                esc(f"leg{h['leg']}.{h['name']}"),
                cell(h["allowed_stress"], f"hinges/hinges/{j}/allowed_stress", 1e-6, 4),
                _range_cell(smallest, f"hinges/hinges/{j}/range/{key}", unit)
                if key
                else "<td>–</td>",
                cell(h["stress"], f"hinges/hinges/{j}/stress", 1e-6, 4),
                cell(h["utilisation"], f"hinges/hinges/{j}/utilisation", 100.0, 3),
            ]
        )
    hinges = table(
        [
            "hinge",
            "allowed [MPa]",
            f"drive range [µ{esc(unit)}]",
            "stress [MPa]",
            "utilisation [%]",
        ],
        rows,
        f"Each hinge: its smallest range over the drives, and its peak stress under the "
        f"loaded case ({wrench_text})",
    )
    html = (
        "<p>Notch hinges (docs/flexures.md): each hinge's peak normal stress (in-plane "
        "bending with the notch's stress concentration factor, out-of-plane bending and "
        "axial force) from the frozen, linear model at the pose; allowed stress = yield "
        "strength (safety factor 1: <code>analyze --safety-factor</code> sets another). A "
        "drive's input is its free displacement (the others held); a platform direction "
        "is made by the drives, the other task coordinates held at 0. Along a growing "
        "load: <code>deflect</code>; over the workspace: <code>map --quantities "
        "hinge_range</code>.</p>" + f'<div class="cols">{ranges}{hinges}</div>' + _json_block(doc)
    )
    return [(SECTION_ID, "Notch hinges: stress and range of motion", html)]


__all__ = ["JSON_ID", "SECTION_ID", "hinge_document", "hinge_sections"]
