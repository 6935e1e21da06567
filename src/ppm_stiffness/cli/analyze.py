"""``ppm-stiffness analyze``: K, screw springs, decoupling, principal stiffnesses."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ppm_stiffness.cli.common import (
    POSE_OPTIONS,
    actuator_stiffness_text,
    add_design_argument,
    add_pose_arguments,
    add_safety_factor_argument,
    add_tool_point_argument,
    add_wrench_argument,
    console,
    eng,
    load_design_arg,
    parse_wrench,
    pose_from_args,
    read_matrix_csv,
    tool_point_from_args,
)
from ppm_stiffness.cli.tolerances import (
    add_tolerance_arguments,
    check_tolerance_options,
    pose_uncertainty,
    print_pose_uncertainty,
    read_tolerance_args,
)
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.names import ANGLE_COORDINATES, POSE_COORDINATES
from ppm_stiffness.leading import lead, leading_keys

if TYPE_CHECKING:  # pragma: no cover - the type only: `analyze --help` stays light
    import numpy as np
    from rich.table import Table


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_argument(parser)
    add_pose_arguments(parser)
    add_wrench_argument(parser)
    add_tool_point_argument(parser)
    add_tolerance_arguments(parser)
    parser.add_argument(
        "--matrix",
        metavar="FILE.csv",
        help="analyse this 6x6 stiffness matrix (SI, order phi_x,phi_y,phi_z,x,y,z) "
        "instead of a design",
    )
    parser.add_argument(
        "--method",
        "--decoupling",
        dest="method",
        choices=("paper", "least-squares"),
        default=None,
        help="decoupling shown first (default: the paper's eq. 19 for a planar design or "
        "a --matrix, the least-squares shift for a spatial design, whose tables lead with "
        "the spatial principal stiffnesses; 'paper' shows eq. 19 and k_phi, k_x, k_y "
        "first there too)",
    )
    parser.add_argument(
        "--geometry",
        choices=("frozen", "moving"),
        default="frozen",
        help="under --wrench: 'frozen' keeps the geometry of the unloaded pose (the "
        "paper's model, default); 'moving' solves the equilibrium with the platform and "
        "legs displaced and gives the loaded tangent K_F, its difference from the frozen "
        "K and the load margin",
    )
    add_safety_factor_argument(
        parser,
        "the hinge table (stress, utilisation, range of motion; default 1: the range to yield)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI)")


def run(args: argparse.Namespace) -> int:
    # imported here, not at the top: ``analyze --help`` stays light
    from ppm_stiffness.analysis import ANALYSIS_UNITS, analyze_design, analyze_matrix, json_document
    from ppm_stiffness.core.inputs import PRINTED_SYMMETRY_TOLERANCE, validate_stiffness_matrix
    from ppm_stiffness.model import check_nonsingular

    if args.matrix is not None:
        check_tolerance_options(args)  # without --tolerances: neither method nor samples
        if (
            args.design is not None
            or args.wrench is not None
            or args.geometry != "frozen"
            or args.safety_factor is not None
            or any(
                getattr(args, k) is not None for k in (*POSE_OPTIONS, "tool_point", "tolerances")
            )
        ):
            raise InputDataError(
                "--matrix cannot be combined with --design, a pose ("
                + ", ".join(f"--{k}" for k in POSE_OPTIONS)
                + "), --wrench, --tool-point, --geometry, --safety-factor or --tolerances"
            )
        k = validate_stiffness_matrix(
            read_matrix_csv(args.matrix), args.matrix, PRINTED_SYMMETRY_TOLERANCE
        )
        check_nonsingular(k, f" ({args.matrix})")
        result: dict[str, Any] = {"pose": None, "actuator_stiffness": None}
        result.update(analyze_matrix(k, args.method or "paper").to_dict())
        result.update(leading_keys(True, args.method), planar=None)  # a matrix: kind unknown
        title = f"matrix {args.matrix}"
    else:
        design = load_design_arg(args)
        pose = pose_from_args(args, design)
        variables = read_tolerance_args(args, design)
        wrench, tool = parse_wrench(args.wrench), tool_point_from_args(args, design)
        if args.geometry == "moving" and wrench is None:
            raise InputDataError(
                "--geometry moving needs a --wrench: the geometry moves under a load"
            )
        if args.geometry == "moving" and variables is not None:
            raise InputDataError("--tolerances works with the frozen geometry only")
        result = analyze_design(design, pose, wrench, args.method, tool, args.geometry).to_dict()
        if variables is not None:
            result["uncertainty"] = pose_uncertainty(args, design, variables, pose, tool, wrench)
        hinges = hinge_table(design, pose, wrench, tool, args.safety_factor)
        if hinges is not None:
            result["hinge_stress"] = hinges
        title = design.name
    if args.json:
        print(json_document("analyze", lead(result), ANALYSIS_UNITS))
    else:
        print_tables(result, title)
        if "uncertainty" in result:
            print_pose_uncertainty(result["uncertainty"])
        if "hinge_stress" in result:
            print_hinge_table(result["hinge_stress"])
    return 0


def _clean(m: Any) -> np.ndarray:
    """Round-off (below 1e-10 of the largest entry) shown as 0."""
    import numpy as np

    a = np.asarray(m, dtype=float)
    return np.where(np.abs(a) < 1e-10 * max(np.max(np.abs(a)), 1e-300), 0.0, a)


def _matrix_table(title: str, m: Any, labels: tuple[str, ...], digits: int = 4) -> Table:
    """A square matrix with labelled rows and columns, entries in engineering notation."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    t = Table(title=escape(title), title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False)
    t.add_column("")
    for lab in labels:
        t.add_column(lab, justify="right")
    for lab, row in zip(labels, _clean(m), strict=True):
        t.add_row(lab, *(eng(v, digits) for v in row))
    return t


