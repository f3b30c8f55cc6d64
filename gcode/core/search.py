"""Where a called subroutine or sub-program file may come from: the search directories only.

A program names the files it calls (``o<name> call``, ``M98 P1234``, Siemens ``CALL``); the
user names the directories they may come from (LinuxCNC's ``SUBROUTINE_PATH``). A name is
never a path out of them: an absolute name, a ``..`` component, or a file (or symlink) whose
real path lies outside the directory it was found in is not found, so a program cannot read
``/etc/passwd`` or ``../secret`` by calling it. The program's own directory is searched only
when no search directory is configured (:func:`search_dirs`), or when the caller puts it on
the path.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence


def unsafe_name(name: str) -> bool:
    """True for a called name that is a path rather than a name: absolute, with a ``..``
    component, a drive, a NUL, or a home-directory ``~``."""
    if not name or "\0" in name or os.path.isabs(name) or name.startswith("~"):
        return True
    parts = name.replace("\\", "/").split("/")
    return ".." in parts or ":" in parts[0]


def inside(path: str, directory: str) -> bool:
    """``path`` (already a real path) lies inside the real directory ``directory``."""
    try:
        return os.path.commonpath([path, directory]) == directory
    except ValueError:  # different drives
        return False


def find_in_dirs(dirs: Iterable[str], names: Sequence[str]) -> str | None:
    """The first of ``names`` that is a regular file in one of ``dirs`` (in order) whose real
    path (symlinks resolved) stays inside that directory's real path; None when there is none."""
    if any(unsafe_name(n) for n in names):
        return None
    for d in dirs:
        real_dir = os.path.realpath(d)
        if not os.path.isdir(real_dir):
            continue
        for name in names:
            p = os.path.join(d, name)
            if not os.path.isfile(p):
                continue
            if inside(os.path.realpath(p), real_dir):
                return p
    return None


def search_dirs(search_path: Sequence[str], program: str) -> list[str]:
    """The directories searched: the configured ones, or the directory of ``program`` (the
    calling program's file) when none is configured."""
    if search_path:
        return list(search_path)
    return [os.path.dirname(os.path.abspath(program)) if program else "."]
