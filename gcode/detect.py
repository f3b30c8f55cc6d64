"""Guess the dialect of a G-code program from its text and its file suffix (``--dialect auto``).

A pure function over the first kilobytes of a program. Each dialect carries *hints*
(:class:`Hint`): a regular expression, a weight and the reason to give. The registry
(:mod:`gcode.registry`) holds them in its rows, so a new dialect brings its own; the shared
groups below (the Fanuc family, lathe, mill) are reused by the rows of the Fanuc-engine
dialects. A dialect's *score* is the sum of the weights of its hints that match anywhere
in the head (each hint once); a negative weight marks content that dialect's control
refuses. Content names a dialect when its score reaches :data:`THRESHOLD`.

Decision (:func:`guess`):

* no dialect reaches the threshold: the suffix's dialect, else the default (RS274/NGC);
* content and suffix agree, or there is no suffix dialect: the content's dialect;
* they disagree: the suffix wins unless the content contradicts the suffix's dialect
  (its score is negative) or is decisive (twice the threshold) while the suffix's
  dialect has no evidence at all; either way the guess says so;
* a second dialect is *plausible* when it also reaches the threshold, comes within
  :data:`MARGIN` of the winner and has evidence of its own (a hint the winner did not
  match): the guess warns. Shared evidence alone (a Fanuc program matches Haas's Fanuc
  family hints too) is no ambiguity; the registry's order decides (Fanuc before Haas).
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from functools import cache
from typing import Any

try:  # the re module's parser (Python 3.11+): only to find what a hint's pattern needs
    _sre = importlib.import_module("re._constants")
    _sre_parse = importlib.import_module("re._parser")
    _PARSE: Callable[[str, int], Any] | None = _sre_parse.parse
    _LITERAL, _SUBPATTERN, _BRANCH = _sre.LITERAL, _sre.SUBPATTERN, _sre.BRANCH
    _IN, _RANGE = _sre.IN, _sre.RANGE
    _REPEATS = (_sre.MAX_REPEAT, _sre.MIN_REPEAT, _sre.POSSESSIVE_REPEAT)
    _ZERO_WIDTH = (_sre.AT, _sre.ASSERT, _sre.ASSERT_NOT)
except (ImportError, AttributeError):  # another Python: every pattern is searched
    _PARSE = None

#: score at which content names a dialect
THRESHOLD = 3
#: a runner-up this close to the winner (with evidence of its own) is plausible too
MARGIN = 3
#: how much of a program the sniffer reads
HEAD_BYTES = 16384
#: how much of each line it looks at
LINE_CHARS = 256

_COMMENTS = re.compile(r"\([^)\n]*\)?|;[^\n]*")


@dataclass(frozen=True, slots=True)
class Hint:
    """One piece of evidence for (positive weight) or against (negative) a dialect.

    ``pattern`` is a regular expression searched case-insensitively, line-anchored
    (``^``/``$`` per line). With ``raw`` it sees the program as written; otherwise the
    text with ``( )`` and ``;`` comments blanked out, so a comment cannot fake code.
    An ``aux`` hint tells apart dialects of one family (mill or lathe) and counts only
    once the family's own evidence has reached the threshold.
    """

    pattern: str
    weight: int
    reason: str
    raw: bool = False
    #: refines a choice the other hints made (mill or lathe within the Fanuc family): it
    #: adds to the score but cannot make a dialect reach the threshold on its own
    aux: bool = False


@cache
def _compiled(pattern: str) -> re.Pattern[str]:
    return re.compile(pattern, re.I | re.M)


@cache
def _needles(pattern: str) -> frozenset[str] | None:
    """Lower-case strings of which every match of ``pattern`` contains one, or None when
    its parse gives none.

    A program's head rarely holds the words most hints look for (``TRANS``, ``GOTOF``,
    ``G154 P``...): checking for them with ``in`` first spares compiling and searching
    those patterns, which took 20-25 ms of every program's start-up. Read from the
    pattern's parse by the ``re`` module's own parser; where that parser is not there
    (another Python), no pattern has needles and every one is searched as before.
    """
    if _PARSE is None:
        return None
    try:
        found = _required(_PARSE(pattern, re.I | re.M))
    except Exception:  # a parser that changed shape: search the pattern itself
        return None
    if found is None:
        return None
    # a string holding another of the set adds nothing ("atrans" holds "trans")
    return frozenset(s for s in found if not any(t != s and t in s for t in found))


#: most strings a run of items may expand to (``G0?7[0-2]``: six)
_MAX_STRINGS = 32


def _required(items: Iterable[tuple[Any, Any]]) -> frozenset[str] | None:
    """What a match of the sequence ``items`` (a parsed pattern) must contain: the most
    selective (longest shortest string) of its requirements. Consecutive items that match
    few strings (characters, small classes, optional ones, short alternations) make one
    requirement, their strings joined (``G0?7[0-2]``: g070 ... g72); zero-width items
    (``\\b``, ``^``, lookarounds) do not break such a run, and require nothing. Of any other
    item, a group or a repeat of at least one requires its content's requirement, an
    alternation one of its branches'."""
    best: frozenset[str] | None = None

    def consider(found: frozenset[str] | None) -> None:
        nonlocal best
        if found and min(map(len, found)) > (0 if best is None else min(map(len, best))):
            best = found

    run: frozenset[str] = frozenset({""})
    for op, av in items:
        if op in _ZERO_WIDTH:
            continue
        strings = _strings(op, av)
        if strings is not None and len(run) * len(strings) <= _MAX_STRINGS:
            run = frozenset(a + b for a in run for b in strings)
            continue
        consider(run)
        run = frozenset({""}) if strings is None else strings
        if op == _SUBPATTERN:
            consider(_required(av[3]))
        elif op in _REPEATS and av[0] >= 1:
            consider(_required(av[2]))
        elif op == _BRANCH:
            branches = [_required(b) for b in av[1]]
            if all(b is not None for b in branches):
                consider(frozenset(n for b in branches if b is not None for n in b))
    consider(run)
    return best


