"""Standard cycles of the 840D expanded into moves (SINUMERIK 840D sl / 828D cycles
programming manual: the parameter list and the "sequence of motions" of each cycle).

The drilling cycles work at the current position along the applicate (the axis normal to
the active plane: Z in G17, Y in G18, X in G19; ``_AXN`` 1/2/3 names X/Y/Z instead). They
share ``RTP`` (retraction plane), ``RFP`` (reference plane), ``SDIS`` (safety distance, no
sign) and the final depth ``DP`` (absolute) or ``DPR`` (below RFP, no sign; DPR wins when
given). All begin with G0 to ``RFP + SDIS`` and end at ``RTP``:

* ``CYCLE81(RTP, RFP, SDIS, DP, DPR)``: G1 to the depth at the feed in force, G0 to RTP.
* ``CYCLE82(..., DTB)``: as CYCLE81 with a dwell of DTB s at depth.
* ``CYCLE83(..., FDEP, FDPR, DAM, DTB, DTS, FRF, VARI, _AXN, _MDEP, _VRT, _DTD, _DIS1)``:
  deep-hole drilling in strokes (see :func:`strokes`); the first at FRF x F, the others at
  F; DTB dwells at each intermediate depth, _DTD (DTB when 0) at the final one. VARI=0
  (chip breaking): G1 back by _VRT (1 mm when 0) before each next stroke. VARI=1 (swarf
  removal): G0 out to RFP + SDIS, dwell DTS, G0 in to the depth reached plus the
  anticipation distance _DIS1 (when 0: 0.6 mm up to 30 mm of hole depth, else depth / 50,
  at most 7 mm).
* ``CYCLE85(..., DTB, FFR, RFF)``: G1 in at FFR, dwell, G1 out to RFP + SDIS at RFF.
* ``CYCLE86(..., DTB, SDIR, RPA, RPO, RPAP, POSS)``: spindle SDIR (3/4), G1 in, dwell,
  oriented stop at POSS, G0 off the wall by RPA/RPO/RPAP (incremental, plane and
  applicate), G0 to RFP + SDIS, G0 back over the hole at RTP, spindle SDIR again.
* ``CYCLE87(..., SDIR)`` and ``CYCLE88(..., DTB, SDIR)``: spindle SDIR, G1 in, (88: dwell),
  M5 and M0 (the operator), G0 to RTP.
* ``CYCLE89(..., DTB)``: G1 in, dwell, G1 out to RFP + SDIS at the same feed.
* ``CYCLE84(..., DTB, SDAC, MPIT, PIT, POSS, SST, SST1, _AXN, _PTAB, _TECHNO, _VARI, _DAM,
  _VRT)``: rigid tapping (RIGID_TAP, or synchronised strokes), see :meth:`Drill._cycle84`.
* ``CYCLE840(..., DTB, SDR, SDAC, ENC, MPIT, PIT, ...)``: tapping with compensating chuck.

The cycles' own feeds (FRF, FFR, RFF) hold inside the cycle: the feed in force before it
is programmed again at its end. Dwells given negative are spindle revolutions.

Position patterns run the cycle selected with ``MCALL`` at each position (G0 to it in the
plane at the height where the tool is): ``HOLES1(SPCA, SPCO, STA1, FDIS, DBH, NUM)`` a row
from its nearer end, ``HOLES2(CPA, CPO, RAD, STA1, INDA, NUM)`` a circle (INDA 0: 360 /
NUM), ``CYCLE801(_SPCA, _SPCO, _STA, _DIS1, _DIS2, _NUM1, _NUM2)`` a grid, row by row in a
meander. Without MCALL they only position.

``CYCLE832`` and an unswivelled ``CYCLE800`` are settings without moves; any other swivel,
and every other cycle, is refused (SIEM-CYCLE-UNSUPPORTED) naming the cycle and, where one
parameter is the reason, that parameter.
"""

from __future__ import annotations

import math

from gcode.siemens import motion
from gcode.siemens.expr import Node, Variables, evaluate
from gcode.siemens.machine import Machine, Values
from gcode.siemens.state import PLANES
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

