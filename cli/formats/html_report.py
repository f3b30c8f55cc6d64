"""The HTML report per program (``cnc run --html``), viewable offline.

Sections: the backplot (an interactive 3-D view of the toolpath drawn by plotly.js, a lathe
program in the ZX plane, beside the program listing: hovering a move names its source line
and feed, clicking a listing line or a finding draws its move in red), summary, cycle-time
breakdown (table and proportional bars), check findings and diagnostics with their source
lines, servo errors, limit hits, then the XY path and one plot per axis (commanded against
actual) as PNG.

Nothing is fetched from the network: CSS, the page's script (``assets/report.js``), the
data and the PNG plots are inline; plotly.js (vendored in ``assets/``, MIT) is either
inline too (``library="inline"``: one file that can be mailed) or the relative file name of
a copy written beside the page (a batch writes it once per output folder).
"""

from __future__ import annotations

import base64
import json
from html import escape
from importlib import resources
from typing import Any

import numpy as np

from kernel.report.backplot import GOUGE_RED, LEFT_BLUE, Backplot, Surface, deviation_scale
from kernel.report.clock import clock

#: the file name of plotly.js beside the reports of a batch
PLOTLY_FILE = "plotly.min.js"
#: the listing holds at most this many lines (the view keeps all of them)
LISTING_LINES = 300_000
#: and at most this many characters
LISTING_CHARS = 24_000_000
#: colours of the tools in the view, in order of appearance
_TOOL_COLOURS = (
    "#1f77b4",
    "#2ca02c",
    "#9467bd",
    "#ff7f0e",
    "#17becf",
    "#8c564b",
    "#e377c2",
    "#bcbd22",
    "#7f7f7f",
    "#d62728",
)

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em;color:#222;
max-width:1500px}
h1{font-size:1.4em;margin-bottom:.2em}h2{font-size:1.1em;margin-top:1.6em;
border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:.25em .6em;
text-align:left;vertical-align:top}th{background:#f3f3f3}td.num{text-align:right;
font-variant-numeric:tabular-nums}
.ok{color:#176f2c}.findings{color:#9a6700}.error{color:#b42318}
.sev-error{color:#b42318;font-weight:bold}.sev-warning{color:#9a6700}.sev-note{color:#175cd3}
.bar{background:#4e79a7;height:.9em;display:inline-block}
img{max-width:100%;border:1px solid #ddd;margin:.4em 0}
.chart{width:100%;height:520px;border:1px solid #ddd;margin:.4em 0}
.bp{display:flex;gap:.8em;align-items:stretch}
#cnc-plot{flex:3;min-width:0;height:620px;border:1px solid #ddd}
#cnc-listing{flex:2;min-width:0;height:620px;overflow:auto;position:relative;
border:1px solid #ddd;font:12px/16px ui-monospace,Menlo,Consolas,monospace;background:#fafafa}
#cnc-rows{position:absolute;left:0;right:0}
.ln{height:16px;white-space:pre;overflow:hidden;text-overflow:ellipsis;cursor:pointer;
padding-right:.4em}.ln:hover{background:#eef3fb}
.ln .no{display:inline-block;width:6ch;padding-right:.6em;text-align:right;color:#888;
user-select:none}
.ln.hov{background:#fff4cc}.ln.sel{background:#ffd6dc}
tr[data-line]{cursor:pointer}tr[data-line]:hover{background:#eef3fb}
.note{color:#555;font-size:.92em}
"""


def _num(v: Any, digits: int = 3) -> str:
    try:
        return f"{float(v):.{digits}f}"
    except (TypeError, ValueError):
        return escape(str(v))


def _table(
    head: list[str],
    rows: list[list[str]],
    numeric: set[int] | None = None,
    lines: list[int] | None = None,
) -> str:
    """A table; a row with a source line in ``lines`` (0: none) selects it when clicked."""
    numeric = numeric or set()
    out = ["<table><tr>", *(f"<th>{escape(h)}</th>" for h in head), "</tr>"]
    for k, row in enumerate(rows):
        line = lines[k] if lines else 0
        out.append(f'<tr data-line="{line}">' if line else "<tr>")
        for i, cell in enumerate(row):
            cls = ' class="num"' if i in numeric else ""
            out.append(f"<td{cls}>{cell}</td>")
        out.append("</tr>")
    out.append("</table>")
    return "".join(out)


def _cycle(measure: dict[str, Any]) -> str:
    cycle = measure.get("cycle", {})
    total = float(cycle.get("total", 0.0)) or 1.0
    rows = []
    for key in ("cutting", "rapid", "dwell", "tool_change", "other", "total"):
        val = float(cycle.get(key, 0.0))
        width = 0 if key == "total" else round(300 * val / total)
        bar = f'<span class="bar" style="width:{width}px"></span>' if width else ""
        rows.append([escape(key.replace("_", " ")), _num(val), f"{100 * val / total:.1f} %", bar])
    return _table(["activity", "time [s]", "share", ""], rows, {1, 2})


def _cycle_time(total: Any) -> str:
    """A cycle time as m:ss with its seconds beside it."""
    try:
        seconds = float(total)
    except (TypeError, ValueError):
        return escape(str(total))
    return f"{escape(clock(seconds))} ({seconds:.3f} s)"


def _times(times: dict[str, Any]) -> str:
    """Time per tool (tool change to tool change) and, for STEP-NC, per workingstep, as m:ss
    (kernel.report.clock); seconds in the cells' titles."""
    parts = []
    if "cycle" in times:
        total = float(times["cycle"])
        parts.append(f"<p>cycle time {escape(clock(total))} ({total:.3f} s)</p>")
    for key, title, first in (
        ("tools", "Time per tool", "tool"),
        ("operations", "Time per operation (workingstep)", "operation"),
    ):
        rows = []
        for s in times.get(key) or []:
            cells = [escape(str(s.get("label", "")))]
            if first == "operation":
                cells.append(escape(str(s.get("tool", ""))))
            cells.append(escape(str(s.get("line") or "")))
            for col in ("start", "cutting", "rapid", "dwell", "tool_change", "other", "total"):
                v = float(s.get(col, 0.0))
                cells.append(f'<span title="{v:.3f} s">{escape(clock(v))}</span>')
            rows.append(cells)
        if not rows:
            continue
        head = [first, *(["tool"] if first == "operation" else []), "line"]
        head += ["start [m:s]", "cutting [m:s]", "rapid [m:s]", "dwell [m:s]"]
        head += ["tool change [m:s]", "other [m:s]", "total [m:s]"]
        skip = len(head) - 8
        parts += [f"<h2>{title}</h2>", _table(head, rows, set(range(skip, len(head))))]
    return "\n".join(parts)


def _line(v: Any) -> int:
    """A record's source line as an int (0: none)."""
    try:
        return max(int(v or 0), 0)
    except (TypeError, ValueError):
        return 0


def _issues(doc: dict[str, Any]) -> str:
    rows = []
    lines = [_line(r.get("line")) for r in (*doc.get("findings", []), *doc.get("diagnostics", []))]
    for f in doc.get("findings", []):
        sev = escape(str(f.get("severity")))
        code = f.get("rule", "") + (f"/{f['code']}" if f.get("code") else "")
        rows.append(
            [
                f'<span class="sev-{sev}">{sev}</span>',
                escape(code),
                escape(str(f.get("line") or "")),
                escape(str(f.get("message", ""))),
            ]
        )
    for d in doc.get("diagnostics", []):
        sev = escape(str(d.get("severity")))
        rows.append(
            [
                f'<span class="sev-{sev}">{sev}</span>',
                escape(str(d.get("code"))),
                escape(str(d.get("line") or "")),
                escape(str(d.get("message", ""))),
            ]
        )
    if not rows:
        return "<p>No findings.</p>"
    return _table(["severity", "rule / code", "line", "message"], rows, {2}, lines)


def _servo(servo: dict[str, Any]) -> str:
    rows = []
    for axis, peak in servo.get("following_error", {}).items():
        rows.append(
            [
                f"following error {escape(axis.upper())}",
                _num(1000 * float(peak["value"]), 2),
                _num(peak["time"]),
                escape(str(peak["line"])),
            ]
        )
    ce = servo.get("contour_error")
    if ce:
        rows.append(
            ["contour error", _num(1000 * float(ce["value"]), 2), _num(ce["time"]), str(ce["line"])]
        )
    return _table(["largest", "value [µm]", "time [s]", "line"], rows, {1, 2, 3})


def _hits(measure: dict[str, Any]) -> str:
    hits = measure.get("hits", [])
    if not hits:
        return "<p>No axis limit exceeded.</p>"
    rows = [
        [
            escape(str(h["line"])),
            _num(h["time"]),
            escape(str(h["axis"]).upper()),
            escape(str(h["kind"])),
            _num(h["value"], 4),
            _num(h["limit"], 4),
            escape(str(h["samples"])),
        ]
        for h in hits
    ]
    head = ["line", "time [s]", "axis", "limit", "value", "bound", "samples"]
    return _table(head, rows, {0, 1, 4, 5, 6}, [_line(h["line"]) for h in hits])


def plotly_js() -> str:
    """The vendored plotly.js (``assets/plotly.min.js``, MIT; see ``assets/README.md``)."""
    return resources.files("cli.formats").joinpath("assets", PLOTLY_FILE).read_text("utf-8")


def _asset(name: str) -> str:
    return resources.files("cli.formats").joinpath("assets", name).read_text("utf-8")


def _b64(a: np.ndarray, dtype: str) -> str:
    """``a`` as base64 of little-endian ``dtype`` (the page decodes typed arrays)."""
    return base64.b64encode(np.ascontiguousarray(a, dtype=dtype).tobytes()).decode("ascii")


def _listing(source: str | None) -> tuple[list[str], str]:
    """The listing's lines (capped at :data:`LISTING_LINES` and :data:`LISTING_CHARS`) and a
    note when it was cut."""
    if source is None:
        return [], ""
    text = source[:LISTING_CHARS]
    if text.endswith("\n"):
        text = text[:-1]  # the last line's end makes no empty line
    lines = text.split("\n")[:LISTING_LINES]
    if len(text) < len(source) or len(lines) == LISTING_LINES:
        total = source.count("\n") + (not source.endswith("\n"))
        if len(lines) < total:
            return lines, f"The listing shows the first {len(lines)} of {total} lines."
    return lines, ""


def _tool_name(tool: str) -> str:
    """``T3 `` for tool 3, a STEP-NC tool by its name, nothing before the first change."""
    if not tool:
        return ""
    return f"T{tool} " if tool.isdigit() else f"{tool} "


def view_data(
    bp: Backplot | None, surface: Surface | None, listing: list[str], library: str
) -> dict[str, Any]:
    """The JSON the page's script draws: traces as base64 typed arrays, boxes, surface."""
    out: dict[str, Any] = {"listing": listing, "library": library, "traces": [], "boxes": []}
    if bp is None:
        return out
    out["dim"] = 2 if bp.lathe else 3
    out["labels"] = list(bp.labels)
    axes = ("x", "y") if bp.lathe else ("x", "y", "z")
    colours: dict[str, str] = {}
    for tr in bp.traces:
        colour = colours.setdefault(tr.tool, _TOOL_COLOURS[len(colours) % len(_TOOL_COLOURS)])
        item: dict[str, Any] = {
            "name": _tool_name(tr.tool) + ("rapid" if tr.rapid else "feed"),
            "rapid": tr.rapid,
            "color": colour,
            "dash": "dash" if tr.rapid else "solid",
            "width": 2 if tr.rapid else 4,
            "line": _b64(tr.lines, "<i4"),
            "feed": _b64(tr.feeds, "<f4"),
        }
        for k, ax in enumerate(axes):
            item[ax] = _b64(tr.points[:, k], "<f4")
        out["traces"].append(item)
    for name, edges in bp.edges:
        box: dict[str, Any] = {
            "name": name,
            "color": "#8a6d3b" if name == "stock" else "#999999",
            "dash": "solid" if name == "stock" else "dot",
            "shown": name == "stock",  # the travel box dwarfs most parts: shown on request
        }
        for k, ax in enumerate(axes):
            box[ax] = _b64(edges[:, k], "<f4")
        out["boxes"].append(box)
    if surface is not None and not bp.lathe:
        ny, nx = surface.z.shape
        out["surface"] = {
            "x0": surface.x0,
            "y0": surface.y0,
            "x1": surface.x1,
            "y1": surface.y1,
            "nx": nx,
            "ny": ny,
            "z": _b64(surface.z, "<f4"),
        }
        if surface.dev is not None:
            span, scale = deviation_scale(surface)
            out["surface"]["deviation"] = {
                # cells the design does not cover are drawn neutral (0)
                "values": _b64(np.nan_to_num(surface.dev, nan=0.0), "<f4"),
                "span": span,
                "tol": surface.tol,
                "colorscale": [list(stop) for stop in scale],
                "marks": [
                    {
                        "label": m.label,
                        "x": m.x,
                        "y": m.y,
                        "z": m.z,
                        "value": m.value,
                        "line": m.line,
                        "color": GOUGE_RED if m.value < 0 else LEFT_BLUE,
                    }
                    for m in surface.marks
                ],
            }
    return out


def _script_json(value: Any) -> str:
    """JSON safe inside a ``<script>`` element."""
    return json.dumps(value, separators=(",", ":")).replace("<", "\\u003c")


def _backplot(
    bp: Backplot | None,
    surface: Surface | None,
    source: str | None,
    library: str,
    note: str = "",
) -> list[str]:
    """The backplot section: the view, the listing beside it, the notes, and the scripts."""
    lines, cut = _listing(source)
    notes = []
    if bp is None:
        notes.append(note or "No moves to draw: the program was not simulated.")
    else:
        notes.append(
            f"{bp.moves} moves; feed moves solid, rapids dashed, one colour per tool"
            + "".join(
                "; the stock as a box" if name == "stock" else "; travel limits in the legend"
                for name, _ in bp.edges
            )
            + (f"; a lathe program drawn in the ZX plane, {bp.labels[1]}" if bp.lathe else "")
            + ". Hover a move for its line and feed; click a listing line or a finding to"
            " draw its move in red."
        )
        if bp.decimated:
            notes.append(
                f"The view is decimated for display: {bp.points} of {bp.source_points} points"
                " drawn (arcs with fewer chords, points on straight lines and very short"
                " moves merged)."
            )
    if cut:
        notes.append(cut)
    data = view_data(bp, surface, lines, library)
    if library == "inline":
        lib = f"<script>{plotly_js()}</script>"
    else:
        lib = f'<script src="{escape(library)}"></script>'
    return [
        "<h2>Backplot</h2>",
        *(f'<p class="note">{escape(n)}</p>' for n in notes),
        '<div class="bp"><div id="cnc-plot"></div>',
        '<div id="cnc-listing"><div id="cnc-spacer"></div><div id="cnc-rows"></div></div>',
        "</div>",
        '<p class="note" id="cnc-selected"></p>',
        lib,
        f'<script type="application/json" id="cnc-view">{_script_json(data)}</script>',
        f"<script>{_asset('report.js')}</script>",
    ]


def render_html(
    doc: dict[str, Any],
    images: dict[str, bytes],
    backplot: Backplot | None = None,
    source: str | None = None,
    surface: Surface | None = None,
    library: str = "inline",
    note: str = "",
    charts: list[dict[str, Any]] | None = None,
) -> str:
    """The report page for one ``cnc run`` report ``doc`` and its PNG ``images`` by title,
    with the ``backplot`` of the program beside its ``source`` text, the cut part's
    ``surface`` when the stock was simulated, and plotly.js inline (``library="inline"``) or
    loaded from the relative URL ``library``; ``note`` says why there is no backplot."""
    status = escape(str(doc.get("status", "")))
    measure = doc.get("measure") or {}
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>cnc run: {escape(str(doc.get('program', '')))}</title>",
        f"<style>{_CSS}</style></head><body>",
        f"<h1>{escape(str(doc.get('program', '')))}</h1>",
        f"<p>machine: {escape(str(doc.get('machine', '')))} &middot; status: "
        f'<span class="{status}">{status}</span></p>',
    ]
    parts += _backplot(backplot, surface, source, library, note)
    if measure:
        summary = [
            ["cycle time", _cycle_time(measure.get("cycle", {}).get("total", 0.0))],
            ["feed path [mm]", _num(measure.get("feed_length", 0.0))],
            ["rapid path [mm]", _num(measure.get("rapid_length", 0.0))],
            ["segments", escape(str(measure.get("segments", "")))],
            ["samples", escape(str(measure.get("samples", "")))],
        ]
        parts += ["<h2>Summary</h2>", _table(["", ""], summary, {1})]
        parts += ["<h2>Cycle time</h2>", _cycle(measure), _times(doc.get("times") or {})]
    parts += ["<h2>Findings and diagnostics</h2>", _issues(doc)]
    if doc.get("servo"):
        parts += ["<h2>Servo errors</h2>", _servo(doc["servo"])]
    if measure:
        parts += ["<h2>Axis limits</h2>", _hits(measure)]
    if charts:
        parts.append("<h2>Plots</h2>")
        parts += [f'<div class="chart" id="cnc-chart-{i}"></div>' for i in range(len(charts))]
        spec = _script_json(charts)
        parts.append(f'<script type="application/json" id="cnc-charts">{spec}</script>')
        parts.append("<script>window.cncDrawCharts && window.cncDrawCharts();</script>")
    if images:
        parts.append("<h2>Plots</h2>")
        for title, png in images.items():
            data = base64.b64encode(png).decode("ascii")
            parts.append(f"<h3>{escape(title)}</h3>")
            parts.append(f'<img alt="{escape(title)}" src="data:image/png;base64,{data}">')
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
