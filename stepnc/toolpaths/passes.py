"""Cutting parameters shared by the slot and step generators: allowances, axial layers,
stepover and retract plane of a side or bottom-and-side milling operation (ISO 14649-11
§4.2.5-4.2.6 attributes; defaults as NIST's ``ISO14649_ALLOW``/``_UP`` and the pocket
generator, docs/stepnc.md)."""

from __future__ import annotations

from dataclasses import dataclass

from stepnc.executor import ALLOW, TINY, UP
from stepnc.model import Entity, tool_dimension
from stepnc.toolpaths.code import check_count


@dataclass(frozen=True)
class Passes:
    diameter: float
    side: float  # side allowance left on the walls
    levels: tuple[float, ...]  # Z of each layer's floor (feature coordinates), top down
    stepover: float  # largest distance between neighbouring strokes
    retract: float  # retract plane above the feature top


def _opt(op: Entity, name: str) -> float | None:
    """An optional real attribute; side milling has no ``allowance_bottom``."""
    value = getattr(op, name, None)
    return None if value is None else float(value)


def passes_of(op: Entity, depth: float) -> Passes:
    """Layers and stepover for milling ``depth`` below the feature top with ``op``.

    Rough milling leaves 0.2 mm on walls and floor unless allowances are given; finish
    milling leaves none. Side milling machines the full depth (it has no bottom allowance)
    with a default axial depth of the tool's cutting edge length; bottom-and-side milling
    defaults to D/2 (as the pocket generator). The radial depth defaults to D/2 (overlap
    0.5) and is capped at D. Layers are equal, no deeper than the axial depth."""
    dim = tool_dimension(op.its_tool)
    diameter = float(dim.diameter)
    finish = op.type.endswith("FINISH_MILLING")
    side_milling = op.type.startswith("SIDE_")
    side = _opt(op, "allowance_side")
    side = (0.0 if finish else ALLOW) if side is None else side
    bottom = 0.0 if side_milling else _opt(op, "allowance_bottom")
    bottom = (0.0 if finish else ALLOW) if bottom is None else bottom
    axial = _opt(op, "axial_cutting_depth")
    if axial is None:
        edge = dim.cutting_edge_length
        axial = float(edge) if side_milling and edge is not None else diameter / 2.0
    radial = _opt(op, "radial_cutting_depth")
    # a radial depth above the diameter would leave ribs between strokes: capped at D
    stepover = diameter / 2.0 if radial is None else min(radial, diameter)
    mill_depth = depth - bottom
    if mill_depth <= TINY or axial <= TINY or stepover <= TINY:
        raise ValueError("depth less bottom allowance, axial and radial depths must be positive")
    check_count(1 + (mill_depth - TINY) / axial, "layers of the operation")
    n = 1 + int((mill_depth - TINY) / axial)
    levels = tuple(-mill_depth * k / n for k in range(1, n + 1))
    retract = _opt(op, "retract_plane")
    return Passes(diameter, side, levels, stepover, UP if retract is None else retract)


def outside_in(rotation: str, cutmode: str) -> bool:
    """Whether contour-parallel loops run from the outside in (ISO 14649-11 §4.2.8.2).

    With a clockwise spindle, climb milling keeps the material on the tool's right. Loops
    turning counterclockwise have the loop's outside on their right, so CCW climb (and CW
    conventional) clears inside out; CCW conventional and CW climb leave the uncut
    material inside the loop, which is clearing from the outside in."""
    return (rotation, cutmode) in (("CW", "CLIMB"), ("CCW", "CONVENTIONAL"))
