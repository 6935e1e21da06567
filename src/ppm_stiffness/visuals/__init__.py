"""Pictures. Only this package imports matplotlib; the core never imports it.

Each module draws one kind of figure and returns a ``matplotlib.figure.Figure``;
:func:`save_figure` writes it in the format its suffix names (PNG, SVG, PDF).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


def save_figure(fig: Any, path: str | Path, dpi: int = 150) -> Path:
    """Save ``fig`` to ``path`` (format from the suffix) and close it."""
    import matplotlib.pyplot as plt

    p = Path(path)
    fig.savefig(p, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return p


def use_headless_backend() -> None:
    """Select the non-interactive Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
