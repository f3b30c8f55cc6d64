"""The one renderer of diagnostics for people, used by every command's text output.

A diagnostic prints like a modern compiler's: the header, then the source line with its
number in a gutter and a caret under the column, spanning the word there::

    prog.ngc:3:10: error[NGC-ARC-R-TOO-SMALL]: arc radius too small to reach end point: ...
      |
    3 | g2 x2 y0 r0.1
      |          ^~~~

With ``-v`` a ``= help:`` line follows with the code's entry in ``docs/errors.md``
(:mod:`cli.explanations`); with ``-q`` only the header prints. The source line is the
text the reader had (``DiagnosticRecord.source_line``, attached by the front end), else
a text the CLI read into memory (:func:`remember`, e.g. standard input), else the line
of the named file. Machine-readable formats (JSON, SARIF, JUnit) do not use this module.
"""

from __future__ import annotations

import os
import re
from array import array
from collections import OrderedDict
from typing import BinaryIO

from cli.explanations import EXPLANATIONS
from kernel.diagnostics import Diagnostic, DiagnosticRecord, Location

#: source characters shown of a long line, around the column
WIDTH = 100
#: a tab shows as this many spaces (the caret line uses the same expansion)
TAB = 4
#: files up to this size are kept as lines for more excerpts of the same file
_CACHE_BYTES = 8 << 20
_CACHE_FILES = 4

_texts: dict[str, list[str]] = {}
_files: OrderedDict[str, list[str]] = OrderedDict()
_offsets: dict[str, _Index] = {}

_NUMBER = re.compile(r"[ \t]*[-+]?[ \t]*(?:\d+\.?\d*|\.\d+)")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*")
_PARAM = re.compile(r"#(?:<[^>]*>?|[ \t]*\d+)")
_HEADER = re.compile(
    r"^(?P<file>.*?):(?:#(?P<entity>\d+):)?(?P<line>\d+):(?P<col>\d+): "
    r"(?:error|warning|note)\[(?P<tag>[^\]]+)\]: "
)


def _split(text: str) -> list[str]:
    """Lines as the readers count them: at ``\\n`` only (``str.splitlines`` would also
    split at form feeds and Unicode separators, and the numbers would drift)."""
    return [line.rstrip("\r") for line in text.split("\n")]


def remember(name: str, text: str) -> None:
    """Keep ``text`` as the program called ``name`` (a program read from standard input):
    its excerpts then come from this text, never from a file of that name."""
    _texts[name] = _split(text)


def _lines(name: str) -> list[str] | None:
    """The lines of ``name``: a remembered text, else the file (kept for later excerpts)."""
    if name in _texts:
        return _texts[name]
    if name in _files:
        _files.move_to_end(name)
        return _files[name]
    if name in ("-", "<stdin>", "<input>"):
        return None
    try:
        if os.path.getsize(name) > _CACHE_BYTES:
            return None
        with open(name, "rb") as fh:
            data = fh.read()
    except OSError:
        return None
    if b"\0" in data:
        return None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    lines = _split(text)
    _files[name] = lines
    if len(_files) > _CACHE_FILES:
        _files.popitem(last=False)
    return lines


class _Index:
    """Where every :data:`_STRIDE`-th line of a file too big to keep starts, found as far
    into the file as the lines asked for: a check of a large program may excerpt thousands
    of its lines, most of them near its start, and the work and memory grow with the last
    line asked for (8 bytes per :data:`_STRIDE` lines), not with the file."""

    def __init__(self) -> None:
        self.marks = array("q", [0])  # marks[k]: offset of the line k * _STRIDE (0-based)
        self.lines = 0  # newlines before ``pos``
        self.pos = 0  # bytes scanned
        self.done = False  # the whole file scanned

    def mark(self, fh: BinaryIO, index: int) -> tuple[int, int] | None:
        """(offset, line) of the last mark at or before the 0-based line ``index``,
        scanning on as far as needed; None when the file ends first."""
        import numpy as np  # large files only: small ones are read whole without it

        k = index // _STRIDE
        while len(self.marks) <= k and not self.done:
            fh.seek(self.pos)
            block = fh.read(_BLOCK)
            if not block:
                self.done = True
                break
            newlines = np.flatnonzero(np.frombuffer(block, dtype=np.uint8) == 10)
            # the line after newline j of the block is line self.lines + j + 1 (0-based)
            first = -(self.lines + 1) % _STRIDE
            self.marks.extend((newlines[first::_STRIDE] + (self.pos + 1)).tolist())
            self.lines += len(newlines)
            self.pos += len(block)
        if len(self.marks) <= k:
            return None
        return self.marks[k], k * _STRIDE


