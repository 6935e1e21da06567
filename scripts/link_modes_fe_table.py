"""The table of docs/dynamics.md, "Against an independent FE frame", column "with link
modes": f1..f3 of the condensed model, of the model with each leg's own modes (the
default number per leg) and of the whole FE frame, at the home pose, locked
actuators, for the designs of tests/test_modal_validation.py (uniform links; the
frame takes no link bodies).

Run from the repository's top folder (about a minute; needs the extra "validate"):

    .venv/bin/python scripts/link_modes_fe_table.py
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))

from helpers import design_named  # noqa: E402
from ppm_stiffness.dynamics.analysis import modal_analysis  # noqa: E402
from ppm_stiffness.validation.modal import modal_comparison  # noqa: E402
from test_dynamics import _with_masses  # noqa: E402

DESIGNS = {
    "3-PRR (shipped file)": lambda: design_named("3prr"),
    "3-RRR, uniform links, geared rotors": lambda: _with_masses(
        "3rrr",
        platform={"mass": 0.75, "shape": "cylinder", "radius": 0.075, "height": 0.012},
        masses={"proximal": {"mass": 0.15}, "distal": {"mass": 0.16}},
        actuator={"rotor_inertia": 2e-5, "gear_ratio": 50.0},
    ),
    "3-PRS (shipped file)": lambda: design_named("3prs"),
    "hexapod, uniform struts (0.45 + 0.40 kg)": lambda: _with_masses(
        "hexapod_6ups",
        platform={"mass": 1.766, "shape": "cylinder", "radius": 0.12, "height": 0.012},
        masses={"cylinder": {"mass": 0.45}, "rod": {"mass": 0.40}},
    ),
}


def main() -> None:
    print(
        "| design | f₁ … f₃ condensed | f₁ … f₃ with link modes | f₁ … f₃ whole FE "
        "| largest difference |"
    )
    print("| --- | --- | --- | --- | --- |")
    for name, make in DESIGNS.items():
        design = make()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            condensed = modal_analysis(design, link_modes=0).frequencies[:3]
        linked = modal_analysis(design).frequencies[:3]
        fe = modal_comparison(design).full_frequencies[:3]
        worst = max(abs(a / b - 1) for a, b in zip(linked, fe, strict=True))
        cells = [", ".join(f"{f:.2f}" for f in v) for v in (condensed, linked, fe)]
        print(f"| {name} | {' | '.join(cells)} | {worst:.1e} |", flush=True)


if __name__ == "__main__":
    main()
