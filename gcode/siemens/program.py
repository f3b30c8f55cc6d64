"""Program files of a Siemens 840D run: text lines, parsed blocks (cached while loops run),
jump targets (labels and N numbers) and the matching ends of control structures.

Main programs are ``.MPF`` files, subprograms ``.SPF`` (840D sl programming manual,
fundamentals, "Subprograms"): ``L100`` and ``NAME`` are looked for as ``L100.SPF`` and
``NAME.SPF`` (also ``.MPF`` and lower case) in the search path and beside the calling file.
"""

from __future__ import annotations

import re
from array import array
from collections import OrderedDict
from itertools import accumulate

import kernel.limits as limits
from gcode.core.search import find_in_dirs, search_dirs
from gcode.siemens.blocks import Block, parse_block
from kernel.diagnostics import Diagnostic, Location

_HEAD = re.compile(r"\s*(?:N\d+\s*)?(?:([A-Z_][A-Z0-9_]*)\s*:(?!=)\s*)?([A-Z_]+)?", re.IGNORECASE)
_NUMBER = re.compile(r"\s*N(\d+)", re.IGNORECASE | re.ASCII)
_ARCHIVE_HEADER = re.compile(r"%_N_\w+_(?:MPF|SPF)\s*$", re.IGNORECASE)
#: "%" alone (or before a ";" comment) as the first line: the program start character of a
#: program written on an external PC (840D sl programming manual, fundamentals, "Character
#: set": "% program start character")
_START_CHARACTER = re.compile(r"%\s*(;.*)?$")
#: structure openers and their closers (840D sl job planning, "Control structures")
CLOSERS = {
    "IF": "ENDIF",
    "WHILE": "ENDWHILE",
    "FOR": "ENDFOR",
    "REPEAT": "UNTIL",
    "LOOP": "ENDLOOP",
}
_CACHE = 4096


