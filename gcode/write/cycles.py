"""Writing a canned cycle as one block (``--cycles keep``) instead of its moves.

A reader run with cycle marks (gcode.core.cycle_marks) brackets each drilling cycle's expansion
with CANNED_CYCLE ... CANNED_CYCLE_END. The writer keeps the cycle when the target has it
with RS274/NGC's motion (``Dialect.cycles``: G73 G81 G82 G83 G85 G89 in LinuxCNC, NIST v3,
Fanuc and Haas), the plane is XY and the block is one hole; it writes
``G98|G99 G8x X Y Z R [Q] [P] F`` in absolute coordinates (``R`` and ``Z`` absolute along
the hole axis, as the reader resolved them) and skips the moves up to the end mark. The
target then expands the block into the same moves: the cycle rules of NIST v3 §3.5.16 are
the same in these dialects, which the round-trip tests check. Anything else is written as
the moves, with a note. Between kept cycles of one series only X and Y are written (the
cycle is modal).
"""

from __future__ import annotations

from gcode.core.cycle_marks import CycleEnd, CycleStart
from gcode.write.context import WriterContext
from kernel.ir import canon

_CODES = {730: "G73", 810: "G81", 820: "G82", 830: "G83", 850: "G85", 890: "G89"}
_PECK = (730, 830)
_DWELL = (820, 890)


def cycle_start(w: WriterContext, c: CycleStart) -> None:
    if w.o.cycles != "keep":
        return
    name = _CODES.get(c.code, f"G{c.code // 10}")
    why = _not_kept(w, c, name)
    if why:
        key = f"cycle {name} {why}"
        if key not in w.noted:  # once per cycle and reason, at its first block
            w.noted.add(key)
            w.change("CONV-CYCLE", "expanded", f"{name} written as its moves: {why}")
        return
    w.flush()
    s = w.fmt.scale
    retract = w.d.cycle_retract[1 if c.retract_r else 0]
    held = (name, retract, c.r, c.bottom, c.q if c.code in _PECK else 0.0, _dwell(w, c))
    words = [
        "X" + w.fmt.length(c.first * s),
        "Y" + w.fmt.length(c.second * s),
    ]
    if held != w.cycle or w.motion != name:
        words += ["Z" + w.fmt.length(c.bottom * s), "R" + w.fmt.length(c.r * s)]
        if c.code in _PECK:
            words.append("Q" + w.fmt.length(c.q * s))
        if c.code in _DWELL:
            words.append("P" + held[5])
        w.motion = name
        w.block(retract, name, *words, w.feed_word())
    else:
        w.block(*words, w.feed_word())
    w.cycle = held
    w.skipping = True


def cycle_end(w: WriterContext, c: CycleEnd) -> None:
    if not w.skipping:
        return
    w.skipping = False
    s = w.fmt.scale
    for letter, value in zip("XYZ", c.position[:3], strict=True):
        w.cur[letter] = value * s
    w.invalidate()  # the text left the tool where the target's expansion ends


def _dwell(w: WriterContext, c: CycleStart) -> str:
    if c.code not in _DWELL:
        return ""
    if w.d.cycle_dwell_ms:  # Fanuc: P in milliseconds, an integer
        return str(round(c.p * 1000.0))
    return w.fmt.number(c.p, 3)


def _not_kept(w: WriterContext, c: CycleStart, name: str) -> str:
    """Why this cycle block cannot be written as a cycle ('' when it can)."""
    if name not in w.d.cycles:
        return f"{w.d.title} has no {name} with the same motion"
    if c.plane != canon.Plane.XY:
        return "a cycle outside the XY plane"
    if c.repeats != 1:
        return "an L/K repeat count"
    if w.d.cycle_dwell_ms and c.code in _DWELL and abs(c.p * 1000.0 - round(c.p * 1000.0)) > 1e-9:
        return "a dwell that is not a whole number of milliseconds"
    return ""
