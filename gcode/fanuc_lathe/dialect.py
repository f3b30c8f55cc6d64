"""Fanuc 0i-TF lathe, G code system A (book Appendix A Table A.1; research/seed-book-interp.md).

The Fanuc milling vocabulary (gcode/fanuc/dialect.py) with a lathe's differences: X and Z
axes only, X programmed as a diameter (the IR's x is the radius), ZX plane, no G90/G91
(absolute X Z, incremental U W: the writer writes absolute), G98 feed per minute and G99
per revolution (the power-on mode), G32 threads with lead F, ``G50 S`` clamps the
constant-surface-speed spindle, ``T0101`` (turret position and offset, no M06) changes the
tool, and the turning cycles G70-G76/G90/G92/G94 are expanded by the reader (the IR holds
their moves). Arc centres I K are radius increments (not doubled).
"""

from dataclasses import replace

from gcode.fanuc.dialect import DIALECT as FANUC

DIALECT = replace(
    FANUC,
    name="fanuc_lathe",
    title="Fanuc 0i-TF lathe",
    reference="book Appendix A Table A.1 (004_7d7d120ca44a306a.txt); Fanuc 0i-TF manuals",
    axes="XZ",
    diameter="X",
    initial_feed_mode=2,
    absolute="",
    nurbs=None,
    feed_modes=("G98", None, "G99"),
    thread=("G32", "F"),
    css="G50 S{max}|G96 S{speed}",
    tool_change="",
    tool_word="T{tool:02d}{tool:02d}",
    tool_length=None,
    tool_register=None,
    tool_register_add=None,
    tool_table_length=None,
    cycles=frozenset(),
    comp_register=None,
    comp_radius_set=None,
    # the lathe reader has G54-G59 only (no additional work offsets G54.1 P)
    extended_offset=None,
    extended_offsets=0,
    extended_offset_set=None,
    notes=(
        "X as a diameter; arcs' I as a radius increment",
        "turning cycles: the reader's moves are written (no G70-G76 blocks)",
        "NURBS, ellipses, multi-turn arcs: approximated or expanded",
        "Y, A, B, C: not on this lathe (refused)",
    ),
)
