"""Reader of Fanuc 0i/30i programs (milling; lathe mode with ``lathe=True``) into the IR.

The readers' contract (:mod:`gcode.readers`): :func:`interpret` and :func:`interpret_text` return
generators of canonical commands and raise :class:`~kernel.diagnostics.Diagnostic`
(``FANUC-*``) at the first error. Semantics: docs/readers/fanuc.md; implementation in
:mod:`gcode.fanuc`.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import replace

from gcode.fanuc.flow import read, read_chunks, read_text
from gcode.fanuc.options import FANUC, Flavour
from gcode.ngc.interpreter import InterpreterOptions
from kernel.ir import canon


def flavour(*, lathe: bool = False, polar_book_convention: bool = False) -> Flavour:
    return replace(FANUC, lathe=lathe, polar_book_convention=polar_book_convention)


def interpret(
    path: str | os.PathLike[str],
    options: InterpreterOptions | None = None,
    *,
    lathe: bool = False,
    polar_book_convention: bool = False,
) -> Iterator[canon.Command]:
    """Canonical commands of the Fanuc program in ``path`` (streaming)."""
    fl = flavour(lathe=lathe, polar_book_convention=polar_book_convention)
    return read(os.fspath(path), options or InterpreterOptions(), fl)


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret` (a mill), with the runs of plain blocks of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays; ``arcs``: runs may hold arcs."""
    return read_chunks(os.fspath(path), options or InterpreterOptions(), FANUC, arcs)


def interpret_text(
    text: str,
    name: str = "<input>",
    options: InterpreterOptions | None = None,
    *,
    lathe: bool = False,
    polar_book_convention: bool = False,
) -> Iterator[canon.Command]:
    """Canonical commands of a Fanuc program given as text."""
    fl = flavour(lathe=lathe, polar_book_convention=polar_book_convention)
    return read_text(text, name, options or InterpreterOptions(), fl)