#: the 840D standard cycles whose names do not begin with CYCLE (cycles manual: drilling
#: patterns HOLES1, HOLES2; milling patterns LONGHOLE, SLOT1, SLOT2, POCKET1 to POCKET4):
#: called without a program file of that name they are the control's cycles, not missing
#: subprograms
STANDARD_CYCLES = frozenset(
    ("HOLES1", "HOLES2", "LONGHOLE", "SLOT1", "SLOT2", "POCKET1", "POCKET2", "POCKET3", "POCKET4")
)
_DRILL = ("RTP", "RFP", "SDIS", "DP", "DPR")
#: the parameters the later cycle versions add (geometry, display and alternative modes)
_MODES = ("_GMODE", "_DMODE", "_AMODE")
#: cycle -> its parameters, in call order
PARAMETERS: dict[str, tuple[str, ...]] = {
    "CYCLE81": (*_DRILL, *_MODES),
    "CYCLE82": (*_DRILL, "DTB", *_MODES),
    "CYCLE83": (
        *_DRILL,
        *("FDEP", "FDPR", "DAM", "DTB", "DTS", "FRF", "VARI", "_AXN", "_MDEP", "_VRT"),
        *("_DTD", "_DIS1", *_MODES),
    ),
    "CYCLE84": (
        *_DRILL,
        *("DTB", "SDAC", "MPIT", "PIT", "POSS", "SST", "SST1", "_AXN", "_PTAB", "_TECHNO"),
        *("_VARI", "_DAM", "_VRT"),
    ),
    "CYCLE840": (
        *_DRILL,
        *("DTB", "SDR", "SDAC", "ENC", "MPIT", "PIT", "_AXN", "_PTAB", "_TECHNO"),
    ),
    "CYCLE85": (*_DRILL, "DTB", "FFR", "RFF", *_MODES),
    "CYCLE86": (*_DRILL, "DTB", "SDIR", "RPA", "RPO", "RPAP", "POSS", *_MODES),
    "CYCLE87": (*_DRILL, "SDIR"),
    "CYCLE88": (*_DRILL, "DTB", "SDIR"),
    "CYCLE89": (*_DRILL, "DTB"),
    "HOLES1": ("SPCA", "SPCO", "STA1", "FDIS", "DBH", "NUM"),
    "HOLES2": ("CPA", "CPO", "RAD", "STA1", "INDA", "NUM"),
    "CYCLE801": ("_SPCA", "_SPCO", "_STA", "_DIS1", "_DIS2", "_NUM1", "_NUM2"),
}
#: the position patterns: they run the modally called cycle at each position
PATTERNS = frozenset(("HOLES1", "HOLES2", "CYCLE801"))
#: most strokes one CYCLE83 may make (a far smaller first depth than the hole is a mistake)
MAX_STROKES = 10_000
MM = 25.4  # mm per inch
#: metric coarse threads M3 to M48 (ISO 261): size -> pitch in mm, CYCLE84/840's MPIT
COARSE = {
    3: 0.5, 4: 0.7, 5: 0.8, 6: 1.0, 8: 1.25, 10: 1.5, 12: 1.75, 14: 2.0, 16: 2.0, 18: 2.5,
    20: 2.5, 22: 2.5, 24: 3.0, 27: 3.0, 30: 3.5, 33: 3.5, 36: 4.0, 39: 4.0, 42: 4.5,
    45: 4.5, 48: 5.0,
}  # fmt: skip


def check_cycle(ex: Machine, name: str, args: tuple[Node | None, ...]) -> None:
    """Refuse a cycle this reader does not expand, or one given too many parameters."""
    if name not in PARAMETERS:
        raise Diagnostic(
            "SIEM-CYCLE-UNSUPPORTED",
            f"{name} is not expanded by this reader (CYCLE81-CYCLE89, CYCLE840, HOLES1, "
            "HOLES2, CYCLE801 are)",
            ex.loc,
        )
    if len(args) > len(PARAMETERS[name]):
        raise Diagnostic(
            "SIEM-CYCLE-ARGS", f"{name} takes at most {len(PARAMETERS[name])} parameters", ex.loc
        )


def _number(node: Node | None, scope: Variables) -> float:
    return 0.0 if node is None else evaluate(node, scope)


