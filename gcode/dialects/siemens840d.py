"""Siemens SINUMERIK 840D sl (ISO-like Siemens mode, not ISO dialect mode).

Comments after ``;``, ``MSG("...")`` messages, G710/G700 (metric/inch including feeds),
``CR=`` radius arcs, ``I=AC(..)`` absolute centres, ``TURN=`` extra full turns,
``G4 F`` dwell in seconds, G60/G64 exact stop/continuous, ``SPOS=`` orientation,
``G96 S.. LIMS=..`` constant surface speed, ``TRANS`` programmable offset, ``MEAS=1``
probing. BSPLINE exists but its knot form (PL intervals) is not written: NURBS are
approximated by arcs.
"""

from gcode.dialects.spec import Dialect

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
    tool_length=None,
    origin="TRANS {axes}",
    feed_override=None,
    speed_override=None,
    end="M30",
    pallet=None,
    work_offsets=("G54", "G55", "G56", "G57"),
    tool_table_set=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    local_offset="ATRANS {axes}",
    xy_rotation="ROT RPL={angle}|ROT",
    cutter_comp=None,
    notes=(
        "NURBS, ELLIPSE_FEED: approximated by arcs",
        "tool length as a value: not in the part program (tool data D numbers)",
        "G61.1 vs G61: both written G60",
        "G64 tolerance, override switches, pallet shuttle: not written",
    ),
)
