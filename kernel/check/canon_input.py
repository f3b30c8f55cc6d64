"""Canonical text as a program for ``check``, keeping LinuxCNC's work offsets.

:func:`kernel.canon.read_commands` drops LinuxCNC's ``SET_G5X_OFFSET`` / ``SET_G92_OFFSET``
(they have no NISTIR counterpart). The checker needs them for travel limits, so this reader
folds them into one ``SET_ORIGIN_OFFSETS`` (G5x + G92, in the current units, as NISTIR 5970
§3.3 defines the program origin). ``SET_XY_ROTATION`` must be zero: a rotated coordinate
system is reported as ``CANON-ROTATION`` rather than checked wrongly.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from kernel import canon
from kernel.diagnostics import Diagnostic, Location


def _vals(tc: canon.TextCommand, skip: int) -> list[float]:
    try:
        v = [float(a) for a in tc.args[skip:]]
    except ValueError:
        raise Diagnostic(
            "CANON-SYNTAX",
            f"cannot read {tc.name}({', '.join(tc.args)})",
            Location(None, tc.line, 1),
        ) from None
    return (v + [0.0] * 6)[:6]


def commands_with_offsets(lines: Iterable[str], file: str | None = None) -> Iterator[canon.Command]:
    """Read canonical text (ours or LinuxCNC ``rs274``) into IR commands, offsets included."""
    g5x = [0.0] * 6
    g92 = [0.0] * 6
    for tc in canon.read_text(lines, file):
        loc = Location(file, tc.line, 1)
        if tc.name in ("SET_G5X_OFFSET", "SET_G92_OFFSET"):
            if tc.name == "SET_G5X_OFFSET":
                g5x = _vals(tc, 1)
            else:
                g92 = _vals(tc, 0)
            s = [a + b for a, b in zip(g5x, g92, strict=True)]
            yield canon.SetOriginOffsets(*s, source=loc)
            continue
        if tc.name == "SET_XY_ROTATION":
            if any(abs(v) > 1e-9 for v in _vals(tc, 0)[:1]):
                raise Diagnostic(
                    "CANON-ROTATION", "rotated coordinate systems (G10 L2 R) are not supported", loc
                )
            continue
        if tc.name in canon.LINUXCNC_ONLY and tc.name not in (
            "SET_FEED_MODE",
            "SET_SPINDLE_MODE",
            "SET_NAIVECAM_TOLERANCE",
        ):
            continue
        yield canon.parse_command(tc, file)
