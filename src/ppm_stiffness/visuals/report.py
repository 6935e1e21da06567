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
reader or a test can trace each printed number back to the analysis. A design with
notch hinges adds their stress and range (``id="analysis-hinges"``,
:mod:`ppm_stiffness.visuals.report_hinges`), one with a mass model its natural
frequencies (``id="analysis-modes"``, :mod:`ppm_stiffness.visuals.report_dynamics`).
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
from ppm_stiffness.core.pose import POSE_INDEX
from ppm_stiffness.design import Design
from ppm_stiffness.maps.slices import cli_scale, map_slice
from ppm_stiffness.model import validate_pose
from ppm_stiffness.visuals import report_spatial as spatial
from ppm_stiffness.visuals import report_tables as tables
from ppm_stiffness.visuals.html import CSS as _CSS
from ppm_stiffness.visuals.html import esc as _esc
from ppm_stiffness.visuals.html import figure_block as _figure
from ppm_stiffness.visuals.html import figure_data_uri
from ppm_stiffness.visuals.html import json_block as _json_block
from ppm_stiffness.visuals.leg_geometry import pose_text
from ppm_stiffness.visuals.report_wrench import PAPER_WRENCH, ReferenceWrench, reference_wrench

#: The paper's loaded case: f = [5, 5, 20] N, m_z = 0.1 N·m, as (m_x, m_y, m_z, f_x, f_y, f_z):
#: the default of a planar design (a spatial one's is scaled to it,
#: :mod:`ppm_stiffness.visuals.report_wrench`).
DEFAULT_WRENCH = PAPER_WRENCH
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

#: The report's tables, also under their former names here.
TWIST_LABELS = tables.TWIST_LABELS
_decoupling_section = tables.decoupling_section

