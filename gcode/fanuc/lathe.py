"""Fanuc lathe mode (G code system A, book Table A.1; Fanuc 0i-TF manual).

X is a diameter (canonical x is the radius), ``U``/``W`` are incremental X/Z (U a diameter
increment), there is no G90/G91 distance mode: G90, G92 and G94 are the single-cut
turning, threading and facing cycles (modal), G70-G76 the multiple repetitive cycles
(expanded by :mod:`gcode.fanuc.turning.cycles`), G98/G99 feed per minute/per revolution (G99 at
power-on), G50 coordinate setting or ``G50 S`` spindle clamp, G32 thread cutting,
``T0101`` = turret position 01 with offset 01. The ZX plane (G18) is selected at start.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

from gcode.core import arcs
from gcode.core.codes import G_GROUPS, Words
from gcode.fanuc import haas_lathe_m, offsets
from gcode.fanuc.executor import _M_PASS, Executor, machine_events, ngc_m_code
from gcode.fanuc.state import Action
from gcode.fanuc.turning.cycles import ProfileStep, cycle_moves
from gcode.fanuc.turning.types import DEFAULT_SETTINGS
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Plane, Units

#: (P, Q, location) -> (line, words, G codes) of the contour blocks N P .. N Q
ContourBlocks = Callable[[int, int, Location], Iterator[tuple[int, dict[str, float], list[int]]]]

#: a cycle to run after the block's S, T and M words: name, words, contour, and the
#: sequence number after which the program goes on (G71-G73)
_Pending = tuple[str, dict[str, float], Sequence[ProfileStep], int | None]

_SINGLE = {900: "G90", 920: "G92", 940: "G94"}
_MULTI = {700: "G70", 710: "G71", 720: "G72", 730: "G73", 740: "G74", 750: "G75", 760: "G76"}
_PASS = frozenset({170, 180, 190, 200, 210, 280, 300, 400, 410, 420, 520, 530, 960, 970})
_PASS |= frozenset({540, 550, 560, 570, 580, 590, 640})
_OWN = frozenset({0, 10, 20, 30, 40, 90, 100, 320, 500, 610, 650, 660, 670, 980, 990})
_INC_PQ = frozenset({740, 750, 760})


class Lathe:
    """Lathe-mode state of one run."""

    def __init__(self, ex: Executor) -> None:
        self.ex = ex
        self.first: dict[int, dict[str, float]] = {}  # first blocks of two-block cycles
        self.single: dict[str, float] = {}  # modal words of G90/G92/G94
        #: set by the flow: (P, Q, loc) -> [(line, words)] of the contour blocks
        self.contour_blocks: ContourBlocks | None = None

    def start(self) -> None:
        ip = self.ex.ip
        s = ip.s
        s.diameter_mode = True
        s.plane = Plane.XZ
        ip.emit(canon.SelectPlane(Plane.XZ, source=ip.loc))
        s.feed_mode = canon.FeedMode.UNITS_PER_REVOLUTION
        ip.emit(canon.SetFeedMode(canon.FeedMode.UNITS_PER_REVOLUTION, source=ip.loc))

    # ------------------------------------------------------------------ one block
    def block(
        self,
        gs: list[int],
        ms: list[int],
        v: dict[str, float],
        cols: dict[str, int],
        raw: dict[str, int | float],
        loc: Location,
    ) -> list[Action]:
        ex = self.ex
        ip = ex.ip
        s = ip.s
        gset = set(gs)
        if 650 in gset:
            return [ex._g65(v, loc)]
        if 660 in gset:
            ex.modal_call = ex._g66(v, loc)
            return []
        if 670 in gset:
            ex.modal_call = None
        multi = next((c for c in gs if c in _MULTI), None)
        pending: _Pending | None = None
        if multi is not None:  # the cycle runs after the block's S, T and M words
            pending = self._multi(multi, v, raw, loc)
            v = {k: val for k, val in v.items() if k in "ST"}
            gs = [c for c in gs if c != multi]
            gset = set(gs)
        w = Words()
        for code in gs:
            if code in (980, 990):
                w.g[5] = 940 if code == 980 else 950
        for code in gs:
            if code in _PASS:
                w.g[_group(code)] = code
        if 610 in gset:
            w.g[13] = 611
        offsets.comp_reissued(ex, w, loc)
        if 100 in gset:
            ex._g10(v, loc, True)
            for letter in "XYZUWRPQL":
                v.pop(letter, None)
        if 40 in gset:
            w.g[0] = 40
            if not any(k in v for k in "XUP"):
                raise Diagnostic("FANUC-DWELL", "G04 without X, U or P", loc)
            w.values["p"] = v.pop("X", v.pop("U", v.pop("P", 0.0)))
        self._incremental(v, loc)
        if 500 in gset:
            if "S" in v and not any(a in v for a in "XZ"):
                ex._spindle_clamp(v.pop("S"), loc)
            elif any(a in v for a in "XZ"):
                w.g[0] = 920
                if "X" in v:
                    v["X"] /= 2.0  # the coordinate setting takes the radius
        motion = next((c for c in reversed(gs) if c in (0, 10, 20, 30, 320) or c in _SINGLE), None)
        if motion is not None:
            ex.motion = motion
            ex.group01 = motion
        has_axis = any(a in v for a in "XYZC")
        if "T" in v:
            self._turret(v.pop("T"), loc)
        for letter in "XYZCFSIKR":
            if letter in v:
                w.values[letter.lower()] = v[letter]
                w.columns[letter.lower()] = cols.get(letter, loc.column)
        machine: list[int] = []  # M codes the control hands to the machine (PLC)
        for m in ms:
            if m in (98, 99, 29) or (m == 97 and ex.fl.local_call):
                continue
            if ex.fl.haas_lathe and self._haas_m(m, loc):
                continue
            group = _M_PASS.get(m)
            if group is None:
                machine.append(m)
                continue
            w.m[group] = ngc_m_code(m, False)
        if machine:
            machine_events(ex, machine, gs, ms, v, w, cols, loc)
        run = motion if motion is not None else (ex.motion if has_axis else None)
        moving = has_axis and w.g.get(0) is None
        if run in _SINGLE and (motion is not None or moving):
            pending = self._single(_SINGLE[run], motion is not None, v, w)
            moving = False
        elif moving or motion is not None:
            if run == 320:
                w.g[1] = 330  # G32 F(lead): F is the lead and stays the modal F
                w.values["k"] = w.values.get("f", s.feed_rate)
            elif run is not None and moving:
                w.g[1] = run
        if 90 in gset:
            ip.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP, source=loc))
        ended = ip.execute(w) if (w.g or w.m or w.values) else False
        s.absolute = True
        s.motion_mode = None if ex.motion in _SINGLE else ex.motion
        if ended:
            return [Action("end")]
        actions = []
        if pending is not None:
            name, params, contour, skip = pending
            self.run_cycle(name, params, contour, loc)
            if skip is not None:
                actions.append(Action("skip", seq=skip))
        if ex.modal_call is not None and moving and ex.depth == ex.modal_call.depth:
            mc = ex.modal_call
            actions.append(Action("g65", mc.number, mc.repeats, dict(mc.args)))
        return actions + ex._flow_m(ms, v, loc)

    def _haas_m(self, m: int, loc: Location) -> bool:
        """A Haas lathe M code the manual documents (gcode/fanuc/haas_lathe_m.py): through-
        spindle coolant is the IR's own command (True: handled); a device function is named
        in a comment and left, like any code the control hands to the machine, to become a
        MACHINE_FUNCTION event (False), so a conversion writes the M code itself."""
        ip = self.ex.ip
        if m in haas_lathe_m.THROUGH_SPINDLE:
            on = haas_lathe_m.THROUGH_SPINDLE[m]
            ip.emit(canon.ThroughToolOn(source=loc) if on else canon.ThroughToolOff(source=loc))
            return True
        name = haas_lathe_m.MACHINE_FUNCTIONS.get(m)
        if name is not None:
            ip.emit(canon.Comment(f"M{m:02d}: {name}", source=loc))
        return False

    def _incremental(self, v: dict[str, float], loc: Location) -> None:
        s = self.ex.ip.s
        for inc, ab, i, k in (("U", "X", 0, 2.0), ("W", "Z", 2, 1.0)):
            if inc in v:
                if ab in v:
                    raise Diagnostic("FANUC-LATHE-AXES", f"{ab} and {inc} in one block", loc)
                v[ab] = s.pos[i] * k + v.pop(inc)

    def _turret(self, t: float, loc: Location) -> None:
        """T0101: turret position 01, offset 01 (the position is the tool number)."""
        ip = self.ex.ip
        n = int(round(t))
        tool = n // 100 if n >= 100 else n
        ip.emit(canon.SelectTool(tool, source=loc))
        ip.emit(canon.ChangeTool(tool, source=loc))
        ip.s.selected_tool = tool
        ip.s.current_tool = tool

    # ------------------------------------------------------------------ cycles
    def _single(self, name: str, new: bool, v: dict[str, float], w: Words) -> _Pending:
        """G90/G92/G94 (modal): the cycle's words, X Z R F kept for the next blocks."""
        if new:
            self.single = {}
        for letter in "XZRF":
            if letter in v:
                self.single[letter] = v[letter]
        w.values = {k: val for k, val in w.values.items() if k not in "xzrikf"}
        w.g.pop(1, None)
        return name, dict(self.single), (), None

    def _multi(
        self, code: int, v: dict[str, float], raw: dict[str, int | float], loc: Location
    ) -> _Pending | None:
        """G70-G76: None for a first block (kept), else the cycle to run and, for G71-G73,
        the sequence number after which the program goes on."""
        name = _MULTI[code]
        inch = self.ex.ip.s.units is Units.INCHES
        inc = 0.0001 if inch else 0.001
        if self.ex.fl.haas_lathe and code == 760 and ("K" in raw or "D" in raw):
            params = self._haas_thread(v, raw, loc)
            return name, params, [], None
        params = dict(v)
        for letter in "PQ":
            if letter in raw and type(raw[letter]) is int:
                if code in _INC_PQ and not (letter == "P" and code == 760 and self._first(code, v)):
                    params[letter] = raw[letter] * inc
                else:
                    params[letter] = float(raw[letter])
        if code == 730 and self._first(code, v) and "R" in raw:
            params["R"] = float(raw["R"])  # G73 R: division count
        if self.ex.fl.haas_lathe and code in (710, 720, 730) and not self._first(code, v):
            params.update(self._haas_one_block(code, params, raw, loc))
        if code != 700 and self._first(code, v):
            self.first[code] = {"1" + k: val for k, val in params.items() if k not in "ST"}
            return None
        params = {**self.first.pop(code, {}), **params}
        contour: list[ProfileStep] = []
        if code in (700, 710, 720, 730):
            if "P" not in params or "Q" not in params:
                raise Diagnostic("FANUC-CYCLE-PQ", f"{name} needs P and Q (contour)", loc)
            contour = self._contour(int(params["P"]), int(params["Q"]), loc)
            if self.ex.fl.haas_lathe and code in (710, 720):
                s = self.ex.ip.s
                contour = _without_retract(contour, (s.pos[0], s.pos[2]), code == 720)
        skip = int(params["Q"]) if code in (710, 720, 730) else None
        return name, {k: val for k, val in params.items() if k not in "ST"}, contour, skip

    def _haas_one_block(
        self, code: int, params: dict[str, float], raw: dict[str, int | float], loc: Location
    ) -> dict[str, float]:
        """Haas's one-block G71/G72 ``P Q U W D F`` (D: depth of cut, a radius) and G73
        ``P Q U W I K D F`` (I K: relief along X (radius) and Z, D: number of passes) as the
        first-block words of Fanuc's two-block form."""
        name = _MULTI[code]
        first: dict[str, float] = {}
        for letter in "IKDR":
            params.pop(letter, None)
        if code == 730:
            for src, dst in (("I", "1U"), ("K", "1W")):
                if src in raw:
                    first[dst] = _length(raw[src], self.ex.ip.s.units)
            if "D" in raw:
                first["1R"] = float(raw["D"])
            return first
        for letter in "IKR":
            if letter in raw:
                raise Diagnostic(
                    "HAAS-CYCLE-WORD",
                    f"{name} {letter}: the rough-pass allowance / type II form is not read",
                    loc,
                )
        if "D" in raw:
            first["1W" if code == 720 else "1U"] = _length(raw["D"], self.ex.ip.s.units)
        return first

    def _haas_thread(
        self, v: dict[str, float], raw: dict[str, int | float], loc: Location
    ) -> dict[str, float]:
        """Haas's one-block ``G76 X(U) Z(W) K D F [I A P Q]`` (lathe operator's manual,
        "G76 Threading Cycle, Multiple Pass") as the 0i-TF two-block words: K the thread
        height (P), D the first pass depth (Q), I the taper (R), all radius values; A the
        tool nose angle in the first-block P (0 when omitted: radial infeed), with the
        finishing passes and chamfer of ``CycleSettings``; P1 (single edge, constant
        cutting amount, the 0i-TF's way) is the only cutting method read; Q, the thread
        start angle, is a spindle phase the IR does not carry."""
        units = self.ex.ip.s.units
        method = raw.get("P", 1)
        if float(method) != 1.0:
            raise Diagnostic(
                "HAAS-CYCLE-WORD",
                f"G76 P{method:g}: only cutting method P1 (single edge, constant amount) is read",
                loc,
            )
        if "K" not in raw or "D" not in raw:
            raise Diagnostic("HAAS-CYCLE-WORD", "G76 needs both K (height) and D (first cut)", loc)
        params = {k: val for k, val in v.items() if k not in "KDIAPQ"}
        params["P"] = _length(raw["K"], units)
        params["Q"] = _length(raw["D"], units)
        if "I" in raw:
            params["R"] = _length(raw["I"], units)
        angle = float(raw.get("A", 0))
        cfg = DEFAULT_SETTINGS
        params["1P"] = float(cfg.thread_finish_passes * 10000 + cfg.thread_chamfer * 100 + angle)
        return {k: val for k, val in params.items() if k not in "ST"}

    @staticmethod
    def _first(code: int, v: dict[str, float]) -> bool:
        if code in (710, 720, 730):
            return not ("P" in v and "Q" in v)
        if code in (740, 750, 760):
            return not any(a in v for a in "XZUW")
        return False

    def _contour(self, p: int, q: int, loc: Location) -> list[ProfileStep]:
        s = self.ex.ip.s
        x, z = s.pos[0], s.pos[2]
        mode = 0
        steps = []
        assert self.contour_blocks is not None
        inch = s.units is Units.INCHES
        for line, v, gs in self.contour_blocks(p, q, loc):
            at = Location(loc.file, line, 1)
            for code in gs:
                if code in (0, 10, 20, 30):
                    mode = code
                elif code not in (400, 410, 420, 40, 90):
                    raise Diagnostic("FANUC-CYCLE-CONTOUR", f"G{code / 10:g} in a contour", at)
            nx = v["X"] / 2.0 if "X" in v else x + v.get("U", 0.0) / 2.0
            nz = v.get("Z", z + v.get("W", 0.0))
            feed = v.get("F")
            if not any(a in v for a in "XZUW"):
                x, z = nx, nz
                continue
            if mode in (20, 30):
                if "R" in v:
                    cz, cx = arcs.radius_format((z, x), (nz, nx), v["R"], mode == 20, at, inch)
                else:
                    cz, cx = z + v.get("K", 0.0), x + v.get("I", 0.0)
                kind = "cw" if mode == 20 else "ccw"
                steps.append(ProfileStep(kind, nx, nz, cx, cz, feed, line))
            else:
                kind = "rapid" if mode == 0 else "line"
                steps.append(ProfileStep(kind, nx, nz, feed=feed, line=line))
            x, z = nx, nz
        return steps

    def run_cycle(
        self, name: str, params: dict[str, float], contour: Sequence[ProfileStep], loc: Location
    ) -> None:
        ip = self.ex.ip
        s = ip.s
        ip.comp_off("turning cycle")
        start = (s.pos[0], s.pos[2])
        if "F" in params and params["F"] != s.feed_rate:  # F is modal: set before the cycle
            s.feed_rate = params["F"]
            ip.emit(canon.SetFeedRate(s.feed_rate, source=loc))
        moves = cycle_moves(
            name, start, params, contour, diameter=True, line=loc.line, path=loc.file or ""
        )
        for m in moves:
            if m.feed is not None and m.feed != s.feed_rate:
                s.feed_rate = m.feed
                ip.emit(canon.SetFeedRate(m.feed, source=loc))
            y, a, b, c = s.pos[1], s.pos[3], s.pos[4], s.pos[5]
            if m.kind == "dwell":
                ip.emit(canon.Dwell(m.seconds, source=loc))
                continue
            if m.kind == "rapid":
                ip.emit(canon.StraightTraverse(m.x, y, m.z, a, b, c, source=loc))
            elif m.kind == "feed":
                ip.emit(canon.StraightFeed(m.x, y, m.z, a, b, c, source=loc))
            elif m.kind in ("cw", "ccw"):
                turn = -1 if m.kind == "cw" else 1
                ip.emit(canon.ArcFeed(m.z, m.x, m.cz, m.cx, turn, y, a, b, c, source=loc))
            elif m.kind == "thread":
                ip.emit(canon.StartSpeedFeedSynch(m.lead, False, source=loc))
                ip.emit(canon.StraightFeed(m.x, y, m.z, a, b, c, source=loc))
                ip.emit(canon.StopSpeedFeedSynch(source=loc))
            else:
                raise Diagnostic("FANUC-CYCLE-MOVE", f"{name}: unknown move {m.kind}", loc)
            s.pos = [m.x, y, m.z, a, b, c]


