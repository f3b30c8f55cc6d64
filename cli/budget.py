"""A CPU-time budget per program in batch commands (``kernel.limits`` ``seconds``): one
runaway program in ``cnc check`` or ``cnc run`` ends with ``LIMIT-TIME`` and the batch goes
on with the next."""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location


class _OverBudget(BaseException):
    """Raised by the timer inside the program's work; a BaseException so that no
    ``except Exception`` of a reader or the kernel swallows it."""


@contextmanager
def cpu_budget(program: str) -> Iterator[None]:
    """Run the block under the ``seconds`` limit of CPU time (none when 0, or off the main
    thread where signals cannot be had); ``LIMIT-TIME`` when it is used up."""
    seconds = limits.current().seconds
    if seconds <= 0 or threading.current_thread() is not threading.main_thread():
        yield
        return

    def expire(signum: int, frame: FrameType | None) -> None:
        raise _OverBudget

    old = signal.signal(signal.SIGPROF, expire)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    except _OverBudget:
        raise Diagnostic(
            "LIMIT-TIME",
            f"more than {seconds:g} s of CPU time (--limit seconds=N)",
            Location(program),
        ) from None
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, old)
