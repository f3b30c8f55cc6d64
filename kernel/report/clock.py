"""Times and numbers as a person reads them: the one clock format of every text, HTML and
JSON output (``cnc plan``, ``cnc run``, the HTML reports).

A time of a minute or more is ``M:SS`` (``2037.6 s`` -> ``33:58``), of an hour or more
``H:MM:SS`` (``3723 s`` -> ``1:02:03``), whole seconds rounded to nearest (halves up).
Under a minute the tenths are kept, ``0:42.5``: a short program must not read as
``0:00``, and a machinist comparing two short cycles wants the tenth. A value that rounds
up across a boundary takes the longer form (``59.96 s`` -> ``1:00``). Negative times keep
their sign; a time that is not finite is ``-``.
"""

from __future__ import annotations

import math


def clock(seconds: float) -> str:
    """``seconds`` as ``H:MM:SS``, ``M:SS`` or (under a minute) ``0:SS.s``."""
    if not math.isfinite(seconds):
        return "-"
    sign = "-" if seconds < 0 else ""
    s = abs(seconds)
    tenths = math.floor(s * 10 + 0.5)  # halves round up
    if tenths < 600:
        if tenths == 0:
            sign = ""  # no "-0:00.0"
        return f"{sign}0:{tenths // 10:02d}.{tenths % 10}"
    whole = math.floor(s + 0.5)
    hours, rest = divmod(whole, 3600)
    minutes, secs = divmod(rest, 60)
    if hours:
        return f"{sign}{hours}:{minutes:02d}:{secs:02d}"
    return f"{sign}{minutes}:{secs:02d}"


def fixed(value: float, digits: int = 3) -> str:
    """``value`` with ``digits`` decimals, never ``-0.0``: a value that rounds to zero
    prints without its sign (a stand-still axis has jerk ``-0.0`` from the arithmetic)."""
    text = f"{value:.{digits}f}"
    if text.startswith("-") and float(text) == 0.0:
        return text[1:]
    return text


__all__ = ["clock", "fixed"]
