"""The settings LinuxCNC's interpreter takes from a machine's INI file (``rs274 -i FILE``).

LinuxCNC 2.9 reads, at start-up, ``[RS274NGC] SUBROUTINE_PATH`` (a ``:``-separated list of
folders searched for ``<name>.ngc``), ``INI_VARS`` (on unless 0: ``#<_ini[section]name>``
reads ``NAME`` of ``[SECTION]`` as a read-only number) and ``DISABLE_FANUC_STYLE_SUB``
(``M98``/``M99`` programs refused) and ``DISABLE_G92_PERSISTENCE`` (the G92 offset
#5210-#5219 of the parameter file not kept). This module reads those from the file's text into
:class:`IniSettings`; :func:`with_ini` puts them into the interpreter's options. A line is
``[SECTION]``, ``NAME = value``, or a comment starting with ``#`` or ``;``; the first of
repeated names wins, as LinuxCNC's ``IniFile::Find`` returns the first.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field

from gcode.ngc.context import InterpreterOptions


@dataclass(frozen=True)
class IniSettings:
    """What the interpreter uses of an INI file."""

    values: dict[tuple[str, str], str] = field(default_factory=dict)  # (SECTION, NAME) -> text
    folder: str = "."  # relative paths in the file are taken from here

    def get(self, section: str, name: str) -> str | None:
        return self.values.get((section.upper(), name.upper()))

    def flag(self, section: str, name: str, default: bool) -> bool:
        """A yes/no setting: a number (0 is no) or TRUE/YES/ON, FALSE/NO/OFF; else ``default``."""
        text = (self.get(section, name) or "").strip().upper()
        if text in ("TRUE", "YES", "ON"):
            return True
        if text in ("FALSE", "NO", "OFF"):
            return False
        number = _number(text)
        return default if number is None else number != 0.0

    @property
    def subroutine_path(self) -> tuple[str, ...]:
        text = self.get("RS274NGC", "SUBROUTINE_PATH")
        if not text:
            return ()
        return tuple(os.path.join(self.folder, p.strip()) for p in text.split(":") if p.strip())

    @property
    def ini_vars(self) -> dict[tuple[str, str], float]:
        """The numeric values ``#<_ini[section]name>`` can read (empty when INI_VARS is 0)."""
        if not self.flag("RS274NGC", "INI_VARS", True):
            return {}
        numbers = {key: _number(text) for key, text in self.values.items()}
        return {key: n for key, n in numbers.items() if n is not None}


def _number(text: str | None) -> float | None:
    if text is None:
        return None
    try:
        return float(text.split()[0]) if text.split() else None
    except ValueError:
        return None


def read_ini_text(text: str, folder: str = ".") -> IniSettings:
    """The settings of an INI file's text (``folder``: where the file is)."""
    values: dict[tuple[str, str], str] = {}
    section = ""
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        if line.startswith("[") and "]" in line:
            section = line[1 : line.index("]")].strip().upper()
            continue
        if "=" in line:
            name, value = line.split("=", 1)
            values.setdefault((section, name.strip().upper()), value.strip())
    return IniSettings(values, folder)


def with_ini(options: InterpreterOptions, ini: IniSettings) -> InterpreterOptions:
    """``options`` with an INI file's settings (its search path before any already given)."""
    parameters = options.parameters
    if parameters is not None and ini.flag("RS274NGC", "DISABLE_G92_PERSISTENCE", False):
        # the G92 offset is not kept from the parameter file: #5210-#5219 start at 0
        parameters = {**parameters, **dict.fromkeys(range(5210, 5220), 0.0)}
    return dataclasses.replace(
        options,
        parameters=parameters,
        search_path=ini.subroutine_path + options.search_path,
        ini_values=ini.ini_vars,
        fanuc_subs=not ini.flag("RS274NGC", "DISABLE_FANUC_STYLE_SUB", False),
    )
