"""Renderers of ``cnc check`` results: text (rich), JSON, JUnit XML and SARIF 2.1.0.

Every renderer takes the same :class:`CheckReport` and returns the document as a string
(text may carry ANSI colour when asked for). The report types are in :mod:`cli.formats.base`;
a renderer is imported when its format is asked for (rich only for text).
"""

from __future__ import annotations

from cli.formats.base import DOCS_URI, FORMATS, CheckReport, FileResult


def render(report: CheckReport, fmt: str, color: bool = False, verbosity: int = 0) -> str:
    """Dispatch to the renderer of ``fmt`` (one of :data:`FORMATS`)."""
    if fmt == "json":
        from cli.formats.json_report import render_json

        return render_json(report)
    if fmt == "junit":
        from cli.formats.junit import render_junit

        return render_junit(report)
    if fmt == "sarif":
        from cli.formats.sarif import render_sarif

        return render_sarif(report)
    from cli.formats.text import render_text

    return render_text(report, color=color, verbosity=verbosity)


__all__ = ["DOCS_URI", "FORMATS", "CheckReport", "FileResult", "render"]
