"""Test configuration: make ``tests/`` importable (shared paper numbers) and
select matplotlib's headless backend."""

from __future__ import annotations

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import settings  # noqa: E402

# Property tests are seeded: the same examples on every run and in CI.
settings.register_profile("seeded", derandomize=True, print_blob=True)
settings.load_profile("seeded")
