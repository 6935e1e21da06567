"""``optimize`` with two or more ``--objective`` on the command line (issue 31, item 5):
the front as CSV, JSON, design files and a picture, the chosen design, and the bad
inputs (exit code 2, one line on stderr, nothing written)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

import ppm_stiffness as pps
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
]


def test_front_files_and_the_chosen_design(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, table, doc_path = tmp_path / "chosen.toml", tmp_path / "f.csv", tmp_path / "f.json"
    figure, designs = tmp_path / "front.png", tmp_path / "designs"
    designs.mkdir()
    argv = [*FRONT, "--out", str(out), "--front", str(table), "--front", str(doc_path)]
    argv += ["--front-designs", str(designs), "--front-figure", str(figure), "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["algorithm"] == "NSGA-II" and doc["evaluations"] <= 24
    front = doc["front"]
    assert figure.stat().st_size > 0
    with table.open(encoding="utf-8") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert len(rows) == len(front) == len(list(designs.glob("front_*.toml")))
    saved = json.loads(doc_path.read_text(encoding="utf-8"))["front"]
    for row, record, line in zip(rows, front, saved, strict=True):
        assert float(row["worst-k-translational"]) == record["objectives"][0]
        assert line["worst-k-rotational"] == record["objectives"][1]
        design = pps.load_design(record["design_file"])
        assert design.parameter("leg2.psi") == record["parameters"]["leg2.psi"]
    # the front is sorted by the first objective (maximised) and non-dominated
    k_t = [r["objectives"][0] for r in front]
    k_r = [r["objectives"][1] for r in front]
    assert k_t == sorted(k_t, reverse=True) and k_r == sorted(k_r)
    # the chosen design, re-evaluated by compare over the region it carries: the same
    chosen = front[doc["chosen"]]
    argv = ["compare", "--json", "--design", str(out), "--link-modes", "0"]
    again = json.loads(_stdout(capsys, argv))
    figures = again["designs"][0]["figures"]
    assert min(figures["k_x_min"], figures["k_y_min"]) == chosen["objectives"][0]
    assert figures["k_phi_min"] == chosen["objectives"][1]


def _stdout(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 0
    return capsys.readouterr().out


def test_weights_pick_the_end_of_the_front(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A weight 1000 times larger on the rotational stiffness picks the front's design
    with the largest (its last row); on the translational one, the first row."""
    docs = []
    for i, weights in enumerate(("1,1000", "1000,1")):
        argv = [*FRONT, "--out", str(tmp_path / f"c{i}.toml"), "--pick", f"weights={weights}"]
        docs.append(json.loads(_stdout(capsys, [*argv, "--json"])))
    assert docs[0]["front"] == docs[1]["front"]
    assert docs[0]["chosen"] == len(docs[0]["front"]) - 1 and docs[1]["chosen"] == 0


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--pick", "weights=1"], "--pick weights=1: give one weight per --objective"),
        (["--pick", "best"], "--pick must be knee or weights"),
        (["--budget", "15"], "needs at least 16 evaluations"),
        (["--front", "f.txt"], "--front f.txt: unknown format .txt"),
        (["--front-designs", "nowhere"], "--front-designs nowhere: not an existing directory"),
        (["--convergence", "c.png"], "--convergence: only with one --objective"),
        (["--objective", "worst-k-rotational"], "--objective: each objective once"),
    ],
)
def test_bad_inputs_exit_2_and_write_nothing(
    extra: list[str],
    message: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main([*FRONT, "--out", "chosen.toml", *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_front_options_refused_with_one_objective(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["optimize", "--design", RPR, REGION, "--vary", "leg1.psi=5.2:6.2", "--quiet"]
    assert main([*argv, "--out", str(tmp_path / "b.toml"), "--pick", "knee"]) == 2
    assert "--pick: only with two or more --objective" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_writes_the_front_so_far(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from ppm_stiffness.optimize.executors import SerialExecutor

    calls = {"n": 0}
    submit = SerialExecutor.submit

    def interrupting(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def]
        calls["n"] += 1
        if calls["n"] > 12:
            raise KeyboardInterrupt
        return submit(self, fn, *args, **kwargs)

    monkeypatch.setattr(SerialExecutor, "submit", interrupting)
    out, table = tmp_path / "chosen.toml", tmp_path / "f.csv"
    assert main([*FRONT, "--out", str(out), "--front", str(table), "--json"]) == 130
    doc = json.loads(capsys.readouterr().out)
    assert doc["interrupted"] and doc["evaluations"] == 12
    partial = "# partial: interrupted after 12 of 24 evaluations; the front so far"
    assert out.read_text(encoding="utf-8").startswith(partial)
    assert table.read_text(encoding="utf-8").startswith(partial)
