"""``cnc check``: lint a canonical command stream against a machine profile.

    from kernel.check import CheckContext, check_stream
    findings = check_stream(interpret(path), CheckContext(machine, config, tools))

The stream is consumed once (bounded memory). Each :class:`~kernel.check.rules.Rule` sees
every command of its kinds with the state before it; a :class:`~kernel.diagnostics.Diagnostic`
raised by the front end ends the stream and becomes a CNC001 finding, after the findings for
the commands before it (rs274 stops at the first error the same way).
"""

from __future__ import annotations

from collections.abc import Iterable

import kernel.ir.canon as canon
from kernel.check import rules_tooling  # noqa: F401 - registers the remaining rules
from kernel.check.config import CheckConfig, config_from_dict
from kernel.check.findings import Finding
from kernel.check.rules import RULES, CheckContext, Rule
from kernel.check.state import CheckState, advance
from kernel.diagnostics import Diagnostic, Location, Severity

__all__ = [
    "RULES",
    "CheckConfig",
    "CheckContext",
    "Finding",
    "Rule",
    "check_stream",
    "config_from_dict",
]


#: interpreter diagnostics that are a rule's problem class rather than a generic CNC001
DIAGNOSTIC_RULES: dict[str, str] = {"NGC-NO-END": "CNC010"}


def _active(ctx: CheckContext) -> list[tuple[Rule, Severity]]:
    out = []
    for r in RULES.values():
        sev = ctx.config.severity(r.id, r.severity, r.default_enabled)
        if sev is not None:
            out.append((r, sev))
    return out


def check_stream(
    commands: Iterable[canon.Command],
    ctx: CheckContext,
    file: str | None = None,
    text_findings: Iterable[tuple[str, str, Location]] = (),
) -> list[Finding]:
    """Run every enabled rule over ``commands``; findings in stream order, then end rules.

    ``text_findings`` (rule, message, location) are what a front end found in the program's
    text for a rule of :data:`~kernel.check.rules.TEXT_RULES` (CNC050); they come first, at
    the severity the configuration gives their rule, and not at all when it is off.

    A run of consecutive offending commands of a rule's kinds is one finding whose message
    ends with the count of further commands, so one missing M3 does not give 10,000 lines;
    a later finding with the same rule and message is folded into the first the same way.
    """
    active = _active(ctx)
    per_cmd = [(r, r.check, s) for r, s in active if r.check is not None]
    st = CheckState()
    severities = {r.id: s for r, s in active}
    findings: list[Finding] = [
        Finding(rid, severities[rid], msg, loc)
        for rid, msg, loc in text_findings
        if rid in severities
    ]
    runs: dict[str, tuple[int, int]] = {}  # rule -> (finding index, repeats)
    repeats: dict[tuple[str, str], int] = {}  # (rule, message) -> further commands
    first: dict[tuple[str, str], int] = {}  # (rule, message) -> finding index
    last_loc = Location(file)

    def close(rid: str) -> None:
        idx, extra = runs.pop(rid)
        key = (rid, findings[idx].message)
        repeats[key] = repeats.get(key, 0) + extra

    try:
        for cmd in commands:
            loc = cmd.source or last_loc
            if loc.line >= last_loc.line or loc.file != last_loc.file:
                last_loc = loc
            for r, check, sev in per_cmd:
                if r.kinds and not isinstance(cmd, r.kinds):
                    continue
                msg = check(cmd, st, ctx)
                if msg is None:
                    if r.id in runs:
                        close(r.id)
                elif r.id in runs:
                    idx, extra = runs[r.id]
                    runs[r.id] = (idx, extra + 1)
                elif (r.id, msg) in first:
                    runs[r.id] = (first[r.id, msg], 1)
                else:
                    first[r.id, msg] = len(findings)
                    runs[r.id] = (len(findings), 0)
                    findings.append(Finding(r.id, sev, msg, loc))
            advance(st, cmd)
    except Diagnostic as diag:
        for rid in list(runs):
            close(rid)
        rid = DIAGNOSTIC_RULES.get(diag.code, "CNC001")
        sev = ctx.config.severity(rid, RULES[rid].severity, True) or Severity.ERROR
        loc = diag.location if diag.location.file or diag.location.line else last_loc
        findings.append(Finding(rid, sev, diag.message, loc, diag.code))
        return _folded(findings, repeats)
    for rid in list(runs):
        close(rid)
    end_loc = Location(last_loc.file, last_loc.line, last_loc.column)
    for r, sev in active:
        if r.at_end is not None:
            msg = r.at_end(st, ctx)
            if msg is not None:
                findings.append(Finding(r.id, sev, msg, end_loc))
    return _folded(findings, repeats)


def _folded(findings: list[Finding], repeats: dict[tuple[str, str], int]) -> list[Finding]:
    out = []
    for f in findings:
        n = repeats.get((f.rule, f.message), 0)
        if n:
            more = f"{f.message} (and {n} more command{'s' * (n > 1)})"
            f = Finding(f.rule, f.severity, more, f.location, f.code)
        out.append(f)
    return out
