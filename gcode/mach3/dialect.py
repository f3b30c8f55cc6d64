"""Mach3 (ArtSoft's PC control): what a program written for it may contain.

From Mach3's G-code manual: G0-G3 with I J (incremental by default, G90.1/G91.1) or R,
G17-G19, G20/G21 (and G70/G71), G31 probe, G40-G42 with D, G43 H / G49, G52, G54-G59,
G61 exact stop / G64 constant velocity (no tolerance word), G73 and G80-G89 with
G98/G99, G90/G91, G92, G93/G94; M0-M9, M30, M48/M49 and M98/M99; every other M code
runs a user macro (M<n>.m1s): a machine function here. No NURBS, G33 threading, G43.1,
M61 or M62-M68 I/O words.
"""

from gcode.write.spec import Dialect

#: the M codes Mach3 defines itself (M47 repeats the program from its first line)
OWN_M_CODES = frozenset({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30, 47, 48, 49, 98, 99})

DIALECT = Dialect(
    name="mach3",
    title="Mach3 (ArtSoft)",
    reference="Mach3 G-code manual (ArtSoft; MachMotion's copy)",
    decimals_mm=4,
    decimals_inch=4,
    header=("%",),
    footer=("%",),
    arc_formats=frozenset({"ijk", "r"}),
    centre_absolute_mode=("G90.1", "G91.1"),
    probe="G31",
    probe_in_place=None,
    thread=None,
    exact_stop=None,
    exact_path="G61",
    continuous="G64",
    blend_word=None,
    naive_word=None,
    orient=None,
    css=None,
    css_off=None,
    tool_length="G10 L1 P{tool} Z{length}|G43 H{tool}",
    tool_register_add=None,
    tool_number=None,
    rigid_tap=None,
    cutter_comp=None,
    io_codes=False,
    feed_override=None,
    speed_override=None,
    xy_rotation=None,
    work_offsets=("G54", "G55", "G56", "G57", "G58", "G59"),
    machine_function="M{code}",
    machine_function_words="PQ",
    own_m_codes=OWN_M_CODES,
    end="M30",
    pallet=None,
    notes=(
        "G31 is Mach3's straight probe (G38.2 of RS274/NGC)",
        "M codes Mach3 does not define run user macros: MACHINE_FUNCTION events",
        "NURBS, ELLIPSE_FEED, G33: approximated or refused",
    ),
)
