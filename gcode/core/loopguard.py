"""The loop guard every G-code reader's flow control shares: a run stops with a located
error instead of running for ever.

Two limits, both checked where a program goes back (a backward jump, a loop's end going
back to its start), since a program that never goes back ends by itself:

* ``LOOP-LIMIT``: more than ``max_blocks`` blocks executed in the run (default 10**8), or
  one loop going back more than ``loop_passes`` times in a row (:mod:`kernel.limits`, default
  100,000: an endless loop that moves, about a second of CPU). "In a row" is per entry into
  the loop: the passes of a loop nested in another's body (or of a subroutine's loop called
  from it) start again from zero at each pass of the outer loop, so a raster of 1,000 rows
  of 1,000 points counts 1,000 passes of each loop, not 10**6. All loops together may go
  back at most ``loop_total`` times (default 10**6): nested loops, each within its own
  limit, would otherwise multiply into a run of hours.
* ``LOOP-NO-PROGRESS``: more than ``max_idle_blocks`` blocks executed since the last
  canonical command was emitted (default 100,000), i.e. a loop that computes but never moves
  nor outputs anything. A real program's computation loops between two motions run a few
  thousand blocks at most (a table of values, a search); 100,000 idle blocks stop an
  endless loop in well under a second and leave those alone.

A reader counts the blocks it executes in :attr:`LoopGuard.blocks` and the commands it
emits in :attr:`LoopGuard.output`, and calls :meth:`LoopGuard.back` at each backward jump.
"""

from __future__ import annotations

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location

MAX_BLOCKS = 10**8
MAX_IDLE_BLOCKS = 100_000
#: loop sites remembered (a memory bound for programs with very many loops one after another)
MAX_SITES = 4096
#: sites looked at, from the most recent, for loops nested in a loop seen for the first time
NEST_SCAN = 64

Site = tuple[str | None, int]


class LoopGuard:
    """Block and output counters of one run, checked at each backward jump."""

    __slots__ = (
        "blocks",
        "max_blocks",
        "max_idle",
        "output",
        "passes",
        "_mark_blocks",
        "_mark_output",
        "_sites",
        "_where",
    )

    def __init__(
        self, max_blocks: int = MAX_BLOCKS, max_idle_blocks: int = MAX_IDLE_BLOCKS
    ) -> None:
        self.max_blocks = max_blocks
        self.max_idle = max_idle_blocks
        self.blocks = 0  # blocks executed so far (the reader adds them)
        self.output = 0  # canonical commands emitted so far (the reader adds them)
        self.passes = 0  # passes of all loops (backward jumps) so far
        self._mark_blocks = 0  # block count when output last changed
        self._mark_output = 0
        # loop sites (file, line of the jump back) with their passes in a row, in the order
        # of their last pass; _where: a site's index in _sites
        self._sites: list[tuple[Site, int]] = []
        self._where: dict[Site, int] = {}

    def back(self, construct: str, loc: Location, target: int = 0) -> None:
        """A backward jump or loop pass of ``construct`` (e.g. ``"GOTOB LAB1"``, ``"WHILE
        (line 3)"``) at ``loc``, going back to line ``target`` of the same file (0: not
        known): raises LOOP-LIMIT or LOOP-NO-PROGRESS past a limit."""
        passes = self._pass((loc.file, loc.line), target)
        self.passes += 1
        if self.passes > limits.current().loop_total:
            raise Diagnostic(
                "LOOP-LIMIT",
                f"endless loop? {construct}: the program's loops went back more than "
                f"{limits.current().loop_total} times in all (--limit loop_total=N)",
                loc,
            )
        if passes > limits.current().loop_passes:
            raise Diagnostic(
                "LOOP-LIMIT",
                f"endless loop? {construct} went back {passes - 1} times in a row (limit "
                f"{limits.current().loop_passes}, --limit loop_passes=N)",
                loc,
            )
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

    def _pass(self, site: Site, target: int) -> int:
        """Count one pass of the loop at ``site``; its passes in a row."""
        sites, where = self._sites, self._where
        i = where.get(site)
        if i is not None:
            # the sites passed since this one's last pass are inside its body: their count
            # starts again
            for other, _ in sites[i + 1 :]:
                del where[other]
            passes = sites[i][1] + 1
            del sites[i:]
        else:
            passes = 1
            if target:
                # first pass: the loops of its body (same file, lines target..site) passed
                # so far were part of its first pass
                tail = max(0, len(sites) - NEST_SCAN)
                inner = [
                    j
                    for j in range(tail, len(sites))
                    if sites[j][0][0] == site[0] and target <= sites[j][0][1] <= site[1]
                ]
                if inner:
                    for j in inner:
                        del where[sites[j][0]]
                    sites[tail:] = [s for j, s in enumerate(sites[tail:], tail) if j not in inner]
                    where.update((s[0], j) for j, s in enumerate(sites[tail:], tail))
            if len(sites) >= MAX_SITES:
                del sites[: MAX_SITES // 2]
                where.clear()
                where.update((s[0], j) for j, s in enumerate(sites))
        where[site] = len(sites)
        sites.append((site, passes))
        return passes


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
