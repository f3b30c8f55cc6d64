"""Haas mill (NGC control): Fanuc-style codes with Haas specifics.

Two-digit codes and decimal points as Fanuc; dwell ``G04 P`` in seconds (with a decimal
point); G187 smoothness instead of G64 tolerances; no NURBS, no G33 on mills; work
offsets and tool lengths with ``G10 L2`` / ``G10 L10`` (Fanuc-compatible forms).
"""

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="haas",
    title="Haas mill (NGC control)",
    reference="Haas mill operator's manual, G-code chapter",
    decimals_mm=3,
    decimals_inch=4,
    point_required=True,
    message=None,
    max_sequence_number=99999,
    header=("%", "O00001"),
    footer=("%",),
    rapid="G00",
    linear="G01",
    arc_cw="G02",
    arc_ccw="G03",
    exact_stop="G61",  # G09 is one-shot on Haas; G61 is the modal exact stop
    exact_path="G61",
    continuous="G64",
    blend_word=None,
    naive_word=None,
    dwell=("G04", "P", 1.0),
    probe="G31",
    thread=None,
    spindle_cw="M03",
    spindle_ccw="M04",
    spindle_stop="M05",
    orient="M19 P{angle}",
    css=None,
    css_off=None,
    tool_change="M06",
    tool_length="G10 L10 P{tool} R{length}|G43 H{tool}",
    tool_register_add=None,
    tool_table_length="G10 L10 P{register} R{length}",
    mist="M07",
    flood="M08",
    coolant_off="M09",
    feed_override=None,
    speed_override=None,
    stop="M00",
    optional_stop="M01",
    end="M30",
    pallet="M50",
    work_offsets=("G54", "G55", "G56", "G57", "G58", "G59"),
    extended_offset="G154 P{register}",
    extended_offsets=99,
    extended_offset_set="G10 L20 P{register} {axes}",
    tool_table_set=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    own_m_codes=frozenset(
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 19, 29, 30, 48, 49, 50, 60, 97, 98, 99}
    ),  # the reader's own
    machine_function="M{code:02d}",  # M codes it does not define go to the PLC
    machine_function_words="PQ",
    xy_rotation=None,  # G68 rotates the commanded path itself; the IR keeps it apart
    cutter_comp=None,
    comp_radius_set="G10 L12 P{register} R{radius}",
    cycle_dwell_ms=True,
    notes=(
        "NURBS, ELLIPSE_FEED: approximated by arcs/lines",
        "G33 threading: not on Haas mills (refused)",
        "multi-turn arcs: expanded; absolute centres: written incremental",
        "G64 tolerance (Haas uses G187), override switches, messages: not written",
    ),
)
