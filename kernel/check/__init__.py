"""``cnc check``: lint a canonical command stream against a machine profile.

    from kernel.check import CheckContext, check_stream
    findings = check_stream(interpret(path), CheckContext(machine, config, tools))

The stream is consumed once (bounded memory). Each :class:`~kernel.check.rules.Rule` sees
every command of its kinds with the state before it; a :class:`~kernel.diagnostics.Diagnostic`
raised by the front end ends the stream and becomes a CNC001 finding, after the findings for
the commands before it (rs274 stops at the first error the same way).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import cast

import numpy as np

import kernel.ir.canon as canon
from kernel.check import rules_tooling  # noqa: F401 - registers the remaining rules
from kernel.check.batch import Judge, Message, Moves, StraightRun, called, kinds_mask
from kernel.check.config import CheckConfig, config_from_dict
from kernel.check.findings import Finding
from kernel.check.rules import RULES, CheckContext, Rule
from kernel.check.state import CheckState, Vec6, advance, motion_end
from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.ir.canon import ArcFeed, SetFeedRate, StraightFeed, StraightTraverse

__all__ = [
    "RULES",
    "CheckConfig",
    "CheckContext",
    "Finding",
    "Moves",
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


#: commands judged together (kernel.check.batch); bounds the memory of a run
BATCH = 8192
#: the commands a run is made of: between them only the position and the feed rate change
RUN_KINDS = frozenset({StraightFeed, StraightTraverse, ArcFeed, SetFeedRate})


class _Book:
    """The findings so far and the runs of offending commands still open, per rule."""

    def __init__(self, findings: list[Finding]) -> None:
        self.findings = findings
        self.runs: dict[str, tuple[int, int]] = {}  # rule -> (finding index, repeats)
        self.repeats: dict[tuple[str, str], int] = {}  # (rule, message) -> further commands
        self.first: dict[tuple[str, str], int] = {}  # (rule, message) -> finding index

    def close(self, rid: str) -> None:
        """End the open run of ``rid`` (if any): its repeats go to its message."""
        run = self.runs.pop(rid, None)
        if run is not None:
            key = (rid, self.findings[run[0]].message)
            self.repeats[key] = self.repeats.get(key, 0) + run[1]

    def offend(
        self, rid: str, sev: Severity, message: Callable[[], str], loc: Location, count: int = 1
    ) -> None:
        """``count`` consecutive offending commands of ``rid``, the first at ``loc``
        (``message``: the first one's message, asked for only when a run starts)."""
        run = self.runs.get(rid)
        if run is not None:
            self.runs[rid] = (run[0], run[1] + count)
            return
        msg = message()
        idx = self.first.get((rid, msg))
        if idx is not None:
            self.runs[rid] = (idx, count)
        else:
            self.first[rid, msg] = len(self.findings)
            self.runs[rid] = (len(self.findings), count - 1)
            self.findings.append(Finding(rid, sev, msg, loc))

    def close_all(self) -> None:
        for rid in list(self.runs):
            self.close(rid)


def check_stream(
    commands: Iterable[canon.Command | Moves],
    ctx: CheckContext,
    file: str | None = None,
    text_findings: Iterable[tuple[str, str, Location]] = (),
    batched: bool = True,
) -> list[Finding]:
    """Run every enabled rule over ``commands``; findings in stream order, then end rules.

    ``text_findings`` (rule, message, location) are what a front end found in the program's
    text for a rule of :data:`~kernel.check.rules.TEXT_RULES` (CNC050); they come first, at
    the severity the configuration gives their rule, and not at all when it is off.

    A run of consecutive offending commands of a rule's kinds is one finding whose message
    ends with the count of further commands, so one missing M3 does not give 10,000 lines;
    a later finding with the same rule and message is folded into the first the same way.

    Consecutive moves are judged up to :data:`BATCH` at a time over arrays
    (:mod:`kernel.check.batch`), and a front end may give blocks of plain moves as arrays
    already (:class:`~kernel.check.batch.Moves`); ``batched=False`` asks every rule command
    by command. The findings are the same.
    """
    active = _active(ctx)
    per_cmd = [(r, r.check, s) for r, s in active if r.check is not None]
    st = CheckState()
    severities = {r.id: s for r, s in active}
    book = _Book(
        [
            Finding(rid, severities[rid], msg, loc)
            for rid, msg, loc in text_findings
            if rid in severities
        ]
    )
    last_loc = Location(file)
    run_cmds: list[canon.Command] = []
    run_ends: list[Vec6] = []
    run_locs: list[Location] = []
    judge = Judge(st, ctx)
    straight = [
        (i, r, sev)
        for i, (r, _, sev) in enumerate(per_cmd)
        if any(called(r, kind) for kind in RUN_KINDS)
    ]

    def flush() -> None:
        if run_cmds:
            run = StraightRun.of(run_cmds, run_ends, run_locs, st)
            _judge_run(judge, run, straight, book)
            run.carry(st)
            run_cmds.clear()
            run_ends.clear()
            run_locs.clear()

    def one(cmd: canon.Command, loc: Location) -> None:
        """Every rule on one command, then its effect on the state."""
        for r, check, sev in per_cmd:
            if r.kinds and not isinstance(cmd, r.kinds):
                continue
            msg = check(cmd, st, ctx)
            if msg is None:
                book.close(r.id)
            else:
                book.offend(r.id, sev, _given(msg), loc)
        advance(st, cmd)

    def moves(m: Moves) -> None:
        """A block of moves as arrays: one by one until the first motion, then runs of up to
        :data:`BATCH` events."""
        a, n = 0, len(m)
        while a < n and not st.moved:
            cmd = m.command(a)
            one(cmd, cmd.source or Location(m.file))
            a += 1
        while a < n:
            b = min(n, a + BATCH)
            run = StraightRun.of_moves(m, a, b, st)
            _judge_run(judge, run, straight, book)
            run.carry(st)
            a = b

    items: Iterable[canon.Command | Moves] = commands if batched else _expanded(commands)
    try:
        for cmd in items:
            if isinstance(cmd, Moves):
                flush()
                if len(cmd):
                    moves(cmd)
                    top = int(cmd.line.max())
                    if top >= last_loc.line or cmd.file != last_loc.file:
                        last_loc = Location(cmd.file, top, 1)
                continue
            loc = cmd.source or last_loc
            if loc.line >= last_loc.line or loc.file != last_loc.file:
                last_loc = loc
            kind = type(cmd)
            if batched and st.moved and kind in RUN_KINDS and _plain(cmd):
                if kind is ArcFeed:
                    end = motion_end(st, cmd, run_ends[-1] if run_ends else st.position)
                    assert end is not None
                elif kind is SetFeedRate:
                    end = run_ends[-1] if run_ends else st.position
                else:
                    move = cast(StraightFeed, cmd)
                    end = (move.x, move.y, move.z, move.a, move.b, move.c)
                run_cmds.append(cmd)
                run_ends.append(end)
                run_locs.append(loc)
                if len(run_cmds) >= BATCH:
                    flush()
                continue
            flush()
            one(cmd, loc)
    except Diagnostic as diag:
        flush()
        book.close_all()
        rid = DIAGNOSTIC_RULES.get(diag.code, "CNC001")
        sev = ctx.config.severity(rid, RULES[rid].severity, True) or Severity.ERROR
        loc = diag.location if diag.location.file or diag.location.line else last_loc
        book.findings.append(Finding(rid, sev, diag.message, loc, diag.code))
        return _folded(book.findings, book.repeats)
    flush()
    book.close_all()
    findings = book.findings
    end_loc = Location(last_loc.file, last_loc.line, last_loc.column)
    for r, sev in active:
        if r.at_end is not None:
            msg = r.at_end(st, ctx)
            if msg is not None:
                findings.append(Finding(r.id, sev, msg, end_loc))
    return _folded(findings, book.repeats)


def _plain(cmd: canon.Command) -> bool:
    """Whether a run's arrays hold the command's numbers as they are (a feed rate that is
    not a float, such as an integer too large for one, is judged on its own)."""
    return type(cmd) is not SetFeedRate or type(cast(SetFeedRate, cmd).rate) is float


def _expanded(items: Iterable[canon.Command | Moves]) -> Iterator[canon.Command]:
    """The commands of a stream whose blocks of moves are arrays."""
    for item in items:
        if isinstance(item, Moves):
            for i in range(len(item)):
                yield item.command(i)
        else:
            yield item


def _judge_run(
    judge: Judge,
    run: StraightRun,
    straight: list[tuple[int, Rule, Severity]],
    book: _Book,
) -> None:
    """Every rule over a run: each rule's stretches of offending commands and the commands
    that end them, applied in stream order (command, then rule order) as the
    command-by-command loop would. ``straight``: the rules called for the commands of a
    run, with their order among all rules."""
    judge.start(run)
    # (command index, rule order, rule, severity, stretch length or 0 for an end, message)
    events: list[tuple[int, int, str, Severity, int, Message]] = []
    for order, r, sev in straight:
        if judge.quiet(r):
            if r.id in book.runs:
                mask = kinds_mask(r, run)
                if mask.any():
                    events.append((int(mask.argmax()), order, r.id, sev, 0, _none))
            continue
        mask, off, message = judge.offences(r)
        idx = np.flatnonzero(mask)
        if not len(idx):
            continue
        o = off[idx]
        before = np.concatenate(([False], o[:-1]))
        starts = np.flatnonzero(o & ~before)
        stops = np.flatnonzero(~o & before)
        ends = np.concatenate((stops, [len(o)])) if o[-1] else stops
        for a, b in zip(starts.tolist(), ends.tolist(), strict=True):
            events.append((int(idx[a]), order, r.id, sev, b - a, message))
        if not o[0]:
            stops = np.concatenate(([0], stops))
        for a in stops.tolist():
            events.append((int(idx[a]), order, r.id, sev, 0, message))
    events.sort(key=lambda e: (e[0], e[1]))
    for i, _, rid, sev, count, message in events:
        if count == 0:
            book.close(rid)
        else:
            first = run.locations[i]
            book.offend(rid, sev, _asked(message, i), first, count)


def _given(msg: str) -> Callable[[], str]:
    """A message already known."""
    return lambda: msg


def _asked(message: Message, i: int) -> Callable[[], str]:
    """The message of command ``i``, asked for when needed."""
    return lambda: message(i) or ""


def _none(i: int) -> str | None:
    return None


def _folded(findings: list[Finding], repeats: dict[tuple[str, str], int]) -> list[Finding]:
    out = []
    for f in findings:
        n = repeats.get((f.rule, f.message), 0)
        if n:
            more = f"{f.message} (and {n} more command{'s' * (n > 1)})"
            f = Finding(f.rule, f.severity, more, f.location, f.code)
        out.append(f)
    return out
