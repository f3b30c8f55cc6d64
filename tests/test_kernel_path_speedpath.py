"""The columnar fast path of the IR -> segment table conversion changes no number.

:func:`kernel.path.build.build_path` converts runs of consecutive ``STRAIGHT_FEED`` /
``STRAIGHT_TRAVERSE`` commands as whole columns (kernel.path.builder). The reference here is
the conversion as it was before: every command through :meth:`PathBuilder.feed` one at a
time, and the light rows vectorised by the former ``table`` (kept verbatim below as
:func:`_reference_rows_table`; the arc frame's cross product, now scalar, is checked against
``np.cross`` separately). The tables must be identical byte for byte (so -0.0 and
0.0 count as different) for every golden program, every corpus ``.canon`` file, random
programs mixing moves with every modal change the builder honours, and streamed programs.
"""

from __future__ import annotations

import math
from itertools import chain
from pathlib import Path as FsPath

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.machine import AXIS_NAMES, DEFAULT_MACHINE, AxisLimits, Machine
from kernel.path import builder as pb
from kernel.path.blend import blend_corners
from kernel.path.build import build_path
from kernel.path.segments import ARC, HOLD, LINE, MIN_LENGTH, RAPID, SEGMENT_DTYPE, Path
from tests.data_paths import CORPUS_NGC

HERE = FsPath(__file__).resolve().parent
GOLDEN = HERE / "golden" / "ngc"
CORPUS = CORPUS_NGC

SIX_AXES = Machine(
    "6ax",
    (
        *DEFAULT_MACHINE.axes,
        *(AxisLimits(n, velocity=3600.0, acceleration=36000.0, jerk=1e6) for n in "abc"),
    ),
    DEFAULT_MACHINE.controller,
)


def _reference_rows_table(rows: list, machine: Machine, file: str | None) -> np.ndarray:
    """The former ``PathBuilder.table``, verbatim (light rows -> segment table)."""
    n = len(rows)
    seg = np.zeros(n, SEGMENT_DTYPE)
    if not n:
        return seg
    (
        kind,
        cat,
        start,
        end,
        rate,
        mode,
        mm,
        spindle,
        synch,
        override,
        stop,
        blend,
        src,
        line,
        duration,
        recs,
    ) = zip(*rows, strict=True)
    kind = np.fromiter(kind, np.int8, n)
    start = np.fromiter(chain.from_iterable(start), float, 6 * n).reshape(n, 6)
    end = np.fromiter(chain.from_iterable(end), float, 6 * n).reshape(n, 6)
    seg["kind"], seg["category"] = kind, np.fromiter(cat, np.int8, n)
    seg["start"], seg["end"] = start, end
    seg["exact_stop"] = np.fromiter(stop, bool, n)
    seg["blend"] = np.fromiter(blend, float, n)
    seg["source"] = np.fromiter(src, np.int64, n)
    seg["line"] = np.fromiter(line, np.int32, n)
    seg["duration"] = np.fromiter(duration, float, n)
    d = end - start
    lin = np.sqrt(np.einsum("ij,ij->i", d[:, :3], d[:, :3]))
    rotary_only = lin <= MIN_LENGTH
    length = np.where(rotary_only, np.linalg.norm(d[:, 3:], axis=1), lin)
    is_arc = kind == ARC
    ai = np.flatnonzero(is_arc)
    for i in ai:
        for key, val in recs[i]._asdict().items():
            seg[key][i] = val
    length[ai] = seg["length"][ai]
    rotary_only[ai] = False
    seg["length"] = np.where(kind == HOLD, 0.0, length)
    # axes the machine lacks must not move
    present = np.array([a in machine.axis_names for a in AXIS_NAMES])
    bad = np.flatnonzero(np.any((np.abs(d) > MIN_LENGTH) & ~present, axis=1))
    if bad.size:
        i = int(bad[0])
        names = ", ".join(
            AXIS_NAMES[j].upper() for j in np.flatnonzero((np.abs(d[i]) > MIN_LENGTH) & ~present)
        )
        raise Diagnostic(
            "PLAN-AXIS",
            f"the move drives axis {names}, which the machine lacks",
            Location(file, int(line[i]), 1 if line[i] else 0),
        )
    # drop motions too short to matter (the position was carried on anyway)
    keep = (kind == HOLD) | (seg["length"] > MIN_LENGTH)
    if keep.all():  # the usual case: no copy of the (wide) table
        sel = np.arange(n)
    else:
        seg, d, rotary_only = seg[keep], d[keep], rotary_only[keep]
        sel = np.flatnonzero(keep)
    rate = np.fromiter(rate, float, n)[sel]
    mode = np.fromiter(mode, float, n)[sel]
    mm = np.fromiter(mm, float, n)[sel]
    spindle = np.fromiter(spindle, float, n)[sel]
    synch = np.fromiter(synch, float, n)[sel]
    override = np.fromiter(override, float, n)[sel]
    length = seg["length"]
    with np.errstate(invalid="ignore"):
        unit = np.where(rotary_only, 1.0, mm)
        # G93 rates arrive per minute already (kernel.ir.canon.SetFeedMode)
        feed = np.where(mode == 2, rate * unit * spindle / 60.0, rate * unit / 60.0)
        feed = np.where(synch > 0, synch * mm * spindle / 60.0, feed) * override
        rapid = seg["category"] == RAPID
        feed = np.where(rapid, rate * unit / 60.0, feed)
    seg["feed"] = feed
    moving = seg["kind"] != HOLD
    bad = np.flatnonzero(moving & ~rapid & ~(feed > 0))
    if bad.size:
        ln = int(seg["line"][bad[0]])
        raise Diagnostic(
            "PLAN-FEED",
            "feed move with a zero feed rate",
            Location(file, ln, 1 if ln else 0),
        )
    safe = np.where(length > 0, length, 1.0)[:, None]
    lines = seg["kind"] == LINE
    u = np.where(lines[:, None], d / safe, 0.0)
    seg["u_start"], seg["u_end"] = u, u
    arcs = np.flatnonzero(seg["kind"] == ARC)
    if arcs.size:
        from kernel.path.geometry import arc_tangent

        sa = seg[arcs]
        us, ue = arc_tangent(sa, np.zeros(arcs.size)), arc_tangent(sa, np.ones(arcs.size))
        rot = d[arcs, 3:] / sa["length"][:, None]
        us[:, 3:], ue[:, 3:] = rot, rot
        seg["u_start"][arcs], seg["u_end"][arcs] = us, ue
    return seg


