"""RS274/NGC line reader: one program line -> :class:`Block` with unevaluated expressions.

Rules (NIST RS274/NGC v3 §3.3, LinuxCNC G-code overview): case is ignored and blanks are
ignored outside comments; ``(...)`` comments do not nest; ``;`` comments to end of line;
``/`` at the start of a line marks it for block delete; ``N`` line numbers come first;
a ``%`` line delimits the program. Values are numbers, parameters ``#n``, ``#<name>``,
``#[expr]``, bracketed expressions or unary functions. Parsing happens once per line (loops
and subroutines reuse the parsed :class:`Block`); evaluation happens at execution time in
:mod:`gcode.core.expr`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import kernel.limits as limits
from gcode.core.codes import Words
from kernel.diagnostics import Diagnostic, Location

# Expression nodes are plain tuples (fast to build and evaluate):
#   float                      constant
#   ("#", node)                numbered parameter
#   ("<", name)                named parameter (name lower-cased, blanks removed)
#   ("u", fn, node)            unary function
#   ("atan", node, node)       ATAN[a]/[b]
#   ("exists", name)           EXISTS[#<name>]
#   ("exists#", node)          EXISTS[#n] (n an expression)
#   ("neg", node)              unary minus
#   ("b", op, node, node)      binary operation
Expr = object

UNARY_FUNCTIONS = frozenset(
    {"abs", "acos", "asin", "cos", "exp", "fix", "fup", "ln", "round", "sin", "sqrt", "tan"}
)
#: every function name, longest first (the longest one a word's letters start with wins)
_FUNCTION_NAMES = sorted(UNARY_FUNCTIONS | {"atan", "exists"}, key=len, reverse=True)
# Binary operators by precedence level (low to high), LinuxCNC: logical < relational <
# additive < multiplicative < power.
_LEVELS: tuple[tuple[str, ...], ...] = (
    ("and", "xor", "or"),
    ("eq", "ne", "gt", "ge", "lt", "le"),
    ("+", "-"),
    ("*", "/", "mod"),
    ("**",),
)
#: operator -> its level in :data:`_LEVELS`
_LEVEL_OF = {op: level for level, ops in enumerate(_LEVELS) for op in ops}
_OPERATOR_RE = re.compile(r"\*\*|[-+*/]|and|xor|or|eq|ne|gt|ge|lt|le|mod")
_NUMBER_RE = re.compile(r"(?:\d+(?:\.\d*)?|\.\d+)", re.ASCII)
_NUMBER_START = frozenset("0123456789.")
_PLAIN_LINE_RE = re.compile(
    r"[ \t]*(?:[xyzabc][ \t]*[-+]?(?:\d+(?:\.\d*)?|\.\d+)[ \t]*)+", re.ASCII
)
_PLAIN_WORD_RE = re.compile(r"([xyzabc])[ \t]*([-+]?(?:\d+(?:\.\d*)?|\.\d+))", re.ASCII)
_SIMPLE_LINE_RE = re.compile(r"[ \t]*(?:[a-z][ \t]*[-+]?(?:\d+(?:\.\d*)?|\.\d+)[ \t]*)+", re.ASCII)
_SIMPLE_WORD_RE = re.compile(r"([a-z])[ \t]*([-+]?(?:\d+(?:\.\d*)?|\.\d+))", re.ASCII)
_OWORD_KEYWORDS = (
    "sub",
    "endsub",
    "call",
    "return",
    "if",
    "elseif",
    "else",
    "endif",
    "while",
    "endwhile",
    "do",
    "repeat",
    "endrepeat",
    "break",
    "continue",
)


@dataclass(slots=True)
class Word:
    letter: str
    value: Expr
    column: int


@dataclass(slots=True)
class OWord:
    """``O<name> keyword [args]``: ``name`` is a string or an expression for numbered O-words."""

    name: str | Expr
    keyword: str
    args: list[Expr]
    column: int


@dataclass(slots=True)
class Block:
    """One parsed line. ``words`` keep program order; evaluation happens later."""

    line: int
    text: str
    deleted: bool = False
    n_number: float | None = None
    words: list[Word] = field(default_factory=list)
    assignments: list[tuple[Expr, Expr, int]] = field(default_factory=list)
    comments: list[tuple[str, int]] = field(default_factory=list)
    oword: OWord | None = None
    percent: bool = False
    #: evaluated words of a block without parameters or expressions (set by the lexer for
    #: plain axis lines, by the interpreter for other constant lines)
    cached_words: Words | None = None
    #: column of the first word
    col0: int = 1

    @property
    def empty(self) -> bool:
        return not (
            self.words or self.assignments or self.comments or self.oword or self.cached_words
        )


class _Scanner:
    """Cursor over the comment-free, blank-free, lower-cased text of one line.

    ``cols[i]`` is the 1-based column in the original line of character ``i``.
    """

    __slots__ = ("s", "i", "cols", "loc_file", "line", "nest", "depth", "limits")

    def __init__(self, s: str, cols: list[int], file: str | None, line: int) -> None:
        self.s = s
        self.i = 0
        self.cols = cols
        self.loc_file = file
        self.line = line
        # brackets, functions and signs open now (parser recursion), and a bound on the
        # depth of the tree being built (evaluation recursion): kernel.limits
        self.nest = 0
        self.depth = 0
        self.limits = limits.current()

    def enter(self, levels: int = 1) -> None:
        """One more nested bracket, function or sign: LIMIT-NESTING past the limits."""
        self.nest += 1
        self.depth += levels
        if self.nest > self.limits.nesting or self.depth > self.limits.expression_depth:
            raise limits.nesting_error(self.loc_file, self.line, self.col())

    def leave(self, levels: int = 1) -> None:
        self.nest -= 1
        self.depth -= levels

    def col(self, i: int | None = None) -> int:
        i = self.i if i is None else i
        if not self.cols:
            return 1
        return self.cols[min(i, len(self.cols) - 1)] + (1 if i >= len(self.cols) else 0)

    def error(self, code: str, msg: str, i: int | None = None) -> Diagnostic:
        return Diagnostic(code, msg, Location(self.loc_file, self.line, self.col(i)))

    def peek(self) -> str:
        return self.s[self.i] if self.i < len(self.s) else ""

    # -------------------------------------------------------------- values
    def real_value(self) -> Expr:
        """A word's value: number, parameter, [expression] or unary function (with sign)."""
        s = self.s
        i = self.i
        if i < len(s) and s[i] in _NUMBER_START:
            m = _NUMBER_RE.match(s, i)
            if m is not None:  # the common value: a plain number
                self.i = m.end()
                return float(m.group())
        c = s[i] if i < len(s) else ""
        if c == "[":
            return self.bracketed()
        if c == "#":
            return self.parameter()
        if c == "-":
            self.i += 1
            self.enter()
            v = self.real_value()
            self.leave()
            return -v if isinstance(v, float) else ("neg", v)
        if c == "+":
            self.i += 1
            self.enter()
            v = self.real_value()
            self.leave()
            return v
        if c == "[":
            return self.bracketed()
        if c == "#":
            return self.parameter()
        if "0" <= c <= "9" or c == ".":  # ASCII: str.isdigit() takes "１" and "٣" too
            m = _NUMBER_RE.match(self.s, self.i)
            if not m:
                raise self.error("NGC-BAD-NUMBER", "bad number format")
            self.i = m.end()
            return float(m.group())
        if c.isalpha():
            return self.function()
        if not c:
            raise self.error("NGC-MISSING-VALUE", "value expected at end of line")
        raise self.error("NGC-BAD-VALUE", f"bad character '{c}' where a value was expected")

    def parameter(self) -> Expr:
        start = self.i
        self.i += 1  # '#'
        if self.peek() == "<":
            end = self.s.find(">", self.i)
            if end < 0:
                raise self.error("NGC-NAMED-PARAM", "named parameter not terminated by '>'", start)
            name = self.s[self.i + 1 : end]
            if not name:
                raise self.error("NGC-NAMED-PARAM", "empty named parameter", start)
            self.i = end + 1
            return ("<", name)
        self.enter()
        node = ("#", self.real_value())
        self.leave()
        return node

    def bracketed(self) -> Expr:
        start = self.i
        self.i += 1  # '['
        self.nest += 1  # enter(), inline: the commonest nesting
        self.depth += 1
        if self.nest > self.limits.nesting or self.depth > self.limits.expression_depth:
            raise limits.nesting_error(self.loc_file, self.line, self.col())
        node = self.expression(0)
        self.nest -= 1
        self.depth -= 1
        if self.i >= len(self.s) or self.s[self.i] != "]":
            raise self.error("NGC-UNCLOSED-EXPR", "expression not closed with ']'", start)
        self.i += 1
        return node

    def function(self) -> Expr:
        start = self.i
        j = self.i
        while j < len(self.s) and self.s[j].isalpha():
            j += 1
        name = self.s[self.i : j]
        # the longest function name that is a prefix of the letters (e.g. "sin[" inside "xsin[")
        for fn in _FUNCTION_NAMES:
            if name.startswith(fn) and self.s.startswith(fn + "[", self.i):
                self.i += len(fn)
                break
        else:
            raise self.error("NGC-UNKNOWN-FUNCTION", f"unknown function or word '{name}'", start)
        if fn == "exists":
            self.i += 1
            if not self.s.startswith("#<", self.i):
                if self.peek() != "#":
                    raise self.error(
                        "NGC-EXISTS-ARG", "EXISTS needs a parameter #<name> or #n", start
                    )
                p = self.parameter()  # #n exists when n is in 1..5601 (rs274 2.9)
                if self.peek() != "]":
                    raise self.error("NGC-UNCLOSED-EXPR", "expression not closed with ']'", start)
                self.i += 1
                assert isinstance(p, tuple)  # parameter() gives (kind, operand)
                return ("exists#", p[1])
            p = self.parameter()
            if self.peek() != "]":
                raise self.error("NGC-UNCLOSED-EXPR", "expression not closed with ']'", start)
            self.i += 1
            assert isinstance(p, tuple)
            return ("exists", p[1])
        arg = self.bracketed()
        if fn == "atan":
            if self.peek() != "/":
                raise self.error("NGC-ATAN-SLASH", "ATAN needs a slash: ATAN[a]/[b]", self.i)
            self.i += 1
            if self.peek() != "[":
                raise self.error("NGC-ATAN-BRACKET", "ATAN second argument needs brackets", self.i)
            return ("atan", arg, self.bracketed())
        return ("u", fn, arg)

    def expression(self, level: int) -> Expr:
        """Precedence climbing over :data:`_LEVELS`, left associative: the operators of
        ``level`` and above. One frame takes every level from ``level`` on (the tree, the
        errors and the depth count are those of one recursive frame per level: an operator
        of level L first closes the chains of the levels above L)."""
        left = self.real_value()
        s = self.s
        m = _OPERATOR_RE.match(s, self.i)
        if m is None:
            if self.i < len(s) and s[self.i] != "]":
                raise self.error("NGC-BAD-OPERATOR", f"unknown operator at '{s[self.i :]}'")
            return left
        op = m.group()
        op_level = _LEVEL_OF[op]
        if op_level < level:
            return left
        chained = [0] * len(_LEVELS)  # operators chained per level in this frame
        open_ops = 0  # their sum: what this frame adds to ``depth``
        while True:
            for k in range(op_level + 1, len(_LEVELS)):
                if chained[k]:
                    self.depth -= chained[k]
                    open_ops -= chained[k]
                    chained[k] = 0
            self.i = m.end()
            chained[op_level] += 1
            open_ops += 1
            self.depth += 1
            if self.depth > self.limits.expression_depth:
                raise limits.nesting_error(self.loc_file, self.line, self.col())
            right = self.expression(op_level + 1)
            left = ("b", op, left, right)
            m = _OPERATOR_RE.match(s, self.i)
            if m is None:
                if self.i < len(s) and s[self.i] != "]":
                    raise self.error("NGC-BAD-OPERATOR", f"unknown operator at '{s[self.i :]}'")
                self.depth -= open_ops
                return left
            op = m.group()
            op_level = _LEVEL_OF[op]
            if op_level < level:
                self.depth -= open_ops
                return left


