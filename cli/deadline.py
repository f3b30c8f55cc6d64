"""A per-program time limit that works the same in a process pool and on a Dask worker.

A worker runs a program in whatever thread it was given (a pool process's main thread, a Dask
worker's task thread), so ``signal.alarm`` cannot be used. Instead a timer thread raises
:class:`ProgramTimeout` in the working thread when the limit passes. Python raises it at the
next bytecode, so a program stuck in the interpreter's loops stops; a single long call into
compiled code (numba, numpy) finishes first and stops after it.
"""

from __future__ import annotations

import ctypes
import threading
from types import TracebackType

#: seconds between raising the timeout again while the program has not stopped
REFIRE = 0.5


class ProgramTimeout(BaseException):  # noqa: N818 - not an Exception: ``except Exception`` must not swallow it
    """The program ran past its time limit (a BaseException, so no handler inside the
    pipeline mistakes it for a bug of the program and records it as such)."""


class deadline:  # noqa: N801 - used as a context manager, like contextlib's
    """``with deadline(seconds):`` raises :class:`ProgramTimeout` in this thread after
    ``seconds`` (None or <= 0: no limit)."""

    def __init__(self, seconds: float | None) -> None:
        self.seconds = seconds
        self._lock = threading.Lock()
        self._done = False
        self._timer: threading.Timer | None = None
        self._thread = 0
        self._fired = False

    def _fire(self) -> None:
        with self._lock:
            if not self._done:
                self._fired = True
                ctypes.pythonapi.PyThreadState_SetAsyncExc(
                    ctypes.c_ulong(self._thread), ctypes.py_object(ProgramTimeout)
                )
                # again until the block ends: an exception raised while a generator is
                # being finalised is printed and dropped ("Exception ignored in"), and the
                # program would then run on past its limit
                self._timer = threading.Timer(REFIRE, self._fire)
                self._timer.daemon = True
                self._timer.start()

    def __enter__(self) -> deadline:
        if self.seconds is not None and self.seconds > 0:
            self._thread = threading.get_ident()
            self._timer = threading.Timer(self.seconds, self._fire)
            self._timer.daemon = True
            self._timer.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        with self._lock:
            self._done = True
            if self._timer is not None:
                self._timer.cancel()
            if self._fired and kind is None:  # fired as the block ended: raise it here, once
                ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(self._thread), None)
                raise ProgramTimeout
