"""The tables of docs/dynamics.md, "Against an independent FE frame", "with link
modes": f1..f3 of the condensed model, of the model with each leg's own modes (the
default number per leg) and of the whole FE frame, at the home pose, locked
actuators, for the designs of tests/test_modal_validation.py with uniform links; then
f1 of every shipped example as it is (links given as bodies included), with the
largest difference of f1..f6 (with link modes against the frame) and f_link,1;
then the Delta's f1..f6 at home and validate's two drawn poses (seed 0): condensed,
reduced frame (Guyan), with link modes, whole frame (``--delta`` prints only that).

Run from the repository's top folder (about two minutes; needs the extra "validate"):

    .venv/bin/python scripts/link_modes_fe_table.py
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))

import numpy as np  # noqa: E402

from helpers import design_named  # noqa: E402
from ppm_stiffness.dynamics.analysis import modal_analysis  # noqa: E402
from ppm_stiffness.validation.compare import validation_poses  # noqa: E402
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


#: Every shipped example (None: the built-in paper design), as its file gives it.
SHIPPED = {
    "built-in 3-PPR (paper)": "paper",
    "symmetric 3-PPR": "symmetric_3ppr",
    "redundant 4-PPR": "redundant_4ppr",
    "3-RPR": "3rpr",
    "3-PRR": "3prr",
    "3-RRR": "3rrr",
    "flexure 3-RRR stage": "flexure_3rrr",
    "spherical 3-RRR": "spherical_3rrr",
    "6-UPS hexapod": "hexapod_6ups",
    "6-RUS": "6rus",
    "6-RUS with flexures": "6rus_flexure",
    "3-PRS spindle head": "3prs",
    "3-RPS tilting table": "3rps",
    "Tricept": "tricept",
    "Delta": "delta",
}


def shipped_table() -> None:
    """f1 of every shipped example: condensed, with link modes, whole FE frame."""
    print(
        "| design | f₁ condensed | f₁ with link modes | f₁ whole FE "
        "| largest difference of f₁ … f₆ | f_link,1 (FE) |"
    )
    print("| --- | --- | --- | --- | --- | --- |")
    for name, file in SHIPPED.items():
        design = design_named(file)
        try:
            c = modal_comparison(design)
        except Exception as exc:  # noqa: BLE001 - a row says why the frame is not built
            print(f"| {name} | not compared: {type(exc).__name__}: {exc} | | | | |", flush=True)
            continue
        worst = float(max(abs(c.linked_frequencies / c.full_frequencies - 1)))
        print(
            f"| {name} | {c.model_frequencies[0]:.2f} | {c.linked_frequencies[0]:.2f} "
            f"| {c.full_frequencies[0]:.2f} | {worst:.1e} | {c.link_frequency:.1f} |",
            flush=True,
        )


def delta_table() -> None:
    """The Delta's f1..f6 at three poses: the model's bar-mass rule (halves lumped at
    the crossbars, no bending) against the frame's continuous bars."""
    print("| pose (x, y, z mm) | | f₁ … f₆ [Hz] |")
    print("| --- | --- | --- |")
    design = design_named("delta")
    for pose in validation_poses(design, 2, 0):
        c = modal_comparison(design, pose)
        where = ", ".join(f"{1e3 * v:.1f}" for v in pose[:3])
        rows = {
            "condensed": c.model_frequencies,
            "frame reduced to P": c.reduced_frequencies,
            "with link modes": c.linked_frequencies,
            "whole frame": c.full_frequencies,
            "with link modes / whole frame − 1": c.linked_frequencies / c.full_frequencies - 1,
        }
        for label, values in rows.items():
            fmt = "{:+.4f}" if "/" in label else "{:.2f}"
            cells = ", ".join(fmt.format(v) for v in np.asarray(values))
            print(f"| {where} | {label} | {cells} |", flush=True)
            where = ""
        print(f"| | f_link,1 (frame) | {c.link_frequency:.2f} |", flush=True)


def main() -> None:
    if "--delta" in sys.argv:
        delta_table()
        return
    shipped_table()
    print()
    delta_table()
    print()
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
