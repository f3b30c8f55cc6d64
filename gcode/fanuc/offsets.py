"""Fanuc offset data: G10 L2 (work offsets), G10 L10-L13 (tool length and radius offset
memory C: geometry and wear), G43 H / G41 D lookups (Fanuc 0i-MF manual, "Programmable
data input (G10)").

Offset number ``n`` of the offset memory is kept as tool ``n`` of the run's tool table
(the table the RS274/NGC executor reads for ``G43 H`` and ``G41 D``), so offsets set by G10
and offsets from the user's table are used the same way. The table is in inches
(LinuxCNC), the program in its own units.
"""

from __future__ import annotations

from dataclasses import replace

from gcode.core.codes import Words
from gcode.core.register_marks import EXTENDED_WORK_OFFSETS, WorkOffsetValues
from gcode.core.state import INCH_MM, CompCode
from gcode.fanuc.state import ExecutorState
from gcode.ngc.comp.cutter_comp import CutterCompensator
from gcode.ngc.offsets import load_system
from kernel.diagnostics import Diagnostic, Location
from kernel.ir.canon import SetToolTableEntry, Units
from kernel.tooltable import Tool

_AXES = "XYZABC"


def _table_scale(ex: ExecutorState) -> float:
    return INCH_MM if ex.ip.s.units is Units.MM else 1.0


def g10(ex: ExecutorState, v: dict[str, float], loc: Location, absolute: bool) -> None:
    if "L" not in v:
        raise Diagnostic("FANUC-G10-L", "G10 without L", loc)
    lword = round(v["L"])
    if "P" not in v:
        raise Diagnostic("FANUC-G10-P", f"G10 L{lword} without P", loc)
    p = round(v["P"])
    if lword == 2:
        _work_offset(ex, p, v, loc, absolute)
    elif lword == 20:
        extended_set(ex, p, v, loc, absolute)
    elif lword in (1, 10, 11, 12, 13):
        _offset_memory(ex, lword, p, v, loc, absolute)
    else:
        raise Diagnostic("FANUC-G10-L", f"G10 L{lword} is not read (L2, L10-L13, L20)", loc)


def _work_offset(
    ex: ExecutorState, p: int, v: dict[str, float], loc: Location, absolute: bool
) -> None:
    if not 1 <= p <= 6:
        raise Diagnostic("FANUC-G10-P", "G10 L2 P must be 1-6 (G54-G59)", loc)
    row = ex.ip.s.coords[p]
    values: dict[str, float] = {"l": 2.0, "p": float(p)}
    for i, a in enumerate(_AXES):
        if a in v:
            values[a.lower()] = v[a] if absolute else row[i] + v[a]
    ex.ip.execute(Words(g={0: 100}, values=values))


def _offset_memory(
    ex: ExecutorState, lword: int, n: int, v: dict[str, float], loc: Location, absolute: bool
) -> None:
    if n < 0 or n > 999:
        raise Diagnostic("FANUC-G10-P", f"offset number P{n} out of range", loc)
    if "R" not in v:
        raise Diagnostic("FANUC-G10-R", f"G10 L{lword} without R (the offset value)", loc)
    table = ex.radii if lword in (12, 13) else ex.lengths
    entry = table.setdefault(n, [0.0, 0.0])
    slot = 1 if lword in (11, 13) else 0
    entry[slot] = v["R"] if absolute else entry[slot] + v["R"]
    k = _table_scale(ex)
    tools = ex.ip.tools
    base = tools.tools.get(n) or Tool(n, n)
    if table is ex.lengths:
        offset = list(base.offset)
        offset[2] = (entry[0] + entry[1]) / k
        new = tools.tools[n] = replace(base, offset=tuple(offset))
        if ex.ip.options.register_marks:
            # cnc convert: the program writes the machine's offset memory, which a converted
            # program must write too (or the conversion says it cannot: gcode.write.extras)
            ex.ip.emit(
                SetToolTableEntry(
                    new.pocket,
                    n,
                    new.offset,
                    new.diameter,
                    new.front_angle,
                    new.back_angle,
                    new.orientation,
                    source=loc,
                )
            )
    else:
        tools.tools[n] = replace(base, diameter=2.0 * (entry[0] + entry[1]) / k)


def tool_length(
    ex: ExecutorState, w: Words, v: dict[str, float], negative: bool, loc: Location
) -> None:
    """G43 H (H0 cancels); G44 is refused (the IR has no negative length offset of a tool)."""
    if negative:
        raise Diagnostic("FANUC-G44", "G44 (negative tool length offset) is not read", loc)
    h = v.get("H")
    if h is not None and round(h) == 0:
        w.g[8] = 490
        ex.modal_h = 0.0
        return
    w.g[8] = 430
    if h is not None:
        w.values["h"] = float(round(h))
        ex.modal_h = float(round(h))


