"""Reading the small CSV files the CLI takes: ``#`` comment lines, then rows.

Each comment and row keeps its line number in the file (1-based, as a text editor
shows it, comment and blank lines counted), so that an error can name the line. Every
CSV reader of the package reads through :func:`read_numbered_csv` (measurements,
force-displacement data, ``--matrix`` and ``--target`` matrices), which accepts UTF-8
with or without a byte-order mark (:data:`CSV_ENCODING`: spreadsheet programs write
one). A reader of a file with a header row takes its names from :func:`header_columns`,
which refuses a column named twice.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

from ppm_stiffness.core.errors import InputDataError

#: The encoding of the CSV files read: UTF-8, a leading byte-order mark dropped.
CSV_ENCODING = "utf-8-sig"


@dataclass(frozen=True)
class CommentedCsv:
    """A CSV file's comment lines and rows, with their line numbers.

    Attributes
    ----------
    comments : list of str
        Text after ``#``, stripped.
    comment_lines : list of int
        Line number (1-based) of each comment.
    rows : list of list of str
        The other non-blank lines, split into fields (the header is the first).
    row_lines : list of int
        Line number (1-based) of each row.
    """

    comments: list[str]
    comment_lines: list[int]
    rows: list[list[str]]
    row_lines: list[int]


def read_numbered_csv(path: str | Path) -> CommentedCsv:
    """Comment lines and the other non-blank rows (as strings) with their line numbers.
    Raises :class:`InputDataError` for a missing file, a directory or a file that is
    not UTF-8 text (a byte-order mark is allowed: :data:`CSV_ENCODING`)."""
    p = Path(path)
    if p.is_dir():
        raise InputDataError(f"{p}: is a directory")
    if not p.is_file():
        raise InputDataError(f"file not found: {p}")
    out = CommentedCsv([], [], [], [])
    try:
        with p.open(newline="", encoding=CSV_ENCODING) as fh:
            for number, line in enumerate(fh, start=1):
                s = line.strip()
                if s.startswith("#"):
                    out.comments.append(s[1:].strip())
                    out.comment_lines.append(number)
                elif s:
                    out.rows.append(next(csv.reader([s])))
                    out.row_lines.append(number)
    except (OSError, UnicodeDecodeError) as exc:
        raise InputDataError(f"cannot read {p}: {exc}") from None
    return out


def header_columns(path: str | Path, row: list[str]) -> list[str]:
    """The header row's column names (stripped), each once.

    Raises
    ------
    InputDataError
        ``"FILE: column 'force_N' appears more than once (columns 2 and 3); give each
        column once"``: a reader that looks a name up would take one of the two
        silently.
    """
    names = [c.strip() for c in row]
    for j, name in enumerate(names):
        if name in names[:j]:
            first = names.index(name)
            raise InputDataError(
                f"{path}: column {name!r} appears more than once (columns {first + 1} and "
                f"{j + 1}); give each column once"
            )
    return names


def read_commented_csv(path: str | Path) -> tuple[list[str], list[list[str]]]:
    """Comment lines (text after ``#``, stripped) and the other non-blank rows, as
    strings (:func:`read_numbered_csv` without the line numbers)."""
    data = read_numbered_csv(path)
    return data.comments, data.rows
