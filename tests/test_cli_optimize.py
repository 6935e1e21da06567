"""``compare``, ``sweep`` and ``optimize`` on the command line: what they write, and the
bad inputs of the issue (exit code 2, one line on stderr, nothing written)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
import tomli_w

import ppm_stiffness as pps
from ppm_stiffness.cli import main
from ppm_stiffness.design.io import design_to_dict
from ppm_stiffness.optimize.executors import SerialExecutor

ROOT = Path(__file__).parents[1]
SYMMETRIC = str(ROOT / "examples/symmetric_3ppr.toml")
#: x, y in +-10 mm, phi in +-5.7 deg, 5 x 5 x 3 poses (mm, deg at the CLI)
REGION = "--region=-10,10,-10,10,-5.7,5.7,5,5,3"
OPTIMIZE = ["optimize", "--design", SYMMETRIC, REGION, "--budget", "12", "--quiet"]
RADIUS = ["--vary", "leg*.platform_radius=0.02:0.06"]


def _json(capsys: pytest.CaptureFixture[str], argv: list[str], code: int = 0) -> dict:
    assert main(argv) == code
    out, err = capsys.readouterr()
    return dict(json.loads(out))


def test_optimize_writes_a_design_that_every_command_reads(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    best = tmp_path / "best.toml"
    conv, maps = tmp_path / "conv.png", tmp_path / "maps.png"
    argv = [*OPTIMIZE, *RADIUS, "--json", "--out", str(best)]
    doc = _json(capsys, [*argv, "--convergence", str(conv), "--maps", str(maps), "--map-grid", "8"])
    assert doc["best_design"] == str(best) and best.is_file() and conv.is_file() and maps.is_file()
    assert doc["evaluations"] <= 12
    assert doc["best_objective"] >= doc["initial_objective"] > 0  # N/m, maximised
    assert set(doc["best_parameters"]) == {"leg*.platform_radius"}
    design = pps.load_design(best)
    assert (
        design.parameter("leg*.platform_radius") == doc["best_parameters"]["leg*.platform_radius"]
    )
    # compare re-evaluates it over the region it carries: the same objective
    again = _json(capsys, ["compare", "--json", "--design", str(best), "--link-modes", "0"])
    figures = again["designs"][0]["figures"]
    assert min(figures["k_x_min"], figures["k_y_min"]) == doc["best_objective"]
    assert main(["analyze", "--design", str(best), "--json"]) == 0
    assert main(["map", "--design", str(best), "--grid", "6", "--quiet"]) == 0
    capsys.readouterr()
    # an existing output is refused without --overwrite, before any computation
    assert main([*argv]) == 2
    assert "file exists" in capsys.readouterr().err


def test_ctrl_c_writes_the_best_so_far(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    calls = {"n": 0}
    submit = SerialExecutor.submit

    def interrupting(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def]
        calls["n"] += 1
        if calls["n"] > 7:
            raise KeyboardInterrupt
        return submit(self, fn, *args, **kwargs)

    monkeypatch.setattr(SerialExecutor, "submit", interrupting)
    best = tmp_path / "best.toml"
    doc = _json(capsys, [*OPTIMIZE, *RADIUS, "--json", "--out", str(best)], code=130)
    assert doc["interrupted"] and doc["evaluations"] == 7 and best.is_file()


def _needs_distributed(message: str) -> None:
    """The unreachable-scheduler cases talk to distributed (the 'dask' extra)."""
    if message == "connection refused":
        pytest.importorskip("distributed", reason="distributed is in the 'dask' extra")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--vary", "leg1.no_such_part=0:1"], "unknown design parameter 'leg1.no_such_part'"),
        (["--vary", "leg*.nothing=0:1"], "unknown design parameter 'leg*.nothing'"),
        (["--vary", "leg*.platform_radius=0.03:0.03"], "empty range"),
        (["--vary", "leg*.platform_radius=0.05:0.03"], "inverted range"),
        (["--vary", "leg*.platform_radius=-0.01:0.03"], "LO = -0.01 m is refused by the design"),
        ([*RADIUS, "--budget", "0"], "--budget must be at least 1"),
        ([*RADIUS, "--budget", "4"], "too small"),
        ([*RADIUS, "--scheduler", "tcp://127.0.0.1:1"], "connection refused"),
        ([*RADIUS, "--scheduler", "nonsense"], "tcp://HOST:PORT"),
        ([*RADIUS, "--region=-90,90,-10,10,0,0,5,5,1"], "does not cover the required region"),
        (
            ["--vary", "leg*.platform_radius=0.04:0.06", "--budget", "10"],
            "needs at least 11 evaluations here: the start design (outside the --vary ranges",
        ),
        ([*RADIUS, "--objective", "max-displacement"], "needs --wrench"),
        ([*RADIUS, "--constraint", "stiffness>=3"], "unknown quantity 'stiffness'"),
        ([*RADIUS, "--region=-10,10,-10,10,-5,5,5,5,2.5"], "must be integers"),
        ([*RADIUS, "--region=-10,10,10,-10,0,0,5,5,1"], "inverted range"),
        ([*RADIUS, "--workers", "0"], "--workers must be at least 1"),
    ],
)
def test_bad_optimize_input_is_one_line_and_writes_nothing(
    args: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _needs_distributed(message)
    best = tmp_path / "best.toml"
    argv = ["optimize", "--design", SYMMETRIC, REGION, "--budget", "12", "--quiet", *args]
    assert main([*argv, "--out", str(best), "--maps", str(tmp_path / "m.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("ppm-stiffness: error:") and message in err
    assert list(tmp_path.iterdir()) == []


def test_a_start_design_outside_the_ranges_is_warned_and_a_worse_best_said(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The new user's run: the 3-RPS's cylinder length, 0.25 m in examples/3rps.toml,
    lies outside --vary 0.15:0.22, so the start design is not a candidate. A one-line
    warning names the parameter, its value and the range; the smallest budget (11: the
    start design, a population of 5, one generation of 5) runs one generation; the best
    in the range is worse than the start and the output says so."""
    from rich.console import Console

    from ppm_stiffness.cli import common

    monkeypatch.setattr(common, "console", Console(width=200))
    monkeypatch.setattr("ppm_stiffness.cli.optimize.console", common.console)
    start = pps.load_design(ROOT / "examples/3rps.toml").parameter("leg*.cylinder_length")
    assert start == 0.25
    argv = ["optimize", "--design", str(ROOT / "examples/3rps.toml"), "--quiet", "--seed", "1"]
    argv += ["--vary", "leg*.cylinder_length=0.15:0.22", "--objective", "first-frequency"]
    argv += ["--link-modes", "0"]  # the reporting under test, on the cheaper condensed f1
    assert main([*argv, "--budget", "10", "--out", str(tmp_path / "no.toml")]) == 2
    assert "needs at least 11 evaluations" in capsys.readouterr().err
    assert main([*argv, "--budget", "11", "--out", str(tmp_path / "best.toml")]) == 0
    out, err = capsys.readouterr()
    assert err == (
        "ppm-stiffness: warning: the start design is not a candidate: leg*.cylinder_length "
        "= 0.25 m lies outside its --vary range 0.15:0.22 m; the best design found may be "
        "worse than the start\n"
    )
    flat = " ".join(out.split())
    assert "11 evaluations of --budget 11 (population 5, 1 generation; 0 refused by" in flat
    assert "worse than the start design (which lies outside the ranges); best design" in out
    doc = _json(capsys, [*argv, "--budget", "11", "--json", "--out", str(tmp_path / "b.toml")])
    assert (doc["evaluations"], doc["generations"]) == (11, 1)
    assert [h["evaluations"] for h in doc["history"]] == [1, 6, 11]
    assert doc["start_outside_ranges"] == [{"name": "leg*.cylinder_length", "value": start}]
    assert doc["best_objective"] < doc["initial_objective"] and doc["worse_than_start"]
    assert doc["improvement"] == doc["best_objective"] / doc["initial_objective"] < 1


