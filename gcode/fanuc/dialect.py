"""Fanuc 0i-MF / 30i-M milling (RS274/VGER-like), book Appendix A Table A.2.

Two-digit codes (``G01``), a decimal point on every length (``X10.``: without it a Fanuc
reads least input increments), IJK always incremental, no ``P`` turns on arcs, G06.2
NURBS (30i), dwell ``G04 X`` in seconds, tool length through ``G10 L10`` and ``G43 H``,
program frame ``%`` / ``O`` number / ``M30`` / ``%``, sequence numbers up to N99999.
"""

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="fanuc",
    title="Fanuc 0i/30i milling",
    reference="book Appendix A Table A.2 (004_7d7d120ca44a306a.txt); Fanuc 0i-MF/30i manuals",
    decimals_mm=3,
    decimals_inch=4,
    point_required=True,
    message=None,
    max_sequence_number=99999,
    header=("%", "O0001"),
    footer=("%",),
    rapid="G00",
    linear="G01",
    arc_cw="G02",
    arc_ccw="G03",
    nurbs="g06.2",
    exact_stop="G61",
    exact_path=None,
    continuous="G64",
    blend_word=None,
    naive_word=None,
    dwell=("G04", "X", 1.0),
    probe="G31",
    thread=("G33", "F"),
    spindle_cw="M03",
    spindle_ccw="M04",
    spindle_stop="M05",
    orient="M19",
    css="G92 S{max}|G96 S{speed}",
    tool_change="M06",
    tool_length="G10 L10 P{tool} R{length}|G43 H{tool}",
    tool_register_add=None,
    tool_table_length="G10 L10 P{register} R{length}",
    cycle_dwell_ms=True,
    origin="G10 L2 P1 {axes}",
    mist="M07",
    flood="M08",
    coolant_off="M09",
    feed_override=None,
    speed_override=None,
    stop="M00",
    optional_stop="M01",
    end="M30",
    pallet=None,
    work_offsets=("G54", "G55", "G56", "G57", "G58", "G59"),
    extended_offset="G54.1 P{register}",
    extended_offsets=48,
    extended_offset_set="G10 L20 P{register} {axes}",
    tool_table_set=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    own_m_codes=frozenset(
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 19, 29, 30, 48, 49, 60, 98, 99}
    ),  # the reader's own
    machine_function="M{code:02d}",  # M codes it does not define go to the PLC
    machine_function_words="PQ",
    xy_rotation=None,  # G68 rotates the commanded path itself; the IR keeps it apart
    cutter_comp=None,
    comp_radius_set="G10 L12 P{register} R{radius}",
    notes=(
        "absolute arc centres (G90.1), multi-turn arcs (P): not in Fanuc; incremental "
        "IJK, turns expanded into full circles",
        "G61.1 exact path: not in Fanuc (G61 exact stop written)",
        "G64 tolerance, override switches, pallet shuttle, operator messages: not written",
        "ORIENT_SPINDLE angle: M19 orients to the parameter angle only",
    ),
)
