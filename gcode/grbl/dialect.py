"""Grbl 1.1 (3-axis hobby controller): its subset of RS274/NGC and its limits.

Grbl 1.1 reads G0-G4, G10 L2/L20, G17-G19, G20/G21, G38.2-G38.5, G40, G43.1, G49,
G53-G59, G61, G80, G90/G91, G91.1, G92, G93/G94, M0-M2, M30, M3-M5, M7-M9 and the words
F I J K L N P R S T X Y Z; a block is at most 80 characters (``LINE_BUFFER_SIZE``).
There is no tool changer (M6), no A/B/C axis, no G95/G96, G33, G64, G61.1, M19 or NURBS.
"""

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="grbl",
    title="Grbl 1.1",
    reference="Grbl v1.1 commands wiki; grbl/gcode.c",
    decimals_mm=3,
    decimals_inch=4,
    max_line_length=80,
    axes="XYZ",
    feed_modes=("G94", "G93", None),
    exact_stop=None,
    exact_path="G61",
    continuous=None,
    blend_word=None,
    naive_word=None,
    thread=None,
    orient=None,
    css=None,
    css_off=None,
    tool_change=None,
    feed_override=None,
    speed_override=None,
    pallet=None,
    end="M2",
    work_offsets=("G54", "G55", "G56", "G57", "G58", "G59"),
    tool_table_set=None,
    tool_register=None,
    tool_register_add=None,
    tool_table_length=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    local_offset=None,
    xy_rotation=None,
    cutter_comp=None,
    comp_register=None,
    cycles=frozenset(),
    notes=(
        "no tool changer: a tool change becomes M0 with a comment (manual change)",
        "no A/B/C axes: a rotary motion is refused",
        "G64/G61.1: not in Grbl (it always blends by junction deviation)",
        "NURBS, ELLIPSE_FEED, multi-turn arcs: approximated or expanded",
    ),
)
