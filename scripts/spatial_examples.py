"""Write the spatial example designs (examples/hexapod_6ups.toml, 3prs.toml, 3rps.toml).

Every number comes from a stated dimension or catalogue-class estimate below: the
section properties from the tube and rod dimensions, the joints' mounting axes from the
home geometry (each joint is mounted along its link at the home pose, as hexapod and
tripod joints are, so that the home pose sits in the middle of the joints' angular
range). Run from the repository's top folder:

    python scripts/spatial_examples.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from example_masses import (
    ALUMINIUM as ALUMINIUM_DENSITY,
)
from example_masses import (
    STEEL as STEEL_DENSITY,
)
from example_masses import (
    bar,
    block,
    composite,
    disk_mass,
    rounded,
    tube_area,
)

ROOT = Path(__file__).resolve().parents[1]

STEEL = (210e9, 81e9)  # E, G [Pa], handbook
ALUMINIUM = (69e9, 26e9)


def tube(outer: float, wall: float, material: tuple[float, float]) -> dict[str, float]:
    """Section of a round tube (outer diameter, wall [m]); a solid rod if wall = outer / 2."""
    ro, ri = outer / 2, outer / 2 - wall
    area = math.pi * (ro**2 - ri**2)
    inertia = math.pi / 4 * (ro**4 - ri**4)
    return {
        "young_modulus": material[0],
        "shear_modulus": material[1],
        "area": area,
        "torsion_constant": 2 * inertia,
        "inertia_y": inertia,
        "inertia_z": inertia,
    }


def fmt(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "0.0" if abs(value) < 1e-12 else repr(float(f"{value:.15g}"))
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(fmt(v) for v in value) + "]"
    if isinstance(value, str):
        return f'"{value}"'
    raise TypeError(value)


def table(name: str, data: dict[str, object], comment: str = "") -> str:
    head = f"[{name}]\n" if not name.startswith("[[") else f"{name}\n"
    lines = [f"# {line}\n" for line in comment.splitlines()] if comment else []
    return "".join(lines) + head + "".join(f"{k} = {fmt(v)}\n" for k, v in data.items()) + "\n"


def unit(v: np.ndarray) -> list[float]:
    return [float(x) for x in v / np.linalg.norm(v)]


def polar(radius: float, angle_deg: float, z: float = 0.0) -> np.ndarray:
    a = math.radians(angle_deg)
    return np.array([radius * math.cos(a), radius * math.sin(a), z])


def hexapod() -> str:
    r_base, r_platform, home_z = 0.150, 0.100, 0.200
    half = 12.0  # half the angular gap of a joint pair [deg]
    header = f"""# A precision positioning hexapod (Gough-Stewart platform, 6-UPS), built from
# catalogue-class parts (estimates of the right order, not one vendor's values):
# - geometry: base U joints on a {r_base * 1e3:.0f} mm circle in pairs at 0, 120, 240 deg
#   (+-{half:.0f} deg); platform S joints on a {r_platform * 1e3:.0f} mm circle in pairs at
#   60, 180, 300 deg (+-{half:.0f} deg); each leg joins a base joint to the nearer platform
#   joint of the next pair (36 deg apart), home height {home_z * 1e3:.0f} mm (P at the
#   centre of the platform joint circle);
# - struts: ball-screw actuators, cylinder (motor and housing) 140 mm, aluminium tube
#   40 x 3 mm; rod steel tube 20 x 2 mm; leg length stroke 175-265 mm;
# - actuator: 12 x 2 mm preloaded ball screw, shaft EA/L (10 mm root, ~0.15 m: 1.1e8 N/m)
#   in series with nut (~1e8 N/m) and support bearings (~1e8 N/m): 3.4e7 N/m, linear;
# - the rod's bushing in the cylinder (the prismatic joint's springs): lateral 2e7 N/m,
#   tilt 1e3 N·m/rad, anti-rotation 200 N·m/rad;
# - base universal joints: radial and axial 5e7 N/m, torsion 300 N·m/rad, +-30 deg;
# - platform spherical joints (precision ball joints): 4e7 N/m, +-25 deg;
# - joints mounted along their leg at the home pose (mounting axes below);
# - masses (docs/dynamics.md): densities 2700 kg/m^3 (aluminium), 7850 kg/m^3 (steel)
#   times the dimensions; the platform an aluminium disk 240 x 12 mm with six ball
#   joints (~50 g each), as a cylinder; the cylinder body: its tube, the 12 mm screw
#   inside it (140 mm) and a motor of ~0.35 kg (estimated) 20 mm from the U joint; the
#   rod: the steel tube, 185 mm long (125 mm free at the longest stroke, 60 mm engaged),
#   with the ball nut (~80 g) at its inner end, fixed to the S joint; no rotor (the
#   screw and nut are the drive's compliance, the motor held by its position loop).
# Section and mass properties computed from the dimensions by scripts/spatial_examples.py.
schema = 2
name = "6-UPS precision positioning hexapod (examples/hexapod_6ups.toml)"
task_coordinates = ["x", "y", "z", "rx", "ry", "rz"]
tool_point = [0.0, 0.0, 0.0]