def _strings(op: Any, av: Any) -> frozenset[str] | None:
    """The few strings (lower case, ASCII) one parsed item matches, or None."""
    if op == _LITERAL:
        return frozenset({chr(av).lower()}) if av < 128 else None
    if op == _IN:
        chars: set[str] = set()
        for kind, value in av:
            if kind == _LITERAL and value < 128:
                chars.add(chr(value).lower())
            elif kind == _RANGE and value[1] < 128 and value[1] - value[0] < 10:
                chars.update(chr(c).lower() for c in range(value[0], value[1] + 1))
            else:  # a negation, a category (digits, ...), a wide range
                return None
        return frozenset(chars)
    if op == _SUBPATTERN:
        return _sequence_strings(av[3])
    if op == _BRANCH:
        out: set[str] = set()
        for branch in av[1]:
            strings = _sequence_strings(branch)
            if strings is None:
                return None
            out |= strings
        return frozenset(out) if len(out) <= _MAX_STRINGS else None
    if op in _REPEATS and av[0] in (0, 1) and av[1] == 1:
        strings = _sequence_strings(av[2])
        if strings is None:
            return None
        return strings | {""} if av[0] == 0 else strings
    return None


def _sequence_strings(items: Iterable[tuple[Any, Any]]) -> frozenset[str] | None:
    """The few strings a parsed sequence matches, or None."""
    out = frozenset({""})
    for op, av in items:
        if op in _ZERO_WIDTH:
            continue
        strings = _strings(op, av)
        if strings is None or len(out) * len(strings) > _MAX_STRINGS:
            return None
        out = frozenset(a + b for a in out for b in strings)
    return out


@dataclass(frozen=True, slots=True)
class Candidate:
    """What the content says for one dialect: its score and the hints it matched."""

    name: str
    score: int
    matched: tuple[Hint, ...]

    @property
    def base(self) -> int:
        """The score without the auxiliary hints: what must reach the threshold."""
        return sum(h.weight for h in self.matched if not h.aux)

    def why(self) -> str:
        """The strongest reasons, for a message: the family's, then the refining ones."""
        own = sorted((h for h in self.matched if h.weight > 0), key=lambda h: -h.weight)
        best = [h for h in own if not h.aux][:3] + [h for h in own if h.aux][:2]
        return ", ".join(h.reason for h in best)