Progress = Callable[[str, float], None]
"""Progress callback: ``progress(description, fraction_done)``, fraction in [0, 1]."""


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
    design_text: str | None = None,
) -> str:
    """The HTML report of ``design`` at ``pose`` (see the module docstring).

    Parameters
    ----------
    design : Design
    pose : array_like, shape (3,), optional
        (x [m], y [m], phi [rad]); the workspace centre if None.
    wrench : array_like, shape (6,), optional
        Loading wrench (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the tool point; default
        the design's reference wrench (:func:`ppm_stiffness.visuals.report_wrench
        .reference_wrench`: the design file's ``[reference_wrench]``, else the paper's
        f = [5, 5, 20] N, m_z = 0.1 N·m for a planar design, scaled to a spatial one).
    grid : int
        Points per axis of the stiffness maps.
    progress : callable, optional
        ``progress(description, fraction_done)``.
    source : str, optional
        Where the design came from (file name), shown in the header.
    extra_sections : list of (id, title, html), optional
        Sections appended after the maps (e.g. the uncertainty section).
    design_text : str, optional
        The design file as written, embedded in the "Design parameters" section;
        without it (a built-in design) the design's TOML serialisation, so labelled.

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

    p = validate_pose(design, pose)  # the full pose (6,)

    step(0)
    # as `analyze --json` prints them (ppm_stiffness.leading: a spatial design leads
    # with the least-squares decoupling)
    unloaded = analyze_design(design, p).to_dict()
    ref = reference_wrench(design, p, unloaded["stiffness_matrix"], wrench)
    w = ref.wrench
    loaded = analyze_design(design, p, w).to_dict()
    finish(0)

    step(1)
    mech_uri = figure_data_uri(plot_mechanism(design, p))
    finish(1)

    step(2)
    same_k = same_stiffness(unloaded, loaded)
    cases = [(unloaded, "Screw springs of K, unloaded (Fig. 5)")]
    if not same_k:
        cases.append((loaded, "Screw springs of K under the wrench (Table 5)"))
    spring_uris = [
        figure_data_uri(
            plot_screw_springs(
                eigenscrews(np.asarray(res["stiffness_matrix"])),
                design,
                p,
                title=title,
                tool_point=res["tool_point"],
            )
        )
        for res, title in cases
    ]
    finish(2)

    step(3)
    if design.planar:
        curves = [
            deflection_curve(design, mode, loads, p, method=method)
            for mode, loads in DEFLECTION_LOADS.items()
            for method in ("integrate", "linear")
        ]
    else:  # along the loaded case's wrench (report_spatial.DEFLECTION_SCALES)
        curves = spatial.deflection_curves(design, p, w)
    defl_uri = figure_data_uri(plot_deflection_curves(curves))
    finish(3)

    map_figs: list[tuple[str, str, str, str]] = []
    # planar: the paper's x-y maps at two orientations; else the default slice (the
    # design's first two task coordinates, x-y for a hexapod), the others at the pose
    slices: list[float | None] = (
        [math.radians(d) for d in MAP_PHIS_DEG] if design.planar else [None]
    )
    states = MAP_ACTUATORS if actuators_differ(design) else MAP_ACTUATORS[:1]
    map_cases = [(ph, ac) for ph in slices for ac in states]
    n_maps = len(map_cases)
    for m, (phi, acts) in enumerate(map_cases):
        step(4, m / n_maps)

        def inner(done_poses: int, total_poses: int, m: int = m) -> None:
            step(4, (m + done_poses / max(total_poses, 1)) / n_maps)

        state = f"actuators at their {'maximum' if acts == 'max' else 'minimum'} stiffness"
        if len(states) == 1:
            state = "actuators at their stiffness (minimum = maximum: linear laws)"
        key = f"{math.degrees(phi):g}" if phi is not None else ""
        where: dict[str, Any] = {"phi": phi}
        if phi is None:  # the default axes, the other task coordinates at the pose
            axes = map_slice(design).axes
            others = [n for n in design.task_coordinates if n not in axes]
            where = {"axes": axes, "fixed": {n: float(p[POSE_INDEX[n]]) for n in others}}
        try:
            smap = stiffness_map(design, actuators=acts, grid=grid, progress=inner, **where)
        except UnreachablePoseError as exc:
            map_figs.append((key or "slice", f"{acts}", "", f"no map: {_esc(exc)}"))
            continue
        if phi is None:
            key = "-".join(smap.axes)
            fixed = ", ".join(
                f"{n} = {v * cli_scale(n)[0]:.4g} {cli_scale(n)[1]}" for n, v in smap.fixed.items()
            )
            caption = f"{key} slice at {fixed}, {state}."
        else:
            caption = f"φ = {key}°, {state}."
        uri = figure_data_uri(plot_stiffness_maps(smap, title=caption.rstrip(".")))
        map_figs.append((f"{key}-{acts}", caption, uri, tables.map_summary(design, smap)))
    finish(4)
    from ppm_stiffness.visuals.report_dynamics import dynamics_sections
    from ppm_stiffness.visuals.report_hinges import hinge_sections

    w_text = f"f = ({w[3]:g}, {w[4]:g}, {w[5]:g}) N, m = ({w[0]:g}, {w[1]:g}, {w[2]:g}) N·m"
    extra_sections = (
        hinge_sections(design, p, w, design.tool_point, w_text)
        + dynamics_sections(design, p, grid)
        + (extra_sections or [])
    )
    if wrench is not None:  # a given wrench: the "Loaded geometry" section
        from ppm_stiffness.visuals.report_loaded import loaded_geometry_section

        extra_sections = [loaded_geometry_section(design, p, w), *extra_sections]
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
        ref,
        design_text,
        len(states) == 1,
    )


#: K under the wrench equals the unloaded K when no entry differs by more than this
#: share of the largest (round-off; linear actuators under the frozen geometry).
SAME_STIFFNESS = 1e-12


def same_stiffness(unloaded: dict[str, Any], loaded: dict[str, Any]) -> bool:
    """True when K under the wrench is the unloaded K to round-off
    (:data:`SAME_STIFFNESS`): linear actuators, whose stiffness does not change with
    the load, under the frozen geometry."""
    k0 = np.asarray(unloaded["stiffness_matrix"], dtype=float)
    k1 = np.asarray(loaded["stiffness_matrix"], dtype=float)
    return bool(np.max(np.abs(k1 - k0)) <= SAME_STIFFNESS * np.max(np.abs(k0)))


def actuators_differ(design: Design) -> bool:
    """True when some actuator's stiffness at the maps' "min" state (eq. 20-21 under
    the reference load) differs from its locked ("max") one; False for linear laws
    (q = 1), whose two maps would be the same picture."""
    from ppm_stiffness.maps.workspace import DEFAULT_REFERENCE_FORCE, minimum_actuator_stiffness
    from ppm_stiffness.model import locked_actuator_stiffness

    k_max = np.asarray(locked_actuator_stiffness(design), dtype=float)
    k_min = minimum_actuator_stiffness(design, DEFAULT_REFERENCE_FORCE)
    return not np.allclose(k_min, k_max, rtol=1e-12, atol=0.0)


def _assemble(
    design: Design,
    pose: np.ndarray,
    unloaded: dict[str, Any],
    loaded: dict[str, Any],
    mech_uri: str,
    spring_uris: list[str],
    defl_uri: str,
    map_figs: list[tuple[str, str, str, str]],
    grid: int,
    source: str | None,
    extra_sections: list[tuple[str, str, str]] | None = None,
    ref: ReferenceWrench | None = None,
    design_text: str | None = None,
    maps_once: bool = False,
) -> str:
    try:
        from importlib.metadata import version

        ver = version("ppm-stiffness")
    except Exception:  # pragma: no cover - not installed
        ver = "unknown"
    stamp = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    planar = design.planar
    pose_txt = (
        f"x = {pose[0] * 1e3:.3f} mm, y = {pose[1] * 1e3:.3f} mm, "
        f"φ = {math.degrees(pose[5]):.3f}° (P in F<sub>b</sub>)"
        if planar
        else "(" + _esc(pose_text(design, pose)) + ") (P in F<sub>b</sub>)"
    )
    point = tables.reference_point(design)
    w = loaded["wrench"]
    wrench_txt = f"f = ({w[3]:g}, {w[4]:g}, {w[5]:g}) N, m = ({w[0]:g}, {w[1]:g}, {w[2]:g}) N·m"
    ref_txt = ref.text if ref is not None else wrench_txt
    if same_stiffness(unloaded, loaded):
        springs_loaded = (
            '<p class="note" id="springs-loaded-same">K under the wrench is the unloaded K '
            "(every actuator linear, the geometry frozen): its screw springs are those "
            "drawn above, not drawn again.</p>"
        )
    else:
        springs_loaded = _figure(
            spring_uris[1], "Screw springs under the wrench.", "fig-springs-loaded"
        )
    mech_caption = (
        f"Top view of the {_esc(design.architecture)} in F<sub>b</sub> "
        "[mm]: each leg's base rail (over the actuator stroke) or base pivot, its "
        "links and joints (R circle, P square with slider, C diamond with sleeve; "
        "the actuated joint ringed), the platform, P and the frames."
        if planar
        else spatial.mechanism_caption(design, pose)
    )
    mechanism = _figure(mech_uri, mech_caption, "fig-mechanism")
    if not planar:
        mechanism = spatial.pose_section(design, unloaded) + mechanism
    springs_where = "P" if point == "P" else "the tool point T"
    sections = [
        ("design", "Design parameters", tables.design_section(design, design_text, source)),
        ("mechanism", "The mechanism at the pose", mechanism),
        (
            "stiffness",
            "Cartesian stiffness matrix K (unloaded)",
            f"<p>w = K t at {point} with the axes of F<sub>b</sub>; t = (φ, u) [rad, m], "
            "w = (m, f) [N·m, N]. Blocks: K<sub>rr</sub> [N·m/rad], K<sub>rt</sub> [N], "
            "K<sub>tt</sub> [N/m]; actuators locked (compare eq. 22).</p>"
            + tables.stiffness_table(
                unloaded, "unloaded", "K, unloaded (units of each block above)"
            ),
        ),
        (
            "screw-springs",
            "Screw springs (eigenscrews, Table 4 and Fig. 5)",
            tables.springs_table(
                unloaded,
                "unloaded",
                f"Six screw springs of K (unloaded); position p relative to {springs_where}",
            )
            + _figure(
                spring_uris[0],
                "Screw springs: axes through p along e; helix right-handed "
                "for pitch &gt; 0, left-handed for pitch &lt; 0; colour and radius show k.",
                "fig-springs",
            ),
        ),
    ]
    if not planar:
        sections.append(
            (
                "principal",
                "Principal stiffnesses (C = K<sup>-1</sup>)",
                spatial.compliance_section(unloaded, "unloaded", point),
            )
        )
    sections += [
        (
            "decoupling",
            "Decoupling and principal stiffnesses (eq. 28–32)"
            if planar
            else "Decoupling (the least-squares shift; eq. 19 for comparison)",
            tables.decoupling_section(unloaded, "unloaded", cards=planar),
        ),
        (
            "loaded",
            f"Loaded case: {wrench_txt} (eq. 33–35, Table 5)",
            f'<p class="meta" id="reference-wrench">Reference wrench: {ref_txt}.</p>'
            + tables.loaded_section(design, loaded, unloaded)
            + (
                "<h3>Principal stiffnesses under the wrench</h3>"
                + tables.principal_cards(loaded, "loaded")
                if planar
                else spatial.twist_table(loaded, point)
                + "<h3>Principal stiffnesses under the wrench (C = K<sup>-1</sup>)</h3>"
                + spatial.compliance_cards(loaded, "loaded")
            )
            + tables.springs_table(loaded, "loaded", "Screw springs under the wrench (Table 5)")
            + springs_loaded
            + "<details><summary>Decoupling under the wrench</summary>"
            + tables.decoupling_section(loaded, "loaded", cards=planar)
            + "</details>",
        ),
        (
            "deflection",
            "Deflection curves (Figs. 9–10)" if planar else "Deflection under the wrench",
            _figure(
                defl_uri,
                "Platform deflection at the pose under a growing planar force "
                "(45°), moment m<sub>z</sub> and vertical force f<sub>z</sub>: with the "
                "actuators' law (eq. 20–21) in the loop (integrate) and with the unloaded, "
                "locked matrix (linear, as the paper's Fig. 10 model)."
                if planar
                else f"Deflection of {point} as the loaded case's wrench ({wrench_txt}) grows "
                "from zero to its full value (the load axis is the force's magnitude [N], "
                "the moment growing in proportion): with the actuators' law (eq. 20–21) in "
                "the loop (integrate) and with the unloaded, locked matrix (linear).",
                "fig-deflection",
            ),
        ),
    ]
    if map_figs:
        what = (
            "Principal stiffnesses k<sub>φ</sub>, k<sub>x</sub>, k<sub>y</sub> (eq. 19)"
            if planar
            else "Spatial principal stiffnesses (eigenvalues of C<sub>rr</sub><sup>-1</sup> "
            "and C<sub>tt</sub><sup>-1</sup>, ascending)"
        )
        sections.append(
            (
                "maps",
                "Stiffness maps (Figs. 6–7)" if planar else "Stiffness maps",
                f"<p>{what} over the reachable workspace, {grid} × {grid} grid.</p>"
                + (
                    '<p class="note" id="maps-once">Every actuator is linear (q = 1): its '
                    "stiffness at the maps' minimum state (eq. 20–21 under the reference "
                    "load) is its locked (maximum) one, so the two maps are the same "
                    "picture, shown once.</p>"
                    if maps_once
                    else ""
                )
                + "".join(
                    (
                        _figure(uri, caption, f"fig-map-{key}")
                        if uri
                        else f'<p class="note">{note}</p>'
                    )
                    + (note if uri else "")
                    for key, caption, uri, note in map_figs
                ),
            )
        )
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
    ref_note = {
        "scaled": " (the paper's load scaled to the design: see the loaded case)",
        "design file": " (the design file's [reference_wrench])",
        "paper": " (the paper's load)",
        "option": " (--wrench)",
    }.get(ref.source if ref is not None else "", "")
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>Stiffness report: {_esc(design.name)}</title><style>{_CSS}</style></head>"
        f"<body><main><h1>Stiffness report: {_esc(design.name)}</h1>"
        f'<p class="meta">{src}; pose {pose_txt}; loaded case {wrench_txt}{ref_note}.<br>'
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