def _coordinates(pose: dict[str, float], names: Any) -> str:
    """``x = 1.000 mm, rx = 2.000 deg, ...`` of the named pose coordinates."""
    import numpy as np

    return ", ".join(
        f"{n} = {np.degrees(pose[n]):.4f} deg"
        if n in ANGLE_COORDINATES
        else f"{n} = {pose[n] * 1e3:.4f} mm"
        for n in names
    )


def _vec(v: Any, digits: int = 4) -> str:
    return " ".join(f"{x + 0.0:+.{digits}f}" for x in _clean(v))


def print_tables(result: dict[str, Any], title: str) -> None:
    """Readable tables of an analysis dict (see :mod:`ppm_stiffness.analysis`)."""
    import numpy as np
    from rich.markup import escape
    from rich.table import Table

    from ppm_stiffness.core.conventions import TWIST_COMPONENTS

    c = console
    c.print(f"[bold]{escape(title)}[/bold]")
    if result["pose"] is not None:
        p = result["pose"]
        task = result.get("task_coordinates", ["x", "y", "rz"])
        if list(task) == ["x", "y", "rz"]:
            c.print(
                f"pose: x = {p['x'] * 1e3:.3f} mm, y = {p['y'] * 1e3:.3f} mm, "
                f"phi = {np.degrees(p['phi']):.3f} deg (P in F_b)"
            )
        else:
            c.print(f"pose (P in F_b, R = Rz Ry Rx): {_coordinates(p, task)}")
            others = [n for n in POSE_COORDINATES if n not in task]
            if others:
                c.print(f"  completed by the legs (parasitic motion): {_coordinates(p, others)}")
        units = result.get("actuator_units") or [["N", "m", "N/m"]] * len(
            result["actuator_stiffness"]
        )
        k_act = ", ".join(
            actuator_stiffness_text(v, ".6g", u[2])
            for v, u in zip(result["actuator_stiffness"], units, strict=True)
        )
        c.print(f"architecture: {result.get('architecture', '')}; actuator stiffness: {k_act}")
        tool = result.get("tool_point", [0.0, 0.0, 0.0])
        if any(tool):
            c.print(
                "tool point T (platform frame): ({:.3f}, {:.3f}, {:.3f}) mm; results "
                "below are at T".format(*(1e3 * np.asarray(tool)))
            )
    if "wrench" in result:
        w = result["wrench"]
        c.print(
            "wrench: f = ({:.4g}, {:.4g}, {:.4g}) N, m = ({:.4g}, {:.4g}, {:.4g}) N·m".format(
                *w[3:], *w[:3]
            )
        )
        units = result["actuator_units"]
        forces = ", ".join(
            f"{v:.4g} {u[0]}" for v, u in zip(result["actuator_forces"], units, strict=True)
        )
        disp = ", ".join(
            f"{v * 1e3:.4g} mm" if u[1] == "m" else f"{np.degrees(v):.4g} deg"
            for v, u in zip(result["actuator_displacements"], units, strict=True)
        )
        c.print(f"actuator forces: {forces}; displacements: {disp}")
        t = result["twist"]  # deg and mm, as every CLI table (docs/conventions.md)
        c.print(
            "deflection: rotation ({:.4g}, {:.4g}, {:.4g}) deg, displacement "
            "({:.4g}, {:.4g}, {:.4g}) mm".format(
                *np.degrees(np.asarray(t[:3]) + 0.0), *(1e3 * np.asarray(t[3:]) + 0.0)
            )
        )
        print_geometry(result)
    if "first_frequency" in result:
        share = result.get("first_mode_platform_share")
        carried = "" if share is None else f"; the platform's kinetic energy {100 * share:.3g} %"
        c.print(
            f"first natural frequency: {result['first_frequency']:.4g} Hz "
            f"({result['first_mode_direction']}{carried}); `ppm-stiffness modes` gives all six"
        )
    k = np.asarray(result["stiffness_matrix"])
    at = "T" if any(result.get("tool_point") or []) else "P"
    what = f"Cartesian stiffness K at {at}"
    if result.get("geometry") == "moving":
        what = f"Symmetric part of K_F at the displaced {at}"
    c.print(
        _matrix_table(
            f"{what}, axes of F_b: w = K t, t = (phi, u) "
            "[rad, m], w = (m, f) [N·m, N]; blocks K_rr [N·m/rad], K_rt [N], "
            "K_tt [N/m]",
            k,
            TWIST_COMPONENTS,
        )
    )
    springs = result["eigenscrews"]
    s = Table(
        title="Screw springs: eigenscrews of K zeta = lambda Gamma zeta (eq. 5-11)",
        title_justify="left",
    )
    for col in ("spring", "lambda [N]", "eigenforce [N]", "k [N/m]", "pitch [m/rad]"):
        s.add_column(escape(col), justify="right")
    for i, sc in enumerate(springs, start=1):
        s.add_row(
            f"s{i}",
            eng(sc["eigenvalue"], 5),
            eng(sc["eigenforce"], 5),
            eng(sc["spring_constant"], 5),
            eng(sc["pitch"], 4),
        )
    c.print(s)
    g = Table(title="Screw springs: axes and positions (F_b)", title_justify="left")
    for col in ("spring", "axis e", "position p [mm]"):
        g.add_column(escape(col), justify="right")
    for i, sc in enumerate(springs, start=1):
        g.add_row(f"s{i}", _vec(sc["axis"]), _vec(1e3 * np.asarray(sc["position"]), 2))
    c.print(g)
    groups = result.get("eigenscrews_repeated") or []
    if groups:
        names = "; ".join(", ".join(f"s{i + 1}" for i in grp) for grp in groups)
        c.print(
            f"note: repeated eigenvalues ({escape(names)}): inside each group the screw "
            "springs are not unique; shown: those whose axes are closest to x, y, z"
        )

    pc = result.get("principal_compliance")
    if pc is not None:
        at = "T" if any(result.get("tool_point") or []) else "P"
        pt = Table(
            title=f"Principal stiffnesses from C = K^-1 (translational at {at})",
            title_justify="left",
        )
        for col in ("", "value", "direction"):
            pt.add_column(col, justify="right")
        for name, block, unit in (
            ("rot", "rotational", "N·m/rad"),
            ("trans", "translational", "N/m"),
        ):
            for j in range(3):
                pt.add_row(
                    f"{name} {j + 1}",
                    f"{eng(pc[block]['values'][j], 5)} {unit}",
                    _vec(np.asarray(pc[block]["directions"])[j]),
                )
        c.print(pt)
        c.print(
            f"worst directions: {eng(pc['worst_rotational'], 5)} N·m/rad against a pure "
            f"moment, {eng(pc['worst_translational'], 5)} N/m against a force at {at}"
        )

    order = [("decoupling", "principal"), ("decoupling_least_squares", "principal_least_squares")]
    if result.get("method") == "least-squares":
        order.reverse()
    spatial = result.get("planar") is False
    if spatial and not result.get("paper_definitions"):
        order = order[:1]  # eq. (19) and its planar k_phi, k_x, k_y on request only
    for key, pkey in order:
        _print_decoupling(result, key, pkey, spatial)
    if spatial and not result.get("paper_definitions"):
        dec = result["decoupling"]
        res = "n/a" if dec["already_decoupled"] else f"{dec['residual_coupling']:.4f}"
        c.print(
            "the paper's eq. (19) decoupling and its planar k_phi, k_x, k_y (residual "
            f"coupling {res}): --method paper"
        )