def reference_build_path(commands, machine: Machine, file: str | None = None) -> Path:
    """build_path as it was: one command at a time, then the former row vectoriser."""
    b = pb.PathBuilder(machine, file)
    for idx, cmd in enumerate(commands):
        b.feed(idx, cmd)
    return blend_corners(Path(_reference_rows_table(b.rows, machine, file), file))


def _outcome(build, commands, machine, file=None):
    """The table's bytes, or the diagnostic's code, message and location."""
    try:
        seg = build(commands, machine, file).segments
    except Diagnostic as d:
        return ("error", d.code, str(d))
    assert seg.dtype == SEGMENT_DTYPE
    return ("table", len(seg), seg.tobytes())


def _canon_files() -> list[FsPath]:
    return sorted(GOLDEN.glob("*.canon")) + sorted(CORPUS.glob("*.canon"))


@pytest.mark.parametrize("min_run", [1, pb.MIN_RUN])
def test_golden_and_corpus_tables_are_byte_identical_to_the_one_by_one_conversion(
    monkeypatch, min_run
):
    """Every golden and corpus .canon program, on a 3- and a 6-axis machine, with runs of
    any length (min_run 1) and the default threshold, gives the same table (or the same
    diagnostic) as the former conversion."""
    monkeypatch.setattr(pb, "MIN_RUN", min_run)
    files = _canon_files()
    assert len(files) >= 150
    tables = 0
    for f in files:
        with open(f) as fh:
            cmds = list(canon.read_commands(fh, str(f), keep_linuxcnc=True))
        for m in (SIX_AXES, DEFAULT_MACHINE):
            new = _outcome(build_path, cmds, m, str(f))
            assert new == _outcome(reference_build_path, cmds, m, str(f)), (f, m.name)
            tables += new[0] == "table"
    assert tables >= 300


