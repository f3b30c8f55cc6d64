"""ISO 10303-21 (STEP physical file) reader and writer.

A hand lexer (one compiled regular expression, driven by an explicit-stack parameter parser)
reads the exchange structure: ``ISO-10303-21;``, the HEADER section, the DATA section with
simple and complex instances, forward references, and ``END-ISO-10303-21;``. Parameter
values are stored compactly so a million-instance file fits in well under 1 KiB per
instance:

====================  ==========================================
Part 21 value         Python value
====================  ==========================================
``123``               ``int``
``1.5``, ``2.E-3``    ``float``
``'it''s'``           ``str`` (decoded: ``''``, ``\\X\\``, ``\\X2\\``, ``\\X4\\``, ``\\S\\``)
``.T.``, ``.LEFT.``   :class:`Enum` (a ``str`` subclass)
``"0FF"``             :class:`Binary` (a ``str`` subclass holding the hex digits)
``#12``               :class:`Ref` (an ``int`` subclass)
``$``                 ``None``
``*``                 :data:`DERIVED`
``(a, b)``            ``tuple``
``LENGTH(2.0)``       :class:`Typed`
====================  ==========================================

Errors are :class:`~kernel.diagnostics.Diagnostic` with ``P21-*`` codes naming the ``#id``,
line and column. In *collect* mode (``diagnostics=[]``) the reader salvages what it can
(book Fig. 11.18 style defects: empty fields, enumerations without dots, ``$66``,
keyword=value pairs, unterminated instances and sections) and records one diagnostic per
defect instead of stopping (research/seed-book-stepnc.md §1.11.3, §8 "strict and salvage
parsing").
"""

from __future__ import annotations

import gc
import math
import re
import sys
from collections.abc import MutableMapping

import numpy as np

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location
from stepnc.p21_fast import FAST_INSTANCE, fast_params
from stepnc.p21_scan import KERNELS, MAX_CHARS, Instances
from stepnc.p21_values import (
    DERIVED,
    Binary,
    Enum,
    Instance,
    Part,
    Part21File,
    Ref,
    Typed,
    decode_string,
    references,
)
from stepnc.p21_write import format_instance, format_value, write

__all__ = [
    "DERIVED",
    "Binary",
    "Enum",
    "Instance",
    "Part",
    "Part21File",
    "Ref",
    "Typed",
    "check_references",
    "format_instance",
    "format_value",
    "parse",
    "read_file",
    "references",
    "write",
]


# --------------------------------------------------------------------------- lexer
# One token per match; leading blanks and /* comments */ are swallowed by the prefix.
_TOKEN = re.compile(
    r"""(?:\s+|/\*.*?\*/)*(?:
      (\#\d+)                                          # 1 reference
    | ([+-]?\d+\.\d*(?:[eE][+-]?\d+)?)                 # 2 real
    | ([+-]?\d+)                                       # 3 integer
    | '((?:[^']|'')*)'                                 # 4 string
    | \.([A-Za-z_][A-Za-z0-9_]*)\.                     # 5 enumeration
    | "([0-3][0-9A-Fa-f]*)"                            # 6 binary
    | (!?[A-Za-z_][A-Za-z0-9_\-]*)                     # 7 keyword
    | ([(),;=$*])                                      # 8 punctuation
    | (\Z)                                             # 9 end of input
    | (.)                                              # 10 anything else
    )""",
    re.VERBOSE | re.DOTALL,
)
_DIGITS_TO_ZERO = bytes.maketrans(b"123456789", b"000000000")
_DIGIT_PIECE = 1 << 20
#: exponents of three digits or more, with every digit made '0' (:meth:`_Reader.check_digits`)
_BIG_EXPONENTS = (b"E000", b"E+000", b"e000", b"e+000")
_EXPONENT = re.compile(r"[eE]\+?\d{3,}")
#: the most instances the fast path takes between two tries of the compiled scanner
_SCAN_BACKOFF = 1024
_INSTANCE_START = re.compile(r"\n[ \t]*#\d+[ \t]*=")
_REF, _REAL, _INT, _STR, _ENUM, _BIN, _KW, _PUNCT, _EOF, _BAD = range(1, 11)


