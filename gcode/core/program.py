"""Streaming access to program files for the interpreter, with the seeks O-words need.

Programs are read line by line (a million-line file is never held in memory); loops and
subroutine calls jump back by byte offset, as LinuxCNC does. Parsed blocks are cached by
(file, offset) with a bounded size so loop bodies are parsed once.
"""

from __future__ import annotations

import io
import re
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import kernel.limits as limits
from gcode.core.lexer import Block, parse_line
from gcode.core.search import find_in_dirs
from kernel.diagnostics import Diagnostic, Location

_CACHE_SIZE = 4096
_OWORD_LINE_RE = re.compile(rb"^\s*/?\s*(?:[nN]\s*[\d.]+\s*)?[oO]")


@dataclass(frozen=True, slots=True)
class Position:
    """A place in a program: which file, the byte offset of a line start, its number."""

    file: str
    offset: int
    line: int


class ProgramFile:
    """One open program file with line numbers and seekable offsets."""

    def __init__(self, path: str, data: bytes | None = None) -> None:
        self.path = path
        if data is not None:
            self._fh: BinaryIO = io.BytesIO(data)
        else:
            try:
                self._fh = open(path, "rb")  # noqa: SIM115 - closed by close()
            except OSError as exc:
                raise Diagnostic(
                    "IO-OPEN", f"cannot open program: {exc.strerror or exc}", Location(path)
                ) from None
        self.line = 0
        self._offset = 0  # byte offset of the next line
        #: where the file itself is: a seek is made only when a line must be read elsewhere
        #: (a subroutine or loop body comes from the block cache, without reading, and
        #: the return continues where the file still is)
        self._pos = 0
        self.line_offset = 0  # byte offset of the line read last
        self.last_nonblank = 0  # number of the last line holding more than blanks
        #: parsed lines by offset: the block, the offset of the next line, whether the line
        #: holds more than blanks
        self._cache: OrderedDict[int, tuple[Block, int, bool]] = OrderedDict()
        #: keep parsed blocks for re-reading (set while loops or subroutines are active)
        self.caching = True

    def close(self) -> None:
        self._fh.close()

    def tell(self) -> Position:
        return Position(self.path, self._offset, self.line)

    def seek_to(self, offset: int, line: int) -> None:
        """Continue reading at byte ``offset``, which starts line ``line + 1``."""
        self._offset = offset
        self.line = line
        self.last_nonblank = line

    def current(self) -> Position:
        """Position of the line read last (to come back to it: loops)."""
        return Position(self.path, self.line_offset, self.line - 1)

    def seek(self, pos: Position) -> None:
        self._offset = pos.offset
        self.line = pos.line

    def next_raw(self) -> tuple[int, bytes] | None:
        """The next raw line with its offset, or None at end of file."""
        offset = self._offset
        if self._pos != offset:
            self._fh.seek(offset)
        data = self._fh.readline()
        self._pos = offset + len(data)
        if not data:
            return None
        self._offset = self._pos
        self.line += 1
        self.line_offset = offset
        if len(data) > limits.current().line_chars:
            limits.check_line(len(data.rstrip(b"\r\n")), self.path, self.line)
        if not data.isspace():
            self.last_nonblank = self.line
        return offset, data

    def line_text(self, line: int) -> str | None:
        """The text of line ``line`` if it is the line read last (a diagnostic's excerpt,
        from the data this reader already has open: stdin and in-memory programs too)."""
        if line != self.line or self._fh.closed:
            return None
        self._fh.seek(self.line_offset)
        data = self._fh.readline()
        self._pos = self.line_offset + len(data)
        return _decode(data, self.path, line)

    def next_block(self) -> Block | None:
        cache = self._cache
        if cache:
            cached = cache.get(self._offset)
            if cached is not None:  # read before (a loop or a subroutine): not read again
                block, end, nonblank = cached
                self.line_offset = self._offset
                self._offset = end
                self.line += 1
                if nonblank:
                    self.last_nonblank = self.line
                return block
        raw = self.next_raw()
        if raw is None:
            return None
        offset, data = raw
        block = parse_line(_decode(data, self.path, self.line), self.line, self.path)
        if self.caching:
            if len(cache) >= _CACHE_SIZE:
                cache.popitem(last=False)
            cache[offset] = (block, self._offset, self.last_nonblank == self.line)
        return block

    def next_oword_block(self, also: re.Pattern[bytes] | None = None) -> Block | None:
        """Skip forward to the next line holding an O-word (used when skipping bodies), or
        matching ``also`` (lines the skipping must see, such as a closing ``%``)."""
        while True:
            raw = self.next_raw()
            if raw is None:
                return None
            offset, data = raw
            if also is not None and also.match(data):
                return parse_line(_decode(data, self.path, self.line), self.line, self.path)
            if _OWORD_LINE_RE.match(data):
                cached = self._cache.get(offset)
                if cached is not None and cached[0].oword is not None:
                    return cached[0]
                block = parse_line(_decode(data, self.path, self.line), self.line, self.path)
                if block.oword is not None:
                    return block


def _decode(data: bytes, path: str, line: int) -> str:
    try:
        return data.decode("utf-8").rstrip("\r\n")
    except UnicodeDecodeError:
        return data.decode("latin-1").rstrip("\r\n")


def find_subroutine_file(name: str, search_path: list[str], current_dir: str) -> str | None:
    """``o<name> call`` of a subroutine not defined in the program: ``name.ngc`` in one of the
    search directories (``current_dir`` when there is none), never outside them
    (:func:`gcode.core.search.find_in_dirs`)."""
    dirs = search_path or [current_dir]
    found = find_in_dirs(dirs, (f"{name}.ngc", f"{name}.NGC"))
    return None if found is None else str(Path(found))