#: a large file's index marks the start of every _STRIDE-th line
_STRIDE = 1024
#: bytes a large file is scanned by for its index
_BLOCK = 1 << 22


def _read_line(name: str, number: int) -> bytes | None:
    """Line ``number`` (1-based) of the file ``name`` without its newline, read from the
    nearest mark of its :class:`_Index`; None past the end."""
    index = _offsets.get(name)
    if index is None:
        index = _offsets[name] = _Index()
        if len(_offsets) > 2:
            del _offsets[next(iter(_offsets))]
    with open(name, "rb") as fh:
        found = index.mark(fh, number - 1)
        if found is None:
            return None
        offset, line = found
        skip = number - 1 - line  # whole lines between the mark and the one asked for
        fh.seek(offset)
        # newlines counted per piece and the pieces joined once: a 100 MB line read by
        # re-counting (and re-copying) all that was read took minutes
        pieces, seen = [], 0
        while True:
            more = fh.read(1 << 16)
            pieces.append(more)
            seen += more.count(b"\n")
            if not more or seen > skip:
                break
        data = b"".join(pieces)
    parts = data.split(b"\n", skip + 1)
    if len(parts) <= skip:
        return None
    if len(parts) == skip + 1 and not parts[skip]:
        return None  # the end of a file whose last line ends with a newline
    return parts[skip]


def _line_of(name: str, number: int) -> str | None:
    """Line ``number`` (1-based) of ``name``; a file too big to keep is read at that line."""
    lines = _lines(name)
    if lines is not None:
        return lines[number - 1] if 0 < number <= len(lines) else None
    if name in ("-", "<stdin>", "<input>") or name in _texts or number < 1:
        return None
    try:
        data = _read_line(name, number)
    except OSError:
        return None
    if data is None:
        return None
    try:
        return data.decode("utf-8").rstrip("\r\n")
    except UnicodeDecodeError:
        return data.decode("latin-1").rstrip("\r\n")


def _entity_place(name: str, entity: int) -> tuple[int, int, str] | None:
    """Line, column and text of the instance ``#entity =`` in the Part 21 file ``name``."""
    lines = _lines(name)
    if lines is None:
        return None
    pattern = re.compile(rf"#{entity}\s*=")
    for n, text in enumerate(lines, 1):
        m = pattern.search(text)
        if m is not None:
            return n, m.start() + 1, text
    return None


def word_span(text: str, index: int) -> int:
    """How many characters from ``index`` the word there takes: a letter with its number
    (``r0.1``), a parameter (``#5``, ``#<name>``), a bracketed expression, a name (``sub``,
    a Part 21 ``#42``), else one character."""
    if index >= len(text):
        return 1
    c = text[index]
    if c == "#":
        m = _PARAM.match(text, index)
        return len(m.group(0)) if m else 1
    if c == "[":
        depth = 0
        for j in range(index, len(text)):
            depth += {"[": 1, "]": -1}.get(text[j], 0)
            if depth == 0:
                return j - index + 1
        return len(text) - index
    if c.isalpha():
        after = index + 1
        while after < len(text) and text[after] in " \t":
            after += 1
        if after < len(text) and text[after] in "#[":
            return after - index + word_span(text, after)
        m = _NUMBER.match(text, index + 1)
        if m is not None:
            return 1 + len(m.group(0))
        m = _NAME.match(text, index)
        return len(m.group(0)) if m else 1
    return 1


