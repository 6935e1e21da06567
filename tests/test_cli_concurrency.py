"""Output files under concurrent runs: written whole or not at all, never over another
run's file without ``--overwrite`` (``ppm_stiffness.cli.output_files``).

Two real processes race for one new file; then every command that writes files meets
a file that "another run" creates between its early check and its commit (the commit
is intercepted to create it): it must say "file exists", exit 2, leave the other
run's file as it was and leave no temporary file behind.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.cli.output_files import OutputFiles, output_files
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.csvio import read_commented_csv

ROOT = Path(__file__).parents[1]
SYMMETRIC = str(ROOT / "examples/symmetric_3ppr.toml")
REGION = "--region=-10,10,-10,10,-5.7,5.7,3,3,3"


def _map_process(grid: int, data: Path) -> subprocess.Popen[str]:
    argv = [sys.executable, "-m", "ppm_stiffness", "map", "--quiet"]
    return subprocess.Popen(
        [*argv, "--grid", str(grid), "--data", str(data)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def test_two_processes_writing_one_new_map_file(tmp_path: Path) -> None:
    """Two ``map --data m.csv`` runs started together, on grids of 300 and 301 points
    per axis (about 1 s of work each, so both pass the early existence check before
    either writes): exactly one succeeds, the other says "file exists" with exit 2,
    and m.csv holds one whole grid."""
    data = tmp_path / "m.csv"
    grids = (300, 301)
    runs = [_map_process(g, data) for g in grids]
    results = [(p.wait(timeout=300), *p.communicate()) for p in runs]
    codes = sorted(code for code, _, _ in results)
    assert codes == [0, 2], [err for _, _, err in results]
    winner = next(g for g, (code, _, _) in zip(grids, results, strict=True) if code == 0)
    loser_err = next(err for code, _, err in results if code == 2)
    assert loser_err.count("\n") == 1 and "file exists" in loser_err
    _, rows = read_commented_csv(data)
    assert rows[0][:2] == ["x_m", "y_m"]
    body = rows[1:]
    assert len(body) == winner**2 and all(len(r) == 6 for r in body)
    xs = np.array([float(r[0]) for r in body]).reshape(winner, winner)
    assert np.all(xs == xs[0])  # one grid, x fastest, rows in order: not two mixed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.csv"]  # no temporary file


def test_a_commit_refused_midway_removes_what_it_placed(tmp_path: Path) -> None:
    """Of two new files, the second exists by the commit: the first, already placed,
    is removed again, the existing one is untouched, no temporary file is left."""
    first, second = tmp_path / "a.csv", tmp_path / "b.png"
    with pytest.raises(InputDataError, match=r"--out .*b\.png: file exists"):
        with output_files(overwrite=False) as out:
            out.temp(first, "--csv").write_text("mine")
            out.temp(second, "--out").write_text("mine")
            second.write_text("theirs")  # another run, meanwhile
    assert second.read_text() == "theirs"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.png"]


def test_overwrite_replaces_and_a_failure_writes_nothing(tmp_path: Path) -> None:
    dest = tmp_path / "best.toml"
    dest.write_text("old")
    with output_files(overwrite=True) as out:
        tmp = out.temp(dest, "--out")
        assert tmp.parent == tmp_path and tmp.suffix == ".toml"  # the format's suffix kept
        tmp.write_text("new")
    assert dest.read_text() == "new"
    with pytest.raises(KeyboardInterrupt):
        with output_files(overwrite=True) as out:
            out.temp(dest, "--out").write_text("half")
            raise KeyboardInterrupt
    assert dest.read_text() == "new" and sorted(p.name for p in tmp_path.iterdir()) == [dest.name]


#: Each command that writes files, with small inputs; {d} is the output folder.
WRITERS = {
    "map": ["map", "--grid", "5", "--quiet", "--data", "{d}/m.csv", "--out", "{d}/m.png"],
    "map-npz": ["map", "--grid", "5", "--quiet", "--data", "{d}/m.npz"],
    "deflect": ["deflect", "--csv", "{d}/c.csv", "--plot", "{d}/c.png"],
    "sweep": [
        "sweep",
        "--design",
        SYMMETRIC,
        REGION,
        "--quiet",
        "--vary",
        "leg*.platform_radius=0.02:0.04:2",
        "--csv",
        "{d}/s.csv",
        "--out",
        "{d}/s.png",
        "--link-modes",
        "0",
    ],
    "optimize": [
        "optimize",
        "--design",
        SYMMETRIC,
        REGION,
        "--quiet",
        "--budget",
        "10",
        "--vary",
        "leg*.platform_radius=0.02:0.06",
        "--out",
        "{d}/best.toml",
        "--convergence",
        "{d}/conv.png",
    ],
    "compare": ["compare", "--design", SYMMETRIC, REGION, "--quiet", "--map-grid", "4"]
    + ["--out", "{d}/cmp.png", "--link-modes", "0"],
    "identify": [
        "identify",
        "--measurements",
        str(ROOT / "examples/identification/measurements.csv"),
        "--free",
        "leg1.guide.yaw",
        "--out",
        "{d}/id.toml",
    ],
    "calibrate": [
        "calibrate",
        "--target",
        str(ROOT / "src/ppm_stiffness/data/paper_eq22.csv"),
        "--free",
        "leg1.guide.yaw",
        "--out",
        "{d}/cal.toml",
    ],
    "fit-actuator": [
        "fit-actuator",
        str(ROOT / "src/ppm_stiffness/data/actuator_synthetic.csv"),
        "--plot",
        "{d}/fit.png",
        "--write-design",
        "{d}/fit.toml",
    ],
    "springs": ["springs", "--out", "{d}/springs.png"],
    "mechanism": ["mechanism", "--out", "{d}/mech.svg"],
    "report": ["report", "--grid", "3", "--quiet", "--out", "{d}/rep"],
    "validate": ["validate", "--poses", "0", "--quiet", "--csv", "{d}/v.csv"],
}


@pytest.mark.parametrize("name", list(WRITERS))
def test_every_writer_refuses_a_file_another_run_created_meanwhile(
    name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    if name == "validate":
        pytest.importorskip("Pynite", reason="validate needs the 'validate' extra (PyNite)")
    argv = [a.replace("{d}", str(tmp_path)) for a in WRITERS[name]]
    if name == "report":  # the page's content is tests/test_report.py's: a stub here
        (tmp_path / "rep").mkdir()
        import ppm_stiffness.visuals.report as report

        monkeypatch.setattr(report, "build_report", lambda *a, **k: "<html></html>\n")
    commit = OutputFiles.commit
    created: list[Path] = []

    def another_run_first(self: OutputFiles) -> None:
        for _, dest, _ in self.pending:
            dest.write_text("another run's file")
            created.append(dest)
        commit(self)

    monkeypatch.setattr(OutputFiles, "commit", another_run_first)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "file exists" in err, err
    assert created and all(p.read_text() == "another run's file" for p in created)
    left = {p for p in tmp_path.rglob("*") if p.is_file()}
    assert left == set(created)  # no temporary file, nothing of this run
