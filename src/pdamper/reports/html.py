"""One self-contained HTML page of a case study: readable offline, in any browser.

Everything is inside the file: the figures as base64 PNG data URIs, the style sheet inline,
no script, no font or link to the network. The page holds the table of the paper's numbers
against ours with the agree column, the Level III models with their run times, the run time
of each step, the figures, the objective landscape and the inputs, with the pdamper version.
"""

from __future__ import annotations

import base64
import html
import json
from collections.abc import Sequence
from dataclasses import dataclass

_STYLE = """
body { font-family: -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 2em auto;
       max-width: 1200px; color: #222; line-height: 1.4; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { margin-top: 1.8em; font-size: 1.25em;
     border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #f0f0f0; }
td.yes { background: #dff0d8; } td.no { background: #f2dede; font-weight: bold; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #555; }
pre { background: #f7f7f7; padding: 0.8em; overflow-x: auto; font-size: 0.8em; }
.summary { font-size: 1.05em; }
"""


@dataclass(frozen=True)
class ReportFigure:
    """A figure of the report: file name, caption and PNG bytes."""

    name: str
    caption: str
    png: bytes


def _e(value) -> str:
    return html.escape(str(value), quote=True)


def _img(fig: ReportFigure) -> str:
    if fig.png[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{fig.name} is not a PNG image")
    data = base64.b64encode(fig.png).decode("ascii")
    return (f'<figure id="{_e(fig.name)}"><img src="data:image/png;base64,{data}" '
            f'alt="{_e(fig.caption)}"><figcaption>{_e(fig.name)}: {_e(fig.caption)}'
            "</figcaption></figure>")


def _table(header: Sequence[str], rows: Sequence[Sequence], table_id: str,
           classes: Sequence[Sequence[str]] | None = None) -> str:
    head = "".join(f"<th>{_e(h)}</th>" for h in header)
    body = []
    for k, row in enumerate(rows):
        cls = classes[k] if classes else [""] * len(row)
        cells = "".join(f'<td class="{c}">{_e(v)}</td>' if c else f"<td>{_e(v)}</td>"
                        for v, c in zip(row, cls, strict=True))
        body.append(f"<tr>{cells}</tr>")
    return (f'<table id="{table_id}"><thead><tr>{head}</tr></thead><tbody>'
            + "".join(body) + "</tbody></table>")


def render_report(*, title: str, version: str, rows: Sequence, figures: Sequence[ReportFigure],
                  models: Sequence[dict], timings: dict[str, float], landscape: Sequence[dict],
                  at: float, inputs: dict) -> str:
    """The page as a string.

    Parameters
    ----------
    title
        Heading of the page.
    version
        pdamper version.
    rows
        The comparison rows (``quantity``, ``paper``, ``ours``, ``agrees``, ``source``,
        ``note`` attributes), e.g. :class:`pdamper.runs.paper_case_study.Row`.
    figures
        The figures, in order.
    models
        One dict per Level III model: ``label``, ``model``, ``source``,
        ``amplitude_0p75`` [m] (None: the run ends before), ``final_amplitude`` [m],
        ``seconds`` (None: not timed).
    timings
        Wall time of each step [s].
    landscape
        The optimisation candidates (``particles``, ``mass``, ``objective``).
    at
        Objective time of the landscape [s].
    inputs
        The inputs, as recorded in results.json.
    """
    agree = sum(r.agrees is True for r in rows)
    verdict = {True: ("yes", "yes"), False: ("no", "no"), None: ("", "")}
    comparison = _table(
        ["quantity", "paper", "pdamper", "agrees", "source", "note"],
        [[r.quantity, r.paper, r.ours, verdict[r.agrees][0], r.source, r.note] for r in rows],
        "comparison",
        [["", "", "", verdict[r.agrees][1], "", ""] for r in rows])
    model_rows = [[m["label"], m["model"], m["source"],
                   "" if m["amplitude_0p75"] is None else f"{m['amplitude_0p75'] * 1e3:.2f}",
                   f"{m['final_amplitude'] * 1e3:.2f}",
                   "" if m["seconds"] is None else f"{m['seconds']:.3f}"] for m in models]
    model_table = _table(["run", "model", "damper data", "amplitude at 0.75 s [mm]",
                          "final amplitude [mm]", "wall time [s]"], model_rows, "models",
                         [["", "", "", "num", "num", "num"]] * len(model_rows))
    timing_table = _table(["step", "wall time [s]"],
                          [[k, f"{v:.3f}"] for k, v in timings.items()], "timings",
                          [["", "num"]] * len(timings))
    land_table = _table(["particles", "mass [g]", f"amplitude at {at:g} s [mm]"],
                        [[c["particles"], f"{c['mass'] * 1e3:.1f}",
                          f"{c['objective'] * 1e3:.2f}"] for c in landscape], "landscape",
                        [["num", "num", "num"]] * len(landscape))
    parts = [
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_e(title)}</title>", f"<style>{_STYLE}</style>", "</head>", "<body>",
        f"<h1>{_e(title)}</h1>",
        f'<p class="summary">pdamper {_e(version)}. <strong>{agree} of {len(rows)}</strong> '
        "reported numbers of the reference paper agree within the tolerance each row states "
        "(see the note of each row).</p>",
        "<h2>The paper's numbers against ours</h2>", comparison,
        "<h2>Level III models (Figs. 7 and 8)</h2>", model_table,
        "<h2>Run times</h2>", timing_table,
        "<h2>Figures</h2>", *(_img(f) for f in figures),
        "<h2>Objective landscape (Sect. 4.2.2)</h2>", land_table,
        "<h2>Inputs</h2>", f"<pre>{_e(json.dumps(inputs, indent=2))}</pre>",
        f"<p>Generated by pdamper {_e(version)}.</p>",
        "</body>", "</html>",
    ]
    return "\n".join(parts) + "\n"