def _print_decoupling(result: dict[str, Any], key: str, pkey: str, spatial: bool) -> None:
    """One decoupling (``key``) and its principal stiffnesses (``pkey``)."""
    import numpy as np
    from rich.table import Table

    c = console
    dec, pr = result[key], result[pkey]
    c.print(f"[bold]Decoupling, method '{dec['method']}'[/bold]")
    c.print(_matrix_table("M [N/m] (eq. 19)", dec["M"], ("x", "y", "z")))
    c.print(f"d \\[mm] = {_vec(1e3 * np.asarray(dec['d']), 2)}")
    if dec["already_decoupled"]:  # K_rt below core.decoupling.DECOUPLED_TOLERANCE
        c.print("residual coupling: n/a (already decoupled: K_rt is round-off)")
    else:
        c.print(f"residual coupling ||K_rt + D K_tt|| / ||K_rt|| = {dec['residual_coupling']:.4f}")
    c.print(_matrix_table("K'_rr [N·m/rad]", dec["K_rr"], ("phi_x", "phi_y", "phi_z")))
    c.print(_matrix_table("K'_tt [N/m]", dec["K_tt"], ("x", "y", "z")))
    pt = Table(title="Principal stiffnesses and directions", title_justify="left")
    for col in ("", "value", "direction"):
        pt.add_column(col, justify="right")
    for name, block, unit in (
        ("rot", "rotational", "N·m/rad"),
        ("trans", "translational", "N/m"),
    ):
        vals = pr[block]["values"]
        dirs = np.asarray(pr[block]["directions"])
        for j in range(3):
            pt.add_row(f"{name} {j + 1}", f"{eng(vals[j], 5)} {unit}", _vec(dirs[j]))
    c.print(pt)
    if key == "decoupling":
        r, tr = pr["rotational"]["values"], pr["translational"]["values"]
        c.print(
            f"k_phi = {eng(r[2], 5)} N·m/rad, k_x = {eng(tr[0], 5)} N/m, "
            f"k_y = {eng(tr[1], 5)} N/m (paper's "
            + ("planar definitions, of a spatial design)" if spatial else "definitions)")
        )