def radius(ex: ExecutorState, w: Words, v: dict[str, float]) -> None:
    w.values["d"] = float(round(v["D"]))


def comp_reissued(ex: ExecutorState, w: Words, loc: Location) -> float | None:
    """G41/G42 given again while compensation is on (Fanuc 0i-MF, Haas: allowed).

    The same side with the same D (or no D) changes nothing: the code is dropped and the
    path goes on as compensated. A new D on the same side is returned (the compensator
    applies it after the block, :meth:`gcode.ngc.comp.cutter_comp.CutterCompensator.change_radius`)
    and dropped from the words too. A change of side is refused (``FANUC-COMP-CHANGE``).
    """
    code = w.g.get(7)
    ip = ex.ip
    s = ip.s
    if code is None:
        return None
    if ip.comp is None and not ip.options.keep_cutter_comp:
        ip.comp = CutterCompensator(comments=ip.compat)
        ip.comp.set_units(s.units is Units.INCHES)
    if code == 400:
        ex.comp_d = None
        return None
    if s.comp_side not in (CompCode.G41, CompCode.G42):
        ex.comp_d = w.values.get("d")
        return None
    d = w.values.get("d", ex.comp_d)
    if code == s.comp_side and d == ex.comp_d:
        del w.g[7]
        w.values.pop("d", None)
        return None
    if code != s.comp_side:
        raise Diagnostic(
            "FANUC-COMP-CHANGE",
            f"G{code // 10} changes the compensation side while compensation is on"
            " (not read: cancel with G40 first)",
            loc,
        )
    if not isinstance(ip.comp, CutterCompensator) or d is None:
        raise Diagnostic(
            "FANUC-COMP-CHANGE",
            f"G{code // 10} D{d or 0:g} changes the offset while compensation is kept as"
            " G41/G42 (not read)",
            loc,
        )
    found = ip.tools.get(int(d) if d else s.current_tool)
    if found is None:
        raise Diagnostic("FANUC-COMP-D", f"no offset D{d:g}", loc)
    radius = found.diameter * _table_scale(ex) / 2.0
    if radius < 0.0:
        raise Diagnostic(
            "FANUC-COMP-CHANGE", "a negative offset changes the side (not read in offset mode)", loc
        )
    del w.g[7]
    w.values.pop("d", None)
    ex.comp_d = d
    return radius


# --------------------------------------------------------------------------- G54.1 P
#: the machine model's coordinate system that holds the selected additional offset
#: (G59.3: Fanuc has no G59.1-G59.3, so the slot is free)
EXTENDED_SLOT = 9


def _extended_count(ex: ExecutorState) -> int:
    return ex.fl.extended_offsets


def extended_set(
    ex: ExecutorState, n: int, v: dict[str, float], loc: Location, absolute: bool
) -> None:
    """G10 L20 P n: additional work offset n (G54.1 P n; Haas G154 P n)."""
    if not 1 <= n <= _extended_count(ex):
        raise Diagnostic("FANUC-G10-P", f"G10 L20 P{n}: no such additional offset", loc)
    row = ex.extended.setdefault(n, [0.0] * 6)
    for i, a in enumerate(_AXES):
        if a in v:
            row[i] = v[a] if absolute else row[i] + v[a]
    if ex.ip.options.register_marks:  # the setting itself, for a writer (register_marks)
        given = [i for i, a in enumerate(_AXES) if a in v]
        number = EXTENDED_WORK_OFFSETS + n
        axes = "".join(_AXES[i] for i in given)
        ex.ip.emit(WorkOffsetValues(number, axes, tuple(row[i] for i in given), source=loc))
    if ex.extended_selected == n:
        _load_extended(ex, n)


def extended_select(ex: ExecutorState, v: dict[str, float], loc: Location) -> None:
    """G54.1 P n (Haas G154 P n): make additional work offset n the active system."""
    if "P" not in v or v["P"] != round(v["P"]) or not 1 <= v["P"] <= _extended_count(ex):
        raise Diagnostic("FANUC-G54-1", "G54.1 needs P1-P48 (Haas G154: P1-P99)", loc)
    n = int(v.pop("P"))
    ex.extended_selected = n
    ex.ip.s.slot9_number = EXTENDED_WORK_OFFSETS + n
    _load_extended(ex, n)
    ex.ip.execute(Words(g={12: 593}))


def _load_extended(ex: ExecutorState, n: int) -> None:
    if ex.ip.s.origin_index == EXTENDED_SLOT:
        ex.ip.comp_off("active coordinate system")
    load_system(ex.ip, EXTENDED_SLOT, ex.extended.get(n, [0.0] * 6)[:], None)


def extended_value(ex: ExecutorState, n: int, axis: int) -> float:
    return ex.extended.get(n, [0.0] * 6)[axis]