def _without_retract(
    steps: list[ProfileStep], start: tuple[float, float], facing: bool
) -> list[ProfileStep]:
    """A Haas G71 contour without the retract many Haas programs end it with: trailing
    blocks moving along Z only (G72: along X only), back towards the start point, outside
    the rest of the finished shape (``N20 G00 G40 Z0.1`` after the last diameter). They run
    along the stock, remove nothing, and stay in the G70 finishing path (the Haas lathe
    manual's G71 examples close the contour on the stock; its roughing ignores such a
    return, which the 0i-TF's monotonic type I check would refuse)."""
    along, across = (0, 1) if facing else (1, 0)  # index into (x, z): the cut's direction
    out = list(steps)
    while len(out) > 1:
        last, before = out[-1], out[-2]
        last_p, before_p = (last.x, last.z), (before.x, before.z)
        if last.kind not in ("rapid", "line") or abs(last_p[across] - before_p[across]) > 1e-9:
            break
        toward = abs(last_p[along] - start[along]) < abs(before_p[along] - start[along])
        rest = [(st.x, st.z)[across] for st in out[:-1]]
        outside = start[across] >= max(rest) - 1e-9 and last_p[across] >= max(rest) - 1e-9
        inside = start[across] <= min(rest) + 1e-9 and last_p[across] <= min(rest) + 1e-9
        if not toward or not (outside or inside):
            break
        out.pop()
    return out


def _length(value: int | float, units: Units) -> float:
    """A length word: without a decimal point it counts least input increments."""
    if type(value) is int:
        return value * (0.0001 if units is Units.INCHES else 0.001)
    return float(value)


def _group(code: int) -> int:
    return G_GROUPS[code]
