"""The loop guard every G-code reader's flow control shares: a run stops with a located
error instead of running for ever.

Two limits, both checked where a program goes back (a backward jump, a loop's end going
back to its start), since a program that never goes back ends by itself:

* ``LOOP-LIMIT``: more than ``max_blocks`` blocks executed in the run (default 10**8).
* ``LOOP-NO-PROGRESS``: more than ``max_idle_blocks`` blocks executed since the last
  canonical command was emitted (default 100,000), i.e. a loop that computes but never moves
  nor outputs anything. A real program's computation loops between two motions run a few
  thousand blocks at most (a table of values, a search); 100,000 idle blocks stop an
  endless loop in well under a second and leave those alone.

A reader counts the blocks it executes in :attr:`LoopGuard.blocks` and the commands it
emits in :attr:`LoopGuard.output`, and calls :meth:`LoopGuard.back` at each backward jump.
"""

from __future__ import annotations

from kernel.diagnostics import Diagnostic, Location

MAX_BLOCKS = 10**8
MAX_IDLE_BLOCKS = 100_000


class LoopGuard:
    """Block and output counters of one run, checked at each backward jump."""

    __slots__ = ("blocks", "max_blocks", "max_idle", "output", "_mark_blocks", "_mark_output")

    def __init__(
        self, max_blocks: int = MAX_BLOCKS, max_idle_blocks: int = MAX_IDLE_BLOCKS
    ) -> None:
        self.max_blocks = max_blocks
        self.max_idle = max_idle_blocks
        self.blocks = 0  # blocks executed so far (the reader adds them)
        self.output = 0  # canonical commands emitted so far (the reader adds them)
        self._mark_blocks = 0  # block count when output last changed
        self._mark_output = 0

    def back(self, construct: str, loc: Location) -> None:
        """A backward jump or loop pass of ``construct`` (e.g. ``"GOTOB LAB1"``, ``"WHILE
        (line 3)"``) at ``loc``: raises LOOP-LIMIT or LOOP-NO-PROGRESS past a limit."""
        if self.output != self._mark_output:
            self._mark_output = self.output
            self._mark_blocks = self.blocks
        elif self.blocks - self._mark_blocks > self.max_idle:
            raise Diagnostic(
                "LOOP-NO-PROGRESS",
                f"endless loop? {construct} ran {self.blocks - self._mark_blocks} blocks "
                f"with no motion or output (limit {self.max_idle})",
                loc,
            )
        if self.blocks > self.max_blocks:
            raise Diagnostic(
                "LOOP-LIMIT",
                f"endless loop? {construct}: more than {self.max_blocks} blocks executed",
                loc,
            )
