"""Fanuc block reader: one program line -> :class:`FBlock` (unevaluated).

Fanuc tape format (Fanuc 0i-MF operator's manual, "Program configuration"; custom macro B
chapter): blanks are ignored outside comments, ``( )`` comments, ``;`` ends the block,
``/`` first marks a block-delete block, ``N`` sequence number, ``O`` program number.
A word's value is a literal number, ``#i``, ``-#i``, ``#[e]`` or ``[e]``. A literal kept as
``int`` had no decimal point (it then counts least input increments for a length word,
docs/dialects.md "Number format"); constants inside expressions count as written with
a point (Fanuc: a constant in an expression has an implied point). Macro statements:
``#i=e``, ``IF[c]GOTOn``, ``IF[c]THEN #i=e``, ``GOTOn``, ``WHILE[c]DOm``, ``DOm``, ``ENDm``.

Expression nodes are tuples: ``float`` constant, ``("#", node)`` variable, ``("neg", node)``,
``("f", name, node, ...)`` function, ``("b", op, left, right)``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location

FUNCTIONS = frozenset(
    {
        "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP",
        "LN", "EXP", "POW", "BIN", "BCD", "ADP",
    }
)  # fmt: skip
#: operator precedence, low to high (Fanuc custom macro B: relational < + - OR XOR <
#: * / AND MOD)
_LEVELS: tuple[tuple[str, ...], ...] = (
    ("EQ", "NE", "GT", "GE", "LT", "LE"),
    ("+", "-", "OR", "XOR"),
    ("*", "/", "AND", "MOD"),
)
_OP_RE = re.compile(r"EQ|NE|GT|GE|LT|LE|OR|XOR|AND|MOD|[-+*/]")
_NUM_RE = re.compile(r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)", re.ASCII)
_PLAIN_RE = re.compile(r"(?:[A-Z][-+]?(?:\d+(?:\.\d*)?|\.\d+))+", re.ASCII)
_WORD_RE = re.compile(r"([A-Z])([-+]?(?:\d+(?:\.\d*)?|\.\d+))", re.ASCII)
_PROGRAM_RE = re.compile(r"[O:](\d+)$", re.ASCII)
_SEQ_RE = re.compile(r"N(\d+)", re.ASCII)

#: an expression node (see above): a float constant or a tuple of a kind and its parts
Expr = float | tuple[Any, ...]
#: a word's value as read: int (no decimal point), float, or an expression node
WordValue = int | float | tuple[Any, ...]


@dataclass(slots=True)
class FBlock:
    """One parsed line. ``kind``: words, assign, if_goto, if_then, if_block (Haas: IF [c]
    then the block's assignment ``then`` and/or ``words``), goto, while, do, end, output
    (POPEN, PCLOS, DPRNT, BPRNT), program (an ``O`` line), percent, empty."""

    line: int
    raw: str
    kind: str = "empty"
    seq: int | None = None
    deleted: bool = False
    #: (letter, value, index in the blank-free text); value int | float | expression
    words: list[tuple[str, WordValue, int]] = field(default_factory=list)
    comment: str | None = None
    target: Expr | None = None  # assignment target (index expression)
    expr: Expr | None = None  # assigned value / condition / GOTO label
    label: int = 0  # DO/END identifier, O number
    then: tuple[Expr, Expr] | None = None  # IF ... THEN assignment
    plain: bool = False  # constant words only (no G/M dependence decided here)
    cols: list[int] | None = None

    def column(self, index: int) -> int:
        """1-based column in the raw line of character ``index`` of the blank-free text."""
        cols = self.cols
        if cols is None:  # a plain line: no comments, so every non-blank character counts
            cols = self.cols = [i + 1 for i, ch in enumerate(self.raw) if ch not in " \t\r\n"]
        if not cols:
            return 1
        return cols[min(index, len(cols) - 1)]


def _strip(raw: str, file: str | None, line: int) -> tuple[str, list[int], str | None]:
    """Upper-case text without blanks and comments, its column map, the last comment."""
    out: list[str] = []
    cols: list[int] = []
    comment = None
    i, n = 0, len(raw)
    while i < n:
        ch = raw[i]
        if ch == "(":
            j = raw.find(")", i + 1)
            if j < 0:
                raise Diagnostic("FANUC-COMMENT", "comment not closed", Location(file, line, i + 1))
            comment = raw[i + 1 : j]
            i = j + 1
            continue
        if ch == ";":
            break
        if ch not in " \t\r\n\ufeff":  # a byte order mark opening the file is no character
            out.append(ch.upper())
            cols.append(i + 1)
        i += 1
    return "".join(out), cols, comment


def parse_line(raw: str, line: int, file: str | None = None) -> FBlock:
    """The block of one line (no evaluation)."""
    limits.check_digits(raw, file, line)
    if "(" not in raw and ";" not in raw and "#" not in raw and "[" not in raw:
        s = raw.replace(" ", "").replace("\t", "").replace("\r", "").upper()
        if s and _PLAIN_RE.fullmatch(s) and s[0] not in "ON":
            blk = FBlock(line, raw, "words", plain=True)
            blk.words = [
                (m[1], float(m[2]) if "." in m[2] else int(m[2]), m.start())
                for m in _WORD_RE.finditer(s)
            ]
            return blk
    s, cols, comment = _strip(raw, file, line)
    blk = FBlock(line, raw, comment=comment, cols=cols)
    if not s:
        return blk
    if s[0] == "%":
        blk.kind = "percent"
        return blk
    sc = _Scanner(s, blk, file)
    if sc.peek() == "/":
        blk.deleted = True
        sc.i += 1
    m = _PROGRAM_RE.match(s, sc.i)
    if m is not None or (sc.peek() in "O:" and "0" <= s[sc.i + 1 : sc.i + 2] <= "9"):
        m = re.match(r"[O:](\d+)", s[sc.i :], re.ASCII)
        assert m is not None
        blk.kind = "program"
        blk.label = int(m.group(1))
        return blk
    if sc.peek() == "O" and s[sc.i + 1 : sc.i + 2].isalpha():
        # "Osample": a CAM system wrote the program's name where the control wants its
        # number (O and up to 4 digits, 8 on the 30i); the control refuses the block
        raise sc.error("FANUC-SYNTAX", "program number (digits) expected after O", sc.i + 1)
    m = _SEQ_RE.match(s, sc.i)
    if m is not None:
        blk.seq = int(m.group(1))
        sc.i = m.end()
    sc.statement()
    return blk


class _Scanner:
    __slots__ = ("s", "i", "blk", "file", "nest", "depth", "limits")

    def __init__(self, s: str, blk: FBlock, file: str | None) -> None:
        self.s = s
        self.i = 0
        self.blk = blk
        self.file = file
        # open brackets, functions and signs (parser recursion) and a bound on the tree's
        # depth (evaluation recursion): kernel.limits
        self.nest = 0
        self.depth = 0
        self.limits = limits.current()

    def enter(self) -> None:
        """One more nested bracket, function or sign: LIMIT-NESTING past the limits."""
        self.nest += 1
        self.depth += 1
        if self.nest > self.limits.nesting or self.depth > self.limits.expression_depth:
            raise limits.nesting_error(self.file, self.blk.line, self.blk.column(self.i))

    def leave(self) -> None:
        self.nest -= 1
        self.depth -= 1

    def error(self, code: str, msg: str, i: int | None = None) -> Diagnostic:
        col = self.blk.column(self.i if i is None else i)
        return Diagnostic(code, msg, Location(self.file, self.blk.line, col))

    def keyword(self, word: str, short: str) -> bool:
        """Step over ``word`` or its two-letter abbreviation (``WH`` for WHILE, ``GO`` for
        GOTO, ``TH`` for THEN, ``EN`` for END: the custom macro manual's short forms)."""
        if self.at(word):
            self.i += len(word)
            return True
        if self.at(short):
            self.i += len(short)
            return True
        return False

    def peek(self) -> str:
        return self.s[self.i] if self.i < len(self.s) else ""

    def at(self, word: str) -> bool:
        return self.s.startswith(word, self.i)

    def expect(self, ch: str) -> None:
        if self.peek() != ch:
            raise self.error("FANUC-SYNTAX", f"'{ch}' expected")
        self.i += 1

    def integer(self) -> int:
        m = re.match(r"\d+", self.s[self.i :], re.ASCII)
        if m is None:
            raise self.error("FANUC-SYNTAX", "number expected")
        self.i += m.end()
        return int(m.group(0))

    # ------------------------------------------------------------ statements
    def statement(self) -> None:
        blk = self.blk
        if self.peek() == "#":
            blk.kind = "assign"
            blk.target, blk.expr = self.assignment()
        elif self.at("IF["):
            self.i += 2
            cond = self.bracketed()
            blk.expr = cond
            if self.keyword("GOTO", "GO"):
                blk.kind = "if_goto"
                blk.target = self.label_value()
            elif self.keyword("THEN", "TH"):
                blk.kind = "if_then"
                blk.then = self.assignment()
            elif self.i < len(self.s):
                # Haas: IF [c] <rest of the block>, without THEN (the Haas mill manual,
                # "Macros", conditional execution: "IF [#1 NE #0] G1 X#24 Y#26 F#9",
                # "IF [#1 GE 180] #101=0.0 M99"). Fanuc alarms: the flow refuses it there,
                # at the column kept in ``label``.
                blk.label = self.i
                if self.peek() == "#":
                    blk.then = self.assignment()
                if self.i < len(self.s):
                    self.words()
                blk.kind = "if_block"
                return
            else:
                raise self.error("FANUC-SYNTAX", "GOTO or THEN expected after IF [...]")
        elif self.output_command():
            blk.kind = "output"
            return
        elif self.at("GO") and not self.at("GO["):
            self.keyword("GOTO", "GO")
            blk.kind = "goto"
            blk.target = self.label_value()
        elif self.at("WHILE[") or self.at("WH["):
            self.keyword("WHILE", "WH")
            blk.expr = self.bracketed()
            if not self.at("DO"):
                raise self.error("FANUC-SYNTAX", "DO expected after WHILE [...]")
            self.i += 2
            blk.kind = "while"
            blk.label = self.integer()
        elif self.at("DO") and "0" <= self.s[self.i + 2 : self.i + 3] <= "9":
            self.i += 2
            blk.kind = "do"
            blk.label = self.integer()
        elif (self.at("END") and "0" <= self.s[self.i + 3 : self.i + 4] <= "9") or (
            self.at("EN") and "0" <= self.s[self.i + 2 : self.i + 3] <= "9"
        ):
            self.keyword("END", "EN")
            blk.kind = "end"
            blk.label = self.integer()
        else:
            self.words()
            return
        if self.i < len(self.s):
            raise self.error("FANUC-SYNTAX", f"unexpected '{self.s[self.i]}'")

    def output_command(self) -> bool:
        """Step over an external output command (custom macro manual, "External output
        commands"; Haas alike): POPEN, PCLOS, DPRNT[...] or BPRNT[...]. They send text to a
        device on the serial port and move nothing; the reader reads and ignores them."""
        if self.peek() not in ("P", "D", "B"):  # the common case: one comparison
            return False
        if self.s[self.i :] in ("POPEN", "PCLOS"):
            self.i = len(self.s)
            return True
        if not (self.at("DPRNT[") or self.at("BPRNT[")):
            return False
        self.i += 5
        depth = 0
        for k in range(self.i, len(self.s)):
            ch = self.s[k]
            depth += (ch == "[") - (ch == "]")
            if depth == 0:
                if k + 1 != len(self.s):
                    raise self.error("FANUC-SYNTAX", f"unexpected '{self.s[k + 1]}'", k + 1)
                self.i = len(self.s)
                return True
        raise self.error("FANUC-SYNTAX", "']' expected", len(self.s))

    def label_value(self) -> Expr:
        if self.peek() in ("#", "["):
            return self.operand()
        return float(self.integer())

    def assignment(self) -> tuple[Expr, Expr]:
        self.expect("#")
        target = self.bracketed() if self.peek() == "[" else float(self.integer())
        self.expect("=")
        value = self.expression(0)
        return target, value

    def words(self) -> None:
        blk = self.blk
        blk.kind = "words"
        s = self.s
        n = len(s)
        while self.i < n:
            ch = s[self.i]
            start = self.i
            if ch == "," and s[self.i + 1 : self.i + 2] in ("C", "R", "A"):
                ch = s[self.i : self.i + 2]  # ,C chamfer / ,R corner R / ,A angle
                self.i += 1
            elif not ("A" <= ch <= "Z"):
                raise self.error("FANUC-SYNTAX", f"bad character '{ch}'")
            self.i += 1
            if self.i >= n:
                raise self.error("FANUC-SYNTAX", f"value missing after {ch}")
            m = _NUM_RE.match(s, self.i)
            if m is not None and (m.end() >= n or s[m.end()] not in "#["):
                text = m.group(0)
                self.i = m.end()
                value: WordValue = float(text) if "." in text else int(text)
            else:
                value = self.operand()
            blk.words.append((ch, value, start))

    # ------------------------------------------------------------ expressions
    def bracketed(self) -> Expr:
        self.expect("[")
        self.enter()
        node = self.expression(0)
        self.leave()
        self.expect("]")
        return node

    def operand(self) -> Expr:
        ch = self.peek()
        if ch == "":
            raise self.error("FANUC-SYNTAX", "value expected at end of block")
        if ch in "-+":
            self.i += 1
            self.enter()
            inner = self.operand()
            self.leave()
            return ("neg", inner) if ch == "-" else inner
        if ch == "#":
            self.i += 1
            if self.peek() == "[":
                return ("#", self.bracketed())
            return ("#", float(self.integer()))
        if ch == "[":
            return self.bracketed()
        m = _NUM_RE.match(self.s, self.i)
        if m is not None and ch not in "-+":
            self.i = m.end()
            return float(m.group(0))
        for name in FUNCTIONS:
            if self.at(name + "["):
                self.i += len(name) + 1
                self.enter()
                args = [self.expression(0)]
                while self.peek() == ",":
                    self.i += 1
                    args.append(self.expression(0))
                self.leave()
                self.expect("]")
                if name == "ATAN" and len(args) == 1 and self.at("/["):
                    self.i += 1
                    args.append(self.bracketed())
                return ("f", name, *args)
        raise self.error("FANUC-SYNTAX", f"bad value starting with '{ch}'")

    def expression(self, level: int) -> Expr:
        if level == len(_LEVELS):
            return self.operand()
        left = self.expression(level + 1)
        ops = _LEVELS[level]
        chained = 0  # operators of this level so far: each deepens the left-leaning tree
        while True:
            m = _OP_RE.match(self.s, self.i)
            if m is None or m.group(0) not in ops:
                self.depth -= chained
                return left
            self.i = m.end()
            chained += 1
            self.depth += 1
            if self.depth > self.limits.expression_depth:
                raise limits.nesting_error(self.file, self.blk.line, self.blk.column(self.i))
            right = self.expression(level + 1)
            left = ("b", m.group(0), left, right)