def test_no_covering_candidate_follows_the_warning_and_writes_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Nothing in alpha 0.3:0.5 covers the region; the start design (alpha = 0) is not a
    candidate, which the warning line says before the error line."""
    argv = [*OPTIMIZE, "--vary", "leg1.alpha=0.3:0.5", "--out", str(tmp_path / "best.toml")]
    assert main(argv) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 2 and "leg1.alpha = 0 rad lies outside its --vary range" in lines[0]
    assert lines[1].startswith("ppm-stiffness: error: none of the ")
    assert "candidates evaluated covers the region" in lines[1]
    assert list(tmp_path.iterdir()) == []


def test_the_start_design_not_covering_says_by_how_much(capsys: pytest.CaptureFixture[str]) -> None:
    argv = [*OPTIMIZE, *RADIUS, "--region=-40,40,0,0,0,0,9,1,1", "--out", "unused.toml"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    # the symmetric 3-PPR reaches x in [-25, 25] mm at phi = 0: 4 of the 9 poses miss
    assert "4 of 9 grid poses (44.4 %)" in err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--vary", "leg*.nothing=0:1:3"], "unknown design parameter"),
        (["--vary", "leg*.platform_radius=0.02:0.04"], "expected NAME=LO:HI:N"),
        (["--vary", "leg*.platform_radius=0.02:0.04:1"], "N must be between 2"),
        (["--vary", "leg*.platform_radius=0.02:0.04", "--sample", "sobol:15"], "power of 2"),
        (
            ["--vary", "leg*.platform_radius=0.02:0.04:3", "--scheduler", "tcp://127.0.0.1:1"],
            "connection refused",
        ),
    ],
)
def test_bad_sweep_input_is_one_line_and_writes_nothing(
    args: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _needs_distributed(message)
    argv = ["sweep", "--design", SYMMETRIC, REGION, "--quiet", *args]
    assert main([*argv, "--csv", str(tmp_path / "s.csv"), "--out", str(tmp_path / "s.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
    assert list(tmp_path.iterdir()) == []


def test_sweep_grid_csv_and_heat_map(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    table, picture = tmp_path / "s.csv", tmp_path / "s.png"
    argv = ["sweep", "--design", SYMMETRIC, REGION, "--quiet", "--csv", str(table)]
    argv += ["--vary", "leg*.platform_radius=0.02:0.04:3", "--vary", "leg1.alpha=-0.01:0.01:2"]
    assert main([*argv, "--out", str(picture), "--link-modes", "0"]) == 0
    rows = list(csv.DictReader(table.open(encoding="utf-8")))
    assert len(rows) == 6 and picture.is_file()
    # the first variable varies slowest; the figures are the summary's
    assert [float(r["leg*.platform_radius"]) for r in rows] == [0.02, 0.02, 0.03, 0.03, 0.04, 0.04]
    assert [float(r["leg1.alpha"]) for r in rows[:2]] == [-0.01, 0.01]
    assert all(r["covers"] == "True" and float(r["k_x_min"]) > 0 for r in rows)


def test_sweep_sobol_is_seeded(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["sweep", "--design", SYMMETRIC, REGION, "--json", "--sample", "sobol:8"]
    argv += ["--vary", "leg*.platform_radius=0.02:0.04", "--link-modes", "0"]
    first = _json(capsys, [*argv, "--seed", "3"])["rows"]
    assert len(first) == 8 and first == _json(capsys, [*argv, "--seed", "3"])["rows"]
    assert first != _json(capsys, [*argv, "--seed", "4"])["rows"]
    radii = [r["leg*.platform_radius"] for r in first]
    assert all(0.02 <= r <= 0.04 for r in radii)


def test_compare_of_the_examples_fits_80_columns(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from rich.console import Console

    from ppm_stiffness.cli import common

    monkeypatch.setattr(common, "console", Console(width=80))
    monkeypatch.setattr("ppm_stiffness.cli.compare.console", common.console)
    files = [f"examples/{n}.toml" for n in ("3prr", "3rpr", "3rrr", "symmetric_3ppr")]
    argv = ["compare", "--quiet", "--region=-10,10,-10,10,-5,5,3,3,2", "--wrench", "5,5,0,0,0,0.1"]
    for f in files:
        argv += ["--design", str(ROOT / f)]
    argv += ["--link-modes", "0"]
    assert main([*argv, "--out", str(tmp_path / "c.png"), "--map-grid", "6"]) == 0
    out = capsys.readouterr().out
    assert max(len(line) for line in out.splitlines()) <= 80
    assert "3-RRR" in out and "max |(dx, dy)| [m]" in out
    assert "figure [unit]" in out  # the header's brackets are text, not rich markup


def test_compare_needs_one_region(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    data = pps.load_design(ROOT / "examples/3rrr.toml")
    from ppm_stiffness.optimize.region import make_region, with_region

    other = with_region(data, make_region((-0.005, 0.005), (0, 0), (0, 0), (3, 1, 1)))
    path = tmp_path / "other.toml"
    pps.save_design(other, path)
    assert (
        main(["compare", "--design", str(ROOT / "examples/3rrr.toml"), "--design", str(path)]) == 2
    )
    assert "different [workspace.required] regions" in capsys.readouterr().err
    bare = design_to_dict(pps.default_design())
    del bare["workspace"]["required"]  # a design without a region of its own
    (tmp_path / "bare.toml").write_text(tomli_w.dumps(bare))
    assert main(["compare", "--design", str(tmp_path / "bare.toml")]) == 2
    assert "pass --region" in capsys.readouterr().err
