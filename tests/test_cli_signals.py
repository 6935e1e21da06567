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


@pytest.mark.parametrize(
    "signum",
    [signal.SIGTERM, getattr(signal, "SIGHUP", None)],
    ids=["SIGTERM", "SIGHUP"],
)
def test_sigterm_during_the_write_leaves_no_temporary_file(
    tmp_path: Path, signum: signal.Signals | None
) -> None:
    """Before the fix, SIGTERM killed the process at once (return code -15) and left
    ``.m.csv.XXXXXXXX.tmp.csv`` and ``.m.png.XXXXXXXX.tmp.png`` behind; Ctrl-C (SIGINT)
    already removed them (tests/test_cli_concurrency.py). SIGHUP (a closed terminal, a
    lost ssh session) did the same until issue 27's attack found it (return code -1, a
    16 KB temporary CSV left): now both exit with 128 + the signal's number."""
    if signum is None:  # pragma: no cover - Windows
        pytest.skip("no SIGHUP on this platform")
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
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert os.listdir(out) == []  # neither the temporary files nor the targets
    assert proc.returncode == 128 + int(signum), err
    assert err == f"ppm-stiffness: terminated ({signum.name})\n"


def test_a_signal_as_the_temporary_file_is_created_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The signal arrives the instant the temporary file exists, before ``temp`` returns
    (issue 27's attack: SIGTERM sent when ``.x.csv.*.tmp.csv`` appeared left it, 0 bytes,
    because the file was registered for clean-up only after it was created)."""
    from ppm_stiffness.cli import Terminated
    from ppm_stiffness.cli.output_files import output_files

    real_open = os.open

    def open_then_signal(path, flags, mode=0o777):  # type: ignore[no-untyped-def]
        os.close(real_open(path, flags, mode))
        raise Terminated(signal.SIGTERM)

    with pytest.raises(Terminated), output_files(overwrite=False) as out:
        monkeypatch.setattr(os, "open", open_then_signal)
        out.temp(tmp_path / "x.csv", "--data")
    monkeypatch.undo()
    assert os.listdir(tmp_path) == []


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
    argv += ["--vary", "leg*.platform_radius=0.02:0.04:6", "--link-modes", "0"]
    assert main(argv) == 128 + 15
    assert signal.getsignal(signal.SIGTERM) is before
    lines = table.read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("# partial: interrupted after 4 of 6 designs")
    assert len(lines) == 2 + 4  # the comment, the header, 4 rows
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.csv"]


def test_an_interrupted_report_leaves_no_empty_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``report --out rep`` creates ``rep``; interrupted as report.html is written (issue
    27's attack: SIGTERM at the first temporary file) it left ``rep/`` behind, empty."""
    import ppm_stiffness.visuals.report as report
    from ppm_stiffness.cli import Terminated, main
    from ppm_stiffness.cli.output_files import OutputFiles

    def interrupted(self: OutputFiles) -> None:
        raise Terminated(signal.SIGTERM)

    monkeypatch.setattr(report, "build_report", lambda *args: "<html></html>")
    monkeypatch.setattr(OutputFiles, "commit", interrupted)
    # 130, Ctrl-C's code: no real signal reached the handler main installs
    assert main(["report", "--out", str(tmp_path / "rep"), "--quiet"]) == 130
    assert capsys.readouterr().err == "ppm-stiffness: terminated (SIGTERM)\n"
    assert os.listdir(tmp_path) == []
