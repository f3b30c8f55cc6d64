"""Custom macro B: variables and expression evaluation (Fanuc 0i-MF manual, "Custom macro").

Variables: ``#0`` is always vacant (``None`` here), ``#1``-``#33`` are local to a macro
call level (G65/G66), ``#100``-``#199`` and ``#500``-``#999`` common, with the extended
common ranges of the Series 30i (``#98000``-``#98499``, ``#100000``-``#499999``, and the
``#900000``-``#999999`` variables shop macros of that series use as common storage) held
the same way; system variables (``#1000``-``#99999`` otherwise) are read and written
through a :class:`SystemVariables` hook. Vacant rules:
a bare vacant reference stays vacant (``#1=#0`` makes ``#1`` vacant; a word whose value is
vacant is ignored); in arithmetic and functions vacant counts as 0; ``EQ``/``NE`` tell
vacant from 0, the other relations count it as 0. Angles are degrees.
"""

from __future__ import annotations

import math
from typing import Protocol

from gcode.fanuc.lexer import Expr
from kernel.diagnostics import Diagnostic, Location

Value = float | None


class SystemVariables(Protocol):
    def read(self, index: int, loc: Location) -> Value: ...

    def write(self, index: int, value: Value, loc: Location) -> None: ...


class Variables:
    """All macro variables of one run; ``locals`` is the current call level's #1-#33."""

    def __init__(self, system: SystemVariables, initial: dict[int, float] | None = None) -> None:
        self.system = system
        self.locals: list[Value] = [None] * 34
        self.levels: list[list[Value]] = []
        self.common: dict[int, Value] = {}
        for k, v in (initial or {}).items():
            if is_common(k):
                self.common[k] = v

    def enter(self, arguments: dict[int, float]) -> None:
        """A G65/G66 call: a fresh local level holding the arguments."""
        self.levels.append(self.locals)
        self.locals = [None] * 34
        for k, v in arguments.items():
            self.locals[k] = v

    def leave(self) -> None:
        self.locals = self.levels.pop()

    @property
    def depth(self) -> int:
        return len(self.levels)

    def read(self, index: float, loc: Location) -> Value:
        i = _index(index, loc)
        if i == 0:
            return None
        if i <= 33:
            return self.locals[i]
        if is_common(i):
            return self.common.get(i)
        if i >= 1000:
            return self.system.read(i, loc)
        raise Diagnostic("FANUC-VARIABLE", f"variable #{i} does not exist", loc)

    def write(self, index: float, value: Value, loc: Location) -> None:
        i = _index(index, loc)
        if i == 0:
            raise Diagnostic("FANUC-VARIABLE", "#0 is read-only (always vacant)", loc)
        if i <= 33:
            self.locals[i] = value
        elif is_common(i):
            self.common[i] = value
        elif i >= 1000:
            self.system.write(i, value, loc)
        else:
            raise Diagnostic("FANUC-VARIABLE", f"variable #{i} does not exist", loc)


def is_common(i: int) -> bool:
    """Whether ``#i`` is a common variable: 0i ranges and the 30i extended ones."""
    return (
        100 <= i <= 199
        or 500 <= i <= 999
        or 98000 <= i <= 98499
        or 100000 <= i <= 499999
        or 900000 <= i <= 999999
    )


def _index(index: float, loc: Location) -> int:
    i = round(index)
    if abs(index - i) > 1e-6 or i < 0 or i > 999999:
        raise Diagnostic("FANUC-VARIABLE", f"bad variable number #{index:g}", loc)
    return i


def _num(v: Value) -> float:
    return 0.0 if v is None else v


def evaluate(node: Expr | None, vars: Variables, loc: Location) -> Value:
    """Value of an expression node (:mod:`gcode.fanuc.lexer`); vacant is ``None``."""
    if type(node) is float:
        return node
    if not isinstance(node, tuple):
        raise Diagnostic("FANUC-EXPRESSION", f"cannot evaluate {node!r}", loc)
    kind = node[0]
    if kind == "#":
        idx = evaluate(node[1], vars, loc)
        return vars.read(_num(idx), loc)
    if kind == "neg":
        v = evaluate(node[1], vars, loc)
        return None if v is None else -v
    if kind == "b":
        _, op, a, b = node
        return _finite(_binary(op, evaluate(a, vars, loc), evaluate(b, vars, loc), loc), loc)
    if kind == "f":
        args = [evaluate(a, vars, loc) for a in node[2:]]
        return _finite(_function(node[1], args, loc), loc)
    raise Diagnostic("FANUC-EXPRESSION", f"cannot evaluate {node!r}", loc)