def print_geometry(result: dict[str, Any]) -> None:
    """Which statics model a loaded analysis used and, with moving geometry, the
    displaced pose, K_F, its difference from the frozen K and the load margin."""
    from rich.markup import escape

    from ppm_stiffness.core.conventions import TWIST_COMPONENTS

    c = console
    if result.get("geometry") != "moving":
        c.print(
            "geometry: frozen (the paper's model: the geometry of the unloaded pose; "
            "--geometry moving lets it move under the load)"
        )
        return
    mg = result["moving_geometry"]
    at = "T" if any(result.get("tool_point") or []) else "P"
    c.print(
        f"geometry: moving (equilibrium with the platform and legs displaced, "
        f"{mg['load_steps']} load step(s), {mg['newton_iterations']} Newton iterations); "
        f"K_F at the displaced {at}"
    )
    c.print(f"displaced pose (P in F_b): {_coordinates(mg['displaced_pose'], POSE_COORDINATES)}")
    c.print(
        _matrix_table(
            f"Loaded tangent stiffness K_F at the displaced {at}, axes of F_b "
            "(dw = K_F dt; K_rr [N·m/rad], K_rt [N], K_tt [N/m])",
            mg["stiffness_matrix"],
            TWIST_COMPONENTS,
        )
    )
    c.print(
        _matrix_table(
            "K_F - K (frozen geometry, same load) [N·m/rad, N, N/m]",
            mg["difference"],
            TWIST_COMPONENTS,
        )
    )
    c.print(
        f"K_F differs from the frozen K by {100 * mg['relative_difference']:.4g} %; its "
        f"geometric term is {100 * mg['relative_geometric']:.4g} % of K_F; its "
        f"antisymmetric part {100 * mg['asymmetry']:.3g} % (length-balanced Frobenius norms)"
    )
    c.print(f"load margin: {escape(mg['load_margin']['description'])}")


