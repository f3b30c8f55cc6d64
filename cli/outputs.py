"""Writing the files a user names, safely.

Every output goes through here so that three promises hold in every command:

- an output that is (or resolves to) one of the inputs is refused, even with ``--force``
  (``IO-SAME-FILE``): ``cnc canon P -o P --force`` must not destroy P;
- an existing output, or a symlink there (even a dangling one), is kept unless ``--force``
  (``IO-EXISTS``);
- the text goes to a temporary file in the target's directory and is renamed into place when
  complete: a failed run leaves the old file (or nothing), and a symlink given as the output
  is replaced by the file, never written through.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import TextIO

from kernel.diagnostics import Diagnostic, Location


def same_file(a: str, b: str) -> bool:
    """``a`` and ``b`` name the same file (after symlinks; by inode where both exist)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def exists_message(what: str = "output file", detail: str = "") -> str:
    """The one wording of ``IO-EXISTS`` in every command: ``<what> exists<detail>; use --force
    to replace it``."""
    return f"{what} exists{detail}; use --force to replace it"


def refuse_output(
    output: str, force: bool, inputs: Iterable[str] = (), what: str = "output file"
) -> None:
    """Refuse ``output`` when it is one of ``inputs`` (always) or exists without ``force``;
    a symlink counts as existing even when it points nowhere."""
    for source in inputs:
        if source and same_file(output, source):
            raise Diagnostic(
                "IO-SAME-FILE",
                f"{what} is the input {source}; refusing to overwrite it (even with --force)",
                Location(output),
            )
    if os.path.lexists(output) and not force:
        link = " (a symlink)" if os.path.islink(output) else ""
        raise Diagnostic("IO-EXISTS", exists_message(what, link), Location(output))
    if os.path.isdir(output):
        raise Diagnostic("IO-NOT-FILE", f"{what} is a directory", Location(output))


@contextmanager
def replacing(path: str) -> Iterator[str]:
    """A temporary path beside ``path`` to write; renamed over ``path`` when the block ends
    without an error (replacing a symlink itself, not its target), removed otherwise."""
    folder = os.path.dirname(os.path.abspath(path))
    base = os.path.basename(path)
    # the temporary name keeps the target's suffix: some writers choose the format by it
    fd, tmp = tempfile.mkstemp(prefix=f".{base}.", suffix=os.path.splitext(base)[1], dir=folder)
    os.close(fd)
    try:
        yield tmp
        mode = 0o666 & ~_umask()
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    finally:
        if os.path.lexists(tmp):
            os.unlink(tmp)


@contextmanager
def open_output(path: str) -> Iterator[TextIO]:
    """``path`` opened for text (UTF-8) through :func:`replacing`."""
    with replacing(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        yield fh


def write_output(path: str, text: str) -> None:
    """``text`` into ``path`` through :func:`replacing`."""
    with open_output(path) as fh:
        fh.write(text)


def _umask() -> int:
    """The process umask (read by setting and restoring it)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
