"""System variables of custom macro B that a shop program uses (Fanuc 0i-MF manual,
"System variables"): ``#1000``-``#1035`` interface input signals (the PLC's: read as
0, no signal), ``#1100``-``#1135`` output signals (kept, no effect), ``#3000`` alarm,
``#3006`` stop with message, ``#3001``/``#3002`` clocks, ``#3011``/``#3012`` date and time
(0), ``#4001``-``#4030`` modal G codes, ``#4102``-``#4130`` modal B D E F H M N O S T P
(``#4201``-``#4330`` the same for the block being run), ``#5001``-``#5006`` block end
position, ``#5021``-``#5026`` machine position, ``#5041``-``#5046`` current position,
``#5061``-``#5066`` skip (G31) position, ``#5081``-``#5086`` tool length offset,
``#5101``-``#5106`` servo deviation (0), ``#5201``-``#5326`` work offsets (``#5221`` + 20
(n - 1) for G54 + n - 1; the older series' ``#2500``-``#2806`` map onto them),
``#2001``-``#2400`` and ``#10001``-``#13400`` tool offsets (memory C: length wear, length
geometry, radius wear, radius geometry). Haas (mill and lathe operator's manuals,
"Macros"): ``#2401``-``#2600`` / ``#2601``-``#2800`` tool diameter geometry / wear,
``#3026`` tool in the spindle, ``#5401``-``#6000`` tool timers, tool life and load monitor
values (0: new tools, no load).
"""

from __future__ import annotations

from typing import Protocol

from gcode.core.codes import Words
from gcode.fanuc import offsets
from gcode.fanuc.state import ExecutorState
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Plane, Units

_PLANE_CODE = {Plane.XY: 17.0, Plane.XZ: 18.0, Plane.YZ: 19.0}


class RunView(Protocol):
    """What the system variables read of a run (:class:`gcode.fanuc.flow.Reader`)."""

    @property
    def ex(self) -> ExecutorState:
        """The run's Fanuc state."""
        ...

    @property
    def current_seq(self) -> int | None:
        """The N number of the block being run, if it has one."""
        ...

    @property
    def current_program(self) -> int:
        """The O number of the program being run."""
        ...


