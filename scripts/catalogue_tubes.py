"""Print the tube tables of examples/catalogues/parts.toml for the shipped studies
(docs/optimization.md, "Shipped studies"): [[delta_arms]], [[delta_forearms]] and
[[hexapod_rods]]. Each entry is computed from its tube's outer diameter and wall and the
material, with the formulas and the lengths of the examples it fits (the same as
scripts/chain_examples.py and scripts/spatial_examples.py use for those examples, and
rounded as they round, so that the example's own part is an entry). Run from the
repository's top folder and paste the output below the [[rods]]:

    python scripts/catalogue_tubes.py
"""

from __future__ import annotations

import math

from example_masses import bar, block, composite, tube_area

ALUMINIUM = ("aluminium 6061-T6", 69e9, 26e9, 2700.0)
CARBON = ("carbon-fibre", 1.1e11, 2e10, 1550.0)  # along the fibres, as examples/delta.toml
STEEL = ("steel", 210e9, 81e9, 7850.0)


def section(outer: float, wall: float) -> tuple[float, float]:
    """Area [m^2] and second moment I [m^4] of a round tube (J = 2 I)."""
    ro, ri = outer / 2, outer / 2 - wall
    return math.pi * (ro**2 - ri**2), math.pi / 4 * (ro**4 - ri**4)


def chain_entry(outer: float, wall: float, material: tuple, length: float) -> dict:
    """A link of a joint-list leg, rounded as scripts/chain_examples.py rounds."""
    _, e, g, rho = material
    area, inertia = section(outer, wall)
    return {
        "young_modulus": float(f"{e:.6g}"),
        "shear_modulus": float(f"{g:.6g}"),
        "area": float(f"{area:.6g}"),
        "torsion_constant": float(f"{2 * inertia:.6g}"),
        "inertia_y": float(f"{inertia:.6g}"),
        "inertia_z": float(f"{inertia:.6g}"),
        "mass": float(f"{rho * area * length:.4g}"),
    }


def hexapod_rod(outer: float, wall: float) -> dict:
    """The hexapod's strut rod as scripts/spatial_examples.py builds it: a steel tube
    185 mm long with the ~80 g ball nut at its inner end (mass, centre and transverse
    inertia rounded to 4 digits, the section not rounded)."""
    _, e, g, rho = STEEL
    area, inertia = section(outer, wall)
    body = composite([bar(0.185, tube_area(outer, wall), rho), block(0.08, 0.185, 0.02)])
    return {
        "young_modulus": e,
        "shear_modulus": g,
        "area": area,
        "torsion_constant": 2 * inertia,
        "inertia_y": inertia,
        "inertia_z": inertia,
        **{k: float(f"{v:.4g}") for k, v in body.items()},
    }


def main() -> None:
    tables = {
        "delta_arms": [
            (
                f"{ALUMINIUM[0]} tube {d} x {t} mm x 300 mm",
                chain_entry(d / 1e3, t / 1e3, ALUMINIUM, 0.3),
            )
            for d, t in ((30, 2), (40, 3), (50, 3))
        ],
        "delta_forearms": [
            (f"{CARBON[0]} tube {d} x {t} mm x 800 mm", chain_entry(d / 1e3, t / 1e3, CARBON, 0.8))
            for d, t in ((12, 1), (16, 1.5), (20, 1.5), (25, 2))
        ],
        "hexapod_rods": [
            (f"steel tube {d} x {t} mm x 185 mm with its ball nut", hexapod_rod(d / 1e3, t / 1e3))
            for d, t in ((16, 2), (20, 2), (25, 2.5), (30, 3))
        ],
    }
    for name, entries in tables.items():
        for title, values in entries:
            print(f"[[{name}]]")
            print(f'name = "{title}"')
            print('source = "computed by scripts/catalogue_tubes.py (see the header)"')
            for key, value in values.items():
                print(f"{key} = {value!r}")
            print()


if __name__ == "__main__":
    main()
