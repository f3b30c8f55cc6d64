"""Large segment tables (kernel.path.columns.segment_table, the table in its own 4 KiB-page mapping
from kernel.interp.bulk) are byte for byte the tables built in ``numpy.zeros``.

Reference: the same conversion with the bulk threshold raised above the program's size,
so the table comes from ``numpy.zeros`` (the small-program path, itself checked against
the one-by-one conversion in tests/test_kernel_path_speedpath.py). Programs: a CAM-style
run of lines with arcs and a dwell, with and without moves shorter than MIN_LENGTH
(dropped before the table is made), and one that raises a diagnostic.
"""

from __future__ import annotations

import math

import pytest

from kernel.diagnostics import Diagnostic
from kernel.interp import bulk
from kernel.interp.bulk import MAPPED_BYTES
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE
from kernel.path.build import build_path
from kernel.path.segments import SEGMENT_DTYPE

ROWS = MAPPED_BYTES // SEGMENT_DTYPE.itemsize + 500  # just over the bulk threshold


def _program(tiny_every: int = 0) -> list[canon.Command]:
    cmds: list[canon.Command] = [canon.SetFeedRate(1800.0), canon.StraightTraverse(0, 0, 5)]
    x = 0.0
    for i in range(ROWS):
        if i % 97 == 96:
            cmds.append(canon.ArcFeed(x + 1.0, 0.0, x + 0.5, 0.0, 1, 0.0))
            x += 1.0
        elif tiny_every and i % tiny_every == 0:
            x += 1e-10  # shorter than MIN_LENGTH: dropped from the table
            cmds.append(canon.StraightFeed(x, 0.0, 0.0))
        else:
            x += 0.25
            cmds.append(canon.StraightFeed(x, 0.0, 0.1 * math.sin(i / 9)))
        if i == ROWS // 2:
            cmds.append(canon.Dwell(0.5))
    cmds.append(canon.ProgramEnd())
    return cmds


@pytest.mark.parametrize("tiny_every", [0, 13])
def test_large_tables_are_byte_identical_to_tables_in_numpy_zeros(monkeypatch, tiny_every):
    cmds = _program(tiny_every)
    big = build_path(cmds, DEFAULT_MACHINE).segments
    assert big.nbytes >= MAPPED_BYTES * (0.9 if tiny_every else 1.0)
    monkeypatch.setattr(bulk, "MAPPED_BYTES", 1 << 60)
    ref = build_path(cmds, DEFAULT_MACHINE).segments
    assert not big.flags.owndata and ref.flags.owndata  # a mapping's view; numpy.zeros
    assert big.dtype == ref.dtype and len(big) == len(ref)
    assert len(big) < ROWS if tiny_every else len(big) > ROWS
    assert big.tobytes() == ref.tobytes()


def test_a_large_program_with_a_zero_feed_still_raises_its_diagnostic():
    cmds = _program()
    cmds.insert(5, canon.SetFeedRate(0.0))
    with pytest.raises(Diagnostic) as e:
        build_path(cmds, DEFAULT_MACHINE)
    assert e.value.code == "PLAN-FEED"