# --------------------------------------------------------------------------- reader
class _Reader:
    def __init__(self, text: str, file: str | None, diagnostics: list[Diagnostic] | None):
        self.text = text
        self.file = file
        self.diags = diagnostics
        self.collect = diagnostics is not None
        self.line_pos = 0  # position up to which newlines are counted
        self.line_no = 1
        self.entity: int | None = None

    # -- positions and errors
    def line_col(self, pos: int) -> tuple[int, int]:
        if pos < self.line_pos:
            self.line_pos, self.line_no = 0, 1
        self.line_no += self.text.count("\n", self.line_pos, pos)
        self.line_pos = pos
        start = self.text.rfind("\n", 0, pos) + 1
        return self.line_no, pos - start + 1

    def error(self, code: str, message: str, pos: int, entity: int | None = None) -> None:
        line, col = self.line_col(pos)
        diag = Diagnostic(code, message, Location(self.file, line, col, entity=entity))
        if not self.collect:
            raise diag
        assert self.diags is not None
        self.diags.append(diag)

    def check_nesting(self, depth: int, pos: int, entity: int | None) -> None:
        """LIMIT-NESTING when parentheses nest deeper than ``kernel.limits`` allows (the
        values are walked recursively later)."""
        if depth > limits.current().nesting:
            line, col = self.line_col(pos)
            lim = limits.nesting_error(self.file, line, col)
            raise Diagnostic(lim.code, lim.message, Location(self.file, line, col, entity=entity))

    def check_digits(self, raw: bytes) -> None:
        """LIMIT-DIGITS at the first number longer than ``kernel.limits`` allows (``raw``:
        the text as latin-1 bytes, one byte a character)."""
        limit = limits.current().digits
        # every digit made '0' by a C-level table, then one substring search: a tenth of the
        # time of a regular expression over the whole file; in pieces that overlap by the
        # limit (a run across two pieces is found whole), so no copy of the whole file
        zeros = b"0" * (limit + 1)
        at = -1
        for start in range(0, len(raw), _DIGIT_PIECE):
            piece = raw[start : start + _DIGIT_PIECE + limit].translate(_DIGITS_TO_ZERO)
            at = piece.find(zeros)
            if at >= 0:
                at += start
                break
            if any(e in piece for e in _BIG_EXPONENTS):
                self.check_range(start, start + len(piece))
        m = None if at < 0 else re.compile(r"\d+").match(self.text, at)
        if m is not None:
            line, col = self.line_col(m.start())
            raise Diagnostic(
                "LIMIT-DIGITS",
                f"a number of {m.end() - m.start()} digits (limit {limit}, --limit digits=N)",
                Location(self.file, line, col),
            )

    def check_range(self, start: int, stop: int) -> None:
        """P21-NUMBER at the first real between ``start`` and ``stop`` too large for a
        float (``1.0E999``): it would be read as infinity. Only pieces holding an exponent
        of three digits or more are searched (:meth:`check_digits`)."""
        for m in _EXPONENT.finditer(self.text, start, stop):
            begin = m.start()
            while begin > 0 and self.text[begin - 1] in "0123456789.+-":
                begin -= 1
            number = self.text[begin : m.end()]
            # a real has a decimal point and starts a value (a string's hex escape such
            # as \X4\0001E470\X0\ does neither)
            if "." not in number or begin and self.text[begin - 1] not in "(, \t\r\n":
                continue
            try:
                value = float(number)
            except ValueError:
                continue  # not a number: the parser says what it is
            if math.isinf(value):
                line, col = self.line_col(begin)
                raise Diagnostic(
                    "P21-NUMBER",
                    f"{number} is out of range (the largest real is about 1.8E308)",
                    Location(self.file, line, col),
                )

    def token(self, pos: int) -> re.Match[str]:
        m = _TOKEN.match(self.text, pos)
        assert m is not None  # the pattern always matches (group 9/10)
        return m

    @staticmethod
    def tok_start(m: re.Match[str]) -> int:
        return m.start(m.lastindex or 0)

    # -- parameters
    def params(self, pos: int, entity: int | None) -> tuple[tuple, int]:
        """Parse ``( ... )`` starting at ``pos`` (which must be at '('); return the tuple
        and the position after ')'."""
        m = self.token(pos)
        if m.lastindex != _PUNCT or m.group(_PUNCT) != "(":
            self.error(
                "P21-SYNTAX",
                f"expected '(' but found {self.describe(m)}",
                self.tok_start(m),
                entity,
            )
            raise _Abort(m.end())
        pos = m.end()
        stack: list[list[object]] = [[]]
        typed: list[str | None] = [None]
        expect_value = True  # after '(' or ','
        issues: dict[str, list[str]] = {}
        try:
            return self._param_loop(pos, stack, typed, expect_value, issues, entity)
        except _Abort as ab:
            ab.partial = tuple(stack[0])
            raise

    def _param_loop(
        self,
        pos: int,
        stack: list[list[object]],
        typed: list[str | None],
        expect_value: bool,
        issues: dict[str, list[str]],
        entity: int | None,
    ) -> tuple[tuple, int]:
        text = self.text
        while True:
            m = _TOKEN.match(text, pos)
            assert m is not None
            k = m.lastindex
            pos = m.end()
            cur = stack[-1]
            if k == _PUNCT:
                p = m.group(_PUNCT)
                if p == ",":
                    if expect_value:
                        issues.setdefault("empty", []).append(str(len(cur) + 1))
                        self.salvage_or_fail(m, entity, "empty parameter (two commas in a row)")
                        cur.append(None)
                    expect_value = True
                    continue
                if p == ")":
                    if expect_value and cur:
                        issues.setdefault("empty", []).append(str(len(cur) + 1))
                        self.salvage_or_fail(m, entity, "empty parameter before ')'")
                        cur.append(None)
                    done = tuple(cur)
                    stack.pop()
                    name = typed.pop()
                    if not stack:
                        self.report_issues(issues, entity)
                        return done, pos
                    stack[-1].append(
                        Typed(name, done[0] if len(done) == 1 else done)
                        if name is not None
                        else done
                    )
                    expect_value = False
                    continue
                if not expect_value:
                    self.fail(m, entity, "expected ',' or ')'")
                if p == "(":
                    stack.append([])
                    typed.append(None)
                    self.check_nesting(len(stack), m.start(), entity)
                    continue
                if p == "$":
                    nxt = _TOKEN.match(text, pos)
                    assert nxt is not None
                    if nxt.lastindex == _INT:
                        issues.setdefault("dollar", []).append(f"${nxt.group(_INT)}")
                        self.salvage_or_fail(
                            nxt,
                            entity,
                            f"'${nxt.group(_INT)}' is not a "
                            f"parameter (a reference is #{nxt.group(_INT)})",
                        )
                        cur.append(Ref(int(nxt.group(_INT))))
                        pos = nxt.end()
                    else:
                        cur.append(None)
                elif p == "*":
                    cur.append(DERIVED)
                else:
                    self.fail(m, entity, f"unexpected '{p}' in parameter list")
                expect_value = False
                continue
            if not expect_value:
                self.fail(m, entity, "expected ',' or ')'")
            expect_value = False
            if k == _REF:
                cur.append(Ref(int(m.group(_REF)[1:])))
            elif k == _REAL:
                cur.append(float(m.group(_REAL)))
            elif k == _INT:
                cur.append(int(m.group(_INT)))
            elif k == _STR:
                try:
                    cur.append(decode_string(m.group(_STR)))
                except (ValueError, IndexError) as exc:
                    self.fail(m, entity, f"bad string escape: {exc}", code="P21-STRING")
            elif k == _ENUM:
                cur.append(Enum(m.group(_ENUM).upper()))
            elif k == _BIN:
                cur.append(Binary(m.group(_BIN)))
            elif k == _KW:
                word = m.group(_KW)
                nxt = _TOKEN.match(text, pos)
                assert nxt is not None
                if nxt.lastindex == _PUNCT and nxt.group(_PUNCT) == "(":
                    stack.append([])
                    typed.append(word.upper())
                    self.check_nesting(len(stack), nxt.start(), entity)
                    pos = nxt.end()
                    expect_value = True
                elif nxt.lastindex == _PUNCT and nxt.group(_PUNCT) == "=":
                    issues.setdefault("keyword", []).append(word)
                    self.salvage_or_fail(
                        m, entity, f"'{word}=' keyword=value pairs are not Part 21 syntax"
                    )
                    pos = nxt.end()
                    expect_value = True
                else:
                    issues.setdefault("bare", []).append(word)
                    self.salvage_or_fail(
                        m,
                        entity,
                        f"'{word}' is not a value (enumerations and logicals are written .{word}.)",
                    )
                    cur.append(Enum(word.upper()))
            elif k == _EOF:
                self.fail(m, entity, "file ends inside a parameter list", code="P21-EOF")
            elif m.group(k) == "'":
                self.fail(m, entity, "string is not terminated by '", code="P21-STRING")
            else:
                self.fail(m, entity, f"unexpected character {m.group(k)!r}")

    def salvage_or_fail(self, m: re.Match[str], entity: int | None, message: str) -> None:
        if not self.collect:
            self.fail(m, entity, message)

    def report_issues(self, issues: dict[str, list[str]], entity: int | None) -> None:
        """Collect mode: one diagnostic per defect kind per instance."""
        if not issues:
            return
        pos = self._inst_pos
        texts = {
            "empty": ("P21-EMPTY-PARAM", "empty parameter at position {}"),
            "bare": ("P21-BARE-ENUM", "enumeration or logical without dots: {}"),
            "dollar": ("P21-BAD-REF", "'$' followed by a number ({}) is not a reference"),
            "keyword": ("P21-KEYWORD-VALUE", "keyword=value pair ({}=...) is not Part 21"),
        }
        for kind, items in issues.items():
            code, msg = texts[kind]
            self.error(code, f"#{entity}: " + msg.format(", ".join(items)), pos, entity)

    def fail(
        self, m: re.Match[str], entity: int | None, message: str, code: str = "P21-SYNTAX"
    ) -> None:
        where = f"#{entity}: " if entity is not None else ""
        self.error(code, f"{where}{message}, found {self.describe(m)}", self.tok_start(m), entity)
        raise _Abort(m.end())

    @staticmethod
    def describe(m: re.Match[str]) -> str:
        k = m.lastindex
        if k == _EOF:
            return "end of file"
        return repr(m.group(k or 0).strip()[:20])

    _inst_pos = 0
    _truncated = False
    _swallowed = -1
    #: turns (each an instance or a run of them) left to the Python reader before the
    #: compiled scanner is tried again, and the next such wait (doubling while the scanner
    #: takes nothing)
    _scan_wait = 0
    _scan_backoff = 1

    # -- file structure
    def expect_word(self, pos: int, word: str, code: str) -> int:
        m = self.token(pos)
        if m.lastindex == _KW and m.group(_KW).upper() == word:
            return m.end()
        self.error(code, f"expected {word} but found {self.describe(m)}", self.tok_start(m))
        return pos

    def expect_semicolon(self, pos: int, after: str) -> int:
        m = self.token(pos)
        if m.lastindex == _PUNCT and m.group(_PUNCT) == ";":
            return m.end()
        self.error("P21-SYNTAX", f"missing ';' after {after}", self.tok_start(m))
        return pos

    def read(self, raw: bytes) -> Part21File:
        out = Part21File(file=self.file)
        table = _scan_table(self.text, raw)
        if table is not None:
            out.instances = table
        pos = self.expect_word(0, "ISO-10303-21", "P21-MAGIC")
        pos = self.expect_semicolon(pos, "ISO-10303-21")
        pos = self.expect_word(pos, "HEADER", "P21-HEADER")
        pos = self.expect_semicolon(pos, "HEADER")
        pos = self.header(pos, out)
        data_seen = False
        while True:
            m = self.token(pos)
            if m.lastindex == _KW and m.group(_KW).upper() == "DATA":
                data_seen = True
                pos = m.end()
                nxt = self.token(pos)
                if nxt.lastindex == _PUNCT and nxt.group(_PUNCT) == "(":
                    try:  # DATA(name, schemas) of Part 21 ed. 3
                        _, pos = self.params(pos, None)
                    except _Abort as ab:  # collect mode: reported; the section starts after ';'
                        at_end = self.text[ab.pos - 1 : ab.pos] == ";"
                        pos = ab.pos if at_end else self.skip_statement(ab.pos)
                        pos = self.data(pos, out)
                        continue
                pos = self.expect_semicolon(pos, "DATA")
                pos = self.data(pos, out)
                continue
            if m.lastindex == _KW and m.group(_KW).upper() == "END-ISO-10303-21":
                self.expect_semicolon(m.end(), "END-ISO-10303-21")
                break
            if m.lastindex == _EOF:
                self.error("P21-EOF", "file ends without END-ISO-10303-21;", self.tok_start(m))
                break
            self.error(
                "P21-SYNTAX",
                f"expected DATA or END-ISO-10303-21, found {self.describe(m)}",
                self.tok_start(m),
            )
            pos = self.skip_statement(m.end())
        if not data_seen:
            self.error("P21-NO-DATA", "file has no DATA section", len(self.text))
        if table is not None:
            table.finish()
        return out

    def skip_statement(self, pos: int) -> int:
        end = self.text.find(";", pos)
        return len(self.text) if end < 0 else end + 1

    def header(self, pos: int, out: Part21File) -> int:
        bad_reported = False
        while True:
            m = self.token(pos)
            k = m.lastindex
            if k == _KW:
                word = m.group(_KW).upper()
                if word == "ENDSEC":
                    return self.expect_semicolon(m.end(), "ENDSEC")
                if word in ("DATA", "END-ISO-10303-21"):
                    self.error(
                        "P21-HEADER", "HEADER section is not closed by ENDSEC;", self.tok_start(m)
                    )
                    return pos
                try:
                    params, p = self.params(m.end(), None)
                except _Abort as ab:
                    pos = self.skip_statement(ab.pos)
                    continue
                out.header.append((word, params))
                pos = self.expect_semicolon(p, word)
                continue
            if k == _EOF:
                self.error("P21-EOF", "file ends inside the HEADER section", self.tok_start(m))
                return pos
            if not bad_reported:
                self.error(
                    "P21-HEADER",
                    f"unexpected {self.describe(m)} in HEADER section "
                    "(FILE_DESCRIPTION, FILE_NAME and FILE_SCHEMA expected)",
                    self.tok_start(m),
                )
                bad_reported = True
            pos = m.end()

    def bulk(self, pos: int, instances: MutableMapping[int, Instance]) -> int:
        """Read the instances from ``pos`` on that the compiled scanner or the fast path
        take; return the position of the first one neither takes (or of ENDSEC)."""
        if not isinstance(instances, Instances):
            return self.fast_run(pos, instances)
        text = self.text
        while True:
            took = False
            if self._scan_wait <= 0:
                if pos < self.line_pos:
                    self.line_pos, self.line_no = 0, 1
                line_no = self.line_no + text.count("\n", self.line_pos, pos)
                before = len(instances)
                pos, self.line_no, _ = instances.scan(pos, line_no, text.rfind("\n", 0, pos))
                self.line_pos = pos
                took = len(instances) > before
                if took:
                    self._scan_backoff = 1
                else:  # instances the scanner leaves: try it again less and less often
                    self._scan_wait = self._scan_backoff
                    self._scan_backoff = min(2 * self._scan_backoff, _SCAN_BACKOFF)
            after = self.fast_run(pos, instances, max(1, self._scan_wait))
            self._scan_wait -= 1
            if after == pos:
                return pos
            pos = after

    def fast_run(self, pos: int, instances: MutableMapping[int, Instance], limit: int = -1) -> int:
        """Read the well-formed simple instances from ``pos`` on through the fast path (at
        most ``limit`` of them when positive); return the position of the first one it
        cannot take (or of ENDSEC)."""
        text = self.text
        fast_match = FAST_INSTANCE.match
        count_nl = text.count
        rfind = text.rfind
        names: dict[str, str] = {}
        line_pos, line_no = self.line_pos, self.line_no
        if pos < line_pos:
            line_pos, line_no = 0, 1
        while limit:
            limit -= 1
            f = fast_match(text, pos)
            if f is None:
                break
            ident_s, raw_name, body = f.groups()
            params = fast_params(body)
            ident = int(ident_s)
            if params is None or ident in instances:
                break
            start = f.start(1) - 1
            line_no += count_nl("\n", line_pos, start)
            line_pos = start
            name = names.get(raw_name)
            if name is None:
                name = names[raw_name] = sys.intern(raw_name.upper())
            instances[ident] = Instance(ident, name, params, line_no, start - rfind("\n", 0, start))
            pos = f.end()
        self.line_pos, self.line_no = line_pos, line_no
        return pos

    def data(self, pos: int, out: Part21File) -> int:
        text = self.text
        instances = out.instances
        while True:
            pos = self.bulk(pos, instances)
            m = _TOKEN.match(text, pos)
            assert m is not None
            k = m.lastindex
            if k == _REF:
                start = m.start(_REF)
                ident = int(m.group(_REF)[1:])
                self._inst_pos = start
                try:
                    pos = self.instance(m.end(), ident, start, instances)
                except _Abort as ab:
                    pos = self.recover(start, ab.pos, ident)
                    if ab.name is not None and ab.partial is not None and self._truncated:
                        line, col = self.line_col(start)
                        partial = ab.partial
                        if partial and partial[-1] == self._swallowed:
                            partial = partial[:-1]  # '#11' of the swallowed '#11='
                        instances[ident] = Instance(ident, ab.name, partial, line, col)
                        out.salvaged.add(ident)
                continue
            if k == _KW and m.group(_KW).upper() == "ENDSEC":
                return self.expect_semicolon(m.end(), "ENDSEC")
            if k == _EOF:
                self.error("P21-EOF", "DATA section is not closed by ENDSEC;", self.tok_start(m))
                return m.end()
            self.error(
                "P21-SYNTAX",
                f"expected an instance '#n=' or ENDSEC, found {self.describe(m)}",
                self.tok_start(m),
            )
            pos = self.recover(m.start(k or 0), m.end(), None)

    def recover(self, start: int, err: int, ident: int | None) -> int:
        """After an error in the instance starting at ``start``: resume at an instance that
        begins on a later line before the error (a truncated instance swallowed it), else at
        the next instance start after the error."""
        text = self.text
        m = _INSTANCE_START.search(text, start, err)
        self._truncated = m is not None
        if m is not None:
            self._swallowed = int(text[m.start() : m.end()].strip().lstrip("#").rstrip("=").strip())
            line, _ = self.line_col(m.start() + 1)
            if self.collect and ident is not None:
                assert self.diags is not None
                sline, scol = self.line_col(start)
                self.diags[-1] = Diagnostic(
                    "P21-UNTERMINATED",
                    f"#{ident} is not terminated: its parameter list runs into the next "
                    f"instance at line {line}",
                    Location(self.file, sline, scol, entity=ident),
                )
            return m.start() + 1
        m = _INSTANCE_START.search(text, err)
        if m is not None:
            return m.start() + 1
        end = text.find("ENDSEC", err)
        return end if end >= 0 else len(text)

    def instance(
        self, pos: int, ident: int, start: int, instances: MutableMapping[int, Instance]
    ) -> int:
        text = self.text
        m = _TOKEN.match(text, pos)
        assert m is not None
        if m.lastindex != _PUNCT or m.group(_PUNCT) != "=":
            self.fail(m, ident, "expected '=' after the instance name")
        m = _TOKEN.match(text, m.end())
        assert m is not None
        if m.lastindex == _KW:
            name: str | None = m.group(_KW).upper()
            try:
                params, pos = self.params(m.end(), ident)
            except _Abort as ab:
                ab.name = name
                raise
        elif m.lastindex == _PUNCT and m.group(_PUNCT) == "(":
            name = None
            parts: list[Part] = []
            pos = m.end()
            while True:
                m = _TOKEN.match(text, pos)
                assert m is not None
                if m.lastindex == _PUNCT and m.group(_PUNCT) == ")":
                    pos = m.end()
                    break
                if m.lastindex != _KW:
                    self.fail(m, ident, "expected an entity name in a complex instance")
                p, pos = self.params(m.end(), ident)
                parts.append(Part(m.group(_KW).upper(), p))
            params = tuple(parts)
        else:
            self.fail(m, ident, "expected an entity name after '='")
            raise AssertionError  # unreachable
        m = _TOKEN.match(text, pos)
        assert m is not None
        if m.lastindex != _PUNCT or m.group(_PUNCT) != ";":
            self.fail(m, ident, "missing ';' after the instance")
        line, col = self.line_col(start)
        if ident in instances:
            self.error(
                "P21-DUPLICATE-ID",
                f"#{ident} is defined twice (first at line {instances[ident].line})",
                start,
                ident,
            )
        instances[ident] = Instance(ident, name, params, line, col)
        return m.end()


