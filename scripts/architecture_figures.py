"""Regenerate the architecture pictures of the docs: ``docs/figures/arch_*.png``.

Top views (:func:`ppm_stiffness.visuals.mechanism.plot_mechanism`) of the shipped
designs at their workspace centre::

    python scripts/architecture_figures.py            # writes docs/figures/arch_*.png
    python scripts/architecture_figures.py --out DIR  # elsewhere
"""

from __future__ import annotations

import argparse
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Output name -> design file (relative to the repository root).
FIGURES = {
    "arch_3ppr.png": "src/ppm_stiffness/data/paper_3ppr.toml",
    "arch_4ppr.png": "examples/redundant_4ppr.toml",
    "arch_3rpr.png": "examples/3rpr.toml",
    "arch_3prr.png": "examples/3prr.toml",
    "arch_3rrr.png": "examples/3rrr.toml",
}


def write_figures(out_dir: Path, dpi: int = 110) -> list[Path]:
    """Write every picture of :data:`FIGURES` into ``out_dir``; returns the paths."""
    from ppm_stiffness.design import load_design
    from ppm_stiffness.visuals import save_figure, use_headless_backend

    use_headless_backend()
    from ppm_stiffness.visuals.mechanism import plot_mechanism

    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, design_file in FIGURES.items():
        design = load_design(ROOT / design_file)
        fig = plot_mechanism(design)
        paths.append(save_figure(fig, out_dir / name, dpi=dpi))
    return paths


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out",
        type=Path,
        default=ROOT / "docs" / "figures",
        help="output directory (default docs/figures)",
    )
    args = parser.parse_args(argv)
    for path in write_figures(args.out):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
