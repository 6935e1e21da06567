"""The chosen front design against the start (issue 31, item 5): ``optimize`` with two
or more objectives prints and returns a comparison of the two, as ``compare`` gives it
from the design files (the start's file and the chosen design written as --out)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from ppm_stiffness.cli import main

pytest.importorskip("pymoo", reason="pymoo is in the 'pareto' extra")

ROOT = Path(__file__).parents[1]
RPR = str(ROOT / "examples/3rpr.toml")
REGION = "--region=-10,10,-10,10,-5.7,5.7,3,3,3"
FRONT = [
    "optimize",
    "--design",
    RPR,
    REGION,
    "--vary",
    "leg1.psi=5.2:6.2",
    "--vary",
    "leg2.psi=1.1:2.1",
    "--objective",
    "worst-k-translational",
    "--objective",
    "worst-k-rotational",
    "--budget",
    "24",
    "--quiet",
    "--wrench",
    "10,10,0,0,0,0.5",
]


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict:  # type: ignore[type-arg]
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_comparison_equals_compare_of_the_two_design_files(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "chosen.toml"
    doc = _json(capsys, [*FRONT, "--out", str(out), "--json"])
    rows = {r["name"]: r for r in doc["comparison"]}
    chosen = doc["front"][doc["chosen"]]
    # the objectives: the start's and the chosen front row's, as the search found them
    for i, name in enumerate(("worst-k-translational", "worst-k-rotational")):
        assert rows[name]["start"] == doc["start"]["objectives"][i]
        assert rows[name]["chosen"] == chosen["objectives"][i]
        assert rows[name]["ratio"] == pytest.approx(
            chosen["objectives"][i] / doc["start"]["objectives"][i], rel=1e-15
        )
    # every figure: what compare gives for the start file and the written chosen file
    again = _json(
        capsys,
        ["compare", "--json", "--quiet", "--design", RPR, "--design", str(out), REGION]
        + ["--wrench", "10,10,0,0,0,0.5"],
    )
    start_figures, chosen_figures = (d["figures"] for d in again["designs"])
    figures = [n for n in rows if n in start_figures]
    assert {"k_phi_min", "max_displacement", "f1_min"} <= set(figures)
    for name in figures:
        assert rows[name]["start"] == pytest.approx(start_figures[name], rel=1e-12)
        assert rows[name]["chosen"] == pytest.approx(chosen_figures[name], rel=1e-12)
    # a figure that changes: the chosen design is not the start
    assert not math.isclose(rows["k_phi_min"]["start"], rows["k_phi_min"]["chosen"])


def test_comparison_is_printed(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*FRONT, "--out", str(tmp_path / "chosen.toml")]) == 0
    text = capsys.readouterr().out
    assert "against the start" in text
    line = next(x for x in text.splitlines() if "worst-k-rotational [N·m/rad]" in x)
    start, chosen, ratio = (float(c) for c in _cells(line)[1:])
    assert ratio == pytest.approx(chosen / start, rel=2e-3)  # 4 printed digits


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("│").split("│")]


def test_front_figure_marks_an_infeasible_start(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A start design that misses a constraint is drawn as "start design (infeasible)"
    (it cannot be on the front it seems to lead); a feasible one as "start design"."""
    import ppm_stiffness.visuals.optimization as visuals

    labels: list[str] = []
    plot = visuals.plot_front

    def recording(*args, **kwargs):  # type: ignore[no-untyped-def]
        labels.append(kwargs["start_label"])
        return plot(*args, **kwargs)

    monkeypatch.setattr(visuals, "plot_front", recording)
    doc = _json(capsys, [*FRONT, "--out", str(tmp_path / "a.toml"), "--json"])
    k_phi = doc["start"]["objectives"][1]  # worst-k-rotational of the start [N·m/rad]
    for name, extra in (("b", []), ("c", ["--constraint", f"worst-k-rotational>={k_phi * 1.001}"])):
        argv = [*FRONT, "--out", str(tmp_path / f"{name}.toml"), *extra]
        assert main([*argv, "--front-figure", str(tmp_path / f"{name}.png")]) == 0
        capsys.readouterr()
    assert labels == ["start design", "start design (infeasible)"]
