"""RS274/NGC parameters: numbered ``#n``, local ``#<name>`` and global ``#<_name>``.

* Numbered parameters 1..5602 exist from the start with value 0 (LinuxCNC's range); the
  5xxx block holds persistent setup data (G28/G30 homes 5161-5169/5181-5189, G92 offsets
  5211-5219, coordinate systems 5221-5389 in steps of 20, current coordinate system 5220).
* Subroutine calls give the callee fresh locals: ``#1..#30`` receive the call arguments and
  named locals start empty; both are restored on return (LinuxCNC O-word semantics).
* Reading an unset named parameter is an error; ``EXISTS[#<name>]`` tests for it.
* Assignments on a line take effect after all of the line's reads (NIST v3 §3.3.2): the
  interpreter evaluates every value first, then calls :meth:`Parameters.assign`.

``.var`` files hold ``<number> <value>`` lines; :func:`read_var_text` and
:func:`write_var_text` implement them. The persistent set written back is 5161-5390 (the
NIST v3 "required parameters"), the rest is not saved.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from kernel.diagnostics import Diagnostic, Location

MAX_PARAMETER = 5602
LOCAL_ARGUMENTS = 30
PERSISTENT = range(5161, 5391)


def param_index(value: float, loc: Location) -> int:
    """Check a parameter number is an integer in range (LinuxCNC rejects others)."""
    idx = round(value)
    if abs(value - idx) > 1e-4:
        raise Diagnostic(
            "NGC-PARAM-NOT-INTEGER", f"parameter number {value:g} is not an integer", loc
        )
    if idx < 1 or idx >= MAX_PARAMETER:
        raise Diagnostic(
            "NGC-PARAM-RANGE",
            f"parameter number {idx} out of range: numbered parameters are #1 to "
            f"#{MAX_PARAMETER - 1}",
            loc,
        )
    return idx


@dataclass
class _Frame:
    locals_named: dict[str, float] = field(default_factory=dict)
    saved_numbered: list[float] = field(default_factory=list)


class Parameters:
    """Parameter store with subroutine scoping. ``predefined`` answers ``#<_x>``-style
    read-only names from interpreter state (returns ``None`` when not one of them)."""

    def __init__(
        self,
        initial: dict[int, float] | None = None,
        predefined: Callable[[str], float | None] | None = None,
    ) -> None:
        self.values: list[float] = [0.0] * MAX_PARAMETER
        for k, v in (initial or {}).items():
            if 1 <= k < MAX_PARAMETER:
                self.values[k] = v
        self.globals: dict[str, float] = {}
        self.frames: list[_Frame] = [_Frame()]
        self.predefined = predefined
        #: live values of read-only numbered parameters (5400-5428, ...); None: stored value
        self.dynamic: Callable[[int], float | None] | None = None

    # ------------------------------------------------------------------ reads
    def numbered(self, index: float, loc: Location) -> float:
        idx = param_index(index, loc)
        if idx >= 5399 and self.dynamic is not None:
            v = self.dynamic(idx)
            if v is not None:
                return v
        return self.values[idx]

    def named(self, name: str, loc: Location) -> float:
        if name.startswith("_"):
            if name in self.globals:
                return self.globals[name]
            if self.predefined is not None:
                v = self.predefined(name)
                if v is not None:
                    return v
        else:
            frame = self.frames[-1].locals_named
            if name in frame:
                return frame[name]
        raise Diagnostic("NGC-NAMED-UNDEFINED", f"named parameter #<{name}> not defined", loc)

    def exists(self, name: str) -> bool:
        if name.startswith("_"):
            return name in self.globals or (
                self.predefined is not None and self.predefined(name) is not None
            )
        return name in self.frames[-1].locals_named

    # ------------------------------------------------------------------ writes
    def set_numbered(self, index: float, value: float, loc: Location) -> None:
        self.values[param_index(index, loc)] = value

    def set_named(self, name: str, value: float, loc: Location) -> None:
        if name.startswith("_"):
            if (
                self.predefined is not None
                and self.predefined(name) is not None
                and (name not in self.globals)
            ):
                raise Diagnostic(
                    "NGC-NAMED-READONLY", f"cannot assign to read-only parameter #<{name}>", loc
                )
            self.globals[name] = value
        else:
            self.frames[-1].locals_named[name] = value

    # ------------------------------------------------------------------ scoping
    def enter(self, arguments: Iterable[float]) -> None:
        """Start a subroutine frame: save #1..#30, load the call arguments into them."""
        saved = self.values[1 : LOCAL_ARGUMENTS + 1]
        self.frames.append(_Frame(saved_numbered=saved))
        args = list(arguments)
        for i in range(1, LOCAL_ARGUMENTS + 1):
            self.values[i] = args[i - 1] if i <= len(args) else 0.0

    def leave(self) -> None:
        frame = self.frames.pop()
        if frame.saved_numbered:
            self.values[1 : LOCAL_ARGUMENTS + 1] = frame.saved_numbered

    def enter_shared(self) -> None:
        """Start an ``M98`` frame: new named locals, #1..#30 shared with the caller (rs274 2.9)."""
        self.frames.append(_Frame())

    @property
    def depth(self) -> int:
        return len(self.frames) - 1


def read_var_text(lines: Iterable[str], file: str | None = None) -> dict[int, float]:
    """Parse a ``.var`` parameter file: ``<number> <value>`` per line, ascending numbers."""
    out: dict[int, float] = {}
    last = 0
    for n, line in enumerate(lines, 1):
        text = line.split(";", 1)[0].strip()
        if not text:
            continue
        parts = text.split()
        loc = Location(file, n, 1)
        try:
            idx = int(parts[0])
            value = float(parts[1])
        except (ValueError, IndexError):
            raise Diagnostic("NGC-VAR-SYNTAX", f"bad parameter file line: '{text}'", loc) from None
        if not 1 <= idx < MAX_PARAMETER:
            raise Diagnostic("NGC-VAR-RANGE", f"parameter number {idx} out of range", loc)
        if idx <= last:
            raise Diagnostic(
                "NGC-VAR-ORDER", f"parameter {idx} out of order in parameter file", loc
            )
        last = idx
        out[idx] = value
    return out


def write_var_text(values: list[float], previous: dict[int, float] | None = None) -> str:
    """Text of a ``.var`` file holding the persistent parameters (5161-5390) and any other
    parameter that was in the previous file (LinuxCNC keeps those too)."""
    keep = set(PERSISTENT) | set(previous or {})
    return "".join(f"{i}\t{values[i]:.6f}\n" for i in sorted(keep) if 1 <= i < len(values))
