"""Arithmetic of Siemens 840D part programs: R parameters, user variables, operators and
functions (840D sl programming manual, fundamentals, "Arithmetic parameters" and "Calculation
parameters"; job planning, "Arithmetic functions", "Comparison and logical operations").

Expressions are parsed once into small tuples and evaluated against a :class:`Variables`
scope. Angles are in degrees; ``POT(x)`` is x squared; ``TRUNC`` cuts toward zero and
``ROUND`` rounds half away from zero. Comparisons give 1 (true) or 0 (false).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from gcode.siemens.lexer import NAME, NUM, OP, STR, WORD, Token
from kernel.diagnostics import Diagnostic, Location

#: deepest nesting of brackets and unary operators in one expression
MAX_NESTING = 100
#: most binary operators in one expression (both bounds keep evaluation within Python's
#: recursion limit)
MAX_OPERATORS = 500
#: most elements of one DEF array (the 840D's limit depends on its memory)
MAX_ARRAY = 100_000
#: highest R parameter number (the 840D default is R0..R99; machine data raise it)
MAX_R = 999
_BINARY = {
    "OR": 1,
    "XOR": 2,
    "AND": 3,
    # bit operators on whole numbers (job planning, "Comparison and logical operations"):
    # above the relations, below + and -, B_AND binding tighter than B_XOR than B_OR
    "B_OR": 5.25,
    "B_XOR": 5.5,
    "B_AND": 5.75,
    "==": 5,
    "<>": 5,
    "<": 5,
    ">": 5,
    "<=": 5,
    ">=": 5,
    "+": 6,
    "-": 6,
    "*": 7,
    "/": 7,
    "DIV": 7,
    "MOD": 7,
}


def _round(x: float) -> float:
    return float(math.floor(abs(x) + 0.5)) * (1.0 if x >= 0 else -1.0)


def _sqrt(x: float) -> float:
    if x < 0:
        raise ValueError("square root of a negative number")
    return math.sqrt(x)


FUNCTIONS: dict[str, tuple[int, Callable[..., float]]] = {
    "SIN": (1, lambda x: math.sin(math.radians(x))),
    "COS": (1, lambda x: math.cos(math.radians(x))),
    "TAN": (1, lambda x: math.tan(math.radians(x))),
    "ASIN": (1, lambda x: math.degrees(math.asin(x))),
    "ACOS": (1, lambda x: math.degrees(math.acos(x))),
    "ATAN2": (2, lambda y, x: math.degrees(math.atan2(y, x))),
    "SQRT": (1, _sqrt),
    "ABS": (1, abs),
    "POT": (1, lambda x: x * x),
    "TRUNC": (1, lambda x: float(math.trunc(x))),
    "ROUND": (1, _round),
    "LN": (1, math.log),
    "EXP": (1, math.exp),
    "MINVAL": (2, min),
    "MAXVAL": (2, max),
}

Node = tuple


#: reads system variable ``$NAME`` (``$NAME[index]``, index an axis name or a number)
SystemReader = Callable[[str, "str | None", Location], float]


class Variables:
    """R parameters (global to the run) and the DEF variables of one program level."""

    def __init__(self, r: dict[int, float], system: SystemReader | None = None) -> None:
        self.r = r
        self.local: dict[str, tuple[str, float]] = {}  # name -> (type, value)
        #: DEF arrays: name -> (type, dimensions, values in row-major order)
        self.arrays: dict[str, tuple[str, tuple[int, ...], list[float]]] = {}
        self.system = system  # reads ``$`` system variables (the run's machine)

    def system_get(self, name: str, index: str | None, loc: Location) -> float:
        if self.system is None:
            raise Diagnostic("SIEM-UNSUPPORTED", f"system variable {name} is not supported", loc)
        return self.system(name, index, loc)

    def get(self, name: str, loc: Location) -> float:
        found = self.local.get(name)
        if found is None:
            raise Diagnostic("SIEM-VARIABLE", f"variable {name} is not defined", loc)
        return found[1]

    def set(self, name: str, value: float, loc: Location) -> None:
        found = self.local.get(name)
        if found is None:
            raise Diagnostic("SIEM-VARIABLE", f"variable {name} is not defined", loc)
        self.local[name] = (found[0], store(found[0], value, loc))

    def define(self, kind: str, name: str, value: float, loc: Location) -> None:
        self.local[name] = (kind, store(kind, value, loc))

    def define_array(
        self, kind: str, name: str, dims: tuple[int, ...], values: list[float], loc: Location
    ) -> None:
        """``DEF REAL NAME[n, m] = SET(...)``: the array, 0 where no value is given."""
        size = math.prod(dims)
        if any(d < 1 for d in dims) or size > MAX_ARRAY:
            raise Diagnostic(
                "SIEM-ARRAY", f"{name}{list(dims)}: dimensions 1..{MAX_ARRAY} elements", loc
            )
        if len(values) > size:
            raise Diagnostic("SIEM-ARRAY", f"{name}: more values than its {size} elements", loc)
        data = [store(kind, v, loc) for v in values] + [0.0] * (size - len(values))
        self.arrays[name] = (kind, dims, data)
        self.local.pop(name, None)

    def _element(self, name: str, index: list[float], loc: Location) -> int:
        found = self.arrays.get(name)
        if found is None:
            raise Diagnostic("SIEM-VARIABLE", f"array {name} is not defined", loc)
        dims = found[1]
        if len(index) != len(dims):
            raise Diagnostic("SIEM-ARRAY", f"{name} has {len(dims)} index(es)", loc)
        flat = 0
        for i, d in zip(index, dims, strict=True):
            k = round(i)
            if abs(i - k) > 1e-9 or not 0 <= k < d:
                raise Diagnostic("SIEM-ARRAY", f"{name}: index {i:g} outside 0..{d - 1}", loc)
            flat = flat * d + k
        return flat

    def array_get(self, name: str, index: list[float], loc: Location) -> float:
        k = self._element(name, index, loc)
        return self.arrays[name][2][k]

    def array_set(self, name: str, index: list[float], value: float, loc: Location) -> None:
        k = self._element(name, index, loc)
        kind, _, data = self.arrays[name]
        data[k] = store(kind, value, loc)

    def r_get(self, index: float, loc: Location) -> float:
        return self.r.get(r_index(index, loc), 0.0)

    def r_set(self, index: float, value: float, loc: Location) -> None:
        self.r[r_index(index, loc)] = value


def store(kind: str, value: float, loc: Location) -> float:
    """A value as a variable of ``kind`` holds it (INT rounds, BOOL is 0/1)."""
    if kind == "INT":
        return _round(value)
    if kind == "BOOL":
        return 1.0 if value else 0.0
    return value


def r_index(index: float, loc: Location) -> int:
    n = int(round(index))
    if abs(index - n) > 1e-9 or not 0 <= n <= MAX_R:
        raise Diagnostic("SIEM-R-INDEX", f"R parameter number {index:g} out of 0..{MAX_R}", loc)
    return n


class Parser:
    """Recursive descent over a token list from ``start``; :attr:`pos` is where it stopped."""

    def __init__(self, tokens: list[Token], start: int, file: str | None, line: int) -> None:
        self.t, self.pos, self.file, self.line = tokens, start, file, line
        self.depth = 0
        self.operators = 0

    def loc(self) -> Location:
        t = self.t
        col = t[self.pos].col if self.pos < len(t) else (t[-1].col + len(t[-1].text) if t else 1)
        return Location(self.file, self.line, col)

    def peek(self) -> Token | None:
        return self.t[self.pos] if self.pos < len(self.t) else None

    def expect(self, text: str) -> None:
        tok = self.peek()
        if tok is None or tok.kind != OP or tok.text != text:
            raise Diagnostic("SIEM-SYNTAX", f"expected {text!r}", self.loc())
        self.pos += 1

    def expression(self, level: float = 0) -> Node:
        left = self.unary()
        while True:
            tok = self.peek()
            if tok is None or tok.kind not in (OP, NAME):
                return left
            prec = _BINARY.get(tok.text)
            if prec is None or prec <= level:
                return left
            loc = self.loc()
            self.operators += 1
            if self.operators > MAX_OPERATORS:
                raise Diagnostic("SIEM-SYNTAX", "expression too long", loc)
            self.pos += 1
            right = self.expression(prec)
            left = ("bin", tok.text, left, right, loc)

    def unary(self) -> Node:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise Diagnostic("SIEM-SYNTAX", "expression nested too deeply", self.loc())
        try:
            return self._unary()
        finally:
            self.depth -= 1

    def _unary(self) -> Node:
        tok = self.peek()
        if tok is None:
            raise Diagnostic("SIEM-SYNTAX", "expression expected", self.loc())
        if tok.kind == OP and tok.text in "+-":
            self.pos += 1
            inner = self.unary()
            return inner if tok.text == "+" else ("neg", inner)
        if tok.kind == NAME and tok.text == "NOT":
            self.pos += 1
            return ("not", self.unary())
        if tok.kind == NAME and tok.text == "B_NOT":
            loc = self.loc()
            self.pos += 1
            return ("bin", "B_XOR", ("num", -1.0), self.unary(), loc)  # ~x = x XOR all ones
        return self.primary(tok)

    def primary(self, tok: Token) -> Node:
        """A number, a parenthesised expression, an R parameter, a variable or a call
        (``tok``: the token at the current position)."""
        loc = self.loc()
        self.pos += 1
        if tok.kind == NUM:
            return ("num", tok.value)
        if tok.kind == OP and tok.text == "(":
            inner = self.expression()
            self.expect(")")
            return inner
        if tok.kind == WORD and tok.text[0] == "R" and tok.value >= 0:
            return ("num_r", r_index(tok.value, loc), loc)
        if tok.kind == NAME:
            name = tok.text
            if name == "R" and self._is("["):
                self.pos += 1
                index = self.expression()
                self.expect("]")
                return ("r", index, loc)
            if name.startswith("$"):
                return self.system_variable(name, loc)
            if name in ("TRUE", "FALSE"):
                return ("num", 1.0 if name == "TRUE" else 0.0)
            if name in FUNCTIONS:
                return self.call(name, loc)
            if name[0] == "R" and name[1:].isdigit():
                return ("num_r", r_index(float(name[1:]), loc), loc)
            if self._is("["):  # an element of a DEF array
                self.pos += 1
                return ("arr", name, tuple(self.indices()), loc)
            return ("var", name, loc)
        if tok.kind == STR:  # a string argument of a cycle (its tool, its mode)
            return ("str", tok.text, loc)
        text = tok.text if tok is not None else "end of block"
        raise Diagnostic("SIEM-SYNTAX", f"unexpected {text!r} in expression", loc)

    def indices(self) -> list[Node]:
        """The index expressions of ``NAME[i, j]`` after the ``[`` (the ``]`` taken)."""
        out = [self.expression()]
        while self._is(","):
            self.pos += 1
            out.append(self.expression())
        self.expect("]")
        return out

    def system_variable(self, name: str, loc: Location) -> Node:
        """``$NAME`` or ``$NAME[AXIS]`` / ``$NAME[n]`` (the index: an axis name or a number)."""
        index: str | None = None
        if self._is("["):
            self.pos += 1
            tok = self.peek()
            if tok is None or tok.kind not in (NAME, WORD, NUM):
                raise Diagnostic("SIEM-SYNTAX", f"index expected after {name}[", loc)
            index = tok.text
            self.pos += 1
            while self._is(","):  # machine data: ``$MA_NAME[0, AX1]`` (element, axis)
                self.pos += 1
                tok = self.peek()
                if tok is None or tok.kind not in (NAME, WORD, NUM):
                    raise Diagnostic("SIEM-SYNTAX", f"index expected in {name}[", loc)
                index += "," + tok.text
                self.pos += 1
            self.expect("]")
        return ("sys", name, index, loc)

    def call(self, name: str, loc: Location) -> Node:
        arity, _ = FUNCTIONS[name]
        self.expect("(")
        args = [self.expression()]
        while self._is(","):
            self.pos += 1
            args.append(self.expression())
        self.expect(")")
        if len(args) != arity:
            raise Diagnostic("SIEM-FUNCTION", f"{name} takes {arity} argument(s)", loc)
        return ("call", name, tuple(args), loc)

    def _is(self, text: str) -> bool:
        tok = self.peek()
        return tok is not None and tok.kind == OP and tok.text == text


def evaluate(node: Node, v: Variables) -> float:
    """The value of a parsed expression in scope ``v``."""
    kind = node[0]
    if kind == "num":
        return node[1]
    if kind == "num_r":
        return v.r.get(node[1], 0.0)
    if kind == "bin":
        return _binary(node[1], evaluate(node[2], v), evaluate(node[3], v), node[4])
    if kind == "neg":
        return -evaluate(node[1], v)
    if kind == "not":
        return 0.0 if evaluate(node[1], v) else 1.0
    if kind == "var":
        return v.get(node[1], node[2])
    if kind == "r":
        return v.r_get(evaluate(node[1], v), node[2])
    if kind == "arr":
        return v.array_get(node[1], [evaluate(i, v) for i in node[2]], node[3])
    if kind == "sys":
        return v.system_get(node[1], node[2], node[3])
    if kind == "str":
        raise Diagnostic("SIEM-SYNTAX", f'string "{node[1]}" where a number is needed', node[2])
    name, args, loc = node[1], node[2], node[3]
    values = [evaluate(a, v) for a in args]
    try:
        result = float(FUNCTIONS[name][1](*values))
    except (ValueError, OverflowError, ZeroDivisionError):
        raise Diagnostic("SIEM-MATH", f"{name} of {values} is undefined", loc) from None
    if not math.isfinite(result):
        raise Diagnostic("SIEM-MATH", f"{name} of {values} is undefined", loc)
    return result


def _binary(op: str, a: float, b: float, loc: Location) -> float:
    if op == "+":
        r = a + b
    elif op == "-":
        r = a - b
    elif op == "*":
        r = a * b
    elif op in ("/", "DIV", "MOD"):
        if b == 0:
            raise Diagnostic("SIEM-MATH", "division by zero", loc)
        r = a / b if op == "/" else float(math.trunc(a / b)) if op == "DIV" else math.fmod(a, b)
    elif op == "==":
        r = float(a == b)
    elif op == "<>":
        r = float(a != b)
    elif op == "<":
        r = float(a < b)
    elif op == ">":
        r = float(a > b)
    elif op == "<=":
        r = float(a <= b)
    elif op == ">=":
        r = float(a >= b)
    elif op in ("B_AND", "B_OR", "B_XOR"):
        if a != int(a) or b != int(b):
            raise Diagnostic("SIEM-MATH", f"{op} takes whole numbers ({a:g}, {b:g})", loc)
        x, y = int(a), int(b)
        r = float(x & y if op == "B_AND" else x | y if op == "B_OR" else x ^ y)
    elif op == "AND":
        r = float(bool(a) and bool(b))
    elif op == "OR":
        r = float(bool(a) or bool(b))
    else:  # XOR
        r = float(bool(a) != bool(b))
    if not math.isfinite(r):
        raise Diagnostic("SIEM-MATH", "number out of range", loc)
    return r


def constant(node: Node) -> bool:
    return node[0] == "num"
