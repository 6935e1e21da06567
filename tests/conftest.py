"""Test configuration: make ``tests/`` importable (shared paper numbers) and
select matplotlib's headless backend."""

from __future__ import annotations

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
os.environ.setdefault("MPLBACKEND", "Agg")