class Program:
    """One program file's text; its lines are found and parsed when executed (a compact
    array of line offsets, no list of line objects)."""

    def __init__(self, name: str, text: str) -> None:
        limits.check_lines(text, name)
        self.name = name
        self.text = text
        self._starts = array("q", [0])  # offsets of the lines found so far
        self._complete = not text
        self._blocks: OrderedDict[int, Block] = OrderedDict()
        self._targets: dict[str, list[int]] | None = None
        self._ends: dict[int, tuple[int, int | None]] = {}
        self.caching = False  # set once a backward jump happened

    def has_line(self, index: int) -> bool:
        """Whether line ``index`` (0-based) exists; finds line ends only as far as needed."""
        starts = self._starts
        text = self.text
        while len(starts) <= index + 1 and not self._complete:
            end = text.find("\n", starts[-1])
            if end < 0:
                self._complete = True
                if starts[-1] < len(text):
                    starts.append(len(text) + 1)
                break
            starts.append(end + 1)
        return index + 1 < len(starts)

    def index_lines(self, found: array[int] | None = None) -> None:
        """Find every line start at once, in C (str.split and accumulate), or take them
        ``found`` by the caller (the same values: 0, one past each line end but a final
        one, and one past the text's end where its last line has no line end): the fast
        lane (gcode.siemens.lane) reads a large file by line offsets and skips whole runs
        of lines, which the line-by-line search of :meth:`has_line` would then walk one by
        one."""
        if self._complete:
            return
        text = self.text
        if found is not None:
            self._starts = found
            self._complete = True
            return
        starts = array("q", [0])
        starts.extend(accumulate(map((1).__add__, map(len, text.split("\n")))))
        if text.endswith("\n"):
            starts.pop()  # the offset past the final line end starts no line
        self._starts = starts
        self._complete = True

    def line_offset(self, index: int) -> int:
        """Where line ``index`` (0-based, existing) starts in :attr:`text`."""
        if not self.has_line(index):
            raise IndexError(index)
        return self._starts[index]

    def line(self, index: int) -> str:
        """The text of line ``index`` (0-based) without its line end."""
        if not self.has_line(index):
            return ""
        line = self.text[self._starts[index] : self._starts[index + 1] - 1].rstrip("\r")
        if index == 0 and line[:1] == "%":
            if _ARCHIVE_HEADER.match(line):
                return ""  # "%_N_PART1_MPF": the 840D's file header when programs are transferred
            if _START_CHARACTER.match(line):
                return line[1:]  # "%" before the first block; a comment after it stays one
        return line

    @classmethod
    def load(cls, path: str) -> Program:
        try:
            with open(path, "rb") as fh:
                data = fh.read()
        except OSError as exc:
            raise Diagnostic(
                "IO-OPEN", f"cannot open program: {exc.strerror or exc}", Location(path)
            ) from None
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            text = data.decode("latin-1")
        return cls(path, text)

    def block(self, index: int) -> Block:
        """The parsed block of line ``index`` (0-based)."""
        if not self.caching:
            return parse_block(self.line(index), self.name, index + 1)
        found = self._blocks.get(index)
        if found is None:
            found = parse_block(self.line(index), self.name, index + 1)
            if len(self._blocks) >= _CACHE:
                self._blocks.popitem(last=False)
            self._blocks[index] = found
        return found

    def head(self, index: int) -> str:
        """The first keyword of a line (after N number and label), upper case, or ''."""
        line = self.line(index)
        semi = line.find(";")
        m = _HEAD.match(line if semi < 0 else line[:semi])
        return (m.group(2) or "").upper() if m else ""

    # ------------------------------------------------------------------ jumps
    def targets(self) -> dict[str, list[int]]:
        """Line indexes of each label (``LAB1``) and block number (``N10``)."""
        if self._targets is None:
            found: dict[str, list[int]] = {}
            index = 0
            while self.has_line(index):
                line = self.line(index)
                m = _HEAD.match(line)
                n = _NUMBER.match(line)
                if n:  # the number's digits without leading zeros: no int() of 5,000 digits
                    found.setdefault(f"N{n.group(1).lstrip('0') or '0'}", []).append(index)
                if m and m.group(1):
                    found.setdefault(m.group(1).upper(), []).append(index)
                index += 1
            self._targets = found
        return self._targets

    def jump(self, label: str, direction: str, here: int, loc: Location) -> int:
        """The line a GOTOF/GOTOB/GOTO/GOTOC to ``label`` from line ``here`` continues at,
        or -1 when GOTOC finds none (840D: GOTO searches forward first, then backward)."""
        lines = self.targets().get(label, [])
        forward = [i for i in lines if i > here]
        backward = [i for i in lines if i < here]
        if direction == "GOTOF" and forward:
            return forward[0]
        if direction == "GOTOB" and backward:
            return backward[-1]
        if direction in ("GOTO", "GOTOC"):
            if forward:
                return forward[0]
            if backward:
                return backward[-1]
            if direction == "GOTOC":
                return -1
        where = {"GOTOF": "after this block", "GOTOB": "before this block"}
        raise Diagnostic(
            "SIEM-LABEL",
            f"jump target {label} not found {where.get(direction, 'in the program')}",
            loc,
        )

    # ------------------------------------------------------------------ structures
    def structure(self, index: int, loc: Location) -> tuple[int, int | None]:
        """(closing line, ELSE line or None) of the structure opened on line ``index``."""
        found = self._ends.get(index)
        if found is not None:
            return found
        opener = self.head(index)
        closer = CLOSERS.get(opener)
        if closer is None:  # the block read it as a keyword the line's head does not show
            raise Diagnostic(
                "SIEM-SYNTAX",
                "a control structure's keyword must follow the block number (a whole "
                "number) and label directly",
                loc,
            )
        stack: list[str] = []
        other: int | None = None
        i = index
        while self.has_line(i + 1):
            i += 1
            head = self.head(i)
            if head in CLOSERS and not _is_statement(head, self.line(i)):
                stack.append(head)
            elif head in CLOSERS.values():
                if not stack:
                    if head != closer:
                        raise Diagnostic(
                            "SIEM-STRUCTURE", f"{opener} closed by {head} on line {i + 1}", loc
                        )
                    self._ends[index] = (i, other)
                    return i, other
                top = stack.pop()
                if CLOSERS[top] != head:
                    raise Diagnostic(
                        "SIEM-STRUCTURE",
                        f"{top} closed by {head} on line {i + 1}",
                        Location(self.name, i + 1, 1),
                    )
            elif head == "ELSE" and not stack and opener == "IF":
                if other is not None:
                    raise Diagnostic("SIEM-STRUCTURE", f"second ELSE on line {i + 1}", loc)
                other = i
        raise Diagnostic("SIEM-STRUCTURE", f"{opener} without {closer}", loc)


def _is_statement(head: str, line: str) -> bool:
    """Whether an ``IF``/``REPEAT`` line opens no structure: ``IF c GOTOF L`` (a jump) or
    ``REPEAT L P=2`` (a section repetition)."""
    code = line.split(";", 1)[0].upper()
    if head == "IF":
        return re.search(r"\bGOTO[FBC]?\b", code) is not None
    if head == "REPEAT":
        return re.search(r"\bREPEAT\s*\S", code) is not None
    return False


def find_subprogram(name: str, search_path: tuple[str, ...], current: str) -> str | None:
    """The file of subprogram ``name``: NAME.SPF (or .MPF, any case) in one of the search
    directories (beside the calling program ``current`` when there is none), never outside
    them (:func:`gcode.core.search.find_in_dirs`)."""
    names = [
        stem + ext for ext in (".SPF", ".spf", ".MPF", ".mpf") for stem in (name, name.lower())
    ]
    return find_in_dirs(search_dirs(search_path, current), names)