def hinge_table(
    design: Any, pose: Any, wrench: Any, tool: Any, safety_factor: float | None
) -> dict[str, Any] | None:
    """The hinge stress and range of a design with notch hinges (frozen, linear;
    :func:`ppm_stiffness.statics.hinge_stress.hinge_summary`), the wrench moved from the
    tool point to P; None without hinges or without every hinge's yield strength
    (``--safety-factor`` then refused)."""
    import numpy as np

    from ppm_stiffness.model import full_pose, tool_offset
    from ppm_stiffness.statics.hinge_stress import (
        has_hinges,
        has_yield_strengths,
        hinge_summary,
    )

    if not has_hinges(design):
        if safety_factor is not None:
            raise InputDataError(
                "--safety-factor: the design has no notch hinge (a joint's hinge table)"
            )
        return None
    if not has_yield_strengths(design):  # no stress limit: no range of motion
        if safety_factor is not None:
            raise InputDataError("--safety-factor: a notch hinge's material has no yield_strength")
        return None
    sf = 1.0 if safety_factor is None else safety_factor
    if not (np.isfinite(sf) and sf > 0.0):
        raise InputDataError(f"--safety-factor {sf:g}: must be a positive number")
    at_p = None
    if wrench is not None:
        offset = tool_offset(full_pose(design, pose), tool)
        at_p = np.concatenate([wrench[:3] + np.cross(offset, wrench[3:]), wrench[3:]])
    return hinge_summary(design, pose, at_p, sf)


def print_hinge_table(data: dict[str, Any]) -> None:
    """Two tables: the stage's range of motion along each input direction (the first
    hinge to reach yield / SF), and each hinge's allowed stress, its smallest range over
    the drives and, under a wrench, its stress and utilisation."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    sf = data["safety_factor"]
    t = Table(
        title=escape(f"Range of motion (notch hinges, frozen, linear; yield / SF, SF = {sf:g})"),
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    for name in ("input", "range (±)", "limiting hinge"):
        t.add_column(name, justify="right" if name == "range (±)" else "left")
    for d in data["directions"]:
        t.add_row(d["name"], f"{eng(d['range'])} {d['unit']}", d["limiting_hinge"])
    console.print(t)
    console.print(
        "  a drive's input is its free displacement (the others held); a platform "
        "direction is made by the drives, the other task coordinates held at 0"
    )
    drives = [d for d in data["directions"] if d["name"].startswith("drive")]
    loaded = "stress" in data["hinges"][0]
    h = Table(
        title="Hinges: allowed stress, range (smallest over the drives), under the wrench",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    h.add_column("hinge", no_wrap=True)
    h.add_column("allowed MPa", justify="right")
    if drives:
        h.add_column(f"drives {drives[0]['unit']}", justify="right")
    if loaded:
        for name in ("stress MPa", "util.", "x wrench"):
            h.add_column(name, justify="right")
    for row in data["hinges"]:
        cells = [f"leg{row['leg']}.{row['name']}", f"{row['allowed_stress'] / 1e6:.4g}"]
        if drives:
            cells.append(eng(min(row["range"][d["name"]] for d in drives)))
        if loaded:
            cells += [
                f"{row['stress'] / 1e6:.4g}",
                eng(row["utilisation"]),
                eng(row["wrench_range"]),
            ]
        h.add_row(*cells)
    console.print(h)
