"""One self-contained HTML report of a design: every table and figure of the paper.

:func:`build_report` returns the page as a string, :func:`write_report` writes it
to ``DIR/report.html``. The page needs no network access: images are embedded as
base64 PNG data URIs and the CSS is inline; there is no script to run.

Numbers. The analyses come from :func:`ppm_stiffness.analysis.analyze_design` (the
function behind ``ppm-stiffness analyze --json``), once unloaded and once under the
loading wrench. Both dicts are embedded verbatim as JSON in
``<script type="application/json" id="analysis-unloaded">`` and
``id="analysis-loaded"``, and every number of the tables is rendered from them. Each
such table cell carries ``data-path`` (``unloaded/stiffness_matrix/2/3``: the key
path in those blocks) and ``data-scale`` (displayed value = SI value x scale), so a
reader or a test can trace each printed number back to the analysis.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.analysis import analyze_design
from ppm_stiffness.core.eigenscrews import eigenscrews
from ppm_stiffness.core.errors import InputDataError, UnreachablePoseError
from ppm_stiffness.design import Design, dump_design
from ppm_stiffness.design.schema import leg_parameter_rows
from ppm_stiffness.model import workspace_centre
from ppm_stiffness.visuals.html import (
    CSS as _CSS,
)
from ppm_stiffness.visuals.html import (
    cell as _cell,
)
from ppm_stiffness.visuals.html import (
    esc as _esc,
)
from ppm_stiffness.visuals.html import (
    figure_block as _figure,
)
from ppm_stiffness.visuals.html import (
    figure_data_uri,
    format_number,
)
from ppm_stiffness.visuals.html import (
    json_block as _json_block,
)
from ppm_stiffness.visuals.html import (
    matrix as _matrix,
)
from ppm_stiffness.visuals.html import (
    table as _table,
)
from ppm_stiffness.visuals.html import (
    vector_cells as _vector_cells,
)

#: The paper's loaded case: f = [5, 5, 20] N, m_z = 0.1 N·m, as (m_x, m_y, m_z, f_x, f_y, f_z).
DEFAULT_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])
#: Load ranges of the three deflection curves (Fig. 9 modes) [N, N·m, N]; the same
#: largest loads as ``ppm-stiffness deflect`` by default.
DEFLECTION_LOADS = {
    "planar-force": np.linspace(0.0, 10.0, 41),
    "moment": np.linspace(0.0, 0.5, 41),
    "vertical-force": np.linspace(0.0, 20.0, 41),
}
#: Orientations of the stiffness maps [deg] (Figs. 6 and 7).
MAP_PHIS_DEG = (0.0, 30.0)
#: Actuator stiffness of the maps: all at the maximum (locked) and at the minimum.
MAP_ACTUATORS = ("max", "min")
TWIST_LABELS = ("φx", "φy", "φz", "x", "y", "z")

Progress = Callable[[str, float], None]
"""Progress callback: ``progress(description, fraction_done)``, fraction in [0, 1]."""


# ----------------------------------------------------------------------------- sections
#: How an SI unit is shown in the report: unit -> (shown unit, scale).
_DISPLAY_UNITS: dict[str, tuple[str, float]] = {
    "m": ("mm", 1e3),
    "rad": ("deg", 180 / math.pi),
    "Pa": ("GPa", 1e-9),
    "m^2": ("m²", 1.0),
    "m^4": ("m⁴", 1.0),
    "1": ("–", 1.0),
}


def _param_text(key: str, value: Any, si_unit: str | None = None) -> tuple[str, str]:
    si = (
        si_unit
        if si_unit is not None
        else (
            "m" if key in ("centre_x", "centre_y", "tool_point") else "rad" if key == "phi" else ""
        )
    )
    if key.endswith("threshold_displacement") and si == "m":
        unit, scale = "µm", 1e6
    else:
        unit, scale = _DISPLAY_UNITS.get(si, (si or "SI", 1.0))
    if isinstance(value, (list, tuple)):
        text = "(" + ", ".join(f"{float(x) * scale:.6g}" for x in value) + ")"
    elif isinstance(value, (int, float)):
        text = f"{float(value) * scale:.6g}"
    else:
        text = _esc(value)
    return text, unit


def _design_section(design: Design) -> str:
    parts = []
    rows = []
    for key, value in design.workspace:
        text, unit = _param_text(key, value)
        rows.append([f"workspace.{key}", f'<td class="num">{text}</td>', unit])
    text, unit = _param_text("tool_point", design.tool_point)
    rows.append(["tool_point", f'<td class="num">{text}</td>', unit])
    rows.append(["architecture", f"<td>{_esc(design.architecture)}</td>", ""])
    parts.append(_table(["parameter", "value", "unit"], rows, cls="params"))
    leg_rows = []
    for key, values, si_unit in leg_parameter_rows(design):
        texts = [("–", "") if v is None else _param_text(key, v, si_unit) for v in values]
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
    toml = _esc(dump_design(design))
    parts.append(f"<details><summary>Design file (TOML, SI)</summary><pre>{toml}</pre></details>")
    return '<div class="cols">' + "".join(parts[:2]) + "</div>" + parts[2]


def _stiffness_table(result: dict[str, Any], key: str, caption: str) -> str:
    cols = [f"{c} [{u}]" for c, u in zip(TWIST_LABELS, ("rad",) * 3 + ("m",) * 3, strict=True)]
    return _matrix(
        result["stiffness_matrix"],
        f"{key}/stiffness_matrix",
        TWIST_LABELS,
        cols,
        caption=caption,
        cls="matrix",
    )


def _springs_table(result: dict[str, Any], key: str, caption: str) -> str:
    rows = []
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
                *_vector_cells(s["position"], f"{p}/position", scale=1e3),
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


def _principal_cards(result: dict[str, Any], key: str) -> str:
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


def _decoupling_section(result: dict[str, Any], key: str) -> str:
    parts = [_principal_cards(result, key)]
    for dkey, pkey, title in (
        ("decoupling", "principal", "paper's eq. (19)"),
        ("decoupling_least_squares", "principal_least_squares", "least-squares shift"),
    ):
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
_DISPLACEMENT_DISPLAY = {"m": ("µm", 1e6), "rad": ("µrad", 1e6)}


def _actuator_units(design: Design) -> list[tuple[str, str, float, str]]:
    """Per leg: force unit, shown displacement unit and its scale, stiffness unit."""
    out = []
    for leg in design.legs:
        force, disp, stiff = leg.actuator_units()
        shown, scale = _DISPLACEMENT_DISPLAY.get(disp, (disp, 1.0))
        out.append((force, shown, scale, stiff))
    return out


def _loaded_section(design: Design, loaded: dict[str, Any], unloaded: dict[str, Any]) -> str:
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
            caption="Applied wrench at P (axes of F<sub>b</sub>)",
        )
    ]
    units = _actuator_units(design)
    shared = len(set(units)) == 1  # one set of units: in the header, else per row
    rows = []
    for i in range(len(loaded["actuator_forces"])):
        force, disp, scale, stiff = units[i]
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
    parts.append(_stiffness_table(loaded, "loaded", "K under the wrench, at P (compare eq. 33)"))
    return "".join(parts)


# ----------------------------------------------------------------------------- assembly
_STEPS = (
    ("analysis (unloaded and loaded)", 1.0),
    ("mechanism picture", 1.0),
    ("screw-spring pictures", 2.0),
    ("deflection curves", 2.0),
    ("stiffness maps", 8.0),
)


def build_report(
    design: Design,
    pose: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
    grid: int = 60,
    progress: Progress | None = None,
    source: str | None = None,
    extra_sections: list[tuple[str, str, str]] | None = None,
) -> str:
    """The HTML report of ``design`` at ``pose`` (see the module docstring).

    Parameters
    ----------
    design : Design
    pose : array_like, shape (3,), optional
        (x [m], y [m], phi [rad]); the workspace centre if None.
    wrench : array_like, shape (6,), optional
        Loading wrench (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P; default
        :data:`DEFAULT_WRENCH`, the paper's f = [5, 5, 20] N, m_z = 0.1 N·m.
    grid : int
        Points per axis of the stiffness maps.
    progress : callable, optional
        ``progress(description, fraction_done)``.
    source : str, optional
        Where the design came from (file name), shown in the header.
    extra_sections : list of (id, title, html), optional
        Sections appended after the maps (e.g. the uncertainty section).

    Returns
    -------
    str
        The complete HTML page.
    """
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.statics.deflection import deflection_curve
    from ppm_stiffness.visuals.deflection import plot_deflection_curves
    from ppm_stiffness.visuals.maps import plot_stiffness_maps
    from ppm_stiffness.visuals.mechanism import plot_mechanism
    from ppm_stiffness.visuals.springs import plot_screw_springs

    total = sum(w for _, w in _STEPS)
    done = 0.0

    def step(i: int, inner: float = 0.0) -> None:
        if progress is not None:
            name, weight = _STEPS[i]
            progress(name, min((done + inner * weight) / total, 1.0))

    def finish(i: int) -> None:
        nonlocal done
        done += _STEPS[i][1]

    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    w = DEFAULT_WRENCH if wrench is None else np.asarray(wrench, dtype=float)

    step(0)
    unloaded = analyze_design(design, p)
    loaded = analyze_design(design, p, w)
    finish(0)

    step(1)
    mech_uri = figure_data_uri(plot_mechanism(design, p))
    finish(1)

    step(2)
    spring_uris = [
        figure_data_uri(
            plot_screw_springs(
                eigenscrews(np.asarray(res["stiffness_matrix"])), design, p, title=title
            )
        )
        for res, title in (
            (unloaded, "Screw springs of K, unloaded (Fig. 5)"),
            (loaded, "Screw springs of K under the wrench (Table 5)"),
        )
    ]
    finish(2)

    step(3)
    curves = [
        deflection_curve(design, mode, loads, p, method=method)
        for mode, loads in DEFLECTION_LOADS.items()
        for method in ("integrate", "linear")
    ]
    defl_uri = figure_data_uri(plot_deflection_curves(curves))
    finish(3)

    map_figs: list[tuple[float, str, str, str]] = []
    n_maps = len(MAP_PHIS_DEG) * len(MAP_ACTUATORS)
    for m, (phi_deg, acts) in enumerate((ph, ac) for ph in MAP_PHIS_DEG for ac in MAP_ACTUATORS):
        step(4, m / n_maps)

        def inner(done_poses: int, total_poses: int, m: int = m) -> None:
            step(4, (m + done_poses / max(total_poses, 1)) / n_maps)

        try:
            smap = stiffness_map(
                design, phi=math.radians(phi_deg), actuators=acts, grid=grid, progress=inner
            )
        except UnreachablePoseError as exc:
            map_figs.append((phi_deg, acts, "", f"no map: {_esc(exc)}"))
            continue
        title = (
            f"φ = {phi_deg:g}°, actuators at the {'maximum' if acts == 'max' else 'minimum'}"
            " stiffness"
        )
        uri = figure_data_uri(plot_stiffness_maps(smap, title=title))
        map_figs.append((phi_deg, acts, uri, _map_summary(design, smap)))
    finish(4)
    if progress is not None:
        progress("done", 1.0)
    return _assemble(
        design,
        p,
        unloaded,
        loaded,
        mech_uri,
        spring_uris,
        defl_uri,
        map_figs,
        grid,
        source,
        extra_sections,
    )


def _map_summary(design: Design, smap: Any) -> str:
    """Actuator stiffness of the map and the range of k_phi, k_x, k_y over it."""
    k_act = np.asarray(smap.actuator_stiffness, dtype=float).reshape(-1, len(design.legs))
    by_unit: dict[str, list[float]] = {}
    for i, (_, _, _, stiff) in enumerate(_actuator_units(design)):
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
    for key, name, unit in (
        ("k_phi", "k<sub>φ</sub>", "N·m/rad"),
        ("k_x", "k<sub>x</sub>", "N/m"),
        ("k_y", "k<sub>y</sub>", "N/m"),
    ):
        st = summary[key]
        rows.append(
            [
                name,
                f'<td class="num">{format_number(st["min"])}</td>',
                f'<td class="num">{format_number(st["max"])}</td>',
                f'<td class="num">{format_number(st["ratio"], 3)}</td>',
                unit,
            ]
        )
    x, y = np.asarray(smap.x) * 1e3, np.asarray(smap.y) * 1e3
    reach = float(np.mean(np.asarray(smap.reachable)))
    cap = (
        f"{act_txt}; grid x ∈ [{x[0]:.1f}, {x[-1]:.1f}] mm, y ∈ [{y[0]:.1f}, {y[-1]:.1f}] "
        f"mm, {reach * 100:.0f}% reachable"
    )
    return f'<p class="meta">{cap}</p>' + _table(["", "min", "max", "max/min", "unit"], rows)


def _assemble(
    design: Design,
    pose: np.ndarray,
    unloaded: dict[str, Any],
    loaded: dict[str, Any],
    mech_uri: str,
    spring_uris: list[str],
    defl_uri: str,
    map_figs: list[tuple[float, str, str, str]],
    grid: int,
    source: str | None,
    extra_sections: list[tuple[str, str, str]] | None = None,
) -> str:
    try:
        from importlib.metadata import version

        ver = version("ppm-stiffness")
    except Exception:  # pragma: no cover - not installed
        ver = "unknown"
    stamp = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    pose_txt = (
        f"x = {pose[0] * 1e3:.3f} mm, y = {pose[1] * 1e3:.3f} mm, "
        f"φ = {math.degrees(pose[2]):.3f}° (P in F<sub>b</sub>)"
    )
    w = loaded["wrench"]
    wrench_txt = f"f = ({w[3]:g}, {w[4]:g}, {w[5]:g}) N, m = ({w[0]:g}, {w[1]:g}, {w[2]:g}) N·m"
    sections = [
        ("design", "Design parameters", _design_section(design)),
        (
            "mechanism",
            "The mechanism at the pose",
            _figure(
                mech_uri,
                f"Top view of the {_esc(design.architecture)} in F<sub>b</sub> "
                "[mm]: each leg's base rail (over the actuator stroke) or base pivot, its "
                "links and joints (R circle, P square with slider, C diamond with sleeve; "
                "the actuated joint ringed), the platform, P and the frames.",
                "fig-mechanism",
            ),
        ),
        (
            "stiffness",
            "Cartesian stiffness matrix K (unloaded)",
            "<p>w = K t at P with the axes of F<sub>b</sub>; t = (φ, u) [rad, m], w = (m, f) "
            "[N·m, N]. Blocks: K<sub>rr</sub> [N·m/rad], K<sub>rt</sub> [N], K<sub>tt</sub> "
            "[N/m]; actuators locked (compare eq. 22).</p>"
            + _stiffness_table(unloaded, "unloaded", "K [SI], unloaded"),
        ),
        (
            "screw-springs",
            "Screw springs (eigenscrews, Table 4 and Fig. 5)",
            _springs_table(
                unloaded, "unloaded", "Six screw springs of K (unloaded); position p relative to P"
            )
            + _figure(
                spring_uris[0],
                "Screw springs: axes through p along e; helix right-handed "
                "for pitch &gt; 0, left-handed for pitch &lt; 0; colour and radius show k.",
                "fig-springs",
            ),
        ),
        (
            "decoupling",
            "Decoupling and principal stiffnesses (eq. 28–32)",
            _decoupling_section(unloaded, "unloaded"),
        ),
        (
            "loaded",
            f"Loaded case: {wrench_txt} (eq. 33–35, Table 5)",
            _loaded_section(design, loaded, unloaded)
            + "<h3>Principal stiffnesses under the wrench</h3>"
            + _principal_cards(loaded, "loaded")
            + _springs_table(loaded, "loaded", "Screw springs under the wrench (Table 5)")
            + _figure(spring_uris[1], "Screw springs under the wrench.", "fig-springs-loaded")
            + "<details><summary>Decoupling under the wrench</summary>"
            + _decoupling_section(loaded, "loaded")
            + "</details>",
        ),
        (
            "deflection",
            "Deflection curves (Figs. 9–10)",
            _figure(
                defl_uri,
                "Platform deflection at the pose under a growing planar force "
                "(45°), moment m<sub>z</sub> and vertical force f<sub>z</sub>: with the "
                "actuators' law (eq. 20–21) in the loop (integrate) and with the unloaded, "
                "locked matrix (linear, as the paper's Fig. 10 model).",
                "fig-deflection",
            ),
        ),
        (
            "maps",
            "Stiffness maps (Figs. 6–7)",
            f"<p>Principal stiffnesses k<sub>φ</sub>, k<sub>x</sub>, k<sub>y</sub> over the "
            f"reachable workspace, {grid} × {grid} grid.</p>"
            + "".join(
                (
                    _figure(
                        uri,
                        f"φ = {ph:g}°, actuators at their "
                        f"{'maximum' if ac == 'max' else 'minimum'} stiffness.",
                        f"fig-map-{ph:g}-{ac}",
                    )
                    if uri
                    else f'<p class="note">{note}</p>'
                )
                + (note if uri else "")
                for ph, ac, uri, note in map_figs
            ),
        ),
    ]
    sections += extra_sections or []
    nav = (
        "<nav><ol>"
        + "".join(f'<li><a href="#{sid}">{title}</a></li>' for sid, title, _ in sections)
        + "</ol></nav>"
    )
    body = "".join(
        f'<section id="{sid}"><h2>{title}</h2>{content}</section>'
        for sid, title, content in sections
    )
    src = f"design file {_esc(source)}" if source else "built-in design"
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>Stiffness report: {_esc(design.name)}</title><style>{_CSS}</style></head>"
        f"<body><main><h1>Stiffness report: {_esc(design.name)}</h1>"
        f'<p class="meta">{src}; pose {pose_txt}; loaded case {wrench_txt}.<br>'
        f"ppm-stiffness {_esc(ver)}, {stamp}. All numbers come from "
        "<code>ppm-stiffness analyze --json</code> (embedded in this page).</p>"
        f"{nav}{body}"
        + _json_block("analysis-unloaded", unloaded)
        + _json_block("analysis-loaded", loaded)
        + "</main></body></html>\n"
    )


def write_report(
    design: Design,
    out_dir: str | Path,
    pose: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
    grid: int = 60,
    progress: Progress | None = None,
    source: str | None = None,
    extra_sections: list[tuple[str, str, str]] | None = None,
) -> Path:
    """Write ``out_dir/report.html`` (see :func:`build_report`); returns its path."""
    out = Path(out_dir)
    if not str(out_dir).strip():
        raise InputDataError("--out: empty path")
    if out.exists() and not out.is_dir():
        raise InputDataError(f"--out {out}: exists and is not a directory")
    if not out.parent.is_dir():
        raise InputDataError(f"--out {out}: directory {out.parent} does not exist")
    page = build_report(design, pose, wrench, grid, progress, source, extra_sections)
    out.mkdir(exist_ok=True)
    path = out / "report.html"
    path.write_text(page, encoding="utf-8")
    return path


def embedded_json(page: str, block_id: str) -> dict[str, Any]:
    """The JSON block ``block_id`` of a report page (for readers and tests)."""
    start_tag = f'<script type="application/json" id="{block_id}">'
    i = page.index(start_tag) + len(start_tag)
    j = page.index("</script>", i)
    data: dict[str, Any] = json.loads(page[i:j])
    return data
