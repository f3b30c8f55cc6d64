"""Fast path of the Part 21 reader for well-formed simple instances.

One C-level match of the whole instance, one ``findall`` of its tokens, one Python loop
over plain strings. Anything unusual (comments, binaries, typed parameters, complex
instances, any defect) gives ``None`` and the exact parser of :mod:`stepnc.part21` handles
the instance and reports its errors.
"""

from __future__ import annotations

import re

from stepnc.p21_values import DERIVED, Enum, Ref, decode_string

FAST_INSTANCE = re.compile(
    r"(?:\s++|/\*.*?\*/)*+#(\d+)\s*=\s*([A-Za-z_][A-Za-z0-9_]*)\s*"
    r"(\((?:[^;'\"/]++|'(?:[^']++|'')*+')*+);",
    re.DOTALL,
)
_FAST_TOKEN = re.compile(r"'(?:[^']|'')*'|[^\s,()']+|[(),]")
_ENUM_NAME = re.compile(r"\.[A-Za-z_][A-Za-z0-9_]*\.\Z")
_NUMBER_START = frozenset("0123456789+-")
#: deeper lists go to the exact parser, which checks ``kernel.limits`` (nesting >= 16 is
#: never seen in real files)
_NESTING = 16


def fast_params(body: str) -> tuple | None:
    toks = _FAST_TOKEN.findall(body)
    if toks[-1] != ")":
        return None
    stack: list[list[object]] = []
    cur: list[object] = []
    expect = True
    try:
        for t in toks[1:-1]:  # inside the outer parentheses
            c = t[0]
            if c == ",":
                if expect:
                    return None
                expect = True
                continue
            if c == ")":
                if (expect and cur) or not stack:
                    return None
                done = tuple(cur)
                cur = stack.pop()
                cur.append(done)
                expect = False
                continue
            if not expect:
                return None
            expect = False
            if c == "#":
                cur.append(Ref(int(t[1:])))
            elif c in _NUMBER_START:
                cur.append(float(t) if "." in t else int(t))
            elif c == "'":
                cur.append(decode_string(t[1:-1]))
            elif t == "$":
                cur.append(None)
            elif c == "(":
                stack.append(cur)
                cur = []
                expect = True
                if len(stack) >= _NESTING:
                    return None  # the exact parser reports LIMIT-NESTING
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
    if stack or (expect and cur):
        return None
    return tuple(cur)