class SystemVariables:
    """Reads and writes the machine state behind ``#1000`` and up."""

    def __init__(self, reader: RunView) -> None:
        self.r = reader
        self.outputs: dict[int, float | None] = {}  # #1100-#1135 interface output signals
        self.input_reads = 0  # reads of #1000-#1035 (a loop waiting on one never ends here)

    def read(self, i: int, loc: Location) -> float | None:
        ex = self.r.ex
        s = ex.ip.s
        if i in (3001, 3002, 3011, 3012, 3901, 3902):
            return 0.0
        if 1000 <= i <= 1035:
            self.input_reads += 1
            return 0.0
        if 1100 <= i <= 1135:
            return self.outputs.get(i, 0.0)
        if 4001 <= i <= 4030 or 4201 <= i <= 4230:
            return self._modal(i % 200 if i > 4200 else i - 4000)
        if 4101 <= i <= 4130 or 4301 <= i <= 4330:
            return self._modal_word(i % 100)
        if 5061 <= i <= 5066:
            return ex.ip.params.values[i]
        if 5081 <= i <= 5086:
            return s.tool_offset[i - 5081]
        if 5101 <= i <= 5106:
            return 0.0
        if self.r.ex.fl.haas_g_codes:
            if i == 3026:
                return float(s.current_tool)
            if 5401 <= i <= 6000:
                return 0.0
        if 5001 <= i <= 5006:
            pos = ex.tf.inverse(s.pos[:3]) + list(s.pos[3:])
            return pos[i - 5001]
        if 5021 <= i <= 5026 or 5041 <= i <= 5046:
            k = i - (5021 if i < 5040 else 5041)
            if i < 5040:
                return s.pos[k] + s.machine_offset(k)
            return s.pos[k]
        if 5221 <= i <= 5326:
            n, k = divmod(i - 5221, 20)
            if k < 6:
                return s.coords[n + 1][k]
        if 5201 <= i <= 5206:
            return 0.0
        if 7001 <= i <= 7946:
            n, k = divmod(i - 7001, 20)
            if k < 6:
                return offsets.extended_value(ex, n + 1, k)
        if 2001 <= i <= 2400 or 10001 <= i <= 13400:
            return self._offset(i)
        if 2401 <= i <= 2800 and ex.fl.haas_g_codes:  # Haas: tool diameters
            n, slot = (i - 2400, 0) if i <= 2600 else (i - 2600, 1)
            return 2.0 * ex.radii.get(n, [0.0, 0.0])[slot]
        old = _old_work_offset(i)
        if old is not None and not ex.fl.haas_g_codes:
            return self.read(old, loc)
        raise Diagnostic("FANUC-SYSTEM-VARIABLE", f"system variable #{i} is not available", loc)

    def write(self, i: int, value: float | None, loc: Location) -> None:
        r = self.r
        ip = r.ex.ip
        if i == 3000:
            n = int(value or 0)
            text = r.ex.last_comment or ""
            raise Diagnostic("FANUC-ALARM", f"macro alarm {3000 + n}: {text}".rstrip(": "), loc)
        if i == 3006:
            ip.emit(canon.Message(r.ex.last_comment or f"stop {int(value or 0)}", source=loc))
            ip.emit(canon.ProgramStop(source=loc))
            return
        if i in (3001, 3002, 3003, 3004, 3901, 3902, 3011, 3012):
            return
        if 1100 <= i <= 1135:
            self.outputs[i] = value
            return
        if 5221 <= i <= 5326:
            n, k = divmod(i - 5221, 20)
            if k < 6:
                axis = "xyzabc"[k]
                values = {"l": 2.0, "p": float(n + 1), axis: value or 0.0}
                ip.execute(Words(g={0: 100}, values=values))
                return
        if 2001 <= i <= 2400 or 10001 <= i <= 13400:
            self._set_offset(i, value or 0.0, loc)
            return
        if 2401 <= i <= 2800 and r.ex.fl.haas_g_codes:  # Haas: tool diameters
            n, lword = (i - 2400, 12.0) if i <= 2600 else (i - 2600, 13.0)
            radius = (value or 0.0) / 2.0
            offsets.g10(r.ex, {"L": lword, "P": float(n), "R": radius}, loc, True)
            return
        old = _old_work_offset(i)
        if old is not None and not r.ex.fl.haas_g_codes:
            self.write(old, value, loc)
            return
        if 7001 <= i <= 7946:
            n, k = divmod(i - 7001, 20)
            if k < 6:
                axis = "XYZABC"[k]
                offsets.extended_set(r.ex, n + 1, {axis: value or 0.0}, loc, True)
                return
        raise Diagnostic("FANUC-SYSTEM-VARIABLE", f"system variable #{i} cannot be set", loc)

    # ------------------------------------------------------------------ helpers
    def _modal(self, group: int) -> float | None:
        ex = self.r.ex
        s = ex.ip.s
        if group == 1:
            m = ex.group01
            return None if m is None else m / 10.0
        if group == 2:
            return _PLANE_CODE[s.plane]
        if group == 3:
            return 90.0 if s.absolute else 91.0
        if group == 5:
            return {0: 94.0, 1: 93.0, 2: 95.0}[s.feed_mode]
        if group == 6:
            return 20.0 if s.units is Units.INCHES else 21.0
        if group == 7:
            return s.comp_side / 10.0
        if group == 8:
            return 43.0 if s.tool_length_mode in (430, 431) else 49.0
        if group == 9:
            m = ex.motion
            return m / 10.0 if m is not None and m >= 730 else 80.0
        if group == 10:
            return 99.0 if s.retract_r else 98.0
        if group == 12:
            return 66.0 if ex.modal_call is not None else 67.0
        if group == 14:
            return 53.0 + s.origin_index
        if group == 15:
            return ex.control / 10.0
        if group == 16:
            return 68.0 if ex.tf.rotate_on else 69.0
        if group == 17:
            return 16.0 if ex.tf.polar else 15.0
        return 0.0

    def _modal_word(self, k: int) -> float | None:
        """#4102-#4130: the modal B D E F H M N O S T values and the G54.1 P number."""
        ex = self.r.ex
        s = ex.ip.s
        if k == 7:
            return ex.comp_d
        if k == 9:
            return s.feed_rate
        if k == 11:
            return ex.modal_h
        if k == 14:
            return float(self.r.current_seq or 0)
        if k == 15:
            return float(self.r.current_program)
        if k == 19:
            return s.speed
        if k == 20:
            return float(s.current_tool)
        if k == 30:
            return float(ex.extended_selected or 0)
        return None

    def _which(self, i: int) -> tuple[dict[int, list[float]], int, int]:
        ex = self.r.ex
        if i <= 2200:
            return ex.lengths, i - 2000, 0
        if i <= 2400:
            return ex.lengths, i - 2200, 1
        bank, n = divmod(i - 10000, 1000)
        table = ex.lengths if bank in (0, 1) else ex.radii
        return table, n, 1 if bank in (0, 2) else 0

    def _offset(self, i: int) -> float:
        table, n, slot = self._which(i)
        return table.get(n, [0.0, 0.0])[slot]

    def _set_offset(self, i: int, value: float, loc: Location) -> None:
        table, n, slot = self._which(i)
        lword = (10 + slot) if table is self.r.ex.lengths else (12 + slot)
        offsets.g10(self.r.ex, {"L": float(lword), "P": float(n), "R": value}, loc, True)


def _old_work_offset(i: int) -> int | None:
    """The #5201-#5326 number of an older series' work offset variable: ``#2500``-``#2506``
    X of the external offset and G54-G59, ``#2600`` Y, ``#2700`` Z, ``#2800`` the 4th axis."""
    axis, n = divmod(i - 2500, 100)
    if 2500 <= i <= 2806 and 0 <= axis <= 3 and n <= 6:
        return 5201 + 20 * n + axis
    return None