def test_streamed_program_in_small_batches_gives_the_same_table(monkeypatch):
    """A generator is drawn in batches; runs cut by batch borders change nothing."""
    monkeypatch.setattr(pb, "_BATCH", 7)
    monkeypatch.setattr(pb, "MIN_RUN", 2)
    cmds = [canon.SetFeedRate(600.0), canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, 0.01)]
    cmds += [canon.StraightFeed(i * 0.5, math.sin(i) * 3, 0.1 * i) for i in range(60)]
    cmds += [canon.Dwell(0.5), canon.StraightTraverse(0.0, 0.0, 10.0), canon.ProgramEnd()]
    new = _outcome(lambda c, m, f: build_path(iter(c), m, f), cmds, DEFAULT_MACHINE)
    assert new[0] == "table"
    assert new == _outcome(reference_build_path, cmds, DEFAULT_MACHINE)


def test_a_failing_stream_reports_an_earlier_builder_error_first():
    """As in the one-by-one walk, an error of a command the stream delivered comes before
    the error that ended the stream."""

    def stream():
        yield canon.SetFeedRate(600.0)
        yield canon.EllipseFeed(1, 1, 0, 0, 1, 1, 0, 1, 0)
        yield canon.StraightFeed(1.0, 0.0, 0.0)
        raise Diagnostic("NGC-TEST", "stream failed", Location("p.ngc", 9, 1))

    with pytest.raises(Diagnostic) as e:
        build_path(stream(), DEFAULT_MACHINE)
    assert e.value.code == "PLAN-ELLIPSE"

    def stream_ok():
        yield canon.SetFeedRate(600.0)
        yield from (canon.StraightFeed(float(i), 0.0, 0.0) for i in range(1, 20))
        raise Diagnostic("NGC-TEST", "stream failed", Location("p.ngc", 9, 1))

    with pytest.raises(Diagnostic) as e:
        build_path(stream_ok(), DEFAULT_MACHINE)
    assert e.value.code == "NGC-TEST"


small = st.floats(-30, 30, allow_nan=False, allow_infinity=False)
coord = st.one_of(small, st.sampled_from([0.0, -0.0, 1.0]))  # repeats: zero-length moves
src = st.one_of(st.none(), st.builds(Location, st.none(), st.integers(0, 999), st.just(1)))


@st.composite
def straight(draw):
    cls = draw(st.sampled_from([canon.StraightFeed, canon.StraightFeed, canon.StraightTraverse]))
    x, y, z = draw(coord), draw(coord), draw(coord)
    rotary = draw(st.integers(0, 5)) == 0  # rotary axes (rotary only when XYZ repeat)
    abc = draw(st.tuples(small, small, small)) if rotary else (0.0, 0.0, 0.0)
    return cls(x, y, z, *abc, source=draw(src))


def _modal(draw) -> canon.Command:
    kind = draw(st.integers(0, 15))
    v = draw(small)
    if kind == 0:
        return canon.UseLengthUnits(draw(st.sampled_from(list(canon.Units))))
    if kind == 1:
        return canon.SetOriginOffsets(v, draw(coord), draw(coord), draw(coord))
    if kind == 2:
        return canon.SetG5xOffset(1, draw(coord), draw(coord), draw(coord), draw(coord))
    if kind == 3:
        return canon.SetG92Offset(draw(coord), draw(coord), draw(coord), draw(coord))
    if kind == 4:
        return canon.SetXYRotation(draw(st.sampled_from([0.0, 30.0, -90.0, 12.5, v])))
    if kind == 5:
        return canon.SetFeedRate(draw(st.sampled_from([0.0, 100.0, 3000.0, abs(v) * 50])))
    if kind == 6:
        return canon.SetTraverseRate(draw(st.sampled_from([0.0, 5000.0])))
    if kind == 7:
        mode = draw(st.sampled_from(list(canon.MotionMode)))
        return canon.SetMotionControlMode(mode, draw(st.sampled_from([0.0, 0.02])))
    if kind == 8:
        return canon.SetFeedMode(draw(st.sampled_from(list(canon.FeedMode))))
    if kind == 9:
        return canon.SetSpindleSpeed(draw(st.sampled_from([0.0, 1000.0])))
    if kind == 10:
        return draw(
            st.sampled_from([canon.StartSpeedFeedSynch(0.5, False), canon.StopSpeedFeedSynch()])
        )
    if kind == 11:
        return draw(st.sampled_from([canon.EnableFeedOverride(), canon.DisableFeedOverride()]))
    if kind == 12:
        return canon.Dwell(abs(v) / 10)
    if kind == 13:
        return canon.ArcFeed(
            v, draw(small), v + 1.0, draw(small), draw(st.sampled_from([1, -1, 2])), draw(small)
        )
    if kind == 14:
        return canon.StraightProbe(v, draw(small), draw(small))
    return canon.SelectPlane(draw(st.sampled_from(list(canon.Plane))))


