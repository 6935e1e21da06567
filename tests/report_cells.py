"""Reading a report page back: its traced number cells, ids and images, and the check
that every traced number equals its JSON value to its printed digits (shared by the
report tests)."""

from __future__ import annotations

import os
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pytest

from helpers import half_unit


class Cells(HTMLParser):
    """Collects (data-path, data-scale, text) of every traced number, ids, images."""

    def __init__(self) -> None:
        super().__init__()
        self.cells: list[tuple[str, float, str]] = []
        self.ids: set[str] = set()
        self.images: list[str] = []
        self._open: tuple[str, float] | None = None
        self._text = ""

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(str(a["id"]))
        if tag == "img":
            self.images.append(str(a.get("src")))
        if "data-path" in a:
            self._open = (str(a["data-path"]), float(a.get("data-scale") or 1.0))
            self._text = ""

    def handle_data(self, data: str) -> None:
        if self._open is not None:
            self._text += data

    def handle_endtag(self, tag: str) -> None:
        if self._open is not None and tag in ("td", "span"):
            self.cells.append((*self._open, self._text.strip()))
            self._open = None


def parse(page: str) -> Cells:
    p = Cells()
    p.feed(page)
    return p


def lookup(blocks: dict[str, dict], path: str) -> tuple[Any, Any]:
    """The value at ``path`` (``unloaded/stiffness_matrix/2/3``) and the top-level
    entry it lies in (``blocks["unloaded"]["stiffness_matrix"]``)."""
    parts = path.split("/")
    node: Any = blocks[parts[0]]
    for part in parts[1:]:
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node, blocks[parts[0]][parts[1]]


def max_abs(node: Any) -> float:
    if isinstance(node, dict):
        return max((max_abs(v) for v in node.values()), default=0.0)
    if isinstance(node, list):
        return max((max_abs(v) for v in node), default=0.0)
    return abs(node) if isinstance(node, (int, float)) else 0.0


def check_cells(cells: list[tuple[str, float, str]], blocks: dict[str, dict]) -> None:
    """Every traced number equals its JSON value (x its scale) to half a unit of its
    last printed digit; a printed 0 is round-off (at most 1e-9 of its entry's largest)."""
    for path, scale, text in cells:
        value, top = lookup(blocks, path)
        if text == "0":  # round-off of a structural zero
            assert abs(value) <= 1e-9 * max_abs(top), path
            continue
        shown = float(text)
        assert abs(shown - value * scale) <= half_unit(text) * (1 + 1e-9), (path, text, value)


def chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(page: Path, tmp_path: Path, height: int = 2000) -> Path:
    """A 1280 x ``height`` screenshot of ``page`` by headless Chromium (Debian's
    ``chromium``); skips where none is installed, fails in CI (.ci/run installs it)."""
    browser = chromium()
    if browser is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is missing in CI: .ci/run installs Debian's chromium")
        pytest.skip("chromium not installed: apt-get install chromium (.ci/run does)")
    shot = tmp_path / "shot.png"
    cmd = [
        browser,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={tmp_path / 'profile'}",
        f"--screenshot={shot}",
        f"--window-size=1280,{height}",
        page.resolve().as_uri(),
    ]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert shot.is_file(), res.stderr[-2000:]
    return shot
