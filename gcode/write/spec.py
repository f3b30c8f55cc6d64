"""What a G-code dialect is, as data: vocabulary, word formats and what it lacks.

A writer (:mod:`gcode.write.writer`) reads these fields and never branches on a dialect's name;
each dialect module holds one :class:`Dialect` value. The fields follow the profile list
of ``research/seed-sandia-full.md`` §5.2 (word separator, sequence numbers, number
format, modal codes, unit codes, dwell unit, axes, supported constructs, program frame).

A ``None`` code means the dialect has no such construct: the writer then expands,
approximates (recording it in the conversion report) or refuses with a located
``CONV-*`` diagnostic, as the user asked.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Dialect:
    """One target language. Codes are written exactly as given here (``G0`` or ``G00``)."""

    name: str
    title: str
    reference: str  # where the vocabulary comes from
    structure: str = "blocks"  # "blocks" (RS274-like words) or "commands" (Sandia generic)
    # ---- format
    separator: str = " "
    comment: str = "({})"  # how a comment is written; "" = no comments
    comment_forbidden: str = "()"  # characters a comment may not contain
    message: str | None = "(MSG, {})"  # operator message; None = none
    decimals_mm: int = 4
    decimals_inch: int = 4
    point_required: bool = False  # "X10." rather than "X10" (Fanuc: no point = increments)
    min_decimals: int = 0
    max_line_length: int | None = None
    max_sequence_number: int | None = None
    header: tuple[str, ...] = ()
    footer: tuple[str, ...] = ()
    axes: str = "XYZABC"
    diameter: str = ""  # axes programmed as a diameter (a lathe's X): their words are 2x
    initial_feed_mode: int = 0  # the control's feed mode at power-on (FeedMode value)
    tool_word: str = "T{tool}"  # the T word of a tool change (a lathe: T0101)
    # ---- modal codes
    rapid: str = "G0"
    linear: str = "G1"
    arc_cw: str = "G2"
    arc_ccw: str = "G3"
    absolute: str = "G90"
    planes: tuple[str, str, str] = ("G17", "G19", "G18")  # XY, YZ, XZ
    inch: str = "G20"
    mm: str = "G21"
    # ---- arcs
    arc_formats: frozenset[str] = frozenset({"ijk", "r"})  # of ijk, ijk-abs, r
    centre_absolute_mode: tuple[str, str] | None = None  # (abs on, incremental) e.g. G90.1
    centre_absolute_word: str | None = None  # "{letter}=AC({value})" (Siemens)
    radius_word: str = "R"
    turns_word: str | None = None  # word giving the number of turns (LinuxCNC P)
    turns_offset: int = 0  # the word's value is turns - offset (Siemens TURN= extra turns)
    nurbs: str | None = None  # "g5.2" (LinuxCNC) or "g06.2" (Fanuc)
    # ---- feed and motion control
    feed_modes: tuple[str | None, str | None, str | None] = ("G94", "G93", "G95")
    exact_stop: str | None = "G61.1"
    exact_path: str | None = "G61"
    continuous: str | None = "G64"
    blend_word: str | None = "P"  # G64 P tolerance
    naive_word: str | None = "Q"
    dwell: tuple[str, str, float] | None = ("G4", "P", 1.0)  # code, word, units per second
    probe: str | None = "G38.2"
    #: a probe code that takes a move of no length (LinuxCNC G38.3); None: such a probe is dropped
    probe_in_place: str | None = None
    thread: tuple[str, str] | None = ("G33", "K")  # spindle-synchronised feed, lead word
    # ---- spindle, tools, coolant
    spindle_cw: str = "M3"
    spindle_ccw: str = "M4"
    spindle_stop: str = "M5"
    orient: str | None = "M19 R{angle} P{mode}"  # mode 0 CW, 1 CCW, 2 shortest
    css: str | None = "G96 D{max} S{speed}"  # {max} omitted when 0
    css_off: str | None = "G97"
    tool_change: str | None = "M6"
    # the tool change that keeps the new tool's length in force where the change itself
    # ends it (Siemens M6 D0 / M6 D1); None: a change leaves the length offset as it is
    tool_change_keeping_length: str | None = None
    tool_length: str | None = "G43.1 Z{length}"  # or "G10 L10 P{tool} R{length}|G43 H{tool}"
    tool_length_off: str = "G49"
    # a tool length kept as its register (gcode.core.register_marks): G43 H n; a form without
    # {register} names the active tool's own edge (Siemens D1), so only H = the tool fits;
    # None: the target has no register form (a located CONV-TOOL-REGISTER)
    tool_register: str | None = "G43 H{register}"
    tool_register_add: str | None = "G43.2 H{register}"  # added to the current offset
    # the length written into the machine's tool table, only with --write-tool-table
    tool_table_length: str | None = "G10 L1 P{register} Z{length}"
    # ---- canned cycles kept by ``--cycles keep`` (gcode.core.cycle_marks): the drilling cycles
    # whose motion is the same in this dialect as in RS274/NGC; (G98, G99) retract codes;
    # the dwell P of a cycle in milliseconds (Fanuc) instead of seconds
    cycles: frozenset[str] = frozenset({"G73", "G81", "G82", "G83", "G85", "G89"})
    cycle_retract: tuple[str, str] = ("G98", "G99")
    cycle_dwell_ms: bool = False
    origin: str | None = "G10 L2 P1 {axes}"
    work_offsets: tuple[str, ...] = (
        "G54",
        "G55",
        "G56",
        "G57",
        "G58",
        "G59",
        "G59.1",
        "G59.2",
        "G59.3",
    )
    # additional work offsets (gcode.core.register_marks.EXTENDED_WORK_OFFSETS) as P words: Fanuc
    # G54.1 P{register}, Haas G154 P{register}; how many there are
    extended_offset: str | None = None
    extended_offsets: int = 0
    # setting a work offset's values in the machine's table (G10 L2 P n of the numbers in
    # work_offsets, G10 L20 P n of the extended ones); None: the program cannot set them
    work_offset_set: str | None = "G10 L2 P{register} {axes}"
    extended_offset_set: str | None = None
    local_offset: str | None = "G52 {axes}"  # the G92/G52 offset, set by value
    xy_rotation: str | None = "G10 L2 P{index} R{angle}"  # rotated work offset; "|" = off
    # a rotation and an offset that share one frame (Siemens ROT/TRANS each replace the
    # programmable frame): both are written together, the offset with this additive form
    # after the rotation (None: the two are independent words)
    rotated_offset: str | None = None
    tool_table_set: str | None = "G10 L1 P{tool} {axes} R{radius}"
    tool_number: str | None = "M61 Q{tool}"
    rigid_tap: str | None = "G33.1"
    cutter_comp: tuple[str, str] | None = ("G41.1", "G42.1")  # left, right, with D diameter
    # left, right with D = tool-table entry / offset register (G41 D1), and how to write a
    # radius given by value into that register when there is no by-value form (Fanuc
    # G10 L12: radius geometry)
    comp_register: tuple[str, str] | None = ("G41", "G42")
    comp_radius_set: str | None = None
    io_codes: bool = True  # M62-M68 digital and analog outputs
    mist: str | None = "M7"
    flood: str | None = "M8"
    coolant_off: str = "M9"
    feed_override: tuple[str, str] | None = ("M50 P1", "M50 P0")  # enable, disable
    speed_override: tuple[str, str] | None = ("M51 P1", "M51 P0")
    # ---- machine functions (MACHINE_FUNCTION: M codes for the PLC): how one is written,
    # None when the control refuses an M code it does not define; and the letters (P, Q)
    # that may follow it
    machine_function: str | None = None  # "M{code:02d}"
    machine_function_words: str = ""
    # the M codes the control defines itself: one of them written for the PLC would mean
    # something else there (Haas M97 is a call, Fanuc M98 ...)
    own_m_codes: frozenset[int] = frozenset()
    # ---- program flow
    stop: str = "M0"
    optional_stop: str | None = "M1"
    end: str = "M2"
    pallet: str | None = "M60"
    notes: tuple[str, ...] = field(default=())  # what the dialect lacks, for docs/dialects.md

    def decimals(self, inch: bool) -> int:
        return self.decimals_inch if inch else self.decimals_mm

    @property
    def has_cutter_comp(self) -> bool:
        """G41/G42 can be kept: by value or with an offset register (``--cutter-comp``)."""
        return self.cutter_comp is not None or self.comp_register is not None