"""
    out = header
    out += table(
        "workspace",
        {"centre_x": 0.0, "centre_y": 0.0, "centre_z": home_z, "rx": 0.0, "ry": 0.0, "phi": 0.0},
        "The home pose: x, y, z [m], rx, ry, phi (= rz) [rad].",
    )
    out += table(
        "workspace.required",
        {
            "x": [-0.01, 0.01],
            "y": [-0.01, 0.01],
            "z": [home_z - 0.01, home_z + 0.01],
            "rx": [-0.05, 0.05],
            "ry": [-0.05, 0.05],
            "rz": [-0.05, 0.05],
            "grid": [3, 3, 3, 3, 3, 3],
        },
        "The required region (SI: m, rad), a grid over the six task coordinates in order.",
    )
    out += table(
        "workspace.candidate",
        {
            "x": [-0.04, 0.04],
            "y": [-0.04, 0.04],
            "z": [home_z - 0.04, home_z + 0.04],
            "rx": [-0.15, 0.15],
            "ry": [-0.15, 0.15],
            "rz": [-0.15, 0.15],
            "grid": [5, 5, 5, 3, 3, 3],
        },
        "A larger candidate region (SI: m, rad): `optimize --objective reachable-workspace`\n"
        "counts the share of its grid poses reached (docs/optimization.md).",
    )
    out += table(
        "platform",
        {
            "mass": round(disk_mass(0.12, 0.012, ALUMINIUM_DENSITY) + 6 * 0.05, 3),
            "shape": "cylinder",
            "radius": 0.12,
            "height": 0.012,
        },
    )
    out += table(
        "parts.actuator",
        {"locked_stiffness": 3.4e7, "k_a": 3.4e7, "q": 1.0, "threshold_displacement": 0.0},
    )
    out += table(
        "parts.guide",
        {"roll": 200.0, "pitch": 1000.0, "yaw": 1000.0, "lateral": 2e7, "vertical": 2e7},
    )
    cylinder_body = composite(
        [
            bar(0.14, tube_area(0.040, 0.003), ALUMINIUM_DENSITY),
            bar(0.14, tube_area(0.012, 0.006), STEEL_DENSITY),
            block(0.35, 0.02, 0.042),
        ]
    )
    rod_body = composite(
        [bar(0.185, tube_area(0.020, 0.002), STEEL_DENSITY), block(0.08, 0.185, 0.02)]
    )
    out += table("parts.cylinder", {**tube(0.040, 0.003, ALUMINIUM), **rounded(cylinder_body)})
    out += table(
        "parts.rod",
        {**tube(0.020, 0.002, STEEL), **rounded({**rod_body, "mass_centre_from": "end"})},
    )
    out += table(
        "parts.base_joint",
        {"radial": 5e7, "axial": 5e7, "torsion": 300.0, "max_angle": math.radians(30.0)},
    )
    out += table(
        "parts.platform_joint", {"axial": 4e7, "radial": 4e7, "max_angle": math.radians(25.0)}
    )
    for k in range(3):
        for side in (1, -1):
            a = polar(r_base, 120 * k + side * half)
            b = polar(r_platform, 120 * k + side * (60 - half))
            n = b + np.array([0, 0, home_z]) - a
            out += table(
                "[[legs]]",
                {
                    "type": "UPS",
                    "base_point": [float(v) for v in a],
                    "platform_point": [float(v) for v in b],
                    "cylinder_length": 0.14,
                    "stroke": [0.175, 0.265],
                    "base_joint_axis": unit(n),
                    "platform_joint_axis": unit(-n),
                },
            )
    return out


def spindle_head() -> dict[str, object]:
    """The 3-PRS head as one rigid body: an aluminium plate 360 x 20 mm centred at P, a
    spindle unit (8 kg, a 90 x 250 mm cylinder from 150 mm below P up), three spherical
    joints (0.3 kg each) on the 150 mm circle; mass, centre and inertia about it."""
    bodies = []  # (mass, centre (3,), inertia about its own centre (3, 3))
    plate = disk_mass(0.18, 0.02, ALUMINIUM_DENSITY)
    bodies.append((plate, np.zeros(3), cylinder(plate, 0.18, 0.02)))
    bodies.append((8.0, np.array([0.0, 0.0, -0.15 + 0.125]), cylinder(8.0, 0.045, 0.25)))
    for angle in (90.0, 210.0, 330.0):
        bodies.append((0.3, polar(0.15, angle), np.zeros((3, 3))))
    mass = sum(m for m, _, _ in bodies)
    centre = sum(m * c for m, c, _ in bodies) / mass
    inertia = np.zeros((3, 3))
    for m, c, i in bodies:
        d = c - centre
        inertia += i + m * (d @ d * np.eye(3) - np.outer(d, d))
    inertia[np.abs(inertia) < 1e-12] = 0.0
    return {
        "mass": round(mass, 4),
        "centre_of_mass": [round(float(v), 6) + 0.0 for v in centre],
        "inertia": [[float(f"{v:.4g}") for v in row] for row in inertia],
    }


def cylinder(mass: float, radius: float, height: float) -> np.ndarray:
    """Inertia (3, 3) of a solid cylinder about its centre, axis along z."""
    transverse = mass * (3 * radius**2 + height**2) / 12
    return np.diag([transverse, transverse, mass * radius**2 / 2])


def tripod(kind: str) -> str:
    if kind == "PRS":
        r_base, r_platform, link, home_z = 0.30, 0.15, 0.45, 0.40
        header = f"""# A 3-PRS spindle head (the tripod of the Sprint Z3 class, scaled down), built
