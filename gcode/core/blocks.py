"""Reading a parsed line into the words the interpreter executes (NIST v3 §3.3, §3.8).

:func:`evaluate_block` evaluates every word's value in line order, sorts G and M codes into
modal groups, rejects repeated words, and returns the line's parameter assignments still
to be made (they take effect after all reads of the line, NIST v3 §3.3.2). A named
parameter assigned on the line exists (as 0) for the reads after its assignment, as in
LinuxCNC. Lines of constant words (what CAM
output is made of) are evaluated once and cached on their :class:`~gcode.core.lexer.Block`.
"""

from __future__ import annotations

from typing import NamedTuple

from gcode.core.codes import (
    G_GROUPS,
    M_GROUPS,
    Words,
    add_g,
    add_m,
    add_value,
    g_code,
    m_code,
)
from gcode.core.expr import evaluate
from gcode.core.lexer import Block, Expr, Word
from gcode.core.params import Parameters
from kernel.diagnostics import Diagnostic, Location


class Assignment(NamedTuple):
    """A parameter assignment of a line, made after all the line's reads."""

    target: str | float  # a named parameter's name, or a numbered parameter's number
    value: float
    loc: Location


def evaluate_block(
    block: Block, params: Parameters, file: str | None
) -> tuple[Words, list[Assignment]]:
    """The block's words and its pending assignments."""
    words = Words()
    line = block.line
    if not block.assignments:
        # the common block: constant words, each valid once; anything else (an expression,
        # an unknown code, a repeated letter or group) is redone below, which says why
        g = words.g
        m = words.m
        values = words.values
        columns = words.columns
        for w in block.words:
            v = w.value
            if type(v) is not float:
                break
            letter = w.letter
            if letter == "g":
                code = round(v * 10)
                group = G_GROUPS.get(code)
                if group is None or group in g or abs(v * 10 - code) > 1e-3:
                    break
                g[group] = code
            elif letter == "m":
                code = round(v)
                group = M_GROUPS.get(code, 10 if 100 <= code <= 199 else None)
                if group is None or group in m or len(m) >= 4 or abs(v - code) > 1e-4:
                    break
                m[group] = code
            elif letter in values:
                break
            else:
                values[letter] = v
                columns[letter] = w.column
        else:
            words.plain = bool(values) and not g and not m and values.keys() <= _AXES
            return words, []
        words = Words()
    items: list[tuple[int, Word | tuple[Expr, Expr, int]]] = [(w.column, w) for w in block.words]
    if block.assignments:
        items += [(a[2], a) for a in block.assignments]
        items.sort(key=lambda item: item[0])
    assigns: list[Assignment] = []
    g, m, values, columns = words.g, words.m, words.values, words.columns
    for col, item in items:
        if not isinstance(item, tuple):
            # a word: its Location is made only where something can fail with it
            v = item.value
            if type(v) is not float:
                v = evaluate(v, params, Location(file, line, col))
            letter = item.letter
            if letter == "g":
                code = round(v * 10)
                group = G_GROUPS.get(code)
                if group is None or group in g or abs(v * 10 - code) > 1e-3:
                    loc = Location(file, line, col)
                    add_g(words, g_code(v, loc, block.text), loc)
                else:
                    g[group] = code
            elif letter == "m":
                code = round(v)
                group = M_GROUPS.get(code, 10 if 100 <= code <= 199 else None)
                if group is None or group in m or len(m) >= 4 or abs(v - code) > 1e-4:
                    loc = Location(file, line, col)
                    add_m(words, m_code(v, loc, block.text), loc)
                else:
                    m[group] = code
            elif letter in values:
                add_value(words, letter, v, Location(file, line, col))  # NGC-DUPLICATE-WORD
            else:
                values[letter] = v
                columns[letter] = col
            continue
        loc = Location(file, line, col)
        target, value, _ = item
        assert isinstance(target, tuple)  # the lexer's ("<", name) or ("#", node)
        val = evaluate(value, params, loc)
        if target[0] == "<":
            # LinuxCNC creates a new named parameter (value 0) as soon as the line is
            # read; its value, like a numbered one's, is set after the line's reads
            name: str = target[1]
            if not params.exists(name):
                params.set_named(name, 0.0, loc)
            assigns.append(Assignment(name, val, loc))
        else:
            idx = evaluate(target[1], params, loc)
            assigns.append(Assignment(idx, val, loc))
    return words, assigns