_BLANKS = frozenset(" \t\r\n")
_NO_BLANKS = str.maketrans("", "", " \t\r\n")


def _strip_comments(
    raw: str, file: str | None, line: int
) -> tuple[str, list[int], list[tuple[str, int]]]:
    """Remove comments and blanks; lower-case; keep original columns and comment texts.

    The text between comments is taken a stretch at a time (each character lower-cased
    on its own, as the column map needs)."""
    parts: list[str] = []
    cols: list[int] = []
    comments: list[tuple[str, int]] = []
    i = 0
    n = len(raw)
    while i < n:
        paren = raw.find("(", i)
        semi = raw.find(";", i)
        j = n if paren < 0 and semi < 0 else (paren if semi < 0 or 0 <= paren < semi else semi)
        if j > i:
            stretch = raw[i:j]
            at = [k for k, c in enumerate(stretch, i + 1) if c not in _BLANKS]
            if at:
                cols += at
                if stretch.isascii():
                    parts.append(stretch.translate(_NO_BLANKS).lower())
                else:
                    parts.append("".join([raw[k - 1].lower() for k in at]))
        if j == n:
            break
        if raw[j] == ";":
            comments.append((raw[j + 1 :], j + 1))
            break
        end = raw.find(")", j + 1)
        if end < 0:
            raise Diagnostic(
                "NGC-UNCLOSED-COMMENT", "unclosed comment found", Location(file, line, j + 1)
            )
        inner = raw[j + 1 : end]
        if "(" in inner:
            raise Diagnostic(
                "NGC-NESTED-COMMENT", "nested comment found", Location(file, line, j + 1)
            )
        comments.append((inner, j + 1))
        i = end + 1
    return "".join(parts), cols, comments


