"""One function per canonical command: how a block writer writes it.

Each receives the writer's state (:class:`gcode.write.context.WriterContext`).

Arcs follow NISTIR 5970 §3.6.1 (end, centre, signed turns; XZ plane is (Z, X)); G2 is
clockwise (rotation < 0), G3 counterclockwise. NURBS follow LinuxCNC G5.2 (current
position = first control point, clamped uniform knots) or Fanuc G06.2 (``P`` order, ``K``
knots, ``R`` weights); anything else is approximated (:mod:`gcode.write.approximate`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from gcode.core.register_marks import ToolLengthRegister
from gcode.ngc.comp.keep import CompRegister
from gcode.write.context import WriterContext
from gcode.write.report import machinist
from gcode.write.state import PLANE_AXES
from kernel import limits
from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.ir.arcsweep import first_turn, total_sweep

TWO_PI = 2 * math.pi


# ---------------------------------------------------------------------- state setters
def units(w: WriterContext, c: canon.UseLengthUnits) -> None:
    if w.units == c.units and w.fmt.units_out is not None:
        return
    changed = w.units is not None and w.units != c.units
    w.units = c.units
    if w.o.units is None or w.fmt.units_out is None:
        w.fmt.units_out = None  # flush writes the code and sets the scale
        w.invalidate()
        if changed:
            w.e_feed = None
    else:
        w.fmt.set_output_units(c.units)


def plane(w: WriterContext, c: canon.SelectPlane) -> None:
    w.plane = c.plane


def feed_rate(w: WriterContext, c: canon.SetFeedRate) -> None:
    w.feed = c.rate


def feed_mode(w: WriterContext, c: canon.SetFeedMode) -> None:
    w.feed_mode = c.mode


def motion_mode(w: WriterContext, c: canon.SetMotionControlMode) -> None:
    w.mode = (c.mode, c.tolerance * w.fmt.scale)


def naive(w: WriterContext, c: canon.SetNaivecamTolerance) -> None:
    w.naive = c.tolerance * w.fmt.scale


def speed(w: WriterContext, c: canon.SetSpindleSpeed) -> None:
    w.speed = c.speed


def spindle_mode(w: WriterContext, c: canon.SetSpindleMode) -> None:
    w.css = (c.css, c.css_max)


def spindle(direction: canon.Direction) -> Callable[[WriterContext, canon.Command], None]:
    def handler(w: WriterContext, c: canon.Command) -> None:
        w.direction = direction

    return handler


def coolant(kind: str, on: bool) -> Callable[[WriterContext, canon.Command], None]:
    def handler(w: WriterContext, c: canon.Command) -> None:
        w.coolant[kind] = on

    return handler


def ignore(w: WriterContext, c: canon.Command) -> None:
    """Commands with no G-code of their own (INIT_CANON, probe power, traverse rate)."""


def feed_reference(w: WriterContext, c: canon.SetFeedReference) -> None:
    if c.reference != canon.FeedReference.XYZ:
        w.lacking("CONV-FEED-MODE", "workpiece feed reference", note=False)


def sync_start(w: WriterContext, c: canon.StartSpeedFeedSynch) -> None:
    w.sync = c.feed_per_revolution * w.fmt.scale


def sync_stop(w: WriterContext, c: canon.StopSpeedFeedSynch) -> None:
    w.sync = None


# ---------------------------------------------------------------------- text and events
def comment(w: WriterContext, c: canon.Comment) -> None:
    if not c.text.startswith("interpreter:"):  # LinuxCNC's own chatter
        w.comment(c.text)


def message(w: WriterContext, c: canon.Message) -> None:
    w.flush()
    if w.d.message is None:
        w.lacking("CONV-MESSAGE", "(MSG,...) operator message", "substituted", note=False)
        w.comment(c.text)
        return
    text = c.text
    forbidden = w.d.comment_forbidden + ('"' if '"' in w.d.message else "")
    for ch in forbidden:
        text = text.replace(ch, "'" if ch == '"' else " ")
    if text != c.text:  # the operator reads another text: said, as for a message dropped
        lost = "".join(ch for ch in forbidden if ch in c.text)
        w.change(
            "CONV-MESSAGE",
            "substituted",
            f"{w.d.title} messages cannot hold {lost}: (MSG,...) written with ' or a blank for it",
        )
    w.block(w.d.message.format(text))


def event(attr: str) -> Callable[[WriterContext, canon.Command], None]:
    def handler(w: WriterContext, c: canon.Command) -> None:
        w.flush()
        code = getattr(w.d, attr)
        if attr == "stop" and w.pallet:
            if w.d.pallet:
                code = w.d.pallet  # M60 = shuttle + stop
            else:
                w.lacking("CONV-PALLET", machinist("PALLET_SHUTTLE"))
        # M30 is PALLET_SHUTTLE then PROGRAM_END in LinuxCNC, whose PALLET_SHUTTLE does
        # nothing on a machine without pallets: the target's own end is the same end
        w.pallet = False
        if code is None:
            w.lacking("CONV-STOP", machinist(c.NAME))
            return
        w.block(code)
        if attr == "end":
            w.ended = True

    return handler


def machine_function(w: WriterContext, c: canon.MachineFunction) -> None:
    """``M<code>`` (with P and Q) where the target hands M codes to its PLC; else, or where
    the target's own M code of that number means something else, reported (never silently
    dropped) or refused with ``--on-missing refuse``."""
    w.flush()
    what = f"machine function {c.word}"
    if w.d.machine_function is None:
        w.lacking("CONV-MACHINE-FUNCTION", f"{what} (it refuses M codes it does not define)")
        return
    if c.code in w.d.own_m_codes:
        w.lacking("CONV-MACHINE-FUNCTION", f"{what} (its own {c.word} means something else)")
        return
    words = [w.d.machine_function.format(code=c.code)]
    for letter, value in (("P", c.p), ("Q", c.q)):
        if value is None:
            continue
        if letter in w.d.machine_function_words:
            words.append(letter + w.fmt.number(value))
        else:
            w.lacking("CONV-MACHINE-FUNCTION", f"{letter} word on {c.word}", note=False)
    w.block(*words)


def pallet(w: WriterContext, c: canon.PalletShuttle) -> None:
    w.pallet = True  # written (or reported) with the stop or end it comes with


def select_tool(w: WriterContext, c: canon.SelectTool) -> None:
    w.pending_select = c.slot


def change_tool(w: WriterContext, c: canon.ChangeTool) -> None:
    w.flush()
    tool = w.pending_select if w.pending_select is not None else c.slot
    w.pending_select = None
    w.tool = tool
    if c.name:
        w.comment(f"tool {c.name}")
    if w.d.tool_change is None:
        w.lacking("CONV-TOOL-CHANGE", "tool changer (M6)", "substituted", note=False)
        w.comment(f"change to tool {tool}")
        w.block(w.d.stop)
        return
    keeping = w.d.tool_change_keeping_length
    if keeping is not None and w.length_register is not None:
        # G43 H n stays in force across M6; this control's change ends it unless told
        if w.length_register != tool:
            w.refuse(
                "CONV-TOOL-REGISTER",
                f"G43 H{w.length_register} stays in force across the change to tool {tool}; "
                f"{w.d.title} takes only the active tool's own length ({keeping})",
            )
        w.block(w.d.tool_word.format(tool=tool), keeping)
    else:
        w.block(w.d.tool_word.format(tool=tool), w.d.tool_change)
    if w.d.tool_change:  # an M6 change cycle stops the spindle (every reader's M6 does)
        w.e_direction = canon.Direction.STOPPED


def tool_length_register(w: WriterContext, c: ToolLengthRegister) -> None:
    w.tool_register = c


def tool_length(w: WriterContext, c: canon.UseToolLengthOffset) -> None:
    """A tool length offset: the register the reader marked (G43 H n, G49) in the target's
    form, else the length by value; the machine's tool table is written only with
    ``--write-tool-table`` (CONV-TOOL-TABLE otherwise)."""
    w.flush()
    w.invalidate()
    mark, w.tool_register = w.tool_register, None
    w.length_register = mark.register if mark is not None and mark.code == "G43" else None
    cancel = mark is None or mark.code == "G49"
    if w.d.tool_length is None and w.d.tool_register is None and cancel and not c.length:
        return  # a control without tool length offsets (the lathes): none to cancel
    if mark is not None and mark.code == "G49":
        w.block(w.d.tool_length_off)
        return
    if mark is not None and mark.register is not None:
        _length_register(w, mark, c.length)
        return
    if abs(c.length) < 1e-12:
        w.block(w.d.tool_length_off)
        return
    if w.d.tool_length is None:
        w.lacking("CONV-TOOL-LENGTH", "tool length value in a program")
        return
    value = w.fmt.length(c.length * w.fmt.scale)
    if "{length}" not in w.d.tool_length:
        if mark is not None:  # G43.1 by value: another length would run the program
            w.refuse("CONV-TOOL-LENGTH", f"{w.d.title} has no tool length by value (G43.1)")
        w.lacking("CONV-TOOL-LENGTH", "tool length value (the tool table's is used)", "substituted")
    elif w.d.tool_length.startswith("G10") and not w.o.write_tool_table:
        w.refuse(
            "CONV-TOOL-TABLE",
            f"tool length {value} by value: {w.d.title} takes it only through its tool "
            "table (G10 L10), which is written only with --write-tool-table",
        )
    for part in w.d.tool_length.split("|"):
        w.block(part.format(length=value, tool=w.tool))


def _length_register(w: WriterContext, mark: ToolLengthRegister, length: float) -> None:
    """``G43 H n`` (or G43.2) as the target says it; the machine keeps its own length."""
    n = mark.register
    add = mark.code == "G43.2"
    form = w.d.tool_register_add if add else w.d.tool_register
    if form is None:
        w.refuse(
            "CONV-TOOL-REGISTER",
            f"{w.d.title} has no tool length register ({mark.code} H{n}): the length "
            "offset cannot be kept",
        )
    if "{register}" not in form and n != w.tool:
        w.refuse(
            "CONV-TOOL-REGISTER",
            f"{mark.code} H{n} takes tool {n}'s length with tool {w.tool} in the spindle; "
            f"{w.d.title} takes only the active tool's own ({form})",
        )
    if w.o.write_tool_lengths and w.d.tool_table_length is not None and not add:
        value = w.fmt.length(length * w.fmt.scale)
        w.block(w.d.tool_table_length.format(register=n, length=value))
    w.block(form.format(register=n))


def origin(w: WriterContext, c: canon.SetOriginOffsets) -> None:
    w.flush_units()  # an offset block needs numbers, not the plane or feed mode yet
    w.invalidate()
    if w.d.origin is None:
        w.lacking("CONV-ORIGIN", "program origin setting")
        return
    if w.d.origin.startswith("G10") and "origin-table" not in w.noted:
        w.noted.add("origin-table")  # once per program: the shop must know
        w.change(
            "CONV-ORIGIN-TABLE",
            "substituted",
            "program origin (SET_ORIGIN_OFFSETS) written as G10 L2 P1: running the program "
            "sets work offset 1 (G54) of the machine",
        )
    t = w.target(c.x, c.y, c.z, c.a, c.b, c.c)
    words = [
        k + (w.fmt.angle(v) if k in "ABC" else w.fmt.length(v))
        for k, v in t.items()
        if k in w.d.axes and (k in "XYZ" or abs(v) > 1e-12)
    ]
    w.block(w.d.origin.format(axes=w.d.separator.join(words)))
    w.invalidate()


def overrides(kind: str, on: bool) -> Callable[[WriterContext, canon.Command], None]:
    def handler(w: WriterContext, c: canon.Command) -> None:
        pair = getattr(w.d, f"{kind}_override")
        if pair is None:
            w.lacking("CONV-OVERRIDE", f"M48/M49 ({kind} override switch)", note=False)
            return
        w.block(pair[0] if on else pair[1])

    return handler


def orient(w: WriterContext, c: canon.OrientSpindle) -> None:
    w.flush()
    if w.d.orient is None:
        w.lacking("CONV-SPINDLE", machinist("ORIENT_SPINDLE"))
        return
    direction = c.direction
    mode = {canon.Direction.CLOCKWISE: 0, canon.Direction.COUNTERCLOCKWISE: 1}.get(
        direction,
        int(direction) if isinstance(direction, float | int) else 0,
    )
    if "{angle}" not in w.d.orient and abs(c.orientation) > 1e-9:
        w.lacking(
            "CONV-SPINDLE",
            "programmed orientation angle (machine's angle used)",
            "substituted",
            note=False,
        )
    w.block(w.d.orient.format(angle=w.fmt.angle(c.orientation), mode=mode))


def dwell(w: WriterContext, c: canon.Dwell) -> None:
    w.flush()
    if w.d.dwell is None:
        w.lacking("CONV-DWELL", machinist("DWELL"))
        return
    code, word, per_second = w.d.dwell
    if w.feed_mode != canon.FeedMode.INVERSE_TIME:
        w.block(w.feed_word())  # a dwell "sees" the feed rate too (corpus/README.md)
    w.block(code, word + w.fmt.number(c.seconds * per_second, 3))


def comp_radius(w: WriterContext, c: canon.SetCutterRadiusCompensation) -> None:
    w.comp_radius = c.radius * w.fmt.scale


def comp_register(w: WriterContext, c: CompRegister) -> None:
    w.comp_register = c.register


def comp_start(w: WriterContext, c: canon.StartCutterRadiusCompensation) -> None:
    """G41/G42 kept: with the source's register where the reader said which (``G41 D1``:
    the target's table or offset register supplies the radius, as on the source), else
    with the radius of SET_CUTTER_RADIUS_COMPENSATION by value (LinuxCNC G41.1 D diameter)
    or written into the register of the tool in the spindle first (Fanuc, Haas: G10 L12,
    then G41 D; reported, since it changes the machine's offset memory)."""
    register, w.comp_register = w.comp_register, None
    left = c.side == canon.CompSide.LEFT
    w.flush()
    if register is not None and w.d.comp_register is not None:
        w.block(w.d.comp_register[0 if left else 1], f"D{register}")
        if w.d.comp_radius_set is not None and "comp-register" not in w.noted:
            w.noted.add("comp-register")
            w.change(
                "CONV-CUTTER-COMP",
                "substituted",
                f"G41/G42 D{register}: the radius comes from the machine's offset register "
                f"(the source's tool table gave {w.fmt.length(w.comp_radius)})",
            )
    elif w.d.cutter_comp is not None:
        diameter = w.fmt.length(2 * w.comp_radius)
        w.block(w.d.cutter_comp[0 if left else 1], "D" + diameter)
    elif w.d.comp_radius_set is not None and w.d.comp_register is not None:
        register = w.tool or 1
        radius = w.fmt.length(w.comp_radius)
        w.block(w.d.comp_radius_set.format(register=register, radius=radius))
        w.block(w.d.comp_register[0 if left else 1], f"D{register}")
        w.change(
            "CONV-CUTTER-COMP",
            "substituted",
            f"compensation radius {radius} by value written into offset register {register} "
            "(G10 L12): running the program changes that register",
        )
    else:
        w.refuse(
            "CONV-CUTTER-COMP",
            f"{w.d.title} has no cutter compensation; convert with --cutter-comp apply",
        )
    w.comp_on = True


def comp_active(w: WriterContext, what: str) -> None:
    """Controls refuse an offset change while G41/G42 is on (LinuxCNC, Fanuc): a program
    whose compensation was kept cannot say it; applying compensation can."""
    if w.comp_on:
        w.refuse(
            "CONV-CUTTER-COMP",
            f"{what} with cutter compensation on: convert with --cutter-comp apply",
        )


def comp_stop(w: WriterContext, c: canon.StopCutterRadiusCompensation) -> None:
    w.flush()
    w.block("G40")
    w.comp_on = False


# ---------------------------------------------------------------------- motions
def traverse(w: WriterContext, c: canon.StraightTraverse) -> None:
    w.flush()
    words = w.axis_words(w.target(c.x, c.y, c.z, c.a, c.b, c.c))
    fw = "" if w.feed_mode == canon.FeedMode.INVERSE_TIME else w.feed_word()
    w.block(w.motion_code(w.d.rapid), *(words or _first_axis(w)), fw)


def _first_axis(w: WriterContext) -> list[str]:
    return [w.words["X"] or w.axis_text("X", w.cur["X"])]


def feed(w: WriterContext, c: canon.StraightFeed) -> None:
    w.flush()
    inverse = w.feed_mode == canon.FeedMode.INVERSE_TIME
    start = [w.written(k) for k in "XYZ"] if inverse else None
    words = w.axis_words(w.target(c.x, c.y, c.z, c.a, c.b, c.c))
    # the length the target's reader works the rate out with: from written point to written
    # point (the rounded words), so the read-back's per-minute rate is the source's
    length = math.dist(start, [w.written(k) for k in "XYZ"]) if start else None
    if w.sync is not None:
        if w.d.thread is None:
            w.refuse("CONV-THREAD", f"{w.d.title} has no spindle-synchronised motion")
        code, lead = w.d.thread
        w.motion = None
        # the feed rate in force at the thread is the source's: an F block of its own before
        # a K lead (LinuxCNC refuses an F word in a G33 block); a Fanuc lead F is the feed
        # rate itself (below)
        fw = "" if lead == "F" else w.feed_word()
        if fw:
            w.block(fw)
        w.block(code, *(words or _first_axis(w)), lead + w.fmt.length(w.sync))
        if lead == "F":  # Fanuc: the lead F is the modal F too; the next feed restates it
            if abs(w.feed - w.sync) > 1e-12:
                what = "the thread lead F is also the feed rate"
                if w.o.on_missing == "refuse":
                    w.refuse("CONV-THREAD", what)
                w.change("CONV-THREAD", "substituted", what)
            w.e_feed = None
        return
    w.block(w.motion_code(w.d.linear), *(words or _first_axis(w)), w.feed_word(length))


def probe(w: WriterContext, c: canon.StraightProbe) -> None:
    w.flush()
    if w.d.probe is None:
        w.lacking("CONV-PROBE-MOVE", machinist("STRAIGHT_PROBE"))
        return
    target = w.target(c.x, c.y, c.z, c.a, c.b, c.c)
    code = w.d.probe
    if _at_written_point(w, target):
        # a G38.3/G38.5 of no length (LinuxCNC runs it; nothing moves): G38.2 would refuse it
        if w.d.probe_in_place is None:
            w.change("CONV-PROBE", "dropped", "a probe to the point it starts from (no motion)")
            return
        code = w.d.probe_in_place
    words = w.axis_words(target, force=True)
    w.motion = None
    w.block(code, *words, w.feed_word())
    if code == w.d.probe:
        w.invalidate()  # the probe stops where it trips


def _at_written_point(w: WriterContext, target: dict[str, float]) -> bool:
    """True when every axis word of ``target`` is the word the text already stands at."""
    for letter in "XYZABC":
        if letter not in w.d.axes:
            continue
        value = target[letter]
        word = letter + w.fmt.number(2 * value if letter in w.d.diameter else value)
        if w.words[letter] != word:
            return False
    return True


def arc(w: WriterContext, c: canon.ArcFeed) -> None:
    w.flush()
    first, second, normal, ci, cj = PLANE_AXES[w.plane]
    for letter in (first, second):
        if letter not in w.d.axes:  # an XY arc on a lathe
            w.refuse("CONV-AXIS", f"{w.d.title} has no {letter} axis for an arc in its plane")
    s = w.fmt.scale
    end1, end2, cen1, cen2 = c.first_end * s, c.second_end * s, c.first_axis * s, c.second_axis * s
    start1, start2 = w.written(first), w.written(second)
    if c.rotation == 0:  # NISTIR 5970 §3.6.1: no arc, a move along the helix axis
        w.change("CONV-ARC-TURNS", "substituted", "ARC_FEED with 0 turns written as a line")
        _line_to(w, c, first, second, normal)
        return
    ccw = c.rotation > 0
    turns = abs(c.rotation)
    a0 = math.atan2(start2 - cen2, start1 - cen1)
    a1 = math.atan2(end2 - cen2, end1 - cen1)
    part = first_turn(a0, a1, ccw)
    if turns > 1 and w.d.turns_word is None:
        _expand_turns(w, c, turns, part)
        return
    _arc_block(w, c, (end1, end2, cen1, cen2), ccw, turns, part)


def _arc_block(
    w: WriterContext,
    c: canon.ArcFeed,
    geo: tuple[float, float, float, float],
    ccw: bool,
    turns: int,
    part: float,
) -> None:
    """One arc block; ``geo``: end and centre in the plane's axes (output units)."""
    first, second, normal, ci, cj = PLANE_AXES[w.plane]
    end1, end2, cen1, cen2 = geo
    start1, start2 = w.written(first), w.written(second)
    s = w.fmt.scale
    t = w.target(0, 0, 0, c.a, c.b, c.c)
    t[first], t[second], t[normal] = end1, end2, c.axis_end_point * s
    length = math.hypot(
        math.hypot(start1 - cen1, start2 - cen2) * total_sweep(part, turns),
        t[normal] - w.written(normal),
    )
    end_words = w.axis_words(t)
    inplane = [x for x in (w.words[first], w.words[second]) if x is not None]
    others = [x for x in end_words if x[0] not in (first, second)]
    fmt = _arc_format(w, turns, part, (start1, start2), (end1, end2), (cen1, cen2), ccw)
    centre: list[str] = []
    if fmt == "r":
        radius = math.hypot(start1 - cen1, start2 - cen2)
        value = radius if part <= math.pi else -radius
        centre = [w.d.radius_word + w.fmt.length(value)]
    elif fmt == "ijk-abs":
        if w.d.centre_absolute_word:
            centre = [
                w.d.centre_absolute_word.format(letter=ci, value=w.fmt.length(cen1)),
                w.d.centre_absolute_word.format(letter=cj, value=w.fmt.length(cen2)),
            ]
        else:
            if not w.centre_abs_on:
                assert w.d.centre_absolute_mode is not None  # ijk-abs needs a word or a mode
                w.block(w.d.centre_absolute_mode[0])
                w.centre_abs_on = True
            centre = [ci + w.fmt.length(cen1), cj + w.fmt.length(cen2)]
    else:
        if w.centre_abs_on:
            assert w.d.centre_absolute_mode is not None  # it was switched on
            w.block(w.d.centre_absolute_mode[1])
            w.centre_abs_on = False
        centre = [ci + w.fmt.length(cen1 - start1), cj + w.fmt.length(cen2 - start2)]
    turn_words = []
    if turns > 1:
        turn_words = [f"{w.d.turns_word}{turns - w.d.turns_offset}"]
    code = w.d.arc_ccw if ccw else w.d.arc_cw
    fw = w.feed_word(length)
    ends = sorted([*inplane, *others], key=lambda word: "XYZABC".index(word[0]))
    centre.sort(key=lambda word: word[0])  # I J K
    w.block(w.motion_code(code), *ends, *centre, *turn_words, fw)


def r_centre(
    start: tuple[float, float], end: tuple[float, float], r: float, ccw: bool
) -> tuple[float, float] | None:
    """The centre a reader finds for an R-format arc (RS274: |R| > 180 degrees when R < 0)."""
    chord = math.dist(start, end)
    if chord < 1e-12 or abs(r) < chord / 2 - 1e-12:
        return None
    h = math.sqrt(max(r * r - chord * chord / 4, 0.0))
    ux, uy = (end[0] - start[0]) / chord, (end[1] - start[1]) / chord
    side = 1.0 if ccw == (r > 0) else -1.0  # centre left of the chord for G3 with R > 0
    mx, my = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
    return mx - side * h * uy, my + side * h * ux


def _arc_format(
    w: WriterContext,
    turns: int,
    part: float,
    start: tuple[float, float],
    end: tuple[float, float],
    centre: tuple[float, float],
    ccw: bool,
) -> str:
    """How the arc's centre is written: the format asked for, or ijk where it cannot be."""
    want = w.o.arc_format
    if want == "ijk-abs" and "ijk-abs" not in w.d.arc_formats:
        if "ijk-abs" not in w.noted:
            w.noted.add("ijk-abs")
            w.change("CONV-ARC-FORMAT", "substituted", f"{w.d.title}: incremental centres")
        return "ijk"
    if want != "r":
        return want
    radius = math.dist(start, centre)
    r_word = float(w.fmt.length(radius if part <= math.pi else -radius))
    end_w = (float(w.fmt.length(end[0])), float(w.fmt.length(end[1])))
    got = r_centre(start, end_w, r_word, ccw)
    exact = got is not None and math.dist(got, centre) <= 0.4 * 10.0**-w.fmt.places
    # A reader finds the centre from 4R^2 - chord^2 of the written numbers, without a
    # tolerance (Grbl's gcode.c stops with error:33 below 0): near a half circle that term
    # is a tiny difference of large numbers, so keep it clear of 0 by 1e-4 of 4R^2 (the arc
    # at least 1.15 degrees away from 180).
    conditioned = 4 * r_word * r_word - math.dist(start, end_w) ** 2 > 4e-4 * r_word * r_word
    if turns > 1 or part > TWO_PI - 1e-6 or not exact or not conditioned:
        w.change(
            "CONV-ARC-FORMAT",
            "substituted",
            "arc written with centres: R cannot state a full circle, several turns "
            "or a near half circle reliably",
        )
        return "ijk"
    return "r"


def _expand_turns(w: WriterContext, c: canon.ArcFeed, turns: int, part: float) -> None:
    """Several turns without a turns word: full circles, then the remaining arc."""
    if w.o.on_missing == "refuse":
        w.refuse("CONV-ARC-TURNS", f"{w.d.title} has no multi-turn arcs")
    limit = limits.current().arc_turns
    if turns - 1 > limit:  # a million turns: a million blocks written and read back
        raise limits.count_error(
            f"full circles of one arc ({w.d.title} has no turns word)",
            turns - 1,
            limit,
            "arc_turns",
            c.source or Location(None),
        )
    first, second, normal, _, _ = PLANE_AXES[w.plane]
    s = w.fmt.scale
    total = total_sweep(part, turns)
    z0, z1 = w.written(normal) / s, c.axis_end_point
    start1, start2 = w.written(first) / s, w.written(second) / s
    ccw = c.rotation > 0
    for k in range(1, turns):
        z = z0 + (z1 - z0) * (k * TWO_PI / total)
        full = canon.ArcFeed(
            start1,
            start2,
            c.first_axis,
            c.second_axis,
            1 if ccw else -1,
            z,
            c.a,
            c.b,
            c.c,
            source=c.source,
        )
        _arc_block(
            w, full, (start1 * s, start2 * s, c.first_axis * s, c.second_axis * s), ccw, 1, TWO_PI
        )
    geo = (c.first_end * s, c.second_end * s, c.first_axis * s, c.second_axis * s)
    _arc_block(w, c, geo, ccw, 1, part)
    w.change(
        "CONV-ARC-TURNS", "expanded", f"{turns}-turn arc written as {turns} arcs", pieces=turns
    )


def _line_to(w: WriterContext, c: canon.ArcFeed, first: str, second: str, normal: str) -> None:
    s = w.fmt.scale
    t = w.target(0, 0, 0, c.a, c.b, c.c)
    t[first], t[second] = c.first_end * s, c.second_end * s
    t[normal] = c.axis_end_point * s
    start = [w.written(k) for k in "XYZ"]
    words = w.axis_words(t)
    length = math.dist(start, [w.cur[k] for k in "XYZ"])
    w.block(w.motion_code(w.d.linear), *(words or _first_axis(w)), w.feed_word(length))