def setting_cycle(ex: Machine, name: str, args: tuple, scope: Variables) -> bool:
    """Run CYCLE832 or a CYCLE800 to the unswivelled plane (True), else False."""
    if name == "CYCLE832":
        tol = _number(args[0] if args else None, scope)
        if tol < 0:
            raise Diagnostic("SIEM-CYCLE-ARGS", "CYCLE832: negative tolerance", ex.loc)
        ex.s.control = 642 if tol > 0 else 60
        mode = canon.MotionMode.CONTINUOUS if tol > 0 else canon.MotionMode.EXACT_STOP
        ex.emit(canon.SetMotionControlMode(mode, tol, source=ex.loc))
        return True
    if name == "CYCLE800" and any(a is not None for a in args) and len(args) < 13:
        return False  # neither "swivel off" nor a swivel stating its offsets and angles
    if name == "CYCLE800":
        swivel = [_number(node, scope) for node in args[4:13]]
        if any(abs(value) > 1e-12 for value in swivel):
            raise Diagnostic(
                "SIEM-CYCLE-UNSUPPORTED",
                "CYCLE800 swivelling the work plane (offsets or angles not 0) is not read: "
                "the IR has no swivelled plane",
                ex.loc,
            )
        return True
    return False


def _args(ex: Machine, name: str, args: tuple, scope: Variables) -> dict[str, float]:
    """The cycle's parameters by name; an omitted one is 0."""
    check_cycle(ex, name, args)
    p = dict.fromkeys(PARAMETERS[name], 0.0)
    for key, node in zip(PARAMETERS[name], args, strict=False):
        if node is not None:
            p[key] = evaluate(node, scope)
    return p


def _bad(ex: Machine, name: str, text: str) -> Diagnostic:
    return Diagnostic("SIEM-CYCLE-ARGS", f"{name}: {text}", ex.loc)


def run_cycle(ex: Machine, name: str, args: tuple, scope: Variables) -> None:
    """Expand one cycle (drilling at the current position, or a position pattern)."""
    if setting_cycle(ex, name, args, scope):
        return
    p = _args(ex, name, args, scope)
    if name in PATTERNS:
        _pattern(ex, name, p, scope)
        return
    Drill(ex, name, p).run()


