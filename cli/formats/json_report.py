"""JSON check report, schema ``cnc-check-report`` version 1.

The schema is ``docs/schemas/check-report-1.schema.json`` (JSON Schema 2020-12) and is
described in ``docs/check-rules.md``. Any incompatible change bumps :data:`VERSION`.
"""

from __future__ import annotations

import json

from cli.formats.base import CheckReport
from kernel.diagnostics import Severity

SCHEMA = "cnc-check-report"
VERSION = 1


def report_dict(report: CheckReport) -> dict[str, object]:
    files = []
    for r in report.files:
        files.append(
            {
                "file": r.file,
                "status": "io-error" if r.io_error else ("findings" if r.findings else "clean"),
                "io_error": r.io_error,
                "seconds": round(r.seconds, 6),
                "counts": {s.value: r.count(s) for s in Severity},
                "findings": [f.to_dict() for f in r.findings],
            }
        )
    return {
        "schema": SCHEMA,
        "version": VERSION,
        "tool": {"name": "cnc check", "version": report.version},
        "machine": report.machine,
        "summary": {
            "files": len(report.files),
            "io_errors": report.io_errors,
            **{s.value: report.total(s) for s in Severity},
            "seconds": round(report.seconds, 6),
        },
        "rules": [
            {
                "id": rule.id,
                "name": rule.name,
                "default_severity": rule.severity.value,
                "severity": sev.value if sev else None,
                "summary": rule.summary,
            }
            for rule, sev in report.rules
        ],
        "files": files,
    }


def render_json(report: CheckReport) -> str:
    return json.dumps(report_dict(report), indent=2) + "\n"