def _finite(value: float, loc: Location) -> float:
    """``value``, or FANUC-OVERFLOW when a calculation left the numbers (the control's
    alarm 111, calculated data overflow): an infinite or not-a-number value would
    otherwise become a move to infinity."""
    if not math.isfinite(value):
        raise Diagnostic("FANUC-OVERFLOW", f"calculation overflow: the result is {value}", loc)
    return value


def truth(node: Expr | None, vars: Variables, loc: Location) -> bool:
    return _num(evaluate(node, vars, loc)) != 0.0


def _binary(op: str, a: Value, b: Value, loc: Location) -> float:
    if op == "EQ":
        return 1.0 if _same(a, b) else 0.0
    if op == "NE":
        return 0.0 if _same(a, b) else 1.0
    x, y = _num(a), _num(b)
    if op == "+":
        return x + y
    if op == "-":
        return x - y
    if op == "*":
        return x * y
    if op == "/":
        if y == 0.0:
            raise Diagnostic("FANUC-DIVIDE-BY-ZERO", "division by zero", loc)
        return x / y
    if op == "MOD":
        if y == 0.0:
            raise Diagnostic("FANUC-DIVIDE-BY-ZERO", "division by zero (MOD)", loc)
        return math.fmod(x, y)
    if op == "GT":
        return float(x > y)
    if op == "GE":
        return float(x >= y)
    if op == "LT":
        return float(x < y)
    if op == "LE":
        return float(x <= y)
    if op == "AND":
        return float(x != 0.0 and y != 0.0)
    if op == "OR":
        return float(x != 0.0 or y != 0.0)
    if op == "XOR":
        return float((x != 0.0) != (y != 0.0))
    raise Diagnostic("FANUC-EXPRESSION", f"unknown operator {op}", loc)


def _same(a: Value, b: Value) -> bool:
    if a is None or b is None:
        return a is None and b is None
    return abs(a - b) < 1e-9 * max(1.0, abs(a), abs(b))


def _function(name: str, args: list[Value], loc: Location) -> float:
    xs = [_num(a) for a in args]
    want = 2 if name == "POW" else (len(xs) if name == "ATAN" else 1)
    if len(xs) != want or (name == "ATAN" and len(xs) not in (1, 2)):
        raise Diagnostic("FANUC-FUNCTION", f"{name} takes {want} argument(s)", loc)
    x = xs[0]
    try:
        if name == "SIN":
            return math.sin(math.radians(x))
        if name == "COS":
            return math.cos(math.radians(x))
        if name == "TAN":
            if abs(math.cos(math.radians(x))) < 1e-15:
                raise Diagnostic("FANUC-FUNCTION", "TAN of 90 degrees", loc)
            return math.tan(math.radians(x))
        if name in ("ASIN", "ACOS"):
            if not -1.0 <= x <= 1.0:
                raise Diagnostic("FANUC-FUNCTION", f"{name} argument out of -1..1", loc)
            return math.degrees(math.asin(x) if name == "ASIN" else math.acos(x))
        if name == "ATAN":
            if len(xs) == 1:
                return math.degrees(math.atan(x))
            return math.degrees(math.atan2(x, xs[1])) % 360.0  # Fanuc: 0..360
        if name == "SQRT":
            if x < 0:
                raise Diagnostic("FANUC-FUNCTION", "SQRT of a negative number", loc)
            return math.sqrt(x)
        if name == "ABS":
            return abs(x)
        if name == "ROUND":
            return float(math.floor(abs(x) + 0.5)) * (1.0 if x >= 0 else -1.0)
        if name == "FIX":
            return float(math.trunc(x))  # towards zero (Fanuc)
        if name == "FUP":
            return float(math.ceil(abs(x))) * (1.0 if x >= 0 else -1.0)  # away from zero
        if name == "LN":
            if x <= 0:
                raise Diagnostic("FANUC-FUNCTION", "LN of zero or a negative number", loc)
            return math.log(x)
        if name == "EXP":
            return math.exp(x)
        if name == "POW":
            return float(math.pow(x, xs[1]))
        if name == "BIN":
            return float(int(f"{int(x):x}", 10)) if x >= 0 else 0.0
        if name == "BCD":
            return float(int(str(int(x)), 16)) if x >= 0 else 0.0
        if name == "ADP":
            return x
    except (OverflowError, ValueError):
        raise Diagnostic("FANUC-FUNCTION", f"{name} result out of range", loc) from None
    raise Diagnostic("FANUC-FUNCTION", f"unknown function {name}", loc)
