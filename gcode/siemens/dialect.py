"""Siemens SINUMERIK 840D sl (ISO-like Siemens mode, not ISO dialect mode).

Comments after ``;``, ``MSG("...")`` messages, G710/G700 (metric/inch including feeds),
``CR=`` radius arcs, ``I=AC(..)`` absolute centres, ``TURN=`` extra full turns,
``G4 F`` dwell in seconds, G60/G64 exact stop/continuous, ``SPOS=`` orientation,
``G96 S.. LIMS=..`` constant surface speed, ``TRANS`` programmable offset (absolute:
the G92/G52 offset by value), ``MEAS=1`` probing. ``M6 D0`` and ``D1``/``D0``: the 840D
activates cutting edge D1 after a tool change (machine data CUTTING_EDGE_DEFAULT = 1), so
the writer says when the tool table's length applies. BSPLINE exists but its knot form
(PL intervals) is not written: NURBS are approximated by arcs.
"""

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="siemens840d",
    title="Siemens SINUMERIK 840D sl",
    reference="SINUMERIK 840D sl programming manual, fundamentals",
    comment="; {}",
    comment_forbidden="",
    message='MSG("{}")',
    decimals_mm=3,
    decimals_inch=4,
    header=(),
    footer=(),
    inch="G700",
    mm="G710",
    arc_formats=frozenset({"ijk", "ijk-abs", "r"}),
    centre_absolute_word="{letter}=AC({value})",
    radius_word="CR=",
    turns_word="TURN=",
    turns_offset=1,
    exact_stop="G60",
    exact_path="G60",
    continuous="G64",
    blend_word=None,
    naive_word=None,
    dwell=("G4", "F", 1.0),
    probe="MEAS=1 G1",
    thread=("G33", "K"),
    orient="SPOS={angle}",
    css="G96 S{speed} LIMS={max}",
    tool_change="M6 D0",
    tool_change_keeping_length="M6 D1",
    tool_length="D1",
    tool_length_off="D0",
    tool_register="D1",
    tool_register_add=None,
    tool_table_length=None,
    cycles=frozenset(),
    origin="TRANS {axes}",
    feed_override=None,
    speed_override=None,
    end="M30",
    pallet=None,
    # settable frames 1-4 and 5-99 (G505-G599); their values are not set in a program
    work_offsets=("G54", "G55", "G56", "G57", *(f"G5{n:02d}" for n in range(5, 100))),
    work_offset_set=None,
    tool_table_set=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    own_m_codes=frozenset({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 17, 19, 30}),  # the reader's own
    machine_function="M{code}",  # M codes beyond the NC's own go to the PLC
    local_offset="TRANS {axes}",
    xy_rotation="ROT Z{angle}|ROT",
    rotated_offset="ATRANS {axes}",
    cutter_comp=None,
    comp_register=None,
    notes=(
        "NURBS, ELLIPSE_FEED: approximated by arcs",
        "tool length as a value: not in the part program; D1 activates the tool table's "
        "(reported as substituted), D0 switches it off",
        "M6 is written M6 D0: the 840D activates D1 after a change by default, the IR "
        "has no tool length until it says so",
        "G92/G52 offset: TRANS; with a G10 L2 R rotation ROT Z then ATRANS (each of ROT "
        "and TRANS replaces the whole programmable frame)",
        "G61.1 vs G61: both written G60",
        "G64 tolerance, override switches, pallet shuttle: not written",
    ),
)
