"""Output files written whole or not at all, and never over another run's file.

Every command that writes files writes each to a temporary file in the target's
folder and, once all are written, moves them into place:

* with ``--overwrite``: ``os.replace(tmp, dest)``, atomic (a reader sees the old file
  or the new one, never a mix);
* without it: ``os.link(tmp, dest)``, which fails if ``dest`` exists (also when
  another run created it since the command's early check), then the temporary file is
  removed. The first run's file stays whole; the later run reports "file exists"
  (exit 2) and removes the files it had already put in place in this commit, so that
  a refused command leaves nothing behind. Where the file system has no hard links,
  an exclusive create (``open(dest, "xb")``) and a copy take their place (no
  clobbering, but a reader may then see a partly copied file).

A temporary file keeps the target's suffix (``.m.csv.1a2b3c4d.tmp.csv``), so that a
writer that picks its format from the suffix (matplotlib's ``savefig``) writes the
target's format; it is created with the permissions a new file gets (umask), and
removed if the command fails or is interrupted before the commit.

Use::

    with output_files(args.overwrite) as out:
        smap.to_csv(out.temp(args.data, "--data"))
        save_figure(fig, out.temp(args.out, "--out"))
    # committed here; InputDataError("... file exists ...") if another run was first
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from pathlib import Path

from ppm_stiffness.core.errors import InputDataError


@dataclass
class OutputFiles:
    """The temporary files of one command and where they go (see the module doc).

    Attributes
    ----------
    overwrite : bool
        The command's ``--overwrite``: replace existing files.
    pending : list of (tmp, dest, option)
        Temporary files written so far, their targets and the options that named them.
    """

    overwrite: bool
    pending: list[tuple[Path, Path, str]] = field(default_factory=list)

    def temp(self, path: str | Path, option: str) -> Path:
        """A new empty temporary file in ``path``'s folder, with ``path``'s suffix: the
        path to write instead of ``path`` (``option`` names it in errors)."""
        import secrets  # hashlib behind it: not for ``COMMAND --help``

        dest = Path(path)
        for _ in range(100):
            tmp = dest.with_name(f".{dest.name}.{secrets.token_hex(4)}.tmp{dest.suffix}")
            # registered before it exists: a signal (Ctrl-C, SIGTERM) that arrives as the
            # file is created then finds it in ``pending`` and the clean-up removes it
            self.pending.append((tmp, dest, option))
            try:
                fd = os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)
            except FileExistsError:  # pragma: no cover - 2^-32 per try
                self.pending.pop()  # another's file: not ours to remove
                continue
            os.close(fd)
            return tmp
        raise InputDataError(f"{option} {path}: cannot create a temporary file beside it")

    def commit(self) -> None:
        """Move every temporary file to its target (module doc), in order.

        Raises
        ------
        InputDataError
            Without ``overwrite``, a target that exists: the files this commit had put
            in place are removed again, and every temporary file is.
        """
        placed: list[tuple[Path, Path]] = []
        try:
            for tmp, dest, option in self.pending:
                if self.overwrite:
                    os.replace(tmp, dest)
                    continue
                try:
                    _link_new(tmp, dest)
                except FileExistsError:
                    for t, d in placed:  # leave nothing of this run behind
                        with suppress(OSError):
                            if os.path.samefile(t, d):
                                d.unlink()
                    raise InputDataError(
                        f"{option} {dest}: file exists (written by another run meanwhile); "
                        "pass --overwrite to replace it"
                    ) from None
                placed.append((tmp, dest))
        finally:
            self.discard()

    def discard(self) -> None:
        """Remove the temporary files (those not moved into place)."""
        while self.pending:  # an entry leaves the list once its file is gone
            tmp = self.pending[-1][0]
            with suppress(OSError):
                tmp.unlink(missing_ok=True)
            self.pending.pop()


def _link_new(tmp: Path, dest: Path) -> None:
    """Give ``tmp``'s content the new name ``dest``; FileExistsError if it exists."""
    try:
        os.link(tmp, dest)
        return
    except FileExistsError:
        raise
    except OSError:  # no hard links on this file system: exclusive create and copy
        pass
    with tmp.open("rb") as src, dest.open("xb") as out:
        try:
            shutil.copyfileobj(src, out)
        except BaseException:
            out.close()
            dest.unlink(missing_ok=True)
            raise


@contextmanager
def output_files(overwrite: bool) -> Iterator[OutputFiles]:
    """An :class:`OutputFiles` committed when the block ends without an exception and
    discarded when it raises (or is interrupted)."""
    files = OutputFiles(overwrite)
    try:
        yield files
    except BaseException:
        files.discard()
        raise
    try:
        files.commit()
    except BaseException:  # a signal during the commit's own clean-up: finish it
        files.discard()
        raise


__all__ = ["OutputFiles", "output_files"]
