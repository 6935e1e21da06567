"""The report's tables (:mod:`ppm_stiffness.visuals.report`): the design's parameters,
K, the screw springs, the decouplings and the paper's principal stiffnesses, the loaded
case, the map summaries.

Every number cell is rendered from an analysis dict
(:func:`ppm_stiffness.analysis.analyze_design`) with its ``data-path`` into the page's
embedded JSON blocks (``unloaded/...``, ``loaded/...``) and its ``data-scale``
(:func:`ppm_stiffness.visuals.html.cell`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ppm_stiffness.core.pose import ANGLE_COORDINATES
from ppm_stiffness.design import Design, dump_design
from ppm_stiffness.design.schema import leg_parameter_rows
from ppm_stiffness.maps.result import QUANTITIES
from ppm_stiffness.maps.slices import cli_scale
from ppm_stiffness.visuals.html import cell as _cell
from ppm_stiffness.visuals.html import esc as _esc
from ppm_stiffness.visuals.html import format_number
from ppm_stiffness.visuals.html import matrix as _matrix
from ppm_stiffness.visuals.html import table as _table
from ppm_stiffness.visuals.html import vector_cells as _vector_cells

TWIST_LABELS = ("φx", "φy", "φz", "x", "y", "z")

#: How an SI unit is shown in the report: unit -> (shown unit, scale).
_DISPLAY_UNITS: dict[str, tuple[str, float]] = {
    "m": ("mm", 1e3),
    "rad": ("deg", 180 / math.pi),
    "Pa": ("GPa", 1e-9),
    "1": ("–", 1.0),
}
#: Powers written as superscripts in every shown unit (``kg·m^2`` -> ``kg·m²``).
_SUPERSCRIPTS = str.maketrans({"2": "²", "3": "³", "4": "⁴"})


def shown_unit(si: str) -> tuple[str, float]:
    """How an SI unit is shown in the report: (unit, scale); the powers 2, 3, 4 as
    superscripts (m², kg·m², kg/m³), another power as written (N/m^q)."""
    if si in _DISPLAY_UNITS:
        return _DISPLAY_UNITS[si]
    head, *powers = si.split("^")
    text = head + "".join(
        p[:1].translate(_SUPERSCRIPTS) + p[1:] if p[:1] in "234" else "^" + p for p in powers
    )
    return text, 1.0


#: SI unit of the design's top-level parameters shown in the report (the legs' come
#: from :func:`ppm_stiffness.design.schema.leg_parameter_rows`).
_DESIGN_UNITS = {
    "centre_x": "m",
    "centre_y": "m",
    "centre_z": "m",
    "rx": "rad",
    "ry": "rad",
    "phi": "rad",
    "tool_point": "m",
}


def param_text(key: str, value: Any, si_unit: str | None = None) -> tuple[str, str]:
    """A parameter as shown: its text in display units (mm, deg, GPa; µm for an
    actuator's threshold displacement) and the unit ("" for a word)."""
    si = si_unit if si_unit is not None else _DESIGN_UNITS.get(key, "")
    if key.endswith("threshold_displacement") and si == "m":
        unit, scale = "µm", 1e6
    elif isinstance(value, str):  # a word (mass_centre_from = "base"): no unit
        unit, scale = "", 1.0
    else:
        unit, scale = shown_unit(si)
    if isinstance(value, (list, tuple)):
        text = "(" + ", ".join(f"{float(x) * scale:.6g}" for x in value) + ")"
    elif isinstance(value, (int, float)):
        text = f"{float(value) * scale:.6g}"
    else:
        text = _esc(value)
    return text, unit


def workspace_rows(design: Design) -> list[list[str]]:
    """The home pose, then the required region's ranges and grid, one row each."""
    rows = []
    for key, value in design.workspace:
        if key != "required":
            text, unit = param_text(key, value)
            rows.append([f"workspace.{key}", f'<td class="num">{text}</td>', unit])
        elif value is not None:
            for name, pair in value.ranges().items():
                text, unit = param_text(name, pair, "rad" if name in ANGLE_COORDINATES else "m")
                rows.append([f"workspace.required.{name}", f'<td class="num">{text}</td>', unit])
            grid = "(" + ", ".join(str(n) for n in value.grid) + ")"
            rows.append(["workspace.required.grid", f'<td class="num">{grid}</td>', "poses"])
    return rows


def design_section(
    design: Design, design_text: str | None = None, source: str | None = None
) -> str:
    """The design's parameters: the workspace and tool point, one column per leg, and
    the design file folded: ``design_text``, the file as written (its comments and
    layout, escaped), or without it (a built-in design) its TOML serialisation, so
    labelled."""
    parts = []
    rows = workspace_rows(design)
    text, unit = param_text("tool_point", design.tool_point)
    rows.append(["tool_point", f'<td class="num">{text}</td>', unit])
    rows.append(["architecture", f"<td>{_esc(design.architecture)}</td>", ""])
    rows.append(["task_coordinates", f"<td>{_esc(', '.join(design.task_coordinates))}</td>", ""])
    parts.append(_table(["parameter", "value", "unit"], rows, cls="params"))
    leg_rows = []
    for key, values, si_unit in leg_parameter_rows(design):
        texts = [("–", "") if v is None else param_text(key, v, si_unit) for v in values]
        unit = next((u for t, u in texts if t != "–"), "")
        leg_rows.append([key] + [f'<td class="num">{t}</td>' for t, _ in texts] + [unit])
    legs = design.legs
    parts.append(
        _table(
            ["leg parameter"] + [f"leg {i + 1}" for i in range(len(legs))] + ["unit"],
            leg_rows,
            cls="params",
        )
    )
    if design_text is not None:
        what = f"Design file {_esc(source)} as written" if source else "Design file as written"
        text = design_text
    else:
        what = "Design as TOML (built-in design: its serialisation, SI)"
        text = dump_design(design)
    parts.append(
        f'<details><summary>{what}</summary><pre id="design-file">{_esc(text)}</pre></details>'
    )
    return '<div class="cols">' + "".join(parts[:2]) + "</div>" + parts[2]


def reference_point(design: Design) -> str:
    """Where K, its springs and the loaded case refer to, in words: ``"P"``, or the
    tool point with its coordinates (platform frame, mm)."""
    t = np.asarray(design.tool_point, dtype=float)
    if not np.any(t != 0.0):
        return "P"
    return "the tool point T = (" + ", ".join(f"{v * 1e3:g}" for v in t) + ") mm (platform frame)"


def stiffness_table(result: dict[str, Any], key: str, caption: str) -> str:
    """K (6x6, SI) of ``result`` with its row and column units."""
    cols = [f"{c} [{u}]" for c, u in zip(TWIST_LABELS, ("rad",) * 3 + ("m",) * 3, strict=True)]
    return _matrix(
        result["stiffness_matrix"],
        f"{key}/stiffness_matrix",
        TWIST_LABELS,
        cols,
        caption=caption,
        cls="matrix",
    )


def springs_table(result: dict[str, Any], key: str, caption: str) -> str:
    """The six screw springs (Table 4 columns) and the note on repeated eigenvalues."""
    rows = []
    # positions below 1e-12 of the table's largest are round-off: shown as 0
    ref = max(float(np.max(np.abs(s["position"]))) for s in result["eigenscrews"])
    for i, s in enumerate(result["eigenscrews"]):
        p = f"{key}/eigenscrews/{i}"
        rows.append(
            [
                f"s{i + 1}",
                _cell(s["eigenvalue"], f"{p}/eigenvalue"),
                _cell(s["eigenforce"], f"{p}/eigenforce"),
                _cell(s["spring_constant"], f"{p}/spring_constant"),
                _cell(s["pitch"], f"{p}/pitch", sig=4),
                *_vector_cells(s["axis"], f"{p}/axis"),
                *[_cell(s["position"][j], f"{p}/position/{j}", 1e3, 4, ref) for j in range(3)],
            ]
        )
    head = [
        "spring",
        "λ [N]",
        "κ [N]",
        "k [N/m]",
        "pitch h [m/rad]",
        "e<sub>x</sub>",
        "e<sub>y</sub>",
        "e<sub>z</sub>",
        "p<sub>x</sub> [mm]",
        "p<sub>y</sub> [mm]",
        "p<sub>z</sub> [mm]",
    ]
    table = _table(head, rows, caption, cls="springs")
    groups = result.get("eigenscrews_repeated") or []
    if not groups:
        return table
    names = "; ".join(", ".join(f"s{i + 1}" for i in g) for g in groups)
    return table + (
        f'<p class="note">Repeated eigenvalues ({names}): inside each group the screw '
        "springs are not unique (any reciprocal combination is as valid); shown: those "
        "whose axes are closest to x, y, z.</p>"
    )


def principal_cards(result: dict[str, Any], key: str) -> str:
    """Cards of the paper's principal stiffnesses k_phi, k_x, k_y (planar designs)."""
    pr = f"{key}/principal"
    rot, tra = result["principal"]["rotational"], result["principal"]["translational"]
    cards = [
        ("k<sub>φ</sub>", rot["values"][2], f"{pr}/rotational/values/2", "N·m/rad"),
        ("k<sub>x</sub>", tra["values"][0], f"{pr}/translational/values/0", "N/m"),
        ("k<sub>y</sub>", tra["values"][1], f"{pr}/translational/values/1", "N/m"),
    ]
    out = ['<div class="cards">']
    for name, value, path, unit in cards:
        cell = _cell(value, path).replace("<td", "<span").replace("</td>", "</span>")
        out.append(f'<div class="card"><div class="name">{name}</div>{cell} {unit}</div>')
    out.append("</div>")
    return "".join(out)


def decoupling_section(result: dict[str, Any], key: str, cards: bool = True) -> str:
    """Both decouplings (eq. 19, least squares): d, the residual coupling, M, K'_rr,
    K'_tt and their eigen-pairs; ``cards``: the paper's k_phi, k_x, k_y and its eq. (19)
    first (planar designs), else the least-squares shift first (spatial designs, as
    ``analyze`` leads)."""
    parts = [principal_cards(result, key)] if cards else []
    cases = [
        ("decoupling", "principal", "paper's eq. (19)"),
        ("decoupling_least_squares", "principal_least_squares", "least-squares shift"),
    ]
    if not cards:
        cases.reverse()
        cases[1] = (*cases[1][:2], "paper's eq. (19), for comparison (planar definitions)")
    for dkey, pkey, title in cases:
        dec, pr = result[dkey], result[pkey]
        base = f"{key}/{dkey}"
        d_cells = _vector_cells(dec["d"], f"{base}/d", scale=1e3, sig=4)
        res = (
            "<td>n/a (already decoupled: K<sub>rt</sub> is round-off)</td>"
            if dec["already_decoupled"]
            else _cell(dec["residual_coupling"], f"{base}/residual_coupling", sig=4)
        )
        block = [
            f"<h3>Decoupling: {title}</h3>",
            _table(
                [
                    "d<sub>x</sub> [mm]",
                    "d<sub>y</sub> [mm]",
                    "d<sub>z</sub> [mm]",
                    "residual coupling ‖K′<sub>rt</sub>‖/‖K<sub>rt</sub>‖",
                ],
                [d_cells + [res]],
            ),
            '<div class="cols">',
            _matrix(
                dec["M"], f"{base}/M", ("x", "y", "z"), ("x", "y", "z"), caption="M [N/m] (eq. 19)"
            ),
            _matrix(
                dec["K_rr"],
                f"{base}/K_rr",
                TWIST_LABELS[:3],
                TWIST_LABELS[:3],
                caption="K′<sub>rr</sub> [N·m/rad]",
            ),
            _matrix(
                dec["K_tt"],
                f"{base}/K_tt",
                TWIST_LABELS[3:],
                TWIST_LABELS[3:],
                caption="K′<sub>tt</sub> [N/m]",
            ),
            "</div>",
        ]
        rows = []
        for blk, unit in (("rotational", "N·m/rad"), ("translational", "N/m")):
            vals, dirs = pr[blk]["values"], np.asarray(pr[blk]["directions"])
            for j in range(3):
                p = f"{key}/{pkey}/{blk}"
                cells = [
                    _cell(
                        dirs[j, i],
                        f"{p}/directions/{j}/{i}",
                        sig=4,
                        ref=float(np.max(np.abs(dirs[j]))),
                    )
                    for i in range(3)
                ]
                rows.append([f"{blk} {j + 1}", _cell(vals[j], f"{p}/values/{j}"), unit, *cells])
        block.append(
            _table(
                ["principal", "stiffness", "unit", "dir x", "dir y", "dir z"],
                rows,
                caption="Principal stiffnesses (eigenvalues of K′<sub>rr</sub>, "
                "K′<sub>tt</sub>) and directions",
            )
        )
        parts.append("".join(block))
    return "".join(parts)


#: Shown unit and scale of an actuator displacement, by its SI unit.
_DISPLACEMENT_DISPLAY = {"m": ("mm", 1e3), "rad": ("deg", 180 / math.pi)}  # as the CLI


def actuator_units(design: Design) -> list[tuple[str, str, float, str]]:
    """Per leg: force unit, shown displacement unit and its scale, stiffness unit."""
    out = []
    for leg in design.legs:
        force, disp, stiff = leg.actuator_units()
        shown, scale = _DISPLACEMENT_DISPLAY.get(disp, (disp, 1.0))
        out.append((force, shown, scale, stiff))
    return out


def loaded_section(design: Design, loaded: dict[str, Any], unloaded: dict[str, Any]) -> str:
    """The wrench, each actuator's force, displacement and stiffness in its own units,
    and K under the wrench."""
    w = loaded["wrench"]
    wrench_rows = [[_cell(w[j], f"loaded/wrench/{j}", sig=4) for j in (3, 4, 5, 0, 1, 2)]]
    parts = [
        _table(
            [
                "f<sub>x</sub> [N]",
                "f<sub>y</sub> [N]",
                "f<sub>z</sub> [N]",
                "m<sub>x</sub> [N·m]",
                "m<sub>y</sub> [N·m]",
                "m<sub>z</sub> [N·m]",
            ],
            wrench_rows,
            caption=f"Applied wrench at {reference_point(design)} (axes of F<sub>b</sub>)",
        )
    ]
    units = actuator_units(design)
    shared = len(set(units)) == 1  # one set of units: in the header, else per row
    rows = []
    for i in range(len(loaded["actuator_forces"])):
        force, disp, scale, stiff = units[i]
        if design.legs[i].actuator is None:  # a passive constraining leg: no actuator
            row = [f"leg {i + 1} (passive)", "—", "—", "—", "—"]
            rows.append(row if shared else row + ["—"])
            continue
        row = [
            f"leg {i + 1}",
            _cell(loaded["actuator_forces"][i], f"loaded/actuator_forces/{i}", sig=4),
            _cell(
                loaded["actuator_displacements"][i],
                f"loaded/actuator_displacements/{i}",
                scale=scale,
                sig=4,
            ),
            _cell(unloaded["actuator_stiffness"][i], f"unloaded/actuator_stiffness/{i}"),
            _cell(loaded["actuator_stiffness"][i], f"loaded/actuator_stiffness/{i}"),
        ]
        rows.append(row if shared else row + [f"{force}, {disp}, {stiff}"])
    force, disp, _, stiff = units[0]
    head = (
        [
            "actuator",
            f"force G [{force}]",
            f"displacement δ [{disp}]",
            f"K<sub>act</sub> unloaded [{stiff}]",
            f"K<sub>act</sub> loaded [{stiff}]",
        ]
        if shared
        else [
            "actuator",
            "force G",
            "displacement δ",
            "K<sub>act</sub> unloaded",
            "K<sub>act</sub> loaded",
            "units (G, δ, K<sub>act</sub>)",
        ]
    )
    parts.append(_table(head, rows, caption="Actuators under the wrench (eq. 20–21)"))
    parts.append(
        stiffness_table(
            loaded,
            "loaded",
            f"K under the wrench, at {reference_point(design)} (compare eq. 33)",
        )
    )
    return "".join(parts)


#: HTML names of the paper's map quantities (others by their name).
_QUANTITY_HTML = {"k_phi": "k<sub>φ</sub>", "k_x": "k<sub>x</sub>", "k_y": "k<sub>y</sub>"}


def _grid_end(value: float, values: np.ndarray) -> str:
    """An end of a map's grid axis: one decimal (mm, deg) for a grid spanning 1 and
    more, else four significant digits (a flexure stage's slice spans micrometres: its
    ends at one decimal of a millimetre read [-0.0, 0.0])."""
    span = float(np.max(values) - np.min(values))
    return f"{value:.1f}" if span >= 1.0 else f"{value:.4g}"


def map_summary(design: Design, smap: Any) -> str:
    """Actuator stiffness of the map and the range of each of its quantities over it."""
    k_act = np.asarray(smap.actuator_stiffness, dtype=float).reshape(-1, len(design.legs))
    by_unit: dict[str, list[float]] = {}
    for i, (_, _, _, stiff) in enumerate(actuator_units(design)):
        by_unit.setdefault(stiff, []).append(float(np.nanmin(k_act[:, i])))
    act_txt = (
        "actuator stiffness "
        + ", ".join(f"{format_number(min(v), 5)} {u}" for u, v in by_unit.items())
        + (
            f" (tangent stiffness under {smap.reference_force:g} N, eq. 21)"
            if getattr(smap, "reference_force", None)
            else " (locked)"
        )
    )
    rows = []
    summary = smap.summary()
    for key in smap.quantities:
        st = summary[key]
        rows.append(
            [
                _QUANTITY_HTML.get(key, key.replace("_", " ")),
                f'<td class="num">{format_number(st["min"])}</td>',
                f'<td class="num">{format_number(st["max"])}</td>',
                f'<td class="num">{format_number(st["ratio"], 3)}</td>',
                QUANTITIES[key][0] if key in QUANTITIES else "",
            ]
        )
    ranges = []
    for name, values in zip(smap.axes, (smap.u, smap.v), strict=True):
        scale, unit = cli_scale(name)
        v = np.asarray(values) * scale
        ranges.append(f"{name} ∈ [{_grid_end(v[0], v)}, {_grid_end(v[-1], v)}] {unit}")
    reach = float(np.mean(np.asarray(smap.reachable)))
    cap = f"{act_txt}; grid {', '.join(ranges)}, {reach * 100:.0f}% reachable"
    return f'<p class="meta">{cap}</p>' + _table(["", "min", "max", "max/min", "unit"], rows)


__all__ = [
    "TWIST_LABELS",
    "actuator_units",
    "decoupling_section",
    "design_section",
    "loaded_section",
    "map_summary",
    "param_text",
    "principal_cards",
    "reference_point",
    "springs_table",
    "stiffness_table",
    "workspace_rows",
]
