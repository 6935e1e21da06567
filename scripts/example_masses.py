"""The mass models of the shipped examples, from densities and the parts' dimensions.

Prints the TOML tables of the planar examples (written into the paper's design and the
planar example files by hand, with these numbers) and provides the helpers that
``scripts/spatial_examples.py`` uses for the spatial ones. Every number is a handbook
density times a stated dimension, or a stated estimate of a catalogue-class part (a
motor, a ball nut, a guide block): see docs/dynamics.md. Run from the repository's top
folder:

    python scripts/example_masses.py
"""

from __future__ import annotations

import math
from dataclasses import dataclass

ALUMINIUM = 2700.0  # density [kg/m^3], handbook
STEEL = 7850.0


@dataclass(frozen=True)
class Piece:
    """A part of a link's body: mass [kg], centre [m] along the link from the end the
    body is measured from, transverse inertia [kg·m^2] about its own centre."""

    mass: float
    centre: float
    transverse: float = 0.0


def bar(length: float, area: float, density: float, start: float = 0.0) -> Piece:
    """A uniform bar of ``length`` along the link, from ``start``."""
    mass = density * area * length
    return Piece(mass, start + 0.5 * length, mass * length**2 / 12.0)


def tube_area(outer: float, wall: float) -> float:
    """Section area [m^2] of a round tube (a solid rod if wall = outer / 2)."""
    return math.pi * ((outer / 2) ** 2 - (outer / 2 - wall) ** 2)


def block(mass: float, centre: float, size: float) -> Piece:
    """A compact part (a motor, a nut, a housing) of edge ``size`` at ``centre``."""
    return Piece(mass, centre, mass * size**2 / 6.0)


def composite(pieces: list[Piece]) -> dict[str, float]:
    """Mass, centre (from the same end) and transverse inertia about the centre."""
    mass = sum(p.mass for p in pieces)
    centre = sum(p.mass * p.centre for p in pieces) / mass
    transverse = sum(p.transverse + p.mass * (p.centre - centre) ** 2 for p in pieces)
    return {"mass": mass, "mass_centre": centre, "inertia_transverse": transverse}


def rounded(table: dict[str, float | str]) -> dict[str, float | str]:
    return {k: float(f"{v:.4g}") if isinstance(v, float) else v for k, v in table.items()}


def disk_mass(radius: float, thickness: float, density: float) -> float:
    return density * math.pi * radius**2 * thickness


def planar_tables() -> dict[str, dict[str, dict[str, float | str]]]:
    """The planar examples' mass tables (docs/dynamics.md gives the sources)."""
    out: dict[str, dict[str, dict[str, float | str]]] = {}
    # The paper's 3-PPR: 35 x 6 mm aluminium bar, 8 mm steel rod (Table 2); r = 30 mm.
    rod_length = 0.16  # 0.12 m of free length (rod_length_range) + 40 mm in the bearing
    rod = bar(rod_length, tube_area(0.008, 0.004), STEEL)
    platform_disk = disk_mass(0.045, 0.010, ALUMINIUM)
    out["paper"] = {
        "platform": {
            "mass": round(platform_disk + 3 * 0.02, 3),
            "shape": "cylinder",
            "radius": 0.045,
            "height": 0.010,
        },
        "distal": rounded(
            {
                **composite([rod]),
                "mass_centre": rod_length / 2,
                "mass_centre_from": "end",
            }
        ),
        "actuator": {"carriage_mass": 0.2},
        # proximal: the 35 x 6 mm aluminium bar, 150 mm (the carriage plate's size: the
        # calibrated layout's lengths B-C are not the parts' dimensions)
        "proximal": rounded({"mass": ALUMINIUM * 2.1e-4 * 0.15}),
    }
    # 3-RPR, 3-PRR, 3-RRR: platform joints at 60 mm: an aluminium disk 150 x 12 mm and
    # three revolutes (a bearing pair in a housing, 60 g each).
    platform = {
        "mass": round(disk_mass(0.075, 0.012, ALUMINIUM) + 3 * 0.06, 4),
        "shape": "cylinder",
        "radius": 0.075,
        "height": 0.012,
    }
    housing = composite(
        [
            bar(0.12, tube_area(0.020, 0.002), ALUMINIUM),  # the housing tube
            bar(0.12, tube_area(0.012, 0.006), STEEL),  # the 12 mm screw inside it
            block(0.30, 0.0, 0.042),  # a NEMA-17 class motor at the pivot
        ]
    )
    rpr_rod_length = 0.23  # 0.18 m free at the longest + 50 mm engaged
    actuator_rod = composite(
        [
            bar(rpr_rod_length, tube_area(0.010, 0.005), STEEL),
            block(0.08, rpr_rod_length, 0.02),  # the ball nut at the rod's inner end
        ]
    )
    out["3rpr"] = {
        "platform": platform,
        "proximal": rounded(housing),
        "distal": rounded({**actuator_rod, "mass_centre_from": "end"}),
    }
    out["3prr"] = {
        "platform": platform,
        "distal": rounded({"mass": STEEL * tube_area(0.016, 0.002) * 0.22}),
        # guide block, carriage plate with the revolute's housing, ball nut
        "actuator": {"carriage_mass": 0.3},
    }
    out["3rrr"] = {
        "platform": platform,
        "proximal": rounded(
            composite(
                [
                    bar(0.15, tube_area(0.020, 0.002), ALUMINIUM),
                    block(0.10, 0.0, 0.03),  # the gear's output flange and clamp
                ]
            )
        ),
        "distal": rounded(
            composite(
                [
                    bar(0.15, tube_area(0.016, 0.002), STEEL),
                    block(0.06, 0.0, 0.03),  # the elbow's bearing housing
                ]
            )
        ),
    }
    return out


def main() -> None:
    for name, tables in planar_tables().items():
        print(f"# {name}")
        for part, fields in tables.items():
            print(f"[{part}]")
            for key, value in fields.items():
                print(f"{key} = {value!r}".replace("'", '"'))
        print()


if __name__ == "__main__":
    main()
