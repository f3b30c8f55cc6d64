"""The Sandia generic language as a writer target (seed 003 Fig. 3 and App. A)."""

from __future__ import annotations

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="sandia",
    title="Sandia generic CNC language",
    reference="seed 003 Fig. 3 and App. A; research/seed-sandia-full.md §5.3-5.4",
    structure="commands",
    comment="# {}",
    comment_forbidden="\n",
    message=None,
    min_decimals=1,
    axes="XYZ",
    xy_rotation=None,
    cutter_comp=None,
    comp_register=None,
    work_offsets=("G54", "G55", "G56", "G57", "G58", "G59"),
    tool_table_set=None,
    tool_register=None,
    tool_register_add=None,
    tool_table_length=None,
    tool_number=None,
    rigid_tap=None,
    io_codes=False,
    local_offset=None,
    cycles=frozenset(),
    origin=None,
    notes=(
        "no arcs, NURBS or ellipses: chords within the tolerance",
        "no spindle, coolant, dwell, stops or program end: dropped with a report entry",
        "MoveTo is world space: A/B/C need a kinematic model and are refused",
    ),
)
