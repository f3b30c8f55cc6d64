"""Where each table and key of a machine profile is written, so a profile error names its
line and column (``machine.toml:7:1: error[MACH-RANGE] ...``) as a program error does.

Python's ``tomllib`` gives values, not positions. This scanner reads the same TOML text
(already accepted by ``tomllib``, so it need not judge syntax) and records the position of
every table header (``[axes.x]``, ``[[tools]]``), every key (bare, quoted and dotted) and
every key of an inline table (``31 = {name = "conveyor", time = 2}``), by its path of keys.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from kernel.diagnostics import Location

Path = tuple[str, ...]
_BARE = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")


@dataclass(frozen=True, slots=True)
class ProfileWhere:
    """A profile's file and the (line, column) of each table and key path in it."""

    file: str | None = None
    positions: dict[Path, tuple[int, int]] = field(default_factory=dict, compare=False)

    def at(self, *path: str) -> Location:
        """The location of ``path`` or, if it is not written, of its nearest written table
        (a key the profile lacks is reported at its table; a table it lacks, at the file)."""
        for n in range(len(path), 0, -1):
            pos = self.positions.get(path[:n])
            if pos is not None:
                return Location(self.file, pos[0], pos[1])
        return Location(self.file)


class _Scanner:
    """One pass over the text: headers and keys at the top level, keys of inline tables."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.i = 0
        self.line = 1
        self.col0 = 0  # index of the current line's first character
        self.out: dict[Path, tuple[int, int]] = {}

    def _pos(self) -> tuple[int, int]:
        return self.line, self.i - self.col0 + 1

    def _peek(self) -> str:
        return self.text[self.i] if self.i < len(self.text) else ""

    def _advance(self) -> str:
        ch = self.text[self.i]
        self.i += 1
        if ch == "\n":
            self.line += 1
            self.col0 = self.i
        return ch

    def _blank(self, newlines: bool) -> None:
        """Skip spaces (and newlines and comments where ``newlines``)."""
        while self.i < len(self.text):
            ch = self._peek()
            if ch in " \t\r" or (newlines and ch == "\n"):
                self._advance()
            elif ch == "#" and newlines:
                while self.i < len(self.text) and self._peek() != "\n":
                    self._advance()
            else:
                return

    def _string(self) -> str:
        """A basic or literal string, single-line or multi-line; returns its raw text."""
        quote = self._advance()
        triple = self.text.startswith(quote * 2, self.i)
        if triple:
            self.i += 2
        start = self.i
        while self.i < len(self.text):
            if quote == '"' and self._peek() == "\\":
                self._advance()
                if self.i < len(self.text):
                    self._advance()
                continue
            if triple and self.text.startswith(quote * 3, self.i):
                body = self.text[start : self.i]
                self.i += 3
                return body
            if not triple and self._peek() == quote:
                body = self.text[start : self.i]
                self._advance()
                return body
            self._advance()
        return self.text[start:]

    def _key(self) -> list[tuple[str, tuple[int, int]]]:
        """A (dotted) key: each part with where it starts."""
        parts: list[tuple[str, tuple[int, int]]] = []
        while True:
            self._blank(False)
            pos = self._pos()
            if self._peek() in ('"', "'"):
                name = self._string()
            else:
                start = self.i
                while self._peek() and self._peek() in _BARE:
                    self._advance()
                name = self.text[start : self.i]
            parts.append((name, pos))
            self._blank(False)
            if self._peek() != ".":
                return parts
            self._advance()

    def _record(self, base: Path, parts: list[tuple[str, tuple[int, int]]]) -> Path:
        path = base
        for name, pos in parts:
            path = (*path, name)
            self.out.setdefault(path, pos)
        return path

    def _value(self, path: Path) -> None:
        """Skip a value, recording the keys of inline tables found in it."""
        self._blank(False)
        ch = self._peek()
        if ch in ('"', "'"):
            self._string()
        elif ch in ("{", "["):
            self._items(path, "}" if ch == "{" else "]")
        else:
            while self._peek() and self._peek() not in ",}]\n#":
                self._advance()

    def _items(self, path: Path, close: str) -> None:
        """The items of an inline table (``key = value``, ``close`` = "}") or an array (values,
        ``close`` = "]"), up to and past ``close``."""
        self._advance()
        while True:
            self._blank(True)
            if self._peek() in (close, ""):
                if self._peek():
                    self._advance()
                return
            if self._peek() == ",":
                self._advance()
                continue
            if close == "}":
                inner = self._record(path, self._key())
                if self._peek() == "=":
                    self._advance()
                self._value(inner)
            else:
                self._value(path)

    def scan(self) -> dict[Path, tuple[int, int]]:
        table: Path = ()
        while True:
            self._blank(True)
            if self.i >= len(self.text):
                return self.out
            if self._peek() == "[":
                at = self._pos()  # a table is reported at its header's bracket
                self._advance()
                if self._peek() == "[":
                    self._advance()
                table = self._record((), [(name, at) for name, _ in self._key()])
                while self._peek() and self._peek() != "\n":
                    self._advance()
                continue
            key = self._record(table, self._key())
            if self._peek() == "=":
                self._advance()
                self._value(key)
            else:  # not TOML tomllib accepted; stop rather than guess
                return self.out


def profile_where(text: str, file: str | None = None) -> ProfileWhere:
    """The positions of every table and key of the TOML ``text`` (read from ``file``)."""
    return ProfileWhere(file, _Scanner(text).scan())
