"""A command killed by SIGTERM (``timeout``, ``kill``, a job scheduler) leaves no
temporary file, as Ctrl-C does (docs/conventions.md, "Output files"), and exits with
128 + the signal's number. Real subprocesses receive real signals; the figure writer is
made to wait after writing so that the signal arrives with both temporary files (the
map data and the figure) on disk."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

#: ``map --data --out`` whose figure writer writes, says so in ``ready`` and sleeps.
SLOW_WRITER = """
import sys, time
from pathlib import Path
import ppm_stiffness.visuals.maps as maps
original = maps.save_map_figure
def slow(fig, path):
    original(fig, path)
    Path(sys.argv[1]).write_text("written")
    time.sleep(120)
maps.save_map_figure = slow
from ppm_stiffness.cli import main
sys.exit(main(sys.argv[2:]))
"""


def _hidden(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def test_sigterm_during_the_write_leaves_no_temporary_file(tmp_path: Path) -> None:
    """Before the fix, SIGTERM killed the process at once (return code -15) and left
    ``.m.csv.XXXXXXXX.tmp.csv`` and ``.m.png.XXXXXXXX.tmp.png`` behind; Ctrl-C (SIGINT)
    already removed them (tests/test_cli_concurrency.py)."""
    out = tmp_path / "out"
    out.mkdir()
    ready = tmp_path / "ready"
    argv = ["map", "--grid", "12", "--quiet", "--data", str(out / "m.csv")]
    argv += ["--out", str(out / "m.png")]
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen(
        [sys.executable, "-c", SLOW_WRITER, str(ready), *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        deadline = time.monotonic() + 120
        while not ready.exists():
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "the map was not written in 120 s"
            time.sleep(0.02)
        hidden = _hidden(out)  # the temporary files the signal must not leave
        assert len(hidden) == 2 and all(".tmp." in name for name in hidden), hidden
        assert os.path.getsize(out / hidden[0]) > 0
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert os.listdir(out) == []  # neither the temporary files nor the targets
    assert proc.returncode == 128 + 15, err
    assert "Traceback" not in err and err.count("\n") == 1
    assert err.startswith("ppm-stiffness: ")


def test_sigterm_during_a_sweep_writes_the_partial_csv_and_exits_143(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A real SIGTERM sent to this process at the 5th design (the handler main installs
    turns it into Ctrl-C's path): the CSV holds the 4 designs done and says it is
    partial, the exit code is 143; after main returns, SIGTERM's handler is restored."""
    from ppm_stiffness.cli import main
    from ppm_stiffness.optimize.executors import SerialExecutor

    calls = {"n": 0}
    submit = SerialExecutor.submit

    def terminating(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def]
        calls["n"] += 1
        if calls["n"] == 5:
            os.kill(os.getpid(), signal.SIGTERM)
        return submit(self, fn, *args, **kwargs)

    monkeypatch.setattr(SerialExecutor, "submit", terminating)
    before = signal.getsignal(signal.SIGTERM)
    table = tmp_path / "s.csv"
    argv = ["sweep", "--design", str(Path(__file__).parents[1] / "examples/symmetric_3ppr.toml")]
    argv += ["--region=-10,10,-10,10,-5.7,5.7,3,3,3", "--quiet", "--csv", str(table)]
    argv += ["--vary", "leg*.platform_radius=0.02:0.04:6"]
    assert main(argv) == 128 + 15
    assert signal.getsignal(signal.SIGTERM) is before
    lines = table.read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("# partial: interrupted after 4 of 6 designs")
    assert len(lines) == 2 + 4  # the comment, the header, 4 rows
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.csv"]
