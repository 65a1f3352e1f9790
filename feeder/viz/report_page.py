"""The report page of a mechanism's run (``report.html`` of ``feeder analyze`` and ``feeder
simulate``): one self-contained HTML file that opens offline.

It holds, in this order: the run's summary (the mobility report, the assembled pose, the peak of
every load with its time, and for a forward run its drift and energy balance), any tables, the
3-D view of the mechanism over the run (the viewer's own page,
:func:`~feeder.viz.viewer.mechanism_html`, in an ``iframe`` of its own; none on the page of
``feeder design optimize``), and every figure (PNG, embedded) under its file name.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Mapping, Sequence

_STYLE = """
body { font: 14px/1.45 sans-serif; color: #222; margin: 24px auto; max-width: 1100px;
  padding: 0 16px; }
h1 { font-size: 20px; } h2 { font-size: 16px; margin-top: 28px; }
pre { background: #f5f6f8; padding: 10px 12px; white-space: pre-wrap; font-size: 12.5px; }
iframe { width: 100%; height: 640px; border: 1px solid #ccd; }
figure { margin: 18px 0; } figure img { max-width: 100%; border: 1px solid #e3e5ea; }
figcaption { font-size: 12px; color: #555; }
table { border-collapse: collapse; font-size: 12px; }
th, td { border: 1px solid #dde; padding: 2px 6px; text-align: left; }
"""


def report_page(
    title: str,
    command: str,
    summary: str,
    view: str | None,
    figures: Mapping[str, bytes],
    heading: str = "Summary: mobility, assembled pose, peak loads",
    tables: Mapping[str, Sequence[Sequence[str]]] | None = None,
) -> str:
    """The report page as HTML text.

    Args:
        title: The page's heading (the mechanism and what was run).
        command: The command line that made the run.
        summary: The run's summary text (``summary.txt``).
        view: The viewer's self-contained HTML page (embedded in an iframe's ``srcdoc``), or
            None for a page without one (``feeder design optimize``'s).
        figures: PNG bytes by file name, in the order shown.
        heading: The summary's heading.
        tables: CSV tables by file name (the header row first), shown after the summary.
    """
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p><code>{html.escape(command)}</code></p>",
        f"<h2>{html.escape(heading)}</h2>",
        f'<pre id="summary">{html.escape(summary)}</pre>',
    ]
    for name, rows in (tables or {}).items():
        parts += [f"<h2>{html.escape(name)}</h2>", "<table>", _row(rows[0], "th")]
        parts += [_row(row, "td") for row in rows[1:]] + ["</table>"]
    if view is not None:
        parts += [
            "<h2>The mechanism over the run (drag to turn, scroll to zoom)</h2>",
            f'<iframe id="view" title="3-D view" srcdoc="{html.escape(view, quote=True)}">'
            "</iframe>",
        ]
    parts.append("<h2>Figures</h2>")
    for name, png in figures.items():
        data = base64.b64encode(png).decode("ascii")
        parts.append(
            f'<figure><img alt="{html.escape(name)}" src="data:image/png;base64,{data}">'
            f"<figcaption>{html.escape(name)}</figcaption></figure>"
        )
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def _row(cells: Sequence[str], tag: str) -> str:
    """One table row of ``cells``, each escaped, in ``<th>`` or ``<td>`` cells."""
    return "<tr>" + "".join(f"<{tag}>{html.escape(c)}</{tag}>" for c in cells) + "</tr>"