# Fast path for well-formed simple instances: one C-level match of the whole instance, one
# findall of its tokens, one Python loop over plain strings. Anything unusual (comments,
# binaries, typed parameters, complex instances, any defect) returns None and the exact
# parser above handles the instance and reports its errors.
class _Abort(Exception):
    def __init__(self, pos: int) -> None:
        self.pos = pos
        self.partial: tuple | None = None
        self.name: str | None = None


#: texts from this many characters on are scanned by the compiled scanner
#: (:mod:`stepnc.p21_scan`) when its kernels load (below it, loading numpy and the kernels
#: costs more than it saves); 0 scans every text, None none (the equivalence tests use both)
SCAN_MIN_CHARS: int | None = 1 << 17


def _scan_table(text: str, raw: bytes) -> Instances | None:
    """An empty compiled-scanner table for ``text`` (``raw``: its latin-1 bytes), or None
    where the pure-Python reader reads it (a small text, or no kernels)."""
    if SCAN_MIN_CHARS is None or not SCAN_MIN_CHARS <= len(text) <= MAX_CHARS:
        return None
    try:
        KERNELS.module()
    except ImportError:
        return None
    buf = np.frombuffer(raw, dtype=np.uint8)
    return Instances(text, buf, raw.count(b";") + 1)


def parse(
    text: str, file: str | None = None, diagnostics: list[Diagnostic] | None = None
) -> Part21File:
    """Read Part 21 text. Strict (raises the first :class:`Diagnostic`) unless a list is given
    for ``diagnostics``, in which case defects are salvaged and recorded there."""
    return _parse(text, text.encode("latin-1", "replace"), file, diagnostics)


