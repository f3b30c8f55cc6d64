"""``ProgramFile``: a body read again (a loop, a subroutine) comes from the block cache.

A subroutine called thousands of times used to seek the file at each call and return,
refilling its read buffer each time; now a cached line is not read again and the file is
sought only when a line must really be read. The counts below are of the file object's
``readline`` calls; the blocks, line numbers and positions must be those of a plain read.
"""

from __future__ import annotations

import io

from gcode.core.program import ProgramFile

PROGRAM = b"o100 sub\nG1 X#1\n\nG1 Y#2\no100 endsub\no100 call [1] [2]\no100 call [3] [4]\nM2\n"


class _Counting(io.BytesIO):
    reads = 0

    def readline(self, size: int | None = -1) -> bytes:
        _Counting.reads += 1
        return super().readline(size)


def test_a_body_read_again_comes_from_the_cache_with_its_line_numbers() -> None:
    pf = ProgramFile("p.ngc", PROGRAM)
    pf._fh = _Counting(PROGRAM)
    _Counting.reads = 0
    first = [pf.next_block() for _ in range(5)]  # the sub, read once
    assert [b.line for b in first if b is not None] == [1, 2, 3, 4, 5]
    for _call in range(100):
        back = pf.tell()
        pf.seek_to(len(b"o100 sub\n"), 1)  # the body: line 2 on
        again = [pf.next_block() for _ in range(3)]
        assert again == first[1:4] and pf.line == 4 and pf.last_nonblank == 4
        assert pf.current().offset == PROGRAM.index(b"G1 Y#2")
        pf.seek(back)
    assert _Counting.reads == 5  # the body was never read again
    rest = [pf.next_block() for _ in range(4)]
    assert [b.line if b else None for b in rest] == [6, 7, 8, None]
    assert _Counting.reads == 9  # one seek back to line 6, then three lines and the end
    assert pf.line_text(8) == "M2" and pf.line_text(7) is None