_AXES = frozenset("xyzabc")
#: letters any block may hold (no code needs to use them): check_letter_uses passes them
_UNCHECKED = frozenset("xyzabcfst@^")
_CYCLES = frozenset({730, 740, 810, 820, 830, 840, 850, 860, 870, 880, 890})
_LATHE_CYCLES = frozenset({700, 710, 711, 712, 720, 721, 722})  # G70-G72.2


def is_constant(block: Block) -> bool:
    """True when no word of the block reads a parameter or an expression."""
    return not block.assignments and all(type(w.value) is float for w in block.words)


def check_letter_uses(words: Words, motion: int | None, loc: Location) -> None:
    """Reject words no code of the block uses (LinuxCNC ``check_other_codes``).

    ``motion`` is the motion the block runs (its own group-1 code or the modal one).
    """
    v = words.values
    if v.keys() <= _UNCHECKED:
        return
    g = words.g
    m = set(words.m.values())
    g0 = g.get(0)

    def bad(letter: str, users: str) -> Diagnostic:
        col = words.columns.get(letter, loc.column)
        return Diagnostic(
            f"NGC-{letter.upper()}-UNUSED",
            f"{letter.upper()} word with no {users} to use it",
            Location(loc.file, loc.line, col),
        )

    for letter in "uvw":
        if letter in v:
            raise Diagnostic(
                "NGC-BAD-CHARACTER",
                f"bad character '{letter}' used (no {letter.upper()} axis)",
                Location(loc.file, loc.line, words.columns.get(letter, loc.column)),
            )
    cycle = motion in _CYCLES
    lathe = motion in _LATHE_CYCLES
    if "d" in v and g.get(7) not in (410, 420, 411, 421) and g.get(14) != 960 and not lathe:
        raise bad("d", "G41, G41.1, G42, G42.1, G70-G72 or G96")
    if "e" in v and not ({66, 67, 68} & m) and motion not in (700, 760):
        raise bad("e", "G70, G76, M66, M67 or M68")
    if "h" in v and g.get(8) not in (430, 432) and motion != 760:
        raise bad("h", "G43 or G76")
    for letter in "ij":
        if (
            letter in v
            and motion not in (20, 30, 50, 51, 331, 760, 870)
            and g0 != 100
            and not (letter == "i" and lathe and motion != 700)
        ):
            raise bad(letter, "G2, G3, G5, G5.1, G10, G33.1, G76, or G87")
    if "k" in v and motion not in (20, 30, 330, 331, 760, 870) and g0 != 100:
        raise bad("k", "G2, G3, G10, G33, G33.1, G76, or G87")
    if "l" in v and not (
        g0 == 100
        or cycle
        or motion in (52, 760)
        or g.get(7) in (410, 420, 411, 421)
        or {66, 98} & m
    ):
        raise bad("l", "G10, cutter compensation, canned cycle, digital/analog input or NURBS code")
    if "p" in v and not (
        motion in (20, 30, 50, 52, 700, 740, 760, 820, 840, 860, 880, 890)
        or g0 in (40, 100)
        or g.get(13) == 640
        or {50, 51, 52, 53, 62, 63, 64, 65, 66, 19, 98} & m
    ):
        raise bad("p", "G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 G89 or M50-M53 M62-M66")
    if "q" in v and not (
        motion in (50, 730, 760, 830)
        or lathe
        or g0 == 100
        or g.get(13) == 640
        or {19, 61, 66, 67, 68} & m
    ):
        raise bad("q", "G5, G10, G64, G73, G76, G83, M19, M61, M66, M67 or M68")
    if "r" in v and not (
        motion in (20, 30, 760) or cycle or (lathe and motion != 700) or g0 == 100 or 19 in m
    ):
        raise Diagnostic(
            "NGC-R-UNUSED",
            "R word with no G code that uses it",
            Location(loc.file, loc.line, words.columns.get("r", loc.column)),
        )