def _parse(
    text: str, raw: bytes, file: str | None, diagnostics: list[Diagnostic] | None
) -> Part21File:
    """:func:`parse` of ``text`` whose latin-1 bytes (one a character) are ``raw``."""
    # a parse allocates millions of small tuples and no cycles: the cyclic collector would
    # only rescan them (about a third of the run time on large files)
    enabled = gc.isenabled()
    gc.disable()
    try:
        reader = _Reader(text, file, diagnostics)
        reader.check_digits(raw)
        return reader.read(raw)
    finally:
        if enabled:
            gc.enable()


def read_file(path: str, diagnostics: list[Diagnostic] | None = None) -> Part21File:
    """Read a Part 21 file (I/O errors propagate as :class:`OSError`)."""
    with open(path, "rb") as fh:
        raw = fh.read()
    if b"\r" in raw:  # universal newlines, as a file opened in text mode reads them
        text = raw.decode("latin-1").replace("\r\n", "\n").replace("\r", "\n")
        raw = text.encode("latin-1")
    else:
        text = raw.decode("latin-1")
    return _parse(text, raw, path, diagnostics)


def check_references(p21: Part21File, diagnostics: list[Diagnostic] | None = None) -> None:
    """Report each undefined instance that is referenced, once, as ``P21-DANGLING-REF``
    located at its first referrer (file order) and naming all referrers."""
    referrers: dict[int, list[int]] = {}
    for inst in p21.instances.values():
        for ref in references(inst.params):
            if ref not in p21.instances:
                users = referrers.setdefault(ref, [])
                if not users or users[-1] != inst.id:
                    users.append(inst.id)
    for ref, users in referrers.items():
        names = ", ".join(f"#{u}" for u in users)
        diag = Diagnostic(
            "P21-DANGLING-REF",
            f"#{ref} is referenced (by {names}) but not defined",
            p21.location(users[0]),
        )
        if diagnostics is None:
            raise diag
        diagnostics.append(diag)