@dataclass(frozen=True, slots=True)
class Guess:
    """The dialect to read a program in, and what to tell the user about the choice.

    ``source`` is ``content``, ``suffix`` or ``default``; ``reason`` says why in a few
    words; ``conflict`` is set when suffix and content disagree, ``plausible`` names
    another dialect the content fits nearly as well (with its reasons).
    """

    dialect: str
    source: str
    reason: str = ""
    conflict: str = ""
    plausible: tuple[str, ...] = ()
    candidates: tuple[Candidate, ...] = field(default=(), compare=False, repr=False)


def _bounded(head: str) -> str:
    """``head`` with every line cut to :data:`LINE_CHARS` (G-code lines are short), so no
    pattern can spend more than linear time on a hostile file."""
    lines = head.splitlines()
    if all(len(line) <= LINE_CHARS for line in lines):
        return head
    return "\n".join(line[:LINE_CHARS] for line in lines)


class _Head:
    """A program's head as the hints read it: cut to :data:`LINE_CHARS` a line, as written
    and with comments blanked, each pattern searched once however many dialects share it
    (the Fanuc-family hints appear in four rows)."""

    __slots__ = ("raw", "code", "found", "lower")

    def __init__(self, head: str) -> None:
        self.raw = _bounded(head)
        self.code = _COMMENTS.sub(lambda m: " " * len(m.group()), self.raw)
        self.found: dict[tuple[str, bool], bool] = {}
        #: raw and code in lower case, for the needles; None unless ASCII (in other text
        #: ``re.I`` folds more than ``lower`` does: ``ſ`` matches ``s``)
        self.lower = (self.raw.lower(), self.code.lower()) if self.raw.isascii() else None

    def matches(self, hint: Hint) -> bool:
        key = (hint.pattern, hint.raw)
        hit = self.found.get(key)
        if hit is None:
            needles = _needles(hint.pattern) if self.lower is not None else None
            if needles is not None and self.lower is not None:
                text = self.lower[0] if hint.raw else self.lower[1]
                if not any(n in text for n in needles):
                    self.found[key] = False
                    return False
            hit = _compiled(hint.pattern).search(self.raw if hint.raw else self.code) is not None
            self.found[key] = hit
        return hit


def score(head: str | _Head, hints: Iterable[Hint]) -> tuple[int, tuple[Hint, ...]]:
    """The score of ``head`` for one dialect's hints and the hints that matched."""
    text = head if isinstance(head, _Head) else _Head(head)
    matched = tuple(h for h in hints if text.matches(h))
    return sum(h.weight for h in matched), matched


def candidates(head: str, table: Sequence[tuple[str, Sequence[Hint]]]) -> list[Candidate]:
    """Every dialect of ``table`` (name, hints; in registry order) with its score."""
    text = _Head(head)
    out = []
    for name, hints in table:
        total, matched = score(text, hints)
        out.append(Candidate(name, total, matched))
    return out


def _plausible(winner: Candidate, others: Iterable[Candidate]) -> tuple[Candidate, ...]:
    """Runners-up close to the winner with evidence of their own; of several with the same
    evidence (Fanuc and Haas lathes) only the first."""
    own = {h.pattern for h in winner.matched}
    seen: list[set[str]] = []
    out = []
    for c in others:
        mine = {h.pattern for h in c.matched if h.weight > 0}
        if (
            c.name == winner.name
            or c.base < THRESHOLD
            or winner.score - c.score >= MARGIN
            or mine <= own
            or any(mine <= s for s in seen)
        ):
            continue
        seen.append(mine)
        out.append(c)
    return tuple(out)


