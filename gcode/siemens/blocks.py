"""One Siemens 840D block (a line) -> a :class:`Block`: its N number, label, comment and
either a control statement or the ordered words and assignments of an NC block.

Block structure after the 840D sl programming manual (fundamentals, "Block structure";
job planning, "Program jumps", "Control structures", "Variable definition"): ``N10``,
``LABEL:``, ``IF cond GOTOF label``, ``IF``/``ELSE``/``ENDIF``, ``WHILE``/``ENDWHILE``,
``FOR i=a TO b``/``ENDFOR``, ``REPEAT``/``UNTIL``, ``LOOP``/``ENDLOOP``, ``CASE e OF 1
GOTOF A DEFAULT GOTOF B``, section repetition (``REPEAT A B P=2``, ``REPEATB A P=3``),
``DEF REAL a=1``, ``MSG("...")``, frames (``TRANS X10`` ...), cycle calls
(``CYCLE81(...)``), subprograms with parameters (``PROC NAME(REAL A, VAR INT B)``,
``EXTERN NAME(REAL, VAR INT)``) and subprogram calls (``L100``, ``NAME P3``, ``NAME(1, R2)``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import kernel.limits as limits
from gcode.siemens.expr import Node, Parser
from gcode.siemens.lexer import NAME, OP, STR, WORD, Token, tokenize
from kernel.diagnostics import Diagnostic, Location

#: addresses written ``X=expr`` or ``CR=expr`` (besides the single letters of words)
EXTENDED = frozenset(
    {"CR", "AR", "TURN", "SPOS", "LIMS", "ADIS", "RPL", "MEAS", "I1", "J1", "K1"}
    | {"CHF", "CHR", "RND", "RNDM"}
)
LETTERS = frozenset("XYZABCIJKFSTDGMP")
AXIS_MODES = frozenset({"AC", "IC"})
FRAMES = frozenset({"TRANS", "ATRANS", "ROT", "AROT", "SCALE", "ASCALE", "MIRROR", "AMIRROR"})
ALONE = frozenset({"ELSE", "ENDIF", "ENDWHILE", "ENDFOR", "REPEAT", "LOOP", "ENDLOOP", "RET"})
JUMPS = frozenset({"GOTOF", "GOTOB", "GOTO", "GOTOC"})
TYPES = frozenset({"REAL", "INT", "BOOL"})
KEYWORDS = (
    FRAMES
    | ALONE
    | JUMPS
    | TYPES
    | {"IF", "WHILE", "FOR", "TO", "UNTIL", "DEF", "PROC", "MSG", "MCALL", "NOT", "AND", "OR"}
    | {"CASE", "OF", "DEFAULT", "REPEATB", "EXTERN", "VAR", "ENDLABEL"}
)
#: 840D instructions this reader knows it does not implement (refused, never taken for
#: subprogram names): transformations, path and dynamic modes, splines, calls
UNSUPPORTED = frozenset(
    [
        "TRAORI",
        "TRANSMIT",
        "TRACYL",
        "TRAANG",
        "CT",
        "ASPLINE",
        "BSPLINE",
        "CSPLINE",
        "POLY",
        "OFFN",
        "SPCON",
        "SPCOF",
        "CTAB",
        "CALL",
        "PCALL",
        "EXTCALL",
        "FRC",  # FRC= / FRCM=: the own feed of a chamfer or rounding (not read)
        "FRCM",
        "WAITM",
        "WAITE",
        "SAVE",
        "DISPLOF",
        "PRINT",
        "WRITE",
        "READ",
        "DELETE",
        "EXECSTRING",
        "EXECTAB",
        "SPRINT",
        "SETM",
        "CLEARM",
        "GET",
        "GETD",
        "RELEASE",
        "DEFINE",
        "GOTOS",
        "ISOCALL",
        "SETINT",
        "CLRINT",
        "ENABLE",
        "DISABLE",
        "PROCESSING",
    ]
)
#: the conditions of synchronized actions (job planning, "Motion-synchronous actions":
#: ``ID=1 WHENEVER $A_IN[1] DO ...``, ``DO ...``): run by the NC in the interpolation cycle,
#: beside the program; the IR has no such actions, so the block is refused (naming them)
SYNCHRONIZED = frozenset({"WHEN", "WHENEVER", "EVERY", "FROM", "DO"})
#: 840D instructions that change how the path is run (jerk and acceleration profiles,
#: feedforward, compressor, look-ahead stop, feed correction under radius compensation,
#: orientation interpolation without a transformation, switching a transformation off while
#: none is on) and not where it goes: read and ignored, the IR has no such setting
#: (fundamentals and job planning: SOFT/BRISK/DRIVE, FFWON, COMPCAD, STOPRE, CFC, FNORM,
#: UPATH/SPATH, DYNNORM..., ORIWKS, TRAFOOF), and single-block suppression SBLOF/SBLON (job
#: planning, "Single block suppression": the operator's single-block mode, not the path)
NEUTRAL = frozenset(
    {"SOFT", "BRISK", "DRIVE", "SOFTA", "BRISKA", "FFWON", "FFWOF", "COMPON", "COMPCURV"}
    | {"COMPCAD", "COMPOF", "STOPRE", "CFC", "CFTCP", "CFIN", "FNORM", "UPATH", "SPATH"}
    | {"DYNNORM", "DYNPOS", "DYNROUGH", "DYNSEMIFIN", "DYNFINISH", "ORIWKS", "ORIMKS"}
    | {"ORIAXES", "ORIVECT", "TRAFOOF", "CPRECON", "CPRECOF"}
    | {"SBLOF", "SBLON"}
)
#: axis-indexed dynamic settings (``ACC[X]=50``: acceleration, jerk and velocity limits in
#: percent): like the NEUTRAL instructions they change how the path is run, not where
AXIS_SETTINGS = frozenset({"ACC", "JERKLIM", "VELOLIM", "ACCLIMA", "JERKLIMA", "VELOLIMA"})
#: diameter programming of the transverse axis X (fundamentals, "Dimensions for turning")
DIAMETER = frozenset({"DIAMON", "DIAMOF", "DIAM90"})
#: the block's positions are machine coordinates (all frames suppressed, non-modal)
SUPPRESS = frozenset({"SUPA"})
#: axis addresses of 840D machines with more axes (W: a second Z, e.g. a quill) that the
#: machine profile (kernel.machine: X Y Z A B C) and the IR do not have
ABSENT_AXES = frozenset({"U", "V", "W"})


def _no_axis(letter: str) -> str:
    return (
        f"{letter}: this machine has no {letter} axis (the machine profile's and the IR's "
        "axes are X Y Z A B C)"
    )


#: drilling cycles expanded into moves (gcode.siemens.cycles)
CYCLES = frozenset({"CYCLE81", "CYCLE82", "CYCLE83"})


@dataclass(slots=True)
class Word:
    """``address`` (``X``, ``G``, ``CR``...) = ``value``; ``mode`` AC/IC for ``X=AC(..)``."""

    address: str
    value: Node
    col: int
    mode: str | None = None


@dataclass(slots=True)
class Assign:
    """``R1=expr``, ``R[i]=expr`` or ``NAME=expr``: ``target`` ("R", index node) or ("V", name)."""

    target: tuple[str, Node | str]
    value: Node
    col: int


@dataclass(slots=True)
class Block:
    line: int
    col: int = 1
    number: int | None = None
    label: str | None = None
    comment: str | None = None
    kind: str = "nc"  # nc | IF | ELSE | ... | GOTO | DEF | PROC | MSG | FRAME | CYCLE | CALL
    items: list[Word | Assign] = field(default_factory=list)
    args: tuple = ()  # statement data (condition, label, cycle arguments, ...)

    @property
    def empty(self) -> bool:
        return self.kind == "nc" and not self.items


def parse_block(text: str, file: str | None, line: int) -> Block:
    """The block on one line (raises a located ``SIEM-*`` Diagnostic on bad syntax)."""
    limits.check_digits(text, file, line)
    tokens, comment = tokenize(text, file, line)
    block = Block(line, comment=comment)
    i = 0
    if i < len(tokens) and tokens[i].kind == WORD and tokens[i].text[0] == "N":
        n = tokens[i].value
        if n < 0 or n != int(n):
            raise Diagnostic(
                "SIEM-BLOCK-NUMBER",
                "block number must be a whole number",
                _at(file, line, tokens[i]),
            )
        block.number = int(n)
        i += 1
    if i + 1 < len(tokens) and tokens[i].kind == NAME and _op(tokens[i + 1], ":"):
        block.label = tokens[i].text
        i += 2
    if i < len(tokens):
        block.col = tokens[i].col
    _Statement(tokens, i, file, line, block).parse()
    return block


def _op(tok: Token, text: str) -> bool:
    return tok.kind == OP and tok.text == text


def _at(file: str | None, line: int, tok: Token) -> Location:
    return Location(file, line, tok.col)


class _Statement:
    def __init__(self, tokens: list[Token], i: int, file: str | None, line: int, b: Block) -> None:
        self.t, self.i, self.file, self.line, self.b = tokens, i, file, line, b

    def loc(self) -> Location:
        t = self.t
        col = t[self.i].col if self.i < len(t) else (t[-1].col + len(t[-1].text) if t else 1)
        return Location(self.file, self.line, col)

    def error(self, code: str, message: str) -> Diagnostic:
        return Diagnostic(code, message, self.loc())

    def expr(self) -> Node:
        p = Parser(self.t, self.i, self.file, self.line)
        node = p.expression()
        self.i = p.pos
        return node

    def done(self) -> bool:
        return self.i >= len(self.t)

    def end(self) -> None:
        if not self.done():
            raise self.error("SIEM-SYNTAX", f"unexpected {self.t[self.i].text!r}")

    def name(self) -> str:
        if self.done() or self.t[self.i].kind != NAME:
            raise self.error(
                "SIEM-SYNTAX", "a name is expected (names begin with two letters or _)"
            )
        self.i += 1
        return self.t[self.i - 1].text

    def take(self, text: str) -> None:
        if self.done() or self.t[self.i].text != text:
            raise self.error("SIEM-SYNTAX", f"{text!r} expected")
        self.i += 1

    def is_op(self, text: str) -> bool:
        return not self.done() and _op(self.t[self.i], text)

    # ------------------------------------------------------------------ statements
    def parse(self) -> None:
        if self.done():
            return
        tok = self.t[self.i]
        b = self.b
        self._synchronized_action()
        if tok.kind == NAME and not self._assignment_ahead():
            head = tok.text
            if head == "REPEAT" and self.i + 1 < len(self.t):
                self.i += 1
                self._section("REPEAT")
                return
            if head in ALONE:
                self.i += 1
                self.end()
                b.kind = head
                return
            handler = getattr(self, "_" + head.lower(), None)
            if head in KEYWORDS and handler is not None:
                self.i += 1
                handler()
                return
            if head in FRAMES:
                self.i += 1
                self._frame(head)
                return
            if head in JUMPS:
                self.i += 1
                b.kind, b.args = "GOTO", (head, self._label())
                self.end()
                return
            if (
                head.startswith("CYCLE")
                and self.i + 1 < len(self.t)
                and _op(self.t[self.i + 1], "(")
            ):
                self.i += 1
                b.kind, b.args = "CYCLE", (head, self._arguments(head))
                self.end()
                return
            if head == "WORKPIECE" and self.i + 1 < len(self.t) and _op(self.t[self.i + 1], "("):
                self.i += 1  # the blank for the control's simulation (ShopMill/ShopTurn)
                self._arguments(head)
                self.end()
                return
            if head == "SETMS":
                self.i += 1
                b.kind, b.args = "SETMS", self._arguments(head) if self.is_op("(") else ()
                self.end()
                return
            if head == "SETAL" and self.i + 1 < len(self.t) and _op(self.t[self.i + 1], "("):
                self.i += 1
                b.kind, b.args = "ALARM", self._arguments(head)
                self.end()
                return
            if head in UNSUPPORTED or head.startswith("$"):
                raise self.error("SIEM-UNSUPPORTED", f"{head} is not supported by this reader")
            known = EXTENDED | NEUTRAL | DIAMETER | SUPPRESS | AXIS_SETTINGS | LETTERS
            known |= KEYWORDS | {"CIP"}
            if head not in known:
                self.i += 1
                self._call(head)
                return
        if tok.kind == WORD and tok.text[0] == "L":
            self.i += 1
            self._call(tok.text)
            return
        self._nc()

    def _synchronized_action(self) -> None:
        """Refuse a synchronized action: a block beginning with ``WHEN``, ``WHENEVER``,
        ``EVERY``, ``FROM`` or ``DO``, or with ``ID=n``/``IDS=n`` before one of them."""
        t, i = self.t, self.i
        if (
            t[i].kind == NAME
            and t[i].text in ("ID", "IDS")
            and i + 2 < len(t)
            and _op(t[i + 1], "=")
        ):
            i += 3
        if i < len(t) and t[i].kind == NAME and t[i].text in SYNCHRONIZED:
            self.i = i
            form = "DO ..." if t[i].text == "DO" else f"{t[i].text} ... DO ..."
            raise self.error(
                "SIEM-UNSUPPORTED",
                f"synchronized action ({form}): actions the NC runs beside the program in "
                "the interpolation cycle are not read",
            )

    def _assignment_ahead(self) -> bool:
        j = self.i + 1
        return j < len(self.t) and (_op(self.t[j], "=") or _op(self.t[j], "["))

    def _label(self) -> str:
        if self.done():
            raise self.error("SIEM-SYNTAX", "jump target (label or block number) expected")
        tok = self.t[self.i]
        self.i += 1
        if tok.kind == NAME or (tok.kind == WORD and tok.text[0] == "N"):
            return tok.text if tok.kind == NAME else f"N{int(tok.value)}"
        raise Diagnostic(
            "SIEM-SYNTAX",
            "jump target (label or block number) expected",
            _at(self.file, self.line, tok),
        )

    def _if(self) -> None:
        cond = self.expr()
        if self.done():
            self.b.kind, self.b.args = "IF", (cond,)
            return
        jump = self.name()
        if jump not in JUMPS:
            raise Diagnostic(
                "SIEM-SYNTAX", f"GOTOF or GOTOB expected after IF condition, not {jump}", self.loc()
            )
        self.b.kind, self.b.args = "IFGOTO", (cond, jump, self._label())
        self.end()

    def _while(self) -> None:
        self.b.kind, self.b.args = "WHILE", (self.expr(),)
        self.end()

    def _until(self) -> None:
        self.b.kind, self.b.args = "UNTIL", (self.expr(),)
        self.end()

    def _for(self) -> None:
        target = self._target()
        self.take("=")
        start = self.expr()
        self.take("TO")
        stop = self.expr()
        self.end()
        self.b.kind, self.b.args = "FOR", (target, start, stop)

    def _def(self) -> None:
        kind = self.name()
        if kind not in TYPES:
            raise Diagnostic(
                "SIEM-UNSUPPORTED", f"DEF {kind}: only REAL, INT and BOOL variables", self.loc()
            )
        names = []
        while True:
            name = self.name()
            if self.is_op("["):
                names.append(self._array(name))
            else:
                value: Node | None = None
                if self.is_op("="):
                    self.i += 1
                    value = self.expr()
                names.append((name, value))
            if not self.is_op(","):
                break
            self.i += 1
        self.end()
        self.b.kind, self.b.args = "DEF", (kind, tuple(names))

    def _array(self, name: str) -> tuple:
        """``NAME[n, m]`` with ``= SET(a, , c)``, ``= REP(v[, count])`` or ``= v``: (name,
        dimension nodes, values: ("SET", nodes or None) or ("REP", value, count or None))."""
        self.i += 1
        dims = []
        while True:
            dims.append(self.expr())
            if self.is_op("]"):
                self.i += 1
                break
            self.take(",")
        init: tuple = ("SET", ())
        if self.is_op("="):
            self.i += 1
            head = self.t[self.i].text if not self.done() else ""
            if head in ("SET", "REP") and self.i + 1 < len(self.t) and _op(self.t[self.i + 1], "("):
                self.i += 1
                args = self._arguments(head)
                if head == "SET":
                    init = ("SET", args)
                else:
                    if not args or args[0] is None or len(args) > 2:
                        raise self.error("SIEM-SYNTAX", "REP(value[, count]) expected")
                    init = ("REP", args[0], args[1] if len(args) == 2 else None)
            else:
                init = ("REP", self.expr(), None)
        return (name, tuple(dims), init)

    def _proc(self) -> None:
        """``PROC NAME(REAL A, VAR INT B)``: args (name, ((by_reference, type, name), ...))."""
        name = self._program_name()
        params: list[tuple[bool, str, str]] = []
        if self.is_op("("):
            self.i += 1
            while not self.is_op(")"):
                by_reference = self._var()
                kind = self._type(f"PROC {name}")
                at = self.loc()
                pname = self.name()
                if self.is_op("["):
                    raise self.error(
                        "SIEM-UNSUPPORTED", f"PROC {name}: array parameter {pname}[...]"
                    )
                if any(p[2] == pname for p in params):
                    raise Diagnostic("SIEM-PROC", f"PROC {name}: parameter {pname} twice", at)
                params.append((by_reference, kind, pname))
                if not self.is_op(")"):
                    self.take(",")
            self.i += 1
        while not self.done() and self.t[self.i].kind == NAME:
            if self.t[self.i].text in ("DISPLOF", "DISPLON", "SBLOF", "SBLON", "ACTBLOCNO"):
                self.i += 1  # display and single-block attributes: no IR meaning
            elif self.t[self.i].text == "SAVE":
                raise self.error(
                    "SIEM-UNSUPPORTED",
                    f"PROC {name} SAVE (the caller's modal state restored at the return) "
                    "is not supported",
                )
            else:
                break
        self.end()
        self.b.kind, self.b.args = "PROC", (name, tuple(params))

    def _program_name(self) -> str:
        """A subprogram's name: a name, or an ``L`` number (``L140``)."""
        if not self.done() and self.t[self.i].kind == WORD and self.t[self.i].text[0] == "L":
            self.i += 1
            return self.t[self.i - 1].text
        return self.name()

    def _var(self) -> bool:
        if not self.done() and self.t[self.i].kind == NAME and self.t[self.i].text == "VAR":
            self.i += 1
            return True
        return False

    def _type(self, what: str) -> str:
        at = self.loc()
        kind = self.name()
        if kind not in TYPES:
            raise Diagnostic(
                "SIEM-UNSUPPORTED", f"{what}: {kind} parameters (only REAL, INT and BOOL)", at
            )
        return kind

    def _extern(self) -> None:
        """``EXTERN NAME(REAL, VAR INT)``: the parameter types of a subprogram the main
        program calls with arguments; args (name, ((by_reference, type), ...))."""
        name = self._program_name()
        types: list[tuple[bool, str]] = []
        if self.is_op("("):
            self.i += 1
            while not self.is_op(")"):
                by_reference = self._var()
                types.append((by_reference, self._type(f"EXTERN {name}")))
                if self.is_op("["):
                    raise self.error("SIEM-UNSUPPORTED", f"EXTERN {name}: array parameters")
                if not self.is_op(")"):
                    self.take(",")
            self.i += 1
        self.end()
        self.b.kind, self.b.args = "EXTERN", (name, tuple(types))

    def _case(self) -> None:
        """``CASE e OF 1 GOTOF A 2 GOTOB B DEFAULT GOTOF C``: args (expression,
        ((constant node, jump, label), ...), (jump, label) or None)."""
        value = self.expr()
        if self.done() or self.t[self.i].text != "OF":
            raise self.error("SIEM-SYNTAX", "CASE expression OF expected")
        self.i += 1
        cases: list[tuple[Node, str, str]] = []
        default: tuple[str, str] | None = None
        while not self.done():
            if self.t[self.i].kind == NAME and self.t[self.i].text == "DEFAULT":
                self.i += 1
                default = (self._jump("CASE DEFAULT"), self._label())
                break
            constant = self.expr()
            cases.append((constant, self._jump("CASE"), self._label()))
        self.end()
        if not cases and default is None:
            raise self.error("SIEM-SYNTAX", "CASE without a constant or DEFAULT")
        self.b.kind, self.b.args = "CASE", (value, tuple(cases), default)

    def _jump(self, what: str) -> str:
        tok = self.t[self.i] if not self.done() else None
        if tok is None or tok.kind != NAME or tok.text not in JUMPS:
            raise self.error("SIEM-SYNTAX", f"{what}: GOTOF, GOTOB, GOTO or GOTOC expected")
        self.i += 1
        return tok.text

    def _repeatb(self) -> None:
        self._section("REPEATB")

    def _section(self, head: str) -> None:
        """``REPEAT A P=n``, ``REPEAT A B P=n``, ``REPEAT A ENDLABEL P=n``, ``REPEATB A
        P=n``: args (head, start label, end label or None, passes node)."""
        start = self._label()
        end: str | None = None
        if head == "REPEAT" and not self.done() and self.t[self.i].kind in (NAME, WORD):
            tok = self.t[self.i]
            if not (tok.text == "P" or (tok.kind == WORD and tok.text[0] == "P")):
                end = self._label()
        passes: Node = ("num", 1.0)
        if not self.done():
            tok = self.t[self.i]
            if tok.kind == WORD and tok.text[0] == "P":
                passes = ("num", tok.value)
                self.i += 1
            elif tok.kind == NAME and tok.text == "P":
                self.i += 1
                self.take("=")
                passes = self.expr()
        self.end()
        self.b.kind, self.b.args = "SECTION", (head, start, end, passes)

    def _msg(self) -> None:
        self.take("(")
        text = ""
        if not self.done() and self.t[self.i].kind == STR:
            text = self.t[self.i].text
            self.i += 1
        self.take(")")
        self.end()
        self.b.kind, self.b.args = "MSG", (text,)

    def _mcall(self) -> None:
        if self.done():
            self.b.kind, self.b.args = "MCALL", (None, ())
            return
        head = self._program_name()
        if head.startswith("CYCLE"):
            args: tuple[Node | None, ...] | None = self._arguments(head)
        else:  # a subprogram: MCALL L10, MCALL NAME(1, 2)
            args = self._arguments(head) if self.is_op("(") else None
            if args == (None,):
                args = ()
        self.b.kind, self.b.args = "MCALL", (head, args)
        self.end()

    def _frame(self, head: str) -> None:
        self._nc()
        for item in self.b.items:
            if isinstance(item, Assign) or item.address not in ("X", "Y", "Z", "RPL"):
                raise Diagnostic(
                    "SIEM-FRAME",
                    f"{head} takes X, Y, Z (and RPL= for rotations) only",
                    Location(self.file, self.line, item.col),
                )
        self.b.kind, self.b.args = "FRAME", (head,)

    def _call(self, name: str) -> None:
        """``NAME``, ``L100 P3``, ``NAME(1.5, , R2) P2``: args (name, passes, arguments or
        None; an omitted argument is None)."""
        repeat: Node = ("num", 1.0)
        args: tuple[Node | None, ...] | None = None
        if self.is_op("("):
            args = self._arguments(name)
            if args == (None,):
                args = ()
        if not self.done() and self.t[self.i].kind == WORD and self.t[self.i].text[0] == "P":
            repeat = ("num", self.t[self.i].value)
            self.i += 1
        self.end()
        self.b.kind, self.b.args = "CALL", (name, repeat, args)

    def _arguments(self, head: str) -> tuple[Node | None, ...]:
        self.take("(")
        args: list[Node | None] = []
        while True:
            if self.is_op(",") or self.is_op(")"):
                args.append(None)
            else:
                args.append(self.expr())
            if self.is_op(")"):
                self.i += 1
                return tuple(args)
            self.take(",")

    def _target(self) -> tuple[str, Node | str]:
        tok = self.t[self.i] if not self.done() else None
        if tok is None or tok.kind != NAME:
            raise self.error("SIEM-SYNTAX", "a variable or R parameter is expected")
        self.i += 1
        name = tok.text
        if name == "R" and self.is_op("["):
            self.i += 1
            index = self.expr()
            self.take("]")
            return ("R", index)
        if name[0] == "R" and name[1:].isdigit():
            return ("R", ("num", float(name[1:])))
        if self.is_op("["):  # an element of a DEF array
            self.i += 1
            index = []
            while True:
                index.append(self.expr())
                if self.is_op("]"):
                    self.i += 1
                    return ("A", (name, tuple(index)))
                self.take(",")
        return ("V", name)

    # ------------------------------------------------------------------ NC words
    def _nc(self) -> None:
        items = self.b.items
        t = self.t
        while not self.done():
            tok = t[self.i]
            if tok.kind == WORD:
                letter = tok.text[0]
                if letter in ABSENT_AXES:
                    raise self.error("SIEM-AXIS", _no_axis(letter))
                if letter not in LETTERS:
                    raise self.error("SIEM-WORD", f"unknown address {letter} in {tok.text}")
                items.append(Word(letter, ("num", tok.value), tok.col))
                self.i += 1
                continue
            if tok.kind != NAME:
                raise self.error("SIEM-SYNTAX", f"unexpected {tok.text!r}")
            name = tok.text
            if name.startswith("$"):
                raise self.error("SIEM-UNSUPPORTED", f"system variable {name} is not supported")
            if name == "CIP" and not self._assignment_ahead():
                items.append(Word("CIP", ("num", 1.0), tok.col))
                self.i += 1
                continue
            if name in AXIS_SETTINGS and self.i + 1 < len(t) and _op(t[self.i + 1], "["):
                self._axis_setting(name)
                continue
            if not self._assignment_ahead() and name in NEUTRAL:
                self.i += 1
                continue
            if not self._assignment_ahead() and name in DIAMETER | SUPPRESS:
                items.append(Word(name, ("num", 1.0), tok.col))
                self.i += 1
                continue
            if not self._assignment_ahead():
                if name in UNSUPPORTED:
                    raise self.error("SIEM-UNSUPPORTED", f"{name} is not supported by this reader")
                if name in KEYWORDS or name.startswith("CYCLE"):
                    raise self.error("SIEM-BLOCK", f"{name} must stand alone in its block")
                raise self.error("SIEM-WORD", f"unknown word {name}")
            if name in UNSUPPORTED:
                raise self.error("SIEM-UNSUPPORTED", f"{name}= is not supported by this reader")
            if name in ABSENT_AXES:
                raise self.error("SIEM-AXIS", _no_axis(name))
            if name in LETTERS and _op(t[self.i + 1], "["):
                raise self.error(
                    "SIEM-UNSUPPORTED",
                    f"{name}[...]=: indirect programming (a G or M function by its group and "
                    "number) is not read",
                )
            if name == "R" and _op(t[self.i + 1], "="):
                raise self.error(
                    "SIEM-WORD",
                    "R=: an R parameter is written with its number (R10=...); a circle's "
                    "radius is CR=",
                )
            if name in LETTERS or name in EXTENDED:
                self.i += 2
                items.append(self._value(name, tok.col))
                continue
            target = self._target()
            self.take("=")
            items.append(Assign(target, self.expr(), tok.col))

    def _axis_setting(self, name: str) -> None:
        """``ACC[X]=50``: read (the value is checked as an expression) and dropped."""
        self.i += 2
        tok = self.t[self.i] if not self.done() else None
        axis = tok.text if tok is not None else ""
        if axis not in ("X", "Y", "Z", "A", "B", "C", "SPI"):
            raise self.error("SIEM-AXIS", f"{name}[{axis}]: this machine has no such axis")
        self.i += 1
        self.take("]")
        self.take("=")
        self.expr()

    def _value(self, address: str, col: int) -> Word:
        mode = None
        if not self.done() and self.t[self.i].kind == STR:
            if address != "T":
                raise self.error("SIEM-WORD", f'{address}="...": a name where a number is needed')
            name = self.t[self.i].text  # T="NAME": a tool of the tool management, by name
            self.i += 1
            return Word(address, ("tool", name), col)
        tok = self.t[self.i] if not self.done() else None
        nxt = self.t[self.i + 1] if self.i + 1 < len(self.t) else None
        if tok is not None and tok.text in AXIS_MODES and nxt is not None and _op(nxt, "("):
            mode = tok.text
            if address not in ("X", "Y", "Z", "A", "B", "C", "I", "J", "K", "I1", "J1", "K1"):
                raise self.error(
                    "SIEM-WORD", f"{mode}() is for axis and centre words, not {address}"
                )
            self.i += 2
            node = self.expr()
            self.take(")")
            return Word(address, node, col, mode)
        return Word(address, self.expr(), col, mode)
