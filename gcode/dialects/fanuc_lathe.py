"""Fanuc 0i-TF lathe, G code system A (book Appendix A Table A.1; research/seed-book-interp.md).

The Fanuc milling vocabulary (gcode/dialects/fanuc.py) with a lathe's differences: X and Z
axes only, X programmed as a diameter (the IR's x is the radius), ZX plane, no G90/G91
(absolute X Z, incremental U W: the writer writes absolute), G98 feed per minute and G99
per revolution (the power-on mode), G32 threads with lead F, ``G50 S`` clamps the
constant-surface-speed spindle, ``T0101`` (turret position and offset, no M06) changes the
tool, and the turning cycles G70-G76/G90/G92/G94 are expanded by the reader (the IR holds
their moves). Arc centres I K are radius increments (not doubled).
"""

from gcode.dialects.spec import Dialect

DIALECT = Dialect(
    name="fanuc_lathe",
    title="Fanuc 0i-TF lathe",
    reference="book Appendix A Table A.1 (004_7d7d120ca44a306a.txt); Fanuc 0i-TF manuals",
    decimals_mm=3,
    decimals_inch=4,
    point_required=True,
    message=None,
    max_sequence_number=99999,
    header=("%", "O0001"),
    footer=("%",),
    axes="XZ",
    diameter="X",
    initial_feed_mode=2,
    absolute="",
    rapid="G00",
    linear="G01",
    arc_cw="G02",
    arc_ccw="G03",
    feed_modes=("G98", None, "G99"),
    exact_stop="G61",
    exact_path=None,
    continuous="G64",
    blend_word=None,
    naive_word=None,
    dwell=("G04", "X", 1.0),
    probe="G31",
    thread=("G32", "F"),
    spindle_cw="M03",
    spindle_ccw="M04",
    spindle_stop="M05",
    orient="M19",
    css="G50 S{max}|G96 S{speed}",
    tool_change="",
    tool_word="T{tool:02d}{tool:02d}",
    tool_length=None,
    cycles=frozenset(),
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
    tool_table_set=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    xy_rotation=None,
    cutter_comp=None,
    comp_register=None,
    notes=(
        "X as a diameter; arcs' I as a radius increment",
        "turning cycles: the reader's moves are written (no G70-G76 blocks)",
        "NURBS, ellipses, multi-turn arcs: approximated or expanded",
        "Y, A, B, C: not on this lathe (refused)",
    ),
)
