"""Evaluation of RS274/NGC expressions parsed by :mod:`gcode.core.lexer`.

Semantics follow the NIST RS274/NGC v3 report (§3.5) and LinuxCNC: angles in degrees,
``FIX`` rounds down, ``FUP`` rounds up, ``ROUND`` to nearest; relational operators give 1.0
or 0.0 (``EQ``/``NE`` compare within 1e-4 as LinuxCNC does); ``MOD`` result has the
divisor's sign convention of LinuxCNC (non-negative for a positive divisor).
"""

from __future__ import annotations

import math
from typing import Protocol

from gcode.core.params import MAX_PARAMETER
from kernel.diagnostics import Diagnostic, Location

TOLERANCE_EQUAL = 0.0001


class ParameterSource(Protocol):
    def numbered(self, index: float, loc: Location) -> float: ...

    def named(self, name: str, loc: Location) -> float: ...

    def exists(self, name: str) -> bool: ...


def _fail(code: str, msg: str, loc: Location) -> Diagnostic:
    return Diagnostic(code, msg, loc)


def _unary(fn: str, x: float, loc: Location) -> float:
    if fn == "abs":
        return abs(x)
    if fn == "acos":
        if x < -1.0 or x > 1.0:
            raise _fail("NGC-ACOS-RANGE", "argument to ACOS out of range", loc)
        return math.degrees(math.acos(x))
    if fn == "asin":
        if x < -1.0 or x > 1.0:
            raise _fail("NGC-ASIN-RANGE", "argument to ASIN out of range", loc)
        return math.degrees(math.asin(x))
    if fn == "cos":
        return math.cos(math.radians(x))
    if fn == "exp":
        try:
            return math.exp(x)
        except OverflowError:
            raise _fail("NGC-EXP-OVERFLOW", "EXP result out of range", loc) from None
    if fn == "fix":
        return float(math.floor(x))
    if fn == "fup":
        return float(math.ceil(x))
    if fn == "ln":
        if x <= 0.0:
            raise _fail("NGC-LN-DOMAIN", "zero or negative argument to LN", loc)
        return math.log(x)
    if fn == "round":
        return float(math.floor(x + 0.5)) if x >= 0 else -float(math.floor(-x + 0.5))
    if fn == "sin":
        return math.sin(math.radians(x))
    if fn == "sqrt":
        if x < 0.0:
            raise _fail("NGC-SQRT-NEGATIVE", "attempt to take square root of negative number", loc)
        return math.sqrt(x)
    if fn == "tan":
        return math.tan(math.radians(x))
    raise _fail("NGC-UNKNOWN-FUNCTION", f"unknown function {fn.upper()}", loc)


def _binary(op: str, a: float, b: float, loc: Location) -> float:
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        if b == 0.0:
            raise _fail("NGC-DIVIDE-BY-ZERO", "attempt to divide by zero", loc)
        return a / b
    if op == "mod":
        if b == 0.0:
            raise _fail("NGC-DIVIDE-BY-ZERO", "attempt to divide by zero (MOD)", loc)
        r = math.fmod(a, b)
        return r + abs(b) if r < 0.0 else r
    if op == "**":
        if a < 0.0 and b != math.floor(b):
            raise _fail("NGC-POWER-DOMAIN", "attempt to raise negative to non-integer power", loc)
        if a == 0.0 and b < 0.0:
            raise _fail("NGC-DIVIDE-BY-ZERO", "attempt to raise zero to a negative power", loc)
        try:
            return float(a**b)
        except OverflowError:
            raise _fail("NGC-POWER-OVERFLOW", "power result out of range", loc) from None
    if op == "eq":
        return 1.0 if abs(a - b) < TOLERANCE_EQUAL else 0.0
    if op == "ne":
        return 1.0 if abs(a - b) >= TOLERANCE_EQUAL else 0.0
    if op == "gt":
        return 1.0 if a > b else 0.0
    if op == "ge":
        return 1.0 if a >= b else 0.0
    if op == "lt":
        return 1.0 if a < b else 0.0
    if op == "le":
        return 1.0 if a <= b else 0.0
    if op == "and":
        return 1.0 if (a != 0.0 and b != 0.0) else 0.0
    if op == "or":
        return 1.0 if (a != 0.0 or b != 0.0) else 0.0
    if op == "xor":
        return 1.0 if ((a != 0.0) != (b != 0.0)) else 0.0
    raise _fail("NGC-BAD-OPERATOR", f"unknown operator {op}", loc)


def _numbered_exists(index: float, loc: Location) -> float:
    """``EXISTS[#n]``: 1 for n in 1..5601 (every numbered parameter rs274 2.9 has), else 0;
    a non-integer n is an error, as rs274 says "Non integer value for integer"."""
    n = round(index)
    if abs(index - n) > 1e-4:
        raise _fail("NGC-PARAM-NOT-INTEGER", f"parameter number {index:g} is not an integer", loc)
    return 1.0 if 1 <= n < MAX_PARAMETER else 0.0


def evaluate(node: object, params: ParameterSource, loc: Location) -> float:
    """Value of an expression node (see :mod:`gcode.core.lexer` for the node forms)."""
    if type(node) is float:
        return node
    if not isinstance(node, tuple):
        raise _fail("NGC-BAD-EXPRESSION", f"cannot evaluate {node!r}", loc)
    kind = node[0]
    if kind == "b":
        _, op, a, b = node
        value = _binary(op, evaluate(a, params, loc), evaluate(b, params, loc), loc)
        if not math.isfinite(value):
            # rs274: "Calculation resulted in 'infinity'" (or 'not a number')
            what = "not a number" if math.isnan(value) else "infinity"
            raise _fail("NGC-NOT-FINITE", f"calculation resulted in {what}", loc)
        return value
    if kind == "#":
        return params.numbered(evaluate(node[1], params, loc), loc)
    if kind == "<":
        return params.named(node[1], loc)
    if kind == "neg":
        return -evaluate(node[1], params, loc)
    if kind == "u":
        return _unary(node[1], evaluate(node[2], params, loc), loc)
    if kind == "atan":
        y = evaluate(node[1], params, loc)
        x = evaluate(node[2], params, loc)
        return math.degrees(math.atan2(y, x))
    if kind == "exists":
        return 1.0 if params.exists(node[1]) else 0.0
    if kind == "exists#":
        return _numbered_exists(evaluate(node[1], params, loc), loc)
    raise _fail("NGC-BAD-EXPRESSION", f"cannot evaluate {node!r}", loc)
