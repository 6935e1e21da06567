"""Test configuration: make ``tests/`` importable (shared paper numbers) and
select matplotlib's headless backend."""

from __future__ import annotations

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
os.environ.setdefault("MPLBACKEND", "Agg")

from collections.abc import Callable  # noqa: E402
from typing import TYPE_CHECKING  # noqa: E402

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

if TYPE_CHECKING:
    from helpers import DocRun

# Property tests are seeded: the same examples on every run and in CI.
settings.register_profile("seeded", derandomize=True, print_blob=True)
settings.load_profile("seeded")


@pytest.fixture(scope="session")
def doc_runs() -> dict[str, DocRun]:
    """The Python blocks of docs/api.md and the README, run once per session (each block
    in a fresh namespace, from the top folder, a package DeprecationWarning an error):
    tests/test_examples.py reads what they print, tests/test_public_api.py that they
    use no deprecated name."""
    from helpers import DOC_PAGES, run_doc_blocks

    return {page: run_doc_blocks(page) for page in DOC_PAGES}


@pytest.fixture(scope="session")
def example_report() -> Callable[[str], str]:
    """The report page of an example (``helpers.design_named``) at its home pose with 6 x
    6 maps, built once per session: tests/test_spatial_report.py reads the spatial
    examples', tests/test_report_loaded.py the 3-RPS's (no wrench: no loaded section),
    tests/test_architecture_pictures.py the 3-RRR's."""
    from helpers import design_named
    from ppm_stiffness.visuals.report import build_report

    pages: dict[str, str] = {}

    def report(name: str) -> str:
        if name not in pages:
            pages[name] = build_report(design_named(name), grid=6)
        return pages[name]

    return report
