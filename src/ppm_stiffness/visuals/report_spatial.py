"""The report's sections for a spatial design (:mod:`ppm_stiffness.visuals.report`).

A spatial design (``design.planar`` False: a hexapod, a tripod) gets, beside the
sections every design has (parameters, mechanism, K, screw springs, decoupling, the
loaded case):

- the **pose** as a table: each of x, y, z, rx, ry, rz, whether it is a task coordinate
  or a parasitic one (imposed by the legs' constraints, :mod:`ppm_stiffness.poses`);
- the **spatial principal stiffnesses** (:mod:`ppm_stiffness.core.principal`, the
  ``principal_compliance`` block of ``analyze --json``) in place of the paper's planar
  k_phi, k_x, k_y: rotational from C_rr, translational from C_tt at the reference point
  of K (the tool point), the worst direction of each;
- the **deflection of the tool point under the loaded case's wrench** (the tool-point
  twist table, and the curve as the wrench grows, :data:`DEFLECTION_SCALES`);
- the stiffness maps (the spatial principal stiffnesses over the default slice of
  two task coordinates) are drawn by :mod:`ppm_stiffness.visuals.report`.

Every number cell carries ``data-path``/``data-scale`` into the embedded analyses, as
in the rest of the report.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.pose import ANGLE_COORDINATES, POSE_COORDINATES
from ppm_stiffness.design import Design
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.visuals.html import cell, esc, table, vector_cells

#: Scales of the loaded case's wrench along the deflection curve of a spatial design:
#: the load grows along the direction of that wrench (the report's reference wrench,
#: :mod:`ppm_stiffness.visuals.report_wrench`) from zero to its full value; the curve's
#: load axis is the force's magnitude [N].
DEFLECTION_SCALES = np.linspace(0.0, 1.0, 41)
#: Displayed unit and scale of each pose coordinate.
POSE_DISPLAY = {
    name: ("deg", 180 / math.pi) if name in ANGLE_COORDINATES else ("mm", 1e3)
    for name in POSE_COORDINATES
}


def mechanism_caption(design: Design, pose: ArrayLike) -> str:
    """The 3-D view's caption (HTML), naming only what this design has: its joint
    kinds (their records' words, in the order the legs meet them), rails, tool point."""
    from ppm_stiffness.visuals.leg_geometry import mechanism_view

    view = mechanism_view(design, pose)
    # each kind once, in the order the legs meet them from the base
    kinds = [joint_kind(k) for k in dict.fromkeys(j.kind for v in view.legs for j in v.joints)]
    rails = any(v.base.kind == "rail" for v in view.legs)
    return (
        f"3-D view of the {esc(design.architecture)} in F<sub>b</sub> [mm, equal scale]: "
        "the base polygon"
        + (", each leg's rail over the actuator stroke" if rails else "")
        + ", the legs' links and joints ("
        + ", ".join(record.caption for record in kinds)
        + "; the actuated joint ringed), the platform, its point P"
        + (", the tool point T" if view.has_tool else "")
        + " and the frames of F<sub>b</sub> and of the platform."
    )


def pose_section(design: Design, result: dict[str, Any], key: str = "unloaded") -> str:
    """The pose table: value, unit, and task or parasitic, of each coordinate."""
    task = set(design.task_coordinates)
    pose = result["pose"]
    rows = []
    for name in POSE_COORDINATES:
        unit, scale = POSE_DISPLAY[name]
        kind = "task" if name in task else "parasitic (imposed by the legs)"
        rows.append(
            [
                name,
                cell(pose[name], f"{key}/pose/{name}", scale=scale, sig=6, ref=1.0),
                unit,
                kind,
            ]
        )
    note = (
        "All six coordinates are task coordinates."
        if len(task) == 6
        else "The task coordinates ("
        + ", ".join(design.task_coordinates)
        + ") are given; the others follow from the legs' constraints (Newton, to "
        "1e-12 m and 1e-12 rad)."
    )
    return (
        table(
            ["coordinate", "value", "unit", "kind"],
            rows,
            "The pose of P in F<sub>b</sub> (R = R<sub>z</sub>(rz) R<sub>y</sub>(ry) "
            "R<sub>x</sub>(rx))",
            cls="params",
        )
        + f'<p class="meta">{esc(note)}</p>'
    )


def compliance_cards(result: dict[str, Any], key: str) -> str:
    """Cards of the worst rotational and translational stiffness (C = K⁻¹)."""
    base = f"{key}/principal_compliance"
    pc = result["principal_compliance"]
    out = ['<div class="cards">']
    for name, value, path, unit in (
        ("worst rotational", pc["worst_rotational"], f"{base}/worst_rotational", "N·m/rad"),
        (
            "worst translational",
            pc["worst_translational"],
            f"{base}/worst_translational",
            "N/m",
        ),
    ):
        c = cell(value, path).replace("<td", "<span").replace("</td>", "</span>")
        out.append(f'<div class="card"><div class="name">{name}</div>{c} {unit}</div>')
    out.append("</div>")
    return "".join(out)


def compliance_section(result: dict[str, Any], key: str, point: str) -> str:
    """The spatial principal stiffnesses: the definitions, the worst directions, and
    each value with its direction (``point``: where K is given, in words)."""
    pc = result["principal_compliance"]
    rows = []
    for blk, unit in (("rotational", "N·m/rad"), ("translational", "N/m")):
        dirs = np.asarray(pc[blk]["directions"], dtype=float)
        for j in range(3):
            p = f"{key}/principal_compliance/{blk}"
            rows.append(
                [
                    f"{blk} {j + 1}",
                    cell(pc[blk]["values"][j], f"{p}/values/{j}"),
                    unit,
                    *vector_cells(dirs[j], f"{p}/directions/{j}"),
                ]
            )
    text = (
        "<p>From the compliance C = K<sup>-1</sup> at "
        f"{point}: <b>rotational</b>, the eigen-pairs of C<sub>rr</sub><sup>-1</sup> (the "
        "stiffness against a pure moment with the platform free to translate; it does not "
        "depend on the reference point); <b>translational</b>, the eigen-pairs of "
        f"C<sub>tt</sub><sup>-1</sup> at {point} (the stiffness against a force applied "
        "there with the platform free to rotate); <b>worst</b>, 1/λ<sub>max</sub> of each "
        "block, the least stiff direction. The decoupling below is a separate output.</p>"
    )
    return (
        text
        + compliance_cards(result, key)
        + table(
            ["principal", "stiffness", "unit", "dir x", "dir y", "dir z"],
            rows,
            caption="Principal stiffnesses from C = K<sup>-1</sup> and their directions "
            "(axes of F<sub>b</sub>)",
        )
    )


def twist_table(loaded: dict[str, Any], point: str) -> str:
    """The deflection (twist) of the reference point under the wrench [deg, mm], the
    CLI's units (``analyze --wrench``)."""
    t = np.asarray(loaded["twist"], dtype=float)
    scales = [180 / math.pi] * 3 + [1e3] * 3
    ref = float(np.max(np.abs(t)))
    cells = [cell(t[j], f"loaded/twist/{j}", scale=scales[j], sig=4, ref=ref) for j in range(6)]
    return table(
        [
            "φ<sub>x</sub> [deg]",
            "φ<sub>y</sub> [deg]",
            "φ<sub>z</sub> [deg]",
            "x [mm]",
            "y [mm]",
            "z [mm]",
        ],
        [cells],
        caption=f"Deflection of {point} under the wrench (twist, axes of F<sub>b</sub>; the "
        "actuators' law in the loop)",
    )


def deflection_curves(design: Design, pose: ArrayLike, wrench: ArrayLike) -> list[Any]:
    """The tool point's deflection as ``wrench`` grows from zero to its full value
    (:data:`DEFLECTION_SCALES` of it), with the actuators' law integrated along the path
    and with the unloaded, locked matrix (:func:`ppm_stiffness.statics.deflection
    .deflection_path`, mode ``"direction"``: the load is the magnitude of the force
    [N], or of the moment [N·m] for a pure moment, :func:`~ppm_stiffness.statics
    .deflection.direction_wrench`)."""
    from ppm_stiffness.statics.deflection import DIRECTION, deflection_path, direction_wrench

    unit = direction_wrench(wrench)
    full = float(np.linalg.norm(np.asarray(wrench, dtype=float)[3:]))
    full = full if full > 0 else float(np.linalg.norm(np.asarray(wrench, dtype=float)[:3]))
    return [
        deflection_path(design, unit, DEFLECTION_SCALES * full, pose, mode=DIRECTION, method=m)
        for m in ("integrate", "linear")
    ]


__all__ = [
    "DEFLECTION_SCALES",
    "compliance_cards",
    "compliance_section",
    "deflection_curves",
    "mechanism_caption",
    "pose_section",
    "twist_table",
]
