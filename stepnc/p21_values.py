"""Values of an ISO 10303-21 exchange structure (see :mod:`stepnc.part21` for the mapping
of Part 21 tokens to these Python values) and the string escapes of ISO 10303-21 §6.4.3."""

from __future__ import annotations

from collections.abc import Iterator, MutableMapping
from dataclasses import dataclass, field
from typing import NamedTuple

from kernel.diagnostics import Location


class Ref(int):
    """An entity instance name ``#n``."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f"#{int(self)}"


class Enum(str):
    """An enumeration or logical value, stored without its dots (``.T.`` -> ``Enum('T')``)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f".{str(self)}."


class Binary(str):
    """A binary value: the hex digits between the quotes, first digit = unused bits."""

    __slots__ = ()


class Typed(NamedTuple):
    """A typed parameter ``NAME(value)`` (e.g. ``LENGTH_MEASURE(2.0)``)."""

    name: str
    value: object


class _Derived:
    __slots__ = ()

    def __repr__(self) -> str:
        return "*"


DERIVED = _Derived()


class Part(NamedTuple):
    """One partial entity value of a complex instance ``#1=(A(..)B(..));``."""

    name: str
    params: tuple


class Instance:
    """One entity instance. ``name`` is ``None`` for a complex instance, whose ``params``
    are then :class:`Part` values."""

    __slots__ = ("id", "name", "params", "line", "column")

    def __init__(self, id: int, name: str | None, params: tuple, line: int, column: int) -> None:
        self.id = id
        self.name = name
        self.params = params
        self.line = line
        self.column = column

    def __repr__(self) -> str:
        return f"Instance(#{self.id}={self.name}{self.params!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Instance) and (self.id, self.name, self.params) == (
            other.id,
            other.name,
            other.params,
        )


@dataclass
class Part21File:
    """A read exchange structure: header entities in order, data instances by id."""

    header: list[tuple[str, tuple]] = field(default_factory=list)
    #: a ``dict``, or the reader's lazy table for a large file (:mod:`stepnc.p21_scan`)
    instances: MutableMapping[int, Instance] = field(default_factory=dict)
    file: str | None = None
    #: ids of unterminated instances kept with the parameters read before the break
    salvaged: set[int] = field(default_factory=set)

    def __getitem__(self, ref: int) -> Instance:
        return self.instances[ref]

    def __len__(self) -> int:
        return len(self.instances)

    def location(self, ref: int) -> Location:
        inst = self.instances.get(ref)
        if inst is None:
            return Location(self.file, entity=ref)
        return Location(self.file, inst.line, inst.column, entity=ref)

    def by_type(self, name: str) -> Iterator[Instance]:
        return (i for i in self.instances.values() if i.name == name)


def decode_string(raw: str) -> str:
    """Decode Part 21 string escapes (ISO 10303-21 §6.4.3)."""
    s = raw.replace("''", "'")
    if "\\" not in s:
        return s
    out: list[str] = []
    i, n = 0, len(s)
    while i < n:
        c = s[i]
        if c != "\\":
            out.append(c)
            i += 1
            continue
        if s.startswith("\\\\", i):
            out.append("\\")
            i += 2
        elif s.startswith("\\X2\\", i) or s.startswith("\\X4\\", i):
            width = 4 if s[i + 2] == "2" else 8
            end = s.find("\\X0\\", i + 4)
            if end < 0:
                raise ValueError("\\X2\\ or \\X4\\ without closing \\X0\\")
            hexs = s[i + 4 : end]
            if len(hexs) % width:
                raise ValueError(f"odd number of hex digits in {s[i : end + 4]}")
            out.extend(chr(int(hexs[k : k + width], 16)) for k in range(0, len(hexs), width))
            i = end + 4
        elif s.startswith("\\X\\", i):
            out.append(chr(int(s[i + 3 : i + 5], 16)))
            i += 5
        elif s.startswith("\\S\\", i):
            out.append(chr(ord(s[i + 3]) + 128))
            i += 4
        elif s.startswith("\\P", i) and s[i + 3 : i + 4] == "\\":
            i += 4  # code page switch: ignored (ISO 8859-1 assumed)
        else:
            out.append(c)
            i += 1
    return "".join(out)


def encode_string(s: str) -> str:
    out: list[str] = []
    wide: list[str] = []

    def flush() -> None:
        if wide:
            out.append("\\X2\\" + "".join(wide) + "\\X0\\")
            wide.clear()

    for ch in s:
        o = ord(ch)
        if 32 <= o < 127:
            flush()
            out.append("''" if ch == "'" else "\\\\" if ch == "\\" else ch)
        elif o < 256 and o >= 128 or o < 32:
            flush()
            out.append(f"\\X\\{o:02X}")
        elif o > 0xFFFF:
            flush()
            out.append(f"\\X4\\{o:08X}\\X0\\")
        else:
            wide.append(f"{o:04X}")
    flush()
    return "'" + "".join(out) + "'"


def references(value: object) -> Iterator[int]:
    """All instance references inside a parameter value."""
    if isinstance(value, Ref):
        yield int(value)
    elif isinstance(value, tuple):
        for v in value:
            yield from references(v)
