"""Starter machine profiles for ``cnc machine init --kind``: one per kind of machine.

Each preset is a profile whose ``kind`` makes ``cnc check`` judge programs as that machine
runs them (:class:`kernel.machine.KindTraits`) and whose limits are those of a typical
machine of the kind. Travel is given on both sides of the program origin (the check does
not know where the operator sets G54), so a program made for the machine fits whether its
origin is at a corner or in the middle of the table; the user narrows it to the real machine.
The values are documented in docs/machine-profile.md, "Presets".
"""

from __future__ import annotations

from dataclasses import dataclass

from kernel.machine import AxisLimits, Machine


@dataclass(frozen=True, slots=True)
class Preset:
    """A kind's starter profile: the machine, its spindle range and ``[check]`` settings.

    ``spindle`` is the (min, max) of S (rpm; the power scale of a laser), None when S
    means nothing to check (a plasma torch); ``check`` the ``[check]`` table; ``about``
    one comment line on how programs for the kind are written.
    """

    kind: str
    name: str
    axes: tuple[AxisLimits, ...]
    spindle: tuple[float, float] | None
    check: dict[str, object]
    about: str

    def machine(self) -> Machine:
        """The preset as a profile (what ``cnc machine init --kind`` writes, parsed)."""
        extra: dict[str, object] = {"check": dict(self.check)}
        if self.spindle is not None:
            extra["spindle"] = {"min_speed": self.spindle[0], "max_speed": self.spindle[1]}
        return Machine(self.name, self.axes, extra=extra, kind=self.kind)


def _axis(name: str, lo: float, hi: float, v: float, a: float, j: float) -> AxisLimits:
    return AxisLimits(name, lo, hi, velocity=v, acceleration=a, jerk=j)


PRESETS: dict[str, Preset] = {
    "mill": Preset(
        "mill",
        "my 3-axis mill",
        (
            _axis("x", -400.0, 400.0, 250.0, 2000.0, 50000.0),
            _axis("y", -250.0, 250.0, 250.0, 2000.0, 50000.0),
            _axis("z", -300.0, 200.0, 200.0, 1500.0, 40000.0),
        ),
        (0.0, 12000.0),
        {"max_dwell": 60.0, "arc_tolerance": "linuxcnc"},
        "a vertical machining centre: M3/M4 with S in rpm, M6 tool changes with G43 H",
    ),
    "router": Preset(
        "router",
        "my CNC router",
        (
            _axis("x", -1250.0, 1250.0, 400.0, 1500.0, 40000.0),
            _axis("y", -1250.0, 1250.0, 400.0, 1500.0, 40000.0),
            _axis("z", -200.0, 200.0, 150.0, 1000.0, 30000.0),
        ),
        (0.0, 24000.0),
        {"max_dwell": 60.0, "arc_tolerance": "linuxcnc"},
        "a gantry router: the spindle speed is often set by hand, so M3 comes without S",
    ),
    "laser": Preset(
        "laser",
        "my laser cutter",
        (
            _axis("x", -600.0, 600.0, 500.0, 3000.0, 100000.0),
            _axis("y", -400.0, 400.0, 500.0, 3000.0, 100000.0),
            _axis("z", -50.0, 50.0, 20.0, 500.0, 20000.0),
        ),
        (0.0, 1000.0),
        {"max_dwell": 60.0, "arc_tolerance": "grbl"},
        "a laser: M3/M4 switch the beam, S is its power (0-1000), G1 with the beam off "
        "(M5 or S0) is a travel move",
    ),
    "plasma": Preset(
        "plasma",
        "my plasma table",
        (
            _axis("x", -2500.0, 2500.0, 400.0, 2000.0, 50000.0),
            _axis("y", -1250.0, 1250.0, 400.0, 2000.0, 50000.0),
            _axis("z", -100.0, 100.0, 100.0, 1500.0, 40000.0),
        ),
        None,
        {"max_dwell": 60.0, "arc_tolerance": "linuxcnc"},
        "a plasma table: M3/M5 (or M7/M8, or M62-M65) switch the torch, G1 with the torch "
        "off is a travel move",
    ),
    "lathe": Preset(
        "lathe",
        "my 2-axis lathe",
        (
            _axis("x", -10.0, 200.0, 200.0, 2000.0, 50000.0),
            _axis("z", -600.0, 100.0, 250.0, 2000.0, 50000.0),
        ),
        (0.0, 4000.0),
        {"max_dwell": 60.0, "arc_tolerance": "linuxcnc"},
        "a lathe (XZ, G18): X is programmed as a diameter and travels as a radius, T0101 "
        "applies the tool's offsets, G96 S is a surface speed capped by G50 S",
    ),
}