@st.composite
def programs(draw):
    """Runs of straight moves (repeated points included) between random modal changes."""
    cmds: list[canon.Command] = [canon.SetFeedRate(1200.0)]
    for _ in range(draw(st.integers(1, 8))):
        run = draw(st.lists(straight(), min_size=0, max_size=12))
        if run and draw(st.booleans()):
            run.insert(draw(st.integers(0, len(run))), run[0])  # a move to where the tool is
        cmds += run
        cmds.append(_modal(draw))
    return cmds


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(), st.sampled_from([1, 2, 5]), st.sampled_from([True, True, True, False]))
def test_random_programs_give_byte_identical_tables(cmds, min_run, six_axes):
    """Random programs (units, G5x / G92 / origin offsets, XY rotation, feed and traverse
    rates, motion and feed modes, spindle synchronisation, overrides, holds, arcs, probes,
    zero-length and rotary moves) give the former table or the former diagnostic."""
    machine = SIX_AXES if six_axes else DEFAULT_MACHINE
    saved = pb.MIN_RUN
    pb.MIN_RUN = min_run
    try:
        new = _outcome(build_path, cmds, machine)
    finally:
        pb.MIN_RUN = saved
    assert new == _outcome(reference_build_path, cmds, machine)


component = st.one_of(small, st.sampled_from([0.0, -0.0, 1.0, -1.0]))


@given(st.tuples(component, component, component), st.tuples(component, component, component))
def test_arc_frame_cross_product_is_numpys_to_the_bit(a, b):
    """The arc builder's scalar cross product (e2 = normal x e1) is ``np.cross`` exactly,
    signed zeros included."""
    a, b = np.array(a), np.array(b)
    assert pb._cross(a, b).tobytes() == np.cross(a, b).tobytes()


def test_signed_zeros_survive_as_in_the_one_by_one_conversion(monkeypatch):
    """-0.0 coordinates and offsets: the columnar path adds the G5x offset and turns by the
    XY rotation only where the one-by-one walk does (x + 0.0 would turn -0.0 into 0.0)."""
    monkeypatch.setattr(pb, "MIN_RUN", 1)
    z = -0.0
    moves = [canon.StraightFeed(z, -1.0, 1.0), canon.StraightFeed(z, 2.0, z)]
    moves += [canon.StraightFeed(1.0, z, z), canon.StraightFeed(z, z, 2.0)]
    cmds = [
        canon.SetFeedRate(600.0),
        canon.SetG92Offset(z, z, z),
        canon.SetG5xOffset(1, z, 5.0, z),
        *moves,
        canon.SetXYRotation(30.0),
        *moves,
        canon.SetXYRotation(0.0),
        canon.SetG5xOffset(1, 0.0, 0.0, 0.0),
        *moves,
    ]
    new = _outcome(build_path, cmds, DEFAULT_MACHINE)
    assert new[0] == "table"
    assert new == _outcome(reference_build_path, cmds, DEFAULT_MACHINE)
    # one frame for every run (broadcast instead of repeated per row)
    same = [*cmds[:3], canon.SetXYRotation(30.0), *moves, canon.Dwell(1.0), *moves]
    new = _outcome(build_path, same, DEFAULT_MACHINE)
    assert new[0] == "table"
    assert new == _outcome(reference_build_path, same, DEFAULT_MACHINE)
