"""A self-contained HTML report per program (``cnc run --html``), viewable offline.

Everything is inline: CSS in a ``<style>`` element, plots as base64 PNG data URIs, no
scripts and no external resources. Sections: summary, cycle-time breakdown (table and
proportional bars), check findings and diagnostics with their source lines, servo errors,
limit hits, then the XY path and one plot per axis (commanded against actual).
"""

from __future__ import annotations

import base64
from html import escape
from typing import Any

from kernel.report.clock import clock

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em;color:#222;
max-width:1100px}
h1{font-size:1.4em;margin-bottom:.2em}h2{font-size:1.1em;margin-top:1.6em;
border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:.25em .6em;
text-align:left;vertical-align:top}th{background:#f3f3f3}td.num{text-align:right;
font-variant-numeric:tabular-nums}
.ok{color:#176f2c}.findings{color:#9a6700}.error{color:#b42318}
.sev-error{color:#b42318;font-weight:bold}.sev-warning{color:#9a6700}.sev-note{color:#175cd3}
.bar{background:#4e79a7;height:.9em;display:inline-block}
img{max-width:100%;border:1px solid #ddd;margin:.4em 0}
"""


def _num(v: Any, digits: int = 3) -> str:
    try:
        return f"{float(v):.{digits}f}"
    except (TypeError, ValueError):
        return escape(str(v))


def _table(head: list[str], rows: list[list[str]], numeric: set[int] | None = None) -> str:
    numeric = numeric or set()
    out = ["<table><tr>", *(f"<th>{escape(h)}</th>" for h in head), "</tr>"]
    for row in rows:
        out.append("<tr>")
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


def _issues(doc: dict[str, Any]) -> str:
    rows = []
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
    return _table(["severity", "rule / code", "line", "message"], rows, {2})


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
    return _table(head, rows, {0, 1, 4, 5, 6})


def render_html(doc: dict[str, Any], images: dict[str, bytes]) -> str:
    """The report page for one ``cnc run`` report ``doc`` and its PNG ``images`` by title."""
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
    if measure:
        summary = [
            ["cycle time [s]", _num(measure.get("cycle", {}).get("total", 0.0))],
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
    if images:
        parts.append("<h2>Plots</h2>")
        for title, png in images.items():
            data = base64.b64encode(png).decode("ascii")
            parts.append(f"<h3>{escape(title)}</h3>")
            parts.append(f'<img alt="{escape(title)}" src="data:image/png;base64,{data}">')
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
