"""Canned-cycle marks: where a reader expanded a drilling cycle, for writers that keep it.

The IR has no canned cycles (NISTIR 5970: the interpreter expands them into straight
moves and dwells). ``cnc convert --cycles keep`` asks the RS274/NGC machine model (also
under the Fanuc and Haas readers) to bracket each cycle block's expansion with
:class:`CycleStart` and :class:`CycleEnd`; a writer whose dialect has the cycle writes one
cycle block instead of the moves between them, any other writer ignores the marks. The
marks exist only on that path: ``canon``, ``plan`` and ``run`` never see them.
"""

from __future__ import annotations

from typing import ClassVar

from kernel.ir import canon
from kernel.record import record


@record
class CycleStart(canon.Command):
    """One cycle block: ``code`` as in gcode.ngc.cycles (810 = G81), the first hole at
    (``first``, ``second``) in the plane, ``r`` and ``bottom`` absolute along the hole
    axis, all in program units; ``repeats`` is its L (or Fanuc K) count."""

    NAME: ClassVar[str] = "CANNED_CYCLE"
    code: int
    plane: canon.Plane
    retract_r: bool  # G99 (back to R) or G98 (back to the initial level)
    first: float
    second: float
    r: float
    bottom: float
    q: float
    p: float
    repeats: int


@record
class CycleEnd(canon.Command):
    """The end of a cycle block's expansion; ``position`` is where it leaves the tool."""

    NAME: ClassVar[str] = "CANNED_CYCLE_END"
    position: tuple[float, ...]
