"""Fast path of the Part 21 reader for well-formed simple instances.

One C-level match of the whole instance checks its structure (parenthesised lists nested at
most :data:`_DEPTH` deep, values separated by commas), one ``findall`` splits it into values
and parentheses, and one Python loop over those plain strings converts them (no commas to
step over, no structure to track). Anything unusual (comments, binaries, typed parameters,
complex instances, any defect) gives ``None`` and the exact parser of :mod:`stepnc.part21`
handles the instance and reports its errors.
"""

from __future__ import annotations

import re

from stepnc.p21_values import DERIVED, Enum, Ref, decode_string

#: list nesting the fast grammar accepts; deeper lists go to the exact parser, which
#: checks ``kernel.limits``
_DEPTH = 4
#: one value as the grammar sees it: a string, or a run of other characters whose
#: conversion in :func:`fast_params` checks it
_ATOM = r"(?:'(?:[^']++|'')*+'|[^\s,()';\"/]++)"


def _list(depth: int) -> str:
    """A parenthesised, comma-separated list of values nested up to ``depth`` deep."""
    value = _ATOM if depth == 1 else f"(?:{_ATOM}|{_list(depth - 1)})"
    return rf"\(\s*+(?:{value}(?:\s*+,\s*+{value})*+)?+\s*+\)"


FAST_INSTANCE = re.compile(
    r"(?:\s++|/\*.*?\*/)*+#(\d+)\s*=\s*([A-Za-z_][A-Za-z0-9_]*)\s*"
    rf"({_list(_DEPTH)})\s*;",
    re.DOTALL,
)
#: values and parentheses (the grammar above has checked the commas between them)
_FAST_TOKEN = re.compile(r"[^\s,()']++|[()]|'(?:[^']++|'')*+'")
_ENUM_NAME = re.compile(r"\.[A-Za-z_][A-Za-z0-9_]*\.\Z")
_NUMBER_START = frozenset("0123456789+-")


class _Split(Exception):
    """Splitting at blanks and commas cut a string value apart."""


def fast_params(body: str) -> tuple | None:
    """The parameters of a body :data:`FAST_INSTANCE` matched, or None when a value needs
    the exact parser (a typed parameter, a malformed number, reference or enumeration).

    The grammar has checked the structure, so the values are first split out with C-level
    string replaces; only a string holding a blank, comma or parenthesis (which that split
    cuts apart, and :func:`_convert` notices) is tokenised by the regular expression."""
    try:
        return _convert(body.replace("(", " ( ").replace(")", " ) ").replace(",", " ").split())
    except _Split:
        return _convert(_FAST_TOKEN.findall(body))


def _convert(toks: list[str]) -> tuple | None:
    stack: list[list[object]] = []
    cur: list[object] = []
    try:
        for t in toks[1:-1]:  # inside the outer parentheses
            c = t[0]
            if c in _NUMBER_START:
                cur.append(float(t) if "." in t else int(t))
            elif c == ")":
                done = tuple(cur)
                cur = stack.pop()
                cur.append(done)
            elif c == "(":
                stack.append(cur)
                cur = []
            elif c == "#":
                cur.append(Ref(t[1:]))
            elif c == "'":
                s = t[1:-1]
                if len(t) < 2 or t[-1] != "'" or "'" in s.replace("''", ""):
                    raise _Split
                cur.append(decode_string(s) if "'" in s or "\\" in s else s)
            elif t == "$":
                cur.append(None)
            elif c == ".":
                if _ENUM_NAME.match(t) is None:
                    return None
                cur.append(Enum(t[1:-1].upper()))
            elif t == "*":
                cur.append(DERIVED)
            else:
                return None  # keyword: typed parameter or a defect
    except (ValueError, IndexError):
        return None
    return tuple(cur)