def guess(
    head: str,
    suffix: str,
    table: Sequence[tuple[str, Sequence[Hint]]],
    suffixes: dict[str, str],
    default: str,
) -> Guess:
    """The dialect of a program whose first bytes are ``head`` and whose file suffix is
    ``suffix`` (``.nc``; may be empty). ``table`` lists (dialect, hints) in registry order,
    ``suffixes`` maps a lower-case suffix to the dialect it names, ``default`` is read when
    nothing else decides."""
    cands = candidates(head, table)
    by_name = {c.name: c for c in cands}
    # stable sort: registry order breaks ties
    ranked = sorted((c for c in cands if c.base >= THRESHOLD), key=lambda c: -c.score)
    top = ranked[0] if ranked else None
    named = suffixes.get(suffix.lower()) if suffix else None
    if top is None:
        if named is not None:
            return Guess(named, "suffix", f"suffix {suffix}", candidates=tuple(cands))
        return Guess(default, "default", "no dialect markers", candidates=tuple(cands))
    plausible = tuple(f"{c.name} ({c.why()})" for c in _plausible(top, ranked))
    if named is None or named == top.name:
        where = f"suffix {suffix} and content" if named else "content"
        return Guess(top.name, "content", f"{where}: {top.why()}", "", plausible, tuple(cands))
    mine = by_name.get(named)
    own = mine.score if mine is not None else 0
    if own < 0 or (top.base >= 2 * THRESHOLD and own == 0 and not (mine and mine.matched)):
        conflict = (
            f"the suffix {suffix} names {named}, but the content is {top.name}'s "
            f"({top.why()}); reading it as {top.name}"
        )
        return Guess(top.name, "content", top.why(), conflict, plausible, tuple(cands))
    conflict = (
        f"the content looks like {top.name} ({top.why()}), but the suffix {suffix} names "
        f"{named}; reading it as {named}"
    )
    return Guess(named, "suffix", f"suffix {suffix}", conflict, (), tuple(cands))