def parse_line(raw: str, line: int, file: str | None = None) -> Block:
    """Parse one line of RS274/NGC into a :class:`Block` (no evaluation)."""
    limits.check_digits(raw, file, line)
    low = raw.lower()
    if _PLAIN_LINE_RE.fullmatch(low):
        # the CAM line: axis words only; evaluated here once (NIST v3 §3.3: order and
        # blanks do not matter); a repeated letter takes the general path below
        pairs = _PLAIN_WORD_RE.findall(low)
        values = {letter: float(number) for letter, number in pairs}
        if len(values) == len(pairs):
            col0 = len(raw) - len(raw.lstrip()) + 1
            return Block(line, raw, cached_words=Words(values=values, plain=True), col0=col0)
    block = Block(line, raw)
    if "%" in raw and raw.strip().startswith("%"):
        block.percent = True
        return block
    # fast path: CAM-style lines of plain words with numbers (blanks between words only)
    if "o" not in low and _SIMPLE_LINE_RE.fullmatch(low):
        words = block.words
        for m in _SIMPLE_WORD_RE.finditer(low):
            letter, number = m.groups()
            if letter not in _LETTERS:
                if letter == "n" and not words and block.n_number is None:
                    block.n_number = float(number)
                    continue
                words.append(Word(letter, 0.0, m.start() + 1))
                _check_letters(block, file)
            words.append(Word(letter, float(number), m.start() + 1))
        return block

    text, cols, comments = _strip_comments(raw, file, line)
    block.comments = comments
    sc = _Scanner(text, cols, file, line)
    if sc.peek() == "/":
        block.deleted = True
        sc.i += 1
    if sc.peek() == "n" and sc.i + 1 < len(text) and ("0" <= text[sc.i + 1] <= "9"):
        sc.i += 1
        m = _NUMBER_RE.match(text, sc.i)
        assert m is not None
        block.n_number = float(m.group())
        sc.i = m.end()
    if sc.peek() == "o":
        block.oword = _parse_oword(sc)
        if sc.i < len(text):
            # only comments may follow an O-word command
            raise sc.error("NGC-OWORD-TRAILING", f"unexpected text after O-word: '{text[sc.i :]}'")
        return block
    while sc.i < len(text):
        c = text[sc.i]
        col = sc.col()
        if c == "#":
            start = sc.i
            target = sc.parameter()
            if sc.peek() != "=":
                raise sc.error("NGC-PARAM-ASSIGN", "equal sign missing in parameter setting", start)
            sc.i += 1
            value = sc.real_value()
            block.assignments.append((target, value, col))
            continue
        if "a" <= c <= "z" or c == "@" or c == "^":  # @ ^: polar radius and angle
            sc.i += 1
            block.words.append(Word(c, sc.real_value(), col))
            continue
        written = raw[sc.col() - 1 : sc.col()] or c  # the character as the user typed it
        raise sc.error("NGC-BAD-CHARACTER", f"bad character '{written}' used")
    _check_letters(block, file)
    return block


