"""Reading the small CSV files the CLI takes: ``#`` comment lines, then rows."""

from __future__ import annotations

import csv
from pathlib import Path

from ppm_stiffness.core.errors import InputDataError


def read_commented_csv(path: str | Path) -> tuple[list[str], list[list[str]]]:
    """Comment lines (text after ``#``, stripped) and the other non-blank rows, as
    strings. Raises :class:`InputDataError` for a missing file, a directory or a file
    that is not UTF-8 text."""
    p = Path(path)
    if p.is_dir():
        raise InputDataError(f"{p}: is a directory")
    if not p.is_file():
        raise InputDataError(f"file not found: {p}")
    comments: list[str] = []
    rows: list[list[str]] = []
    try:
        with p.open(newline="", encoding="utf-8") as fh:
            for line in fh:
                s = line.strip()
                if s.startswith("#"):
                    comments.append(s[1:].strip())
                elif s:
                    rows.append(next(csv.reader([s])))
    except (OSError, UnicodeDecodeError) as exc:
        raise InputDataError(f"cannot read {p}: {exc}") from None
    return comments, rows