# from catalogue-class parts (estimates of the right order, not one vendor's values):
# - geometry: three vertical rails on a {r_base * 1e3:.0f} mm circle at 90, 210, 330 deg,
#   carriages above the platform (branch -1); revolute axes tangential; links 450 mm;
#   platform S joints on a {r_platform * 1e3:.0f} mm circle at the same angles; home height of P
#   {home_z * 1e3:.0f} mm; the spindle nose (tool point) 150 mm below P;
# - rails: two size-35 linear guide blocks per carriage (the guide's springs): lateral
#   8e8 N/m, vertical 1e9 N/m, roll 2e4, pitch and yaw 3e4 N·m/rad;
# - actuator: 32 x 10 mm ball screw with preloaded nut, ~1e8 N/m in series, linear;
# - carriage revolute: a pair of angular-contact bearings, radial 5e8, axial 3e8 N/m,
#   tilt 1e5 N·m/rad;
# - links: steel tube 60 x 5 mm;
# - platform spherical joints: 3e8 N/m, +-35 deg, mounted along the link at home;
# - masses (docs/dynamics.md; steel 7850, aluminium 2700 kg/m^3 times the dimensions,
#   the rest estimated): the head an aluminium plate 360 x 20 mm, a spindle unit of
#   ~8 kg (a 90 x 250 mm cylinder from the nose 150 mm below P) and three spherical
#   joints of ~0.3 kg, as one rigid body (its inertia computed); the links uniform steel
#   tubes; each carriage two guide blocks (~1.5 kg each), a plate (~2 kg), the
#   revolute's housing and bearings (~1 kg) and the ball nut (~0.8 kg): 6.8 kg; no rotor
#   (the screw and nut are the drive's compliance).
# Task coordinates (z, rx, ry): x, y and rz follow from the revolutes (parasitic motion).
# Section and mass properties computed from the dimensions by scripts/spatial_examples.py.
schema = 2
name = "3-PRS spindle head (examples/3prs.toml)"
task_coordinates = ["z", "rx", "ry"]
tool_point = [0.0, 0.0, -0.15]