_LETTERS = frozenset("abcdefghijklmpqrstuvwxyz@^")  # no 'n' or 'o' after the start


def _check_letters(block: Block, file: str | None) -> None:
    for w in block.words:
        if w.letter not in _LETTERS:
            if w.letter == "n":
                raise Diagnostic(
                    "NGC-LINE-NUMBER",
                    "line number (N) must be the first word of the line",
                    Location(file, block.line, w.column),
                )
            raise Diagnostic(
                "NGC-UNKNOWN-WORD",
                f"unknown word starting with '{block.text[w.column - 1 : w.column] or w.letter}'",
                Location(file, block.line, w.column),
            )


def _parse_oword(sc: _Scanner) -> OWord:
    col = sc.col()
    sc.i += 1  # 'o'
    if sc.peek() == "<":
        end = sc.s.find(">", sc.i)
        if end < 0:
            raise sc.error("NGC-OWORD-NAME", "O-word name not terminated by '>'")
        name: str | Expr = sc.s[sc.i + 1 : end]
        sc.i = end + 1
    else:
        value = sc.real_value()
        name = value
    if sc.i >= len(sc.s):  # "O123" or "O<name>" alone: a program's number or name
        return OWord(name, "", [], col)
    for kw in sorted(_OWORD_KEYWORDS, key=len, reverse=True):
        if sc.s.startswith(kw, sc.i):
            sc.i += len(kw)
            break
    else:
        raise sc.error("NGC-OWORD-KEYWORD", "unknown control command in O-word")
    args: list[Expr] = []
    if kw in ("call",):
        while sc.peek() == "[":
            args.append(sc.bracketed())
    elif kw in ("if", "elseif", "while", "repeat", "return", "endsub"):
        if sc.peek() == "[":
            args.append(sc.bracketed())
        elif kw in ("if", "elseif", "while", "repeat"):
            raise sc.error("NGC-OWORD-CONDITION", f"O-word {kw} needs a [condition]")
    return OWord(name, kw, args, col)
