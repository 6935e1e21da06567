"""HTML building blocks of the report: number cells that carry their JSON path,
tables, matrices, embedded figures, the page's CSS and its JSON data block.

Every number cell is ``<td class="num" data-path=... data-scale=...>`` so that tests can
trace each shown value back to the analysis JSON embedded in the page.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Sequence
from typing import Any

import numpy as np


# ----------------------------------------------------------------------------- numbers
def format_number(value: float, sig: int = 5) -> str:
    """``value`` with ``sig`` significant digits; fixed notation from 1e-3 to 1e7."""
    v = float(value)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if v == 0.0:
        return "0"
    e = math.floor(math.log10(abs(v)))
    if -3 <= e < 7:
        return f"{v:.{max(sig - 1 - e, 0)}f}"
    return f"{v:.{sig - 1}e}"


def cell(value: float, path: str, scale: float = 1.0, sig: int = 5, ref: float = 0.0) -> str:
    """A <td> with the number (SI x scale), its data-path and data-scale.

    Values below ``1e-12 * ref`` in magnitude (round-off of structural zeros) show 0.
    ``data-scale`` is the scale in full (the shortest text that reads back as the same
    float), so that a reader recovers the SI value to the printed digits.
    """
    v = float(value)
    text = "0" if abs(v) < 1e-12 * ref else format_number(v * scale, sig)
    return f'<td class="num" data-path="{path}" data-scale="{float(scale)!r}">{text}</td>'


def esc(text: Any) -> str:
    return html.escape(str(text), quote=True)


def table(
    head: Sequence[str], rows: Sequence[Sequence[str]], caption: str = "", cls: str = ""
) -> str:
    """A table; ``rows`` hold ready-made cells (``<td>`` strings) or plain text."""
    out = [f'<table class="{cls}">' if cls else "<table>"]
    if caption:
        out.append(f"<caption>{caption}</caption>")
    out.append("<thead><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr></thead><tbody>")
    for row in rows:
        cells = [c if c.startswith("<td") or c.startswith("<th") else f"<td>{c}</td>" for c in row]
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def matrix(
    m: Any,
    path: str,
    rows: Sequence[str],
    cols: Sequence[str],
    sig: int = 5,
    caption: str = "",
    cls: str = "",
) -> str:
    a = np.asarray(m, dtype=float)
    ref = float(np.max(np.abs(a))) if a.size else 0.0
    body = [
        [f"<th>{rows[i]}</th>"]
        + [cell(a[i, j], f"{path}/{i}/{j}", sig=sig, ref=ref) for j in range(a.shape[1])]
        for i in range(a.shape[0])
    ]
    return table([""] + list(cols), body, caption, cls)


def vector_cells(v: Any, path: str, scale: float = 1.0, sig: int = 4) -> list[str]:
    a = np.asarray(v, dtype=float)
    ref = float(np.max(np.abs(a))) if a.size else 0.0
    return [cell(a[j], f"{path}/{j}", scale, sig, ref) for j in range(a.size)]


# ----------------------------------------------------------------------------- figures
def figure_data_uri(fig: Any, dpi: int = 100) -> str:
    """The figure as a ``data:image/png;base64,...`` URI; closes the figure.

    A figure with a layout engine (constrained layout) already fits its canvas and is
    saved as it is; only the others are cropped to their tight bounding box, which costs
    a second draw (half the time of a report went there)."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    tight = "tight" if fig.get_layout_engine() is None else None
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches=tight)
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def figure_block(uri: str, caption: str, fig_id: str) -> str:
    return (
        f'<figure id="{fig_id}"><img src="{uri}" alt="{esc(caption)}">'
        f"<figcaption>{caption}</figcaption></figure>"
    )


CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;
 margin:0;background:#f4f5f7;color:#1d232b;line-height:1.45}
main{max-width:1180px;margin:0 auto;padding:24px 32px 64px;background:#fff}
h1{font-size:1.7em;margin:0 0 .2em}h2{border-bottom:2px solid #2f6db5;padding-bottom:.2em;
 margin-top:2.2em;color:#23508a}h3{margin:1.4em 0 .4em;color:#333}
.meta{color:#555;font-size:.92em}nav ol{columns:2;font-size:.95em}
table{border-collapse:collapse;margin:.6em 1.2em .9em 0;font-size:.86em}
caption{caption-side:top;text-align:left;font-weight:600;padding:.3em 0}
th,td{border:1px solid #d3d8de;padding:3px 8px}th{background:#eef2f7;font-weight:600}
td.num{text-align:right;font-variant-numeric:tabular-nums;font-family:ui-monospace,
 "DejaVu Sans Mono",monospace}
table.matrix tbody tr:nth-child(-n+3) td:nth-of-type(-n+3),
table.matrix tbody tr:nth-child(n+4) td:nth-of-type(n+4){background:#f6f9fd}
.cols{display:flex;flex-wrap:wrap;gap:0 16px;align-items:flex-start}
figure{margin:1em 0;text-align:center}figure img{max-width:100%;height:auto;
 border:1px solid #e1e4e8}figcaption{font-size:.9em;color:#444;margin-top:.3em}
.cards{display:flex;gap:16px;margin:1em 0}.card{border:1px solid #cfd8e3;border-radius:8px;
 padding:10px 18px;background:#f6f9fd;font-size:1.05em}.card .name{font-size:.9em;color:#555}
.card span{font-weight:700;font-size:1.35em;font-family:ui-monospace,"DejaVu Sans Mono",
 monospace}.note{background:#fff8e6;border-left:4px solid #e0a800;padding:8px 12px;
 font-size:.92em}pre{background:#f6f8fa;padding:10px;font-size:.8em;overflow:auto}
"""


def json_block(block_id: str, data: dict[str, Any]) -> str:
    """An analysis (:func:`ppm_stiffness.analysis.analyze_design`) embedded as the very
    document ``ppm-stiffness analyze --json`` prints, in a ``<script>`` element."""
    from ppm_stiffness.analysis import ANALYSIS_UNITS, json_document

    text = json_document("analyze", data, ANALYSIS_UNITS)
    text = text.replace("</", "<\\/").replace("<!--", "<\\!--")
    return f'<script type="application/json" id="{block_id}">{text}</script>'
