"""SARIF 2.1.0 check report (OASIS Static Analysis Results Interchange Format).

One run; the driver lists every rule (id, name, descriptions, default level, help URI into
docs/check-rules.md); each finding is a result with ruleId/ruleIndex, level and a physical
location (artifact URI relative to the working directory when possible, 1-based region).
Unreadable files become tool execution notifications. Validated in tests against the
published sarif-schema-2.1.0.json (tests/schemas/).
"""

from __future__ import annotations

import json
from pathlib import Path

from cli.formats.base import DOCS_URI, CheckReport

SARIF_SCHEMA = (
    "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
)


def _uri(file: str) -> str:
    p = Path(file)
    try:
        rel = p.resolve().relative_to(Path.cwd().resolve())
        return rel.as_posix()
    except ValueError:
        return p.resolve().as_uri()


def render_sarif(report: CheckReport) -> str:
    index = {rule.id: i for i, (rule, _) in enumerate(report.rules)}
    rules = []
    for rule, sev in report.rules:
        rules.append(
            {
                "id": rule.id,
                "name": rule.name,
                "shortDescription": {"text": rule.summary},
                "helpUri": f"{DOCS_URI}#{rule.id.lower()}",
                "defaultConfiguration": {
                    "level": (sev or rule.severity).value,
                    "enabled": sev is not None,
                },
            }
        )
    results = []
    notifications = []
    artifacts = []
    for r in report.files:
        uri = _uri(r.file)
        artifacts.append({"location": {"uri": uri}, "roles": ["analysisTarget"]})
        if r.io_error:
            notifications.append(
                {
                    "level": "error",
                    "message": {"text": f"{r.file}: {r.io_error}"},
                    "locations": [{"physicalLocation": {"artifactLocation": {"uri": uri}}}],
                }
            )
        for f in r.findings:
            phys: dict[str, object] = {"artifactLocation": {"uri": uri}}
            if f.location.line > 0:
                phys["region"] = {
                    "startLine": f.location.line,
                    "startColumn": max(1, f.location.column),
                }
            res: dict[str, object] = {
                "ruleId": f.rule,
                "ruleIndex": index[f.rule],
                "level": f.severity.value,
                "message": {"text": f.message},
                "locations": [{"physicalLocation": phys}],
            }
            if f.code:
                res["properties"] = {"diagnosticCode": f.code}
            results.append(res)
    run = {
        "tool": {
            "driver": {
                "name": "cnc check",
                "version": report.version,
                "informationUri": DOCS_URI,
                "rules": rules,
            }
        },
        "invocations": [
            {
                "executionSuccessful": report.io_errors == 0,
                "toolExecutionNotifications": notifications,
                "workingDirectory": {"uri": Path.cwd().resolve().as_uri() + "/"},
            }
        ],
        "artifacts": artifacts,
        "results": results,
        "columnKind": "unicodeCodePoints",
    }
    doc = {"$schema": SARIF_SCHEMA, "version": "2.1.0", "runs": [run]}
    return json.dumps(doc, indent=2) + "\n"