# --------------------------------------------------------------------------- shared hints
#: a Fanuc-engine control: program numbers, tape marks, macro B, Fanuc-only G codes
FANUC_FAMILY: tuple[Hint, ...] = (
    Hint(r"^[ \t]*(?:N\d+[ \t]*)?[O:]\d{1,5}[ \t]*$", 3, "program number O…"),
    Hint(r"^[ \t]*%[ \t]*$", 1, "% tape marks"),
    Hint(r"\bWHILE[ \t]*\[[^\n]*\][ \t]*DO[ \t]*\d", 3, "macro B WHILE […] DOn"),
    Hint(r"\bIF[ \t]*\[[^\n]*\][ \t]*(?:GOTO|THEN)", 3, "macro B IF […] GOTO/THEN"),
    Hint(r"(?:^|[ \t\]])GOTO[ \t]*[\d#]", 3, "macro B GOTO n"),
    Hint(r"^[ \t]*(?:N\d+[ \t]*)?END[ \t]*\d[ \t]*$", 2, "macro B ENDn"),
    Hint(r"\bG0?65[ \t]*P[ \t]*\d", 2, "G65 macro call"),
    Hint(r"\bM98[ \t]*P[ \t]*\d", 2, "M98 P subprogram call"),
    Hint(r"^[ \t]*(?:N\d+[ \t]*)?#\d+[ \t]*=[^\n]*\[", 1, "macro B #n=[…]"),
    Hint(r"\bG0?5\.1[ \t]*Q", 2, "G05.1 Q AI contour control"),
    Hint(r"\bG54\.1[ \t]*P", 2, "G54.1 P extra work offsets"),
    Hint(r"\bG10[ \t]*L1[0-3]\b[^\n]*\bP", 1, "G10 L1x tool offset setting"),
    Hint(
        r"(?<![A-Z#])[XYZ][ \t]*-?\d+\.(?!\d)", 1, "numbers with a trailing point (X10.)", aux=True
    ),
    Hint(
        r"(?<![A-Z#.\d])[XYZ][ \t]*-?[1-9]\d*(?![.\d])",
        1,
        "lengths without a decimal point",
        aux=True,
    ),
    Hint(
        r"\bo[ \t]*(?:\d+|<[^>\n]*>)[ \t]*(?:sub|call|while|do|if|repeat)\b", -3, "LinuxCNC O-word"
    ),
    Hint(r"#<[_a-z]", -3, "LinuxCNC named parameter"),
    Hint(r"\bDEF[ \t]+(?:REAL|INT|BOOL|CHAR|STRING|AXIS|FRAME)\b", -3, "Siemens DEF"),
)
#: turning on a Fanuc-engine lathe (G code system A)
LATHE: tuple[Hint, ...] = (
    Hint(
        r"\bG0?7[0-2]\b[^\n]*\bP[ \t]*\d[^\n]*\bQ|\bG0?73\b[^\n]*\bP[^\n]*\b[UW]",
        3,
        "G70-G73 P Q stock-removal cycle",
    ),
    Hint(r"\bG0?7[1-3][ \t]*U", 3, "G71/G72 U R depth of cut"),
    Hint(r"\bG76\b[^\n]*\bP[ \t]*\d{6}", 3, "G76 P threading cycle"),
    Hint(r"\bG50[ \t]*S[ \t]*\d", 3, "G50 S spindle clamp"),
    Hint(r"\bG28[ \t]*U[^\n]*W|\bG28[ \t]*W[^\n]*U", 3, "G28 U W"),
    Hint(r"\bG96\b", 2, "G96 constant surface speed", aux=True),
    Hint(r"^(?![^\n]*\bG[89]\d)[^\n]*\bG99\b", 1, "G99 feed per revolution", aux=True),
    Hint(r"(?<![A-Z#])[UW][ \t]*-?\.?\d", 1, "U/W incremental words", aux=True),
    Hint(
        r"(?<![A-Z#])T[ \t]*\d{3,4}\b(?![^\n]*M0?6\b)", 2, "T0101 turret tool and offset", aux=True
    ),
    Hint(r"\bG18\b", 1, "G18 XZ plane", aux=True),
    Hint(
        r"\A(?![\s\S]*(?<![A-Z#])Y[ \t]*[-+.\d#\[])(?=[\s\S]*(?<![A-Z#])Z)",
        1,
        "no Y words",
        aux=True,
    ),
)
#: milling on a Fanuc-engine control
MILL: tuple[Hint, ...] = (
    Hint(r"\bG17\b", 1, "G17 XY plane", aux=True),
    Hint(r"\bG0?4[34][ \t]*(?:Z[^\n]*)?H[ \t]*\d", 1, "G43 H tool length compensation", aux=True),
    Hint(r"\bM0?6\b", 1, "M6 tool change", aux=True),
    Hint(r"(?<![A-Z#])Y[ \t]*-?\.?\d", 1, "Y words", aux=True),
    Hint(r"\bG(?:8[1-9]|73)\b", 1, "drilling cycles", aux=True),
)
#: what only a Haas control takes (mill and lathe)
HAAS: tuple[Hint, ...] = (
    Hint(r"\bG187\b", 3, "Haas G187 smoothness"),
    Hint(r"\bG154[ \t]*P", 3, "Haas G154 P work offsets"),
    Hint(r"\bM97[ \t]*P", 3, "Haas M97 local subprogram"),
    Hint(r"\bG1[1-2]\d\b", 2, "Haas G110-G129 work offsets"),
    Hint(r"\bG(?:47|150|103|234|254|255)\b", 2, "Haas-only G code"),
    Hint(r"\bM(?:109|130|133|134|135)\b", 2, "Haas-only M code"),
    Hint(r"\bM8[89]\b", 1, "M88/M89 through-spindle coolant"),
    Hint(r"\(\s*[^)\n]*\bHAAS\b", 2, "a comment names Haas", raw=True),
)
#: what only a Haas mill takes
HAAS_MILL: tuple[Hint, ...] = (Hint(r"\bG1[23](?![.\d])", 2, "Haas G12/G13 circular pocket"),)
#: what only a Haas lathe takes
HAAS_LATHE: tuple[Hint, ...] = (
    Hint(r"\bG14\b|\bG186\b", 2, "Haas lathe spindle codes"),
    Hint(r"\bG0?7[12]\b[^\n]*\bP[^\n]*\bQ[^\n]*\bD[ \t]*[.\d]", 3, "Haas one-block G71 … D"),
)
#: not in the text: the machine profile says the machine is a lathe (``kind = "lathe"``);
#: added to the lathe dialects' hints by the registry, it tips a Fanuc-family program with
#: no turning codes to the lathe reader (X is then a diameter)
LATHE_PROFILE = Hint(r"", 3, "the machine profile is a lathe", aux=True)
#: a comment naming a Fanuc control
FANUC_NAME: tuple[Hint, ...] = (
    Hint(r"\(\s*[^)\n]*\bFANUC\b", 2, "a comment names Fanuc", raw=True),
)
#: LinuxCNC's RS274/NGC
RS274NGC: tuple[Hint, ...] = (
    Hint(
        r"\bo[ \t]*(?:\d+|<[^>\n]*>)[ \t]*"
        r"(?:sub|endsub|call|while|endwhile|do|if|elseif|else|endif|repeat|endrepeat|return)\b",
        3,
        "O-words (o100 sub)",
    ),
    Hint(r"#<[_a-z]", 3, "named parameters #<…>"),
    Hint(r"\(\s*(?:MSG|DEBUG|PRINT|LOGOPEN|LOGAPPEND|LOG|PROBEOPEN)\s*,", 2, "(MSG,…)", raw=True),
    Hint(r"\bG[78]\b(?![.\d])", 2, "G7/G8 lathe diameter/radius mode"),
    Hint(r"\bM6[2-8][ \t]*P", 2, "M62-M68 motion I/O"),
    Hint(r"\bG64[ \t]*P", 1, "G64 P blending"),
    Hint(r"\bG5\.[123]\b", 1, "G5.x splines"),
    Hint(r"\(\s*[^)\n]*\b(?:LINUXCNC|EMC2?|AXIS)\b", 2, "a comment names LinuxCNC", raw=True),
    Hint(r"\bWHILE[ \t]*\[[^\n]*\][ \t]*DO[ \t]*\d|(?:^|[ \t\]])GOTO[ \t]*\d", -3, "macro B"),
)
#: Siemens Sinumerik 840D
SIEMENS: tuple[Hint, ...] = (
    Hint(r";", 1, "; comments", raw=True),
    Hint(r"\bDEF[ \t]+(?:REAL|INT|BOOL|CHAR|STRING|AXIS|FRAME)\b", 3, "DEF variables"),
    Hint(r"\bMSG[ \t]*\([ \t]*\"", 3, 'MSG("…")', raw=True),
    Hint(r"(?:^|[ \t])R\d+[ \t]*=", 2, "R parameters R1="),
    Hint(r"\bG500\b|\bG7[01]0\b", 2, "G500/G710"),
    Hint(r"\b(?:CYCLE\d+|POCKET\d|SLOT\d|LONGHOLE|HOLES\d)[ \t]*\(", 3, "CYCLE8x(…) calls"),
    Hint(r"\b(?:A?TRANS|A?ROT|A?SCALE|A?MIRROR)\b", 2, "frames TRANS/ROT"),
    Hint(
        r"\b(?:GOTOF|GOTOB|ENDFOR|ENDLOOP|STOPRE|SUPA|TRAORI|TRAFOOF|SPOS|DIAMON)\b",
        2,
        "840D keywords",
    ),
    Hint(r"\$[APMTS][A-Z]?_[A-Z]", 3, "$P_/$AA_ system variables"),
    Hint(r"\bT[ \t]*=[ \t]*\"", 3, 'T="name" tools', raw=True),
    Hint(r"\b(?:AC|IC|ACP|ACN)[ \t]*\(", 2, "AC()/IC()"),
    Hint(r"\b(?:SOFT|BRISK|FFWON|CFC|G642)\b", 1, "840D path modes"),
    Hint(r"^[ \t]*:\d+", 1, ": main blocks"),
    Hint(r"\bM17\b|^[ \t]*RET\b", 1, "M17/RET subprogram end"),
    Hint(r"(?:^|[ \t])(?:SINUMERIK|SIEMENS|840D)\b", 2, "a comment names Sinumerik", raw=True),
)
#: Grbl 1.1
GRBL: tuple[Hint, ...] = (
    Hint(r"^[ \t]*\$(?:\$|#|[A-Z]+\b|\d+[ \t]*=)", 3, "Grbl $ lines"),
    Hint(r"(?:\(|;)[^\n]*\bGRBL\b", 3, "a comment names Grbl", raw=True),
    Hint(r"\bo[ \t]*(?:\d+|<)|#\d|#<", -2, "parameters or O-words (not in Grbl)"),
    Hint(r"\bM0?6\b|\bG(?:4[12]|8[1-9]|73)\b|\bG43[ \t]*H", -1, "codes Grbl lacks"),
)
#: the Sandia generic language (one command per line)
SANDIA: tuple[Hint, ...] = (
    Hint(
        r"^[ \t]*(?:point_to_point_positioning|MoveTo|MoveReact|SetUnits|SetSpeed|GetTool"
        r"|PutTool|SetToolLength|StopMotion|Deactivate)\b",
        4,
        "Sandia commands (MoveTo, SetUnits, …)",
    ),
    Hint(r"^[ \t]*#(?![ \t]*[\d<\[])", 1, "# comments", raw=True),
)
