"""The table of docs/dynamics.md, "The shipped examples at their home pose (locked
actuators)", and the platform-only percentages below it.

Each row: the design's masses (platform, links, carriages [kg], as ``modes --json``'s
``masses``), its six natural frequencies [Hz] at its home pose with locked actuators
and its first mode's direction (``ppm_stiffness.dynamics.analysis.modal_analysis``).
The percentages: each frequency of the platform alone (the legs' masses, carriages and
rotors left out) against the full model's, in ascending order.
``tests/test_modes_table.py`` checks the table in the docs against the code.

Run from the repository's top folder (a few seconds):

    .venv/bin/python scripts/modes_table.py
"""

from __future__ import annotations

import copy
from typing import Any

from ppm_stiffness.design import Design, default_design, design_from_dict, load_design
from ppm_stiffness.design.io import design_to_dict
from ppm_stiffness.design.schema import MASS_FIELDS
from ppm_stiffness.dynamics.analysis import modal_analysis

#: The table's rows: name in the docs, design file (None: the built-in paper design).
DESIGNS = (
    ("built-in 3-PPR (paper)", None),
    ("symmetric 3-PPR", "examples/symmetric_3ppr.toml"),
    ("redundant 4-PPR", "examples/redundant_4ppr.toml"),
    ("3-RPR", "examples/3rpr.toml"),
    ("3-PRR", "examples/3prr.toml"),
    ("3-RRR", "examples/3rrr.toml"),
    ("6-UPS hexapod", "examples/hexapod_6ups.toml"),
    ("3-PRS spindle head", "examples/3prs.toml"),
    ("3-RPS tilting table", "examples/3rps.toml"),
)
#: The mass keys of a leg's parts (left out for the platform alone).
LEG_MASS_KEYS = MASS_FIELDS


def design_of(file: str | None) -> Design:
    return default_design() if file is None else load_design(file)


def row(name: str, design: Design) -> str:
    """One markdown row of the table (the legs condensed statically)."""
    result = modal_analysis(design, link_modes=0).to_dict()
    masses = result["masses"]
    freqs = ", ".join(f"{f:.1f}" for f in result["frequencies"])
    cells = [name, *(f"{masses[k]:.4g}" for k in ("platform", "links", "carriages")), freqs]
    return "| " + " | ".join([*cells, result["modes"][0]["direction"]]) + " |"


def link_row(name: str, design: Design) -> str:
    """One markdown row of the table with the legs' own modes (the default number per
    leg): f1..f6, the first mode's direction and platform share, and the legs' own
    lowest frequency with the platform held."""
    from ppm_stiffness.dynamics.legmodes import design_leg_modes
    from ppm_stiffness.model import actuator_stiffness_vector
    from ppm_stiffness.poses import full_pose

    result = modal_analysis(design).to_dict()
    p, k = full_pose(design, None), actuator_stiffness_vector(design, None)
    f_leg = min(float(leg.frequencies[0, 0]) for leg in design_leg_modes(design, p, k, 1))
    freqs = ", ".join(f"{f:.1f}" for f in result["frequencies"])
    first = result["modes"][0]
    share = f"{100 * first['platform_share']:.2g} %"
    return f"| {name} | {freqs} | {first['direction']} | {share} | {f_leg:.1f} |"


def _without_leg_masses(data: Any) -> Any:
    if isinstance(data, dict):
        return {k: _without_leg_masses(v) for k, v in data.items() if k not in LEG_MASS_KEYS}
    if isinstance(data, list):
        return [_without_leg_masses(v) for v in data]
    return data


def platform_alone(design: Design) -> Design:
    """The design with only its platform's mass."""
    data = copy.deepcopy(design_to_dict(design))
    platform = data.pop("platform")
    stripped = _without_leg_masses(data)
    stripped["platform"] = platform
    return design_from_dict(stripped, source="platform alone")


def platform_alone_change(design: Design) -> str:
    """Each frequency of the platform alone against the full model's, in %."""
    full = modal_analysis(design, link_modes=0).frequencies
    alone = modal_analysis(platform_alone(design), link_modes=0).frequencies
    return ", ".join(f"{100 * (a / f - 1):+.0f}" for a, f in zip(alone, full, strict=True))


def main() -> None:
    print("| design | platform [kg] | links [kg] | carriages [kg] | f₁ … f₆ [Hz] | first mode |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, file in DESIGNS:
        print(row(name, design_of(file)), flush=True)
    print()
    print(
        "| design | f₁ … f₆ [Hz] with link modes | first mode | its platform share | f_leg,1 [Hz] |"
    )
    print("| --- | --- | --- | --- | --- |")
    for name, file in DESIGNS:
        print(link_row(name, design_of(file)), flush=True)
    print()
    print("Platform alone against the full model, each frequency in %:")
    for name, file in DESIGNS:
        print(f"{name}: {platform_alone_change(design_of(file))}")


if __name__ == "__main__":
    main()