class Drill:
    """One drilling cycle at the current position: its planes along the drilling axis."""

    def __init__(self, ex: Machine, name: str, p: dict[str, float]) -> None:
        self.ex, self.name, self.p = ex, name, p
        if p["SDIS"] < 0 or p["DPR"] < 0 or (name == "CYCLE82" and p["DTB"] < 0):
            raise _bad(ex, name, "SDIS, DPR and DTB are given without sign")
        self.depth = p["RFP"] - p["DPR"] if p["DPR"] else p["DP"]
        self.top = p["RFP"] + p["SDIS"]
        if not self.depth < self.top <= p["RTP"]:
            raise _bad(
                ex,
                name,
                f"the depth must lie below RFP + SDIS ({self.top:g}) and RTP not below it",
            )
        axn = p.get("_AXN", 0.0)
        if axn not in (0.0, 1.0, 2.0, 3.0):
            raise Diagnostic(
                "SIEM-CYCLE-UNSUPPORTED",
                f"{name} _AXN={axn:g}: the tool axis is 1, 2 or 3 (X, Y, Z) or 0 (the plane's)",
                ex.loc,
            )
        index = int(axn) - 1 if axn else PLANES[ex.s.plane][1][2]
        self.axis = "XYZ"[index]
        self.inch = ex.s.units is canon.Units.INCHES
        if "_AMODE" in p:
            self.modes()

    def modes(self) -> None:
        """The later cycle versions' ``_GMODE, _DMODE, _AMODE`` (CAM posts write them, e.g.
        Fusion 360's 840D post ``..., 0, 0, 1001110)``). _GMODE 0 (drill to the tip) and
        _DMODE 0 (the programmed plane) are the compatible readings, and are read. An
        _AMODE digit chooses how one parameter is read: 0 compatible, 1 absolute depth,
        value, seconds (the post's choice for its absolute DP and FDEP). With digits 0 and 1
        and a call that gives no relative depth (DPR, FDPR), no degression factor and no
        dwell in revolutions, every reading is the compatible one; anything else is
        refused naming the parameter."""
        p, ex, name = self.p, self.ex, self.name
        for key in ("_GMODE", "_DMODE"):
            if p[key]:
                raise Diagnostic(
                    "SIEM-CYCLE-UNSUPPORTED",
                    f"{name} {key}={p[key]:g}: only 0 (drilling to the tip in the programmed "
                    "plane) is read",
                    ex.loc,
                )
        amode = p["_AMODE"]
        if not amode:
            return
        digits = f"{amode:.0f}"
        signed = [p.get(k, 0.0) for k in ("DAM", "DTB", "DTS", "_DTD")]
        if (
            amode != int(amode)
            or amode < 0
            or set(digits) - {"0", "1"}
            or p["DPR"]
            or p.get("FDPR", 0.0)
            or min(signed) < 0
        ):
            raise Diagnostic(
                "SIEM-CYCLE-UNSUPPORTED",
                f"{name} _AMODE={amode:g}: alternative parameter readings (digits 2, or with "
                "DPR/FDPR, a degression factor or dwells in revolutions) are not read",
                ex.loc,
            )

    def run(self) -> None:
        s = self.ex.s
        saved = (s.motion, s.absolute)
        s.absolute = True
        try:
            getattr(self, "_" + self.name.lower())()
        finally:
            s.motion, s.absolute = saved

    # ------------------------------------------------------------------ steps
    def move(self, code: int, value: float) -> None:
        """G0/G1 of the drilling axis to ``value`` (absolute, program coordinates)."""
        self.ex.s.motion = code
        motion.execute(self.ex, Values(v={self.axis: value}), False)

    def rapid_plane(self, a: float, b: float, c: float) -> None:
        """G0 to (a, b) in the plane and c along the drilling axis together."""
        first, second, _ = PLANES[self.ex.s.plane][1]
        v = {"XYZ"[first]: a, "XYZ"[second]: b, self.axis: c}
        self.ex.s.motion = 0
        motion.execute(self.ex, Values(v=v), False)

    def feed(self, rate: float) -> None:
        s = self.ex.s
        if rate != s.feed:
            s.feed = rate
            self.ex.emit(canon.SetFeedRate(rate, source=self.ex.loc))

    def dwell(self, value: float, key: str) -> None:
        """A dwell of ``value`` s (negative: revolutions at the speed in force); 0: none."""
        if value == 0:
            return
        seconds = value
        if value < 0:
            if self.ex.s.speed <= 0:
                raise _bad(self.ex, self.name, f"{key} in revolutions with spindle speed S0")
            seconds = -value * 60.0 / self.ex.s.speed
        self.ex.emit(canon.Dwell(seconds, source=self.ex.loc))

    def spindle(self, key: str) -> None:
        """Start the spindle as SDIR says (3: M3, 4: M4)."""
        code = self.p[key]
        if code not in (3.0, 4.0):
            raise _bad(self.ex, self.name, f"{key}={code:g}: the spindle direction is 3 or 4")
        self.turn(code)

    def turn(self, code: float) -> None:
        """M3, M4 or M5 (``code`` 3, 4, 5)."""
        s, loc = self.ex.s, self.ex.loc
        if code == 3:
            s.direction = canon.Direction.CLOCKWISE
            self.ex.emit(canon.StartSpindleClockwise(source=loc))
        elif code == 4:
            s.direction = canon.Direction.COUNTERCLOCKWISE
            self.ex.emit(canon.StartSpindleCounterclockwise(source=loc))
        else:
            self.stop_spindle()

    def stop_spindle(self) -> None:
        self.ex.s.direction = canon.Direction.STOPPED
        self.ex.emit(canon.StopSpindleTurning(source=self.ex.loc))

    def mm(self, value: float) -> float:
        """A length the manual gives in mm, in the program's units."""
        return value / MM if self.inch else value

    # ------------------------------------------------------------------ cycles
    def _cycle81(self) -> None:
        self.move(0, self.top)
        self.move(1, self.depth)
        self.move(0, self.p["RTP"])

    def _cycle82(self) -> None:
        self.move(0, self.top)
        self.move(1, self.depth)
        self.ex.emit(canon.Dwell(self.p["DTB"], source=self.ex.loc))
        self.move(0, self.p["RTP"])

    def _cycle83(self) -> None:
        p, ex = self.p, self.ex
        if p["VARI"] not in (0.0, 1.0):
            raise _bad(ex, "CYCLE83", f"VARI={p['VARI']:g}: 0 (chip breaking) or 1 (swarf removal)")
        frf = p["FRF"] or 1.0
        if not 0.001 <= frf <= 1.0:
            raise _bad(ex, "CYCLE83", f"FRF={frf:g}: the feed factor lies in 0.001..1")
        if min(p["FDPR"], p["DTS"], p["_VRT"], p["_DIS1"], p["_MDEP"]) < 0:
            raise _bad(ex, "CYCLE83", "FDPR, DTS, _MDEP, _VRT and _DIS1 are given without sign")
        levels = self.strokes()
        feed = ex.s.feed
        self.move(0, self.top)
        self.feed(feed * frf)
        self.move(1, levels[0])
        self.feed(feed)
        vrt = p["_VRT"] or self.mm(1.0)
        hole = (p["RFP"] - self.depth) * (MM if self.inch else 1.0)
        ahead = p["_DIS1"] or self.mm(0.6 if hole <= 30 else min(hole / 50, 7.0))
        for reached, level in zip(levels, levels[1:], strict=False):
            self.dwell(p["DTB"], "DTB")
            if p["VARI"] == 0:
                self.move(1, min(reached + vrt, self.top))
            else:
                self.move(0, self.top)
                self.dwell(p["DTS"], "DTS")
                self.move(0, min(reached + ahead, self.top))
            self.move(1, level)
        self.dwell(p["_DTD"] or p["DTB"], "_DTD")
        self.move(0, p["RTP"])

    def strokes(self) -> list[float]:
        """CYCLE83's intermediate depths (manual, "FDEP, FDPR and DAM"): the first depth
        (FDPR below RFP, else FDEP) unless the hole is shallower; then each stroke is the
        last minus DAM while that exceeds DAM, then DAM while more than twice DAM remains,
        and the last two share the rest equally. DAM 0: equal strokes; DAM < 0: a factor
        on the last stroke, not below _MDEP."""
        p, name = self.p, "CYCLE83"
        first = p["RFP"] - p["FDPR"] if p["FDPR"] else p["FDEP"]
        if not first < p["RFP"]:
            raise _bad(
                self.ex, name, f"the first depth ({first:g}) must lie below RFP (alarm 61107)"
            )
        dam = p["DAM"]
        if dam < 0 and not (-1.0 <= dam <= -0.001 and p["_MDEP"] > 0):
            raise _bad(
                self.ex, name, "a degression factor (DAM < 0) lies in -1..-0.001 with _MDEP > 0"
            )
        level = max(first, self.depth)
        levels = [level]
        last = p["RFP"] - level
        while level > self.depth:
            rest = level - self.depth
            if dam < 0:
                stroke = max(last * -dam, p["_MDEP"])
            elif dam == 0 or last - dam > dam:
                stroke = last - dam
            elif rest > 2 * dam:
                stroke = dam
            elif rest > dam:
                stroke = rest / 2
            else:
                stroke = rest
            stroke = min(stroke, rest)
            level = self.depth if rest - stroke < 1e-9 else level - stroke
            levels.append(level)
            last = stroke
            if len(levels) > MAX_STROKES:
                raise _bad(self.ex, name, f"more than {MAX_STROKES} strokes to the depth")
        return levels

    def pitch(self) -> float:
        """The thread's lead in program units, signed (negative: left hand, M4) from MPIT
        (metric coarse size) or PIT (in the unit _PTAB says: 0 the program's, 1 mm,
        2 threads per inch, 3 inch per revolution); both given must agree (alarm 61001)."""
        p, ex, name = self.p, self.ex, self.name
        value = 0.0
        if p["PIT"]:
            unit = p["_PTAB"]
            if unit == 0.0:
                value = p["PIT"] * (MM if self.inch else 1.0)
            elif unit == 1.0:
                value = p["PIT"]
            elif unit == 2.0:  # threads per inch: the lead is the inverse
                value = MM / p["PIT"]
            elif unit == 3.0:
                value = p["PIT"] * MM
            else:
                raise _bad(ex, name, f"_PTAB={unit:g}: the pitch unit is 0, 1, 2 or 3")
        if p["MPIT"]:
            size = abs(p["MPIT"])
            if size not in COARSE:
                raise _bad(ex, name, f"MPIT={p['MPIT']:g}: not a metric coarse thread M3..M48")
            coarse = COARSE[int(size)] * (1 if p["MPIT"] > 0 else -1)
            if value and abs(value - coarse) > 1e-6:
                raise _bad(ex, name, "MPIT and PIT give different pitches (alarm 61001)")
            value = coarse
        if not value:
            raise _bad(ex, name, "no thread pitch (MPIT or PIT)")
        return value / MM if self.inch else value

    def synchronised(self, value: float, lead: float) -> None:
        """Spindle-synchronised feed along the drilling axis (as the reader's G33)."""
        ex = self.ex
        _, _, end = motion.ends(ex, Values(v={self.axis: value}))
        ex.emit(canon.StartSpeedFeedSynch(lead, False, source=ex.loc))
        ex.emit(canon.StraightFeed(*end, source=ex.loc))
        ex.emit(canon.StopSpeedFeedSynch(source=ex.loc))
        ex.s.pos = end

    def speed(self, rpm: float) -> None:
        s = self.ex.s
        if rpm != s.speed:
            s.speed = rpm
            self.ex.emit(canon.SetSpindleSpeed(rpm, source=self.ex.loc))

    def _cycle84(self) -> None:
        """Rigid tapping: G0 to RFP + SDIS, oriented stop at POSS (the spindle becomes an
        axis), tap to the depth at speed SST, dwell DTB, back to RFP + SDIS reversed at
        SST1, G0 to RTP, then the speed of before in the direction SDAC. Without dwell and
        at one speed the tap is the IR's RIGID_TAP (as G33.1); else synchronised in and out.
        _VARI 1 (chip breaking) / 2 (swarf removal) tap in strokes of _DAM: after each
        intermediate depth the spindle reverses and the tap comes back by _VRT (0: 1 mm) /
        to RFP + SDIS, synchronised, and reverses again to go on."""
        p, ex = self.p, self.ex
        if p["_VARI"] not in (0.0, 1.0, 2.0):
            raise _bad(ex, "CYCLE84", f"_VARI={p['_VARI']:g}: 0, 1 or 2")
        if p["_VARI"] and p["_DAM"] <= 0:
            raise _bad(ex, "CYCLE84", "tapping in strokes (_VARI 1, 2) needs _DAM above 0")
        if p["_VRT"] < 0:
            raise _bad(ex, "CYCLE84", "_VRT is given without sign")
        if p["SDAC"] not in (3.0, 4.0, 5.0):
            raise _bad(ex, "CYCLE84", f"SDAC={p['SDAC']:g}: the direction after is 3, 4 or 5")
        if not 0.0 <= p["POSS"] < 360.0:
            raise _bad(ex, "CYCLE84", f"POSS={p['POSS']:g} must be within 0..360 degrees")
        lead = self.pitch()
        before = ex.s.speed
        tap = p["SST"] or before
        if tap <= 0:
            raise _bad(ex, "CYCLE84", "no tapping speed (SST and S are 0)")
        out = p["SST1"] or tap
        forward, backward = (3.0, 4.0) if lead > 0 else (4.0, 3.0)
        levels = [self.depth]
        if p["_VARI"]:
            count = math.ceil((self.top - self.depth) / p["_DAM"] - 1e-9)
            if count > MAX_STROKES:
                raise _bad(ex, "CYCLE84", f"more than {MAX_STROKES} strokes to the depth")
            levels = [max(self.top - i * p["_DAM"], self.depth) for i in range(1, count + 1)]
        self.move(0, self.top)
        ex.s.direction = canon.Direction.STOPPED
        ex.emit(canon.OrientSpindle(p["POSS"], canon.Direction.CLOCKWISE, source=ex.loc))
        self.speed(tap)
        self.turn(forward)
        if p["DTB"] == 0 and out == tap and not p["_VARI"]:
            _, _, end = motion.ends(ex, Values(v={self.axis: self.depth}))
            ex.emit(canon.StartSpeedFeedSynch(abs(lead), False, source=ex.loc))
            ex.emit(canon.RigidTap(end[0], end[1], end[2], source=ex.loc))
            ex.emit(canon.StopSpeedFeedSynch(source=ex.loc))
        else:
            back = p["_VRT"] or self.mm(1.0)
            for level in levels[:-1]:
                self.synchronised(level, abs(lead))
                self.turn(backward)
                self.synchronised(
                    min(level + back, self.top) if p["_VARI"] == 1 else self.top, abs(lead)
                )
                self.turn(forward)
            self.synchronised(self.depth, abs(lead))
            self.dwell(p["DTB"], "DTB")
            self.speed(out)
            self.turn(backward)
            self.synchronised(self.top, abs(lead))
        self.move(0, p["RTP"])
        self.speed(before)
        self.turn(p["SDAC"])

    def _cycle840(self) -> None:
        """Tapping with compensating chuck: G0 to RFP + SDIS; in to the depth, with the
        encoder (ENC 0) synchronised to the spindle at the pitch (G33), without (ENC 1) at
        the feed in force (G63); dwell DTB; the spindle reversed (SDR 0: the other way
        than it turns, else 3/4); out the same way to RFP + SDIS; G0 to RTP; spindle SDAC."""
        p, ex = self.p, self.ex
        if p["ENC"] not in (0.0, 1.0):
            raise Diagnostic(
                "SIEM-CYCLE-UNSUPPORTED",
                f"CYCLE840 ENC={p['ENC']:g}: only 0 (with encoder) and 1 (without) are read",
                ex.loc,
            )
        if p["SDAC"] not in (3.0, 4.0, 5.0):
            raise _bad(ex, "CYCLE840", f"SDAC={p['SDAC']:g}: the direction after is 3, 4 or 5")
        if p["SDR"] not in (0.0, 3.0, 4.0):
            raise _bad(ex, "CYCLE840", f"SDR={p['SDR']:g}: the reversal is 0, 3 or 4")
        turning = ex.s.direction
        if turning is canon.Direction.STOPPED:
            raise _bad(ex, "CYCLE840", "the spindle must turn (M3/M4) before tapping")
        back = p["SDR"] or (4.0 if turning is canon.Direction.CLOCKWISE else 3.0)
        self.move(0, self.top)
        if p["ENC"] == 0:
            lead = abs(self.pitch())
            self.synchronised(self.depth, lead)
            self.dwell(p["DTB"], "DTB")
            self.turn(back)
            self.synchronised(self.top, lead)
        else:
            self.move(1, self.depth)
            self.dwell(p["DTB"], "DTB")
            self.turn(back)
            self.move(1, self.top)
        self.move(0, p["RTP"])
        self.turn(p["SDAC"])

    def _cycle85(self) -> None:
        p, ex = self.p, self.ex
        if p["FFR"] <= 0 or p["RFF"] <= 0:
            raise _bad(ex, "CYCLE85", "FFR and RFF (the feeds in and out) must be above 0")
        feed = ex.s.feed
        self.move(0, self.top)
        self.feed(p["FFR"])
        self.move(1, self.depth)
        self.dwell(p["DTB"], "DTB")
        self.feed(p["RFF"])
        self.move(1, self.top)
        self.move(0, p["RTP"])
        self.feed(feed)

    def _cycle86(self) -> None:
        p, ex = self.p, self.ex
        position = motion.program_position(ex)
        first, second, _ = PLANES[ex.s.plane][1]
        if not 0.0 <= p["POSS"] < 360.0:
            raise _bad(ex, "CYCLE86", f"POSS={p['POSS']:g} must be within 0..360 degrees")
        self.move(0, self.top)
        self.spindle("SDIR")
        self.move(1, self.depth)
        self.dwell(p["DTB"], "DTB")
        ex.s.direction = canon.Direction.STOPPED
        ex.emit(canon.OrientSpindle(p["POSS"], canon.Direction.CLOCKWISE, source=ex.loc))
        a, b = position[first], position[second]
        self.rapid_plane(a + p["RPA"], b + p["RPO"], self.depth + p["RPAP"])
        self.move(0, self.top)
        self.rapid_plane(a, b, p["RTP"])
        self.spindle("SDIR")

    def _cycle87(self) -> None:
        self.move(0, self.top)
        self.spindle("SDIR")
        self.move(1, self.depth)
        self._operator()

    def _cycle88(self) -> None:
        self.move(0, self.top)
        self.spindle("SDIR")
        self.move(1, self.depth)
        self.dwell(self.p["DTB"], "DTB")
        self._operator()

    def _operator(self) -> None:
        """M5 and M0 at depth (the operator takes the tool out), then G0 to RTP."""
        self.stop_spindle()
        self.ex.emit(canon.ProgramStop(source=self.ex.loc))
        self.move(0, self.p["RTP"])

    def _cycle89(self) -> None:
        self.move(0, self.top)
        self.move(1, self.depth)
        self.dwell(self.p["DTB"], "DTB")
        self.move(1, self.top)
        self.move(0, self.p["RTP"])