def excerpt(number: int, column: int, text: str, width: int = WIDTH) -> list[str]:
    """The gutter, source and caret lines for ``text`` (line ``number``) with the caret at
    1-based character ``column`` (0: no caret). Tabs become :data:`TAB` spaces; a line
    longer than ``width`` is cut around the column, the cuts marked with ``…``."""
    text = text.rstrip("\r\n")
    index = max(column - 1, 0)
    cut_head = cut_tail = False
    if len(text) > 8 * width:
        # a huge line (100 MB): only a window round the column is laid out, not a display
        # position per character of the whole line
        lo = max(0, min(index, len(text)) - 2 * width)
        hi = lo + 4 * width
        cut_head, cut_tail = lo > 0, hi < len(text)
        text, index = text[lo:hi], index - lo
    span = word_span(text, index) if column else 0
    # display position of each character once tabs are TAB wide
    disp = [0]
    for ch in text:
        disp.append(disp[-1] + (TAB if ch == "\t" else 1))
    line = "".join(" " * TAB if ch == "\t" else ch for ch in text)
    caret = disp[min(index, len(text))] if column else 0
    end = disp[min(index + span, len(text))] if column else 0
    length = max(end - caret, 1)
    if len(line) > width:
        start = max(0, min(caret - width // 3, len(line) - width))
        stop = start + width
        head = "…" if start > 0 or cut_head else ""
        line = head + line[start:stop] + ("…" if stop < len(line) or cut_tail else "")
        length = max(1, min(end, stop) - caret)
        caret = caret - start + len(head)
    gutter = str(number)
    pad = " " * len(gutter)
    out = [f"{pad} |", f"{gutter} | {line}".rstrip()]
    if column:
        out.append(f"{pad} | {' ' * caret}^{'~' * (length - 1)}")
    return out


def explanation(code: str | None) -> str | None:
    """The entry of ``code`` in ``docs/errors.md`` (or of a check rule's underlying code)."""
    if not code:
        return None
    return EXPLANATIONS.get(code.rpartition("/")[2]) or EXPLANATIONS.get(code)


def render(
    header: str,
    location: Location,
    code: str | None = None,
    source_line: str | None = None,
    verbosity: int = 0,
) -> str:
    """``header`` with its excerpt (verbosity >= 0) and explanation (verbosity >= 1); one
    string without a final newline."""
    return "\n".join([header, *detail_lines(location, code, source_line, verbosity)])


def detail_lines(
    location: Location,
    code: str | None = None,
    source_line: str | None = None,
    verbosity: int = 0,
    help_text: str | None = None,
) -> list[str]:
    """What :func:`render` prints under a diagnostic's header: the excerpt with its caret
    (verbosity >= 0) and the code's explanation (verbosity >= 1; ``help_text`` where the
    code has none in docs/errors.md, e.g. a check rule's summary)."""
    out: list[str] = []
    if verbosity >= 0 and location.file is not None:
        number, column, text = location.line, location.column, source_line
        if text is None and number:
            text = _line_of(location.file, number)
        if text is None and location.entity is not None and not number:
            place = _entity_place(location.file, location.entity)
            if place is not None:
                number, column, text = place
        if text is not None and number:
            out.extend(excerpt(number, column, text))
    if verbosity >= 1:
        help_text = explanation(code) or help_text
        if help_text:
            pad = " " * (len(str(location.line)) if location.line else 1)
            out.append(f"{pad} = help: {code.rpartition('/')[2] if code else ''}: {help_text}")
    return out


def render_record(record: DiagnosticRecord, verbosity: int = 0) -> str:
    """A diagnostic record for people (:func:`render`)."""
    return render(record.format(), record.location, record.code, record.source_line, verbosity)


def render_diagnostic(diag: Diagnostic, verbosity: int = 0) -> str:
    """A raised diagnostic for people (:func:`render`)."""
    return render_record(diag.record, verbosity)


def render_line(text: str, verbosity: int = 0) -> str:
    """A diagnostic already formatted as one header line (e.g. a batch row's message made in
    a worker process) with its excerpt; other text comes back unchanged."""
    m = _HEADER.match(text)
    if m is None:
        return text
    entity = m.group("entity")
    loc = Location(
        m.group("file"),
        int(m.group("line")),
        int(m.group("col")),
        int(entity) if entity else None,
    )
    return render(text, loc, m.group("tag"), None, verbosity)