"""
        region = {
            "z": [home_z - 0.05, home_z + 0.05],
            "rx": [-0.35, 0.35],
            "ry": [-0.35, 0.35],
            "grid": [5, 7, 7],
        }
    else:
        r_base, r_platform, home_z = 0.25, 0.15, 0.35
        header = f"""# A 3-RPS tilting table, built from catalogue-class parts (estimates of the
# right order, not one vendor's values):
# - geometry: base revolutes on a {r_base * 1e3:.0f} mm circle at 90, 210, 330 deg with
#   tangential axes; platform S joints on a {r_platform * 1e3:.0f} mm circle at the same angles;
#   home height of P {home_z * 1e3:.0f} mm;
# - struts: ball-screw actuators, cylinder 250 mm (aluminium tube 50 x 4 mm), rod steel
#   tube 30 x 3 mm, leg length stroke 300-450 mm;
# - actuator: 20 x 5 mm preloaded ball screw, ~6e7 N/m in series, linear;
# - the rod's bushing: lateral 3e7 N/m, tilt 2e3 N·m/rad, anti-rotation 500 N·m/rad;
# - base revolute: a pair of angular-contact bearings, radial 3e8, axial 2e8 N/m, tilt
#   5e4 N·m/rad;
# - platform spherical joints: 1e8 N/m, +-30 deg, mounted along the leg at home;
# - masses (docs/dynamics.md; steel 7850, aluminium 2700 kg/m^3 times the dimensions,
#   the rest estimated): the table an aluminium disk 400 x 25 mm with three spherical
#   joints (~50 g each), as a cylinder; the cylinder body: its tube, the 20 mm screw
#   inside it (250 mm) and a motor of ~1 kg 30 mm from the revolute; the rod: the steel
#   tube, 280 mm long (200 mm free at the longest stroke, 80 mm engaged), with its ball
#   nut (~0.2 kg) at the inner end, fixed to the S joint; no rotor.
# Task coordinates (z, rx, ry): x, y and rz follow from the revolutes (parasitic motion).
# Section and mass properties computed from the dimensions by scripts/spatial_examples.py.
schema = 2
name = "3-RPS tilting table (examples/3rps.toml)"
task_coordinates = ["z", "rx", "ry"]
tool_point = [0.0, 0.0, 0.0]