def positions(ex: Machine, name: str, p: dict[str, float]) -> list[tuple[float, float]]:
    """The pattern's positions in the active plane, in the order they are machined."""
    count = p["_NUM1"] * p["_NUM2"] if name == "CYCLE801" else p["NUM"]
    for key in ("NUM", "_NUM1", "_NUM2"):
        value = p.get(key, 1.0)
        if value < 1 or value != int(value):
            raise _bad(ex, name, f"{key}={value:g}: the number of positions is a whole number >= 1")
    if count > MAX_STROKES:
        raise _bad(ex, name, f"more than {MAX_STROKES} positions")
    if name == "HOLES1":
        rad = math.radians(p["STA1"])
        row = [
            (
                p["SPCA"] + (p["FDIS"] + i * p["DBH"]) * math.cos(rad),
                p["SPCO"] + (p["FDIS"] + i * p["DBH"]) * math.sin(rad),
            )
            for i in range(int(count))
        ]
        first, second, _ = PLANES[ex.s.plane][1]
        here = motion.program_position(ex)
        at = (here[first], here[second])
        return row[::-1] if math.dist(at, row[-1]) < math.dist(at, row[0]) else row
    if name == "HOLES2":
        if p["RAD"] <= 0:
            raise _bad(ex, name, f"RAD={p['RAD']:g}: the circle's radius must be above 0")
        step = p["INDA"] or 360.0 / count
        return [
            (
                p["CPA"] + p["RAD"] * math.cos(math.radians(p["STA1"] + i * step)),
                p["CPO"] + p["RAD"] * math.sin(math.radians(p["STA1"] + i * step)),
            )
            for i in range(int(count))
        ]
    rad = math.radians(p["_STA"])
    u = (math.cos(rad), math.sin(rad))
    w = (-math.sin(rad), math.cos(rad))
    grid = []
    for j in range(int(p["_NUM2"])):
        columns = range(int(p["_NUM1"]))
        for i in columns if j % 2 == 0 else reversed(columns):
            a, b = i * p["_DIS1"], j * p["_DIS2"]
            grid.append((p["_SPCA"] + a * u[0] + b * w[0], p["_SPCO"] + a * u[1] + b * w[1]))
    return grid


def _pattern(ex: Machine, name: str, p: dict[str, float], scope: Variables) -> None:
    """G0 to each position in the plane; the MCALLed cycle runs there."""
    s = ex.s
    call = s.mcall
    if call is not None and call[0] in PATTERNS:
        call = None  # a pattern called modally: its own moves call nothing (job planning)
    if call is not None and call[2]:
        raise Diagnostic(
            "SIEM-CYCLE-UNSUPPORTED",
            f"{name} under MCALL of the program {call[0]}: the pattern repeats only a "
            "standard cycle here",
            ex.loc,
        )
    first, second, _ = PLANES[s.plane][1]
    saved = (s.motion, s.absolute)
    s.absolute = True
    try:
        for a, b in positions(ex, name, p):
            s.motion = 0
            motion.execute(ex, Values(v={"XYZ"[first]: a, "XYZ"[second]: b}), False)
            if call is not None:
                run_cycle(ex, call[0], call[1] or (), scope)
    finally:
        s.motion, s.absolute = saved
