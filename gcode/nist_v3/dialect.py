"""NIST RS274/NGC interpreter version 3 (seed 002, research/seed-canon-rs274.md §4-5).

The v3 language has no O-words, named parameters, NURBS, G33 threading, G95, G96, G90.1,
G43.1, G64 P/Q, M19 or M50/M51; tool length comes only from the tool table (G43 H), and
overrides are switched together (M48/M49).
"""

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="nist_v3",
    title="NIST RS274/NGC interpreter v3",
    reference="seed 002 §2; research/seed-canon-rs274.md §4-5",
    decimals_mm=5,
    decimals_inch=5,
    header=("%",),
    footer=("%",),
    feed_modes=("G94", "G93", None),
    turns_word=None,
    blend_word=None,
    naive_word=None,
    thread=None,
    orient=None,
    css=None,
    css_off=None,
    tool_length="G43 H{tool}",
    tool_register_add=None,
    tool_table_length=None,
    feed_override=None,
    speed_override=None,
    work_offsets=("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"),
    tool_table_set=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    local_offset=None,
    xy_rotation=None,
    cutter_comp=None,
    comp_register=None,
    cycles=frozenset({"G81", "G82", "G83", "G85", "G89"}),  # G73 is LinuxCNC's
    notes=(
        "NURBS, ELLIPSE_FEED: approximated; multi-turn arcs (LinuxCNC's P): expanded",
        "G64 tolerance, G95, G96, G33, M19: not in v3",
        "tool length: G43 H<tool> from the tool table only (the value is not in the program)",
        "separate feed/speed override switches: only M48/M49 together",
    ),
)
