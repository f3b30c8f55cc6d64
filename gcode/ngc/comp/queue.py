"""The held-move queue of cutter radius compensation (LinuxCNC ``interp_queue.cc``).

A compensated move is held until the next one shows whether its end must move (concave
corner) or an arc must follow it (convex corner). Commands LinuxCNC queues behind it are
held too and released in order. Semantics learnt from LinuxCNC's ``enqueue_*``,
``dequeue_canons``, ``move_endpoint_and_flush``, ``set_endpoint`` and ``qc_scale``,
including two quirks rs274's output depends on:

* the gouge tests compare each held line's *programmed* direction with its new direction
  from the held start point (``endpoint``), and each held arc's programmed sweep with its
  new sweep; they apply only while that start point is valid;
* ``front()`` of an empty queue reads the stale first slot of the underlying vector: the
  first command of the last non-empty queue (:meth:`MotionQueue.front`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

from gcode.ngc import offset_geometry as geo
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

Point = tuple[float, float]


@dataclass(slots=True)
class HeldMove:
    """A held motion in plane coordinates (LinuxCNC ``queued_canon``)."""

    kind: str  # "feed", "traverse" or "arc"
    end: Point
    normal: float  # end on the axis normal to the plane
    abc: tuple[float, float, float]
    source: Location | None
    direction: Point = (0.0, 0.0)  # lines: the direction the gouge test compares with
    centre: Point = (0.0, 0.0)
    turn: int = 0
    sweep: float = 0.0  # arcs: programmed swept angle (0: not checked)

    @property
    def is_arc(self) -> bool:
        return self.kind == "arc"

    @property
    def radius(self) -> float:
        return math.hypot(self.centre[0] - self.end[0], self.centre[1] - self.end[1])


Held = HeldMove | canon.Command


class MotionQueue:
    """LinuxCNC's ``qc()`` vector with its ``endpoint`` (start of the held motion)."""

    def __init__(self) -> None:
        self.items: list[Held] = []
        self._last_front: Held | None = None
        self.endpoint: Point = (0.0, 0.0)
        self.endpoint_valid = False

    def __bool__(self) -> bool:
        return bool(self.items)

    def front(self) -> Held | None:
        """``qc().front()``; on an empty queue, the stale first slot (see module doc)."""
        return self.items[0] if self.items else self._last_front

    def front_arc(self) -> HeldMove | None:
        """The front if it is a held arc (LinuxCNC ``front().type == QARC_FEED``)."""
        f = self.front()
        return f if isinstance(f, HeldMove) and f.is_arc else None

    def push(self, item: Held) -> None:
        if not self.items:
            self._last_front = item
        self.items.append(item)

    def set_endpoint(self, p: Point) -> None:
        self.endpoint = p
        self.endpoint_valid = True

    def release(self, emit: Callable[[HeldMove], canon.Command]) -> list[canon.Command]:
        """``dequeue_canons``: everything held, in order; the endpoint becomes invalid."""
        self.endpoint_valid = False
        out = [emit(q) if isinstance(q, HeldMove) else q for q in self.items]
        self.items.clear()
        return out

    def move_endpoint_and_release(
        self,
        p: Point,
        source: Location | None,
        emit: Callable[[HeldMove], canon.Command],
        inches: bool,
    ) -> list[canon.Command]:
        """``move_endpoint_and_flush``: every held motion now ends at ``p``; release.

        A held arc may not sweep more than programmed; LinuxCNC's slack for that is 0.001
        rad in inch programs and 0.0254 rad in mm programs.
        """
        slack = 0.001 if inches else 0.0254
        if not self.items:
            return []
        for i, q in enumerate(self.items):
            if not isinstance(q, HeldMove):
                continue
            if q.is_arc:
                r1 = q.radius
                r2 = math.hypot(p[0] - q.centre[0], p[1] - q.centre[1])
                sweep = geo.find_turn(self.endpoint, q.centre, q.turn, p)
                if abs(r1 - r2) > 0.01:
                    raise Diagnostic(
                        "NGC-COMP-BUG",
                        "cutter compensation has generated an invalid arc with mismatched "
                        f"radii r1 {r1:f} r2 {r2:f}",
                        source,
                    )
                if q.sweep and self.endpoint_valid and abs(sweep) > abs(q.sweep) + slack:
                    raise Diagnostic(
                        "NGC-COMP-GOUGE",
                        "Arc move in concave corner cannot be reached by the tool without gouging",
                        source,
                    )
            else:
                dx, dy = p[0] - self.endpoint[0], p[1] - self.endpoint[1]
                if self.endpoint_valid and q.direction[0] * dx + q.direction[1] * dy < 0:
                    what = "Straight traverse" if q.kind == "traverse" else "Straight feed"
                    raise Diagnostic(
                        "NGC-COMP-GOUGE",
                        f"{what} in concave corner cannot be reached by the tool without gouging",
                        source,
                    )
            self.items[i] = replace(q, end=p)
        out = self.release(emit)
        self.set_endpoint(p)
        return out

    def scale(self, factor: float) -> None:
        """``qc_scale`` (units change): the endpoint is scaled once per held command."""
        for i, q in enumerate(self.items):
            self.endpoint = (self.endpoint[0] * factor, self.endpoint[1] * factor)
            if isinstance(q, HeldMove):
                self.items[i] = replace(
                    q,
                    end=(q.end[0] * factor, q.end[1] * factor),
                    centre=(q.centre[0] * factor, q.centre[1] * factor),
                    normal=q.normal * factor,
                )


def lathe_origin(
    plane: canon.Plane, orientation: int, radius: float, x: float, z: float
) -> tuple[float, float]:
    """Tool-origin point of a lathe tool whose nose centre is at (x, z) (orientations 1-8).

    Mill tools (orientation 0 or 9) and planes other than XZ are unchanged.
    """
    if plane != canon.Plane.XZ:
        return x, z
    if orientation in (2, 6, 1):
        x -= radius
    if orientation in (3, 8, 4):
        x += radius
    if orientation in (2, 7, 3):
        z -= radius
    if orientation in (1, 5, 4):
        z += radius
    return x, z


def motion_command(
    q: HeldMove, plane: canon.Plane, orientation: int, radius: float
) -> canon.Command:
    """The canonical command of a held motion (plane order back to x y z)."""
    a, b, c = q.abc
    if plane == canon.Plane.XZ:
        x, z = lathe_origin(plane, orientation, radius, q.end[1], q.end[0])
        if q.is_arc:
            cx, cz = lathe_origin(plane, orientation, radius, q.centre[1], q.centre[0])
            return canon.ArcFeed(z, x, cz, cx, q.turn, q.normal, a, b, c, source=q.source)
        cls = canon.StraightTraverse if q.kind == "traverse" else canon.StraightFeed
        return cls(x, q.normal, z, a, b, c, source=q.source)
    if q.is_arc:
        e, m = q.end, q.centre
        return canon.ArcFeed(e[0], e[1], m[0], m[1], q.turn, q.normal, a, b, c, source=q.source)
    cls = canon.StraightTraverse if q.kind == "traverse" else canon.StraightFeed
    return cls(q.end[0], q.end[1], q.normal, a, b, c, source=q.source)
