"""Cycle time per tool and per operation as ``cnc plan`` and ``cnc run`` report it.

The sums are kernel.report.breakdown's; here the workingsteps of a STEP-NC program get their
names from the file (the IR carries each command's workingstep as an entity id), and the
shares become the ``times`` object of the JSON reports and a text table.

JSON (``times``): ``cycle`` seconds and ``cycle_hms`` (the clock form of
kernel.report.clock), ``tools`` and ``operations``: one object per stretch in program order
with ``label``, ``tool``, ``line``, ``start``, ``total``, ``cutting``, ``rapid``, ``dwell``,
``tool_change``, ``other`` (seconds) and ``total_hms``. ``operations`` is empty for G-code.
"""

from __future__ import annotations

from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from kernel.plan.planner import Plan
from kernel.report.breakdown import Share, Stretches, StretchSums, breakdown
from kernel.report.clock import clock


def workingstep_names(program: str, keys: set[int]) -> dict[int, str]:
    """The names (``its_id``) of the entities ``keys`` of the Part 21 file ``program``;
    an entity without a name, or a file that cannot be read again, keeps its ``#id``."""
    from stepnc.model import Model  # only for STEP-NC programs
    from stepnc.part21 import read_file

    try:
        model = Model(read_file(program))
    except Exception:  # noqa: BLE001 - the program already ran: names are a nicety
        return {}
    out = {}
    for key in keys:
        try:
            name = model.entity(key).its_id
        except Exception:  # noqa: BLE001 - not a workingstep (a rapid movement, a stop...)
            continue
        if isinstance(name, str) and name:
            out[key] = name
    return out


def shares(plan: Plan, stretches: Stretches, program: str) -> tuple[list[Share], list[Share]]:
    """The program's time per tool and per operation (workingsteps named from the file)."""
    keys = {m.key for m in stretches.operations if m.key is not None}
    names = workingstep_names(program, keys) if keys else {}
    tools = breakdown(plan, stretches.tools)
    ops = breakdown(plan, stretches.operations, names, stretches.tools)
    return tools, ops


def summed_shares(
    tools: StretchSums, operations: StretchSums, stretches: Stretches, program: str
) -> tuple[list[Share], list[Share]]:
    """:func:`shares` of a program planned window by window (kernel.stream): the sums
    kept over the marks of ``stretches``."""
    keys = {m.key for m in stretches.operations if m.key is not None}
    names = workingstep_names(program, keys) if keys else {}
    return tools.shares(), operations.shares(names, stretches.tools)


def times_doc(plan: Plan, stretches: Stretches, program: str) -> dict[str, Any]:
    """The ``times`` object of a JSON report."""
    tools, ops = shares(plan, stretches, program)
    return times_object(plan.total_time, tools, ops)


def times_object(cycle: float, tools: list[Share], ops: list[Share]) -> dict[str, Any]:
    """The ``times`` object of a JSON report: the cycle time and the shares."""
    return {
        "cycle": cycle,
        "cycle_hms": clock(cycle),
        "tools": [s.to_dict() for s in tools],
        "operations": [s.to_dict() for s in ops],
    }


def share_table(title: str, rows: list[Share], first: str) -> Table:
    """A text table of ``rows``: label (column ``first``), then the tool (operations) or
    the first source line (tools), and the times as m:ss (``stops``: dwells, tool changes
    and other stand-stills). The start of each stretch is in the JSON report."""
    t = Table(title=title)
    t.add_column(first, overflow="fold")
    t.add_column(
        "tool" if first != "tool" else "line",
        justify="left" if first != "tool" else "right",
        overflow="fold",
    )
    for col in ("cut", "rapid", "stops", "total"):
        t.add_column(f"{col} \\[m:s]", justify="right", no_wrap=True)
    for s in rows:
        c = s.cycle
        t.add_row(
            escape(s.label),
            escape(s.tool) if first != "tool" else str(s.line),
            clock(c.cutting),
            clock(c.rapid),
            clock(c.dwell + c.tool_change + c.other),
            clock(c.total),
        )
    return t


def print_shares(tools: list[Share], ops: list[Share], console: Console) -> None:
    """The per-tool table, and the per-operation one when the program has workingsteps."""
    if tools:
        console.print(share_table("time per tool (tool change to tool change)", tools, "tool"))
    if ops:
        console.print(share_table("time per operation (workingstep)", ops, "operation"))


__all__ = [
    "print_shares",
    "share_table",
    "shares",
    "summed_shares",
    "times_doc",
    "times_object",
    "workingstep_names",
]
