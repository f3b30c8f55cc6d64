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


class RepeatGuard:
    """The states a main program was in at its unconditional jumps back (Fanuc ``GOTO``,
    Siemens ``GOTOB``/``ENDLOOP``): arriving again and again in a state seen before, nothing
    can leave the loop, so the control would run it for ever (a production loop). At most
    ``max_states`` states are kept (a memory bound); :meth:`endless` is true after more than
    ``max_repeats`` such arrivals, and the reader then stops with its loop-limit error."""

    __slots__ = ("max_repeats", "max_states", "repeats", "states")

    def __init__(self, max_states: int, max_repeats: int) -> None:
        self.max_states = max_states
        self.max_repeats = max_repeats
        self.states: set[tuple[object, ...]] = set()
        self.repeats = 0  # arrivals at a jump back in a state seen before

    def endless(self, state: tuple[object, ...]) -> bool:
        """Record an arrival in ``state``; true once the loop has shown it never ends."""
        if state not in self.states:
            if len(self.states) < self.max_states:
                self.states.add(state)
            return False
        self.repeats += 1
        return self.repeats > self.max_repeats