"""
        region = {
            "z": [home_z - 0.03, home_z + 0.03],
            "rx": [-0.15, 0.15],
            "ry": [-0.15, 0.15],
            "grid": [5, 7, 7],
        }
    out = header
    out += table(
        "workspace",
        {"centre_x": 0.0, "centre_y": 0.0, "centre_z": home_z, "rx": 0.0, "ry": 0.0, "phi": 0.0},
        "The home pose: x, y, z [m], rx, ry, phi (= rz) [rad]; x, y and rz are the start\n"
        "of the completion (the parasitic coordinates are solved from the legs).",
    )
    out += table(
        "workspace.required", region, "The required region (SI: m, rad), a grid over (z, rx, ry)."
    )
    if kind == "PRS":
        out += table("platform", spindle_head(), "The head: plate, spindle and joints (above).")
        out += table(
            "parts.actuator",
            {
                "locked_stiffness": 1e8,
                "k_a": 1e8,
                "q": 1.0,
                "threshold_displacement": 0.0,
                "carriage_mass": 6.8,
            },
        )
        out += table(
            "parts.guide", {"roll": 2e4, "pitch": 3e4, "yaw": 3e4, "lateral": 8e8, "vertical": 1e9}
        )
        out += table("parts.carriage_revolute", {"tilt": 1e5, "axial": 3e8, "radial": 5e8})
        link_mass = STEEL_DENSITY * tube_area(0.060, 0.005) * link
        out += table("parts.link", {**tube(0.060, 0.005, STEEL), "mass": round(link_mass, 4)})
        out += table(
            "parts.platform_joint", {"axial": 3e8, "radial": 3e8, "max_angle": math.radians(35.0)}
        )
    else:
        out += table(
            "platform",
            {
                "mass": round(disk_mass(0.2, 0.025, ALUMINIUM_DENSITY) + 3 * 0.05, 3),
                "shape": "cylinder",
                "radius": 0.2,
                "height": 0.025,
            },
        )
        out += table(
            "parts.actuator",
            {"locked_stiffness": 6e7, "k_a": 6e7, "q": 1.0, "threshold_displacement": 0.0},
        )
        out += table(
            "parts.guide",
            {"roll": 500.0, "pitch": 2000.0, "yaw": 2000.0, "lateral": 3e7, "vertical": 3e7},
        )
        out += table("parts.base_revolute", {"tilt": 5e4, "axial": 2e8, "radial": 3e8})
        cylinder_body = composite(
            [
                bar(0.25, tube_area(0.050, 0.004), ALUMINIUM_DENSITY),
                bar(0.25, tube_area(0.020, 0.010), STEEL_DENSITY),
                block(1.0, 0.03, 0.06),
            ]
        )
        rod_body = composite(
            [bar(0.28, tube_area(0.030, 0.003), STEEL_DENSITY), block(0.2, 0.28, 0.03)]
        )
        out += table("parts.cylinder", {**tube(0.050, 0.004, ALUMINIUM), **rounded(cylinder_body)})
        out += table(
            "parts.rod",
            {**tube(0.030, 0.003, STEEL), **rounded({**rod_body, "mass_centre_from": "end"})},
        )
        out += table(
            "parts.platform_joint", {"axial": 1e8, "radial": 1e8, "max_angle": math.radians(30.0)}
        )
    for angle in (90.0, 210.0, 330.0):
        a = polar(r_base, angle)
        b = polar(r_platform, angle)
        c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        b_home = b + np.array([0.0, 0.0, home_z])
        if kind == "PRS":
            across = float(np.linalg.norm((b_home - a)[:2]))
            rho_home = home_z + math.sqrt(link**2 - across**2)  # carriage above B
            to_carriage = a + np.array([0, 0, rho_home]) - b_home
            out += table(
                "[[legs]]",
                {
                    "type": "PRS",
                    "base_point": [float(v) for v in a],
                    "rail_direction": [0.0, 0.0, 1.0],
                    "revolute_axis": [-s, c, 0.0],
                    "link_length": link,
                    "platform_point": [float(v) for v in b],
                    "branch": -1,
                    "stroke": [0.55, 1.05],
                    "platform_joint_axis": unit(to_carriage),
                },
            )
        else:
            out += table(
                "[[legs]]",
                {
                    "type": "RPS",
                    "base_point": [float(v) for v in a],
                    "revolute_axis": [-s, c, 0.0],
                    "cylinder_length": 0.25,
                    "platform_point": [float(v) for v in b],
                    "stroke": [0.30, 0.45],
                    "platform_joint_axis": unit(a - b_home),
                },
            )
    return out


def main() -> None:
    for name, text in (
        ("hexapod_6ups.toml", hexapod()),
        ("3prs.toml", tripod("PRS")),
        ("3rps.toml", tripod("RPS")),
    ):
        path = ROOT / "examples" / name
        path.write_text(text.rstrip("\n") + "\n", encoding="utf-8")
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
