"""What the user controls when writing G-code: a leaf, so that the writer, its handlers,
the number formatter and the Sandia writer all share one typed options object."""

from __future__ import annotations

from dataclasses import dataclass

ARC_FORMATS = ("ijk", "ijk-abs", "r")
CYCLE_MODES = ("keep", "expand")


@dataclass(frozen=True)
class WriterOptions:
    """What the user controls. ``units``/``decimals``/``max_line_length`` None: as given."""

    arc_format: str = "ijk"  # ijk (incremental centres) | ijk-abs | r
    units: str | None = None  # None: the program's own | "mm" | "inch"
    line_numbers: int = 0  # increment; 0: no N words
    decimals: int | None = None  # None: the dialect's default for the output units
    header: tuple[str, ...] | None = None  # None: the dialect's program frame
    footer: tuple[str, ...] | None = None
    max_line_length: int | None = None  # None: the dialect's limit
    on_missing: str = "approximate"  # approximate | refuse
    tolerance: float = 0.001  # approximation tolerance, output length units
    comments: bool = True
    # write the machine's tool table (G10 L10 / G10 L1) where the program sets a length by
    # value or edits the table; off: such a program is refused (CONV-TOOL-TABLE)
    write_tool_table: bool = False
    # with write_tool_table and a tool table given: a kept register's length (from that
    # table) is written into the machine's table before G43 H
    write_tool_lengths: bool = False
    cycles: str = "expand"  # keep: drilling cycles as cycle blocks where the target has them
