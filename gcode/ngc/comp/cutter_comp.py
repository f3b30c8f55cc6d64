"""Cutter radius compensation G40/G41/G42/G41.1/G42.1, as LinuxCNC's interpreter does it.

The book (research/seed-book-interp.md §2.3.4) gives the modes: cancel, start-up (the first
move after G41/G42), offset mode, offset cancel (G40); NISTIR 5970 App. A.8 leaves
compensation to the level above the canonical commands, which is where LinuxCNC (and this
module) does it. The geometry is in :mod:`gcode.ngc.offset_geometry`; this module holds the
state machine and LinuxCNC's *queue* (``interp_queue.cc``): a compensated move cannot be
emitted before the next one is known, because a concave corner moves its end point back.
So each compensated motion is held; non-motion commands that LinuxCNC queues behind it
(:data:`gcode.ngc.comp.rules.QUEUED_NAMES`) are held too and released in order; every other
command passes straight through (so, e.g., ``MESSAGE`` or ``SELECT_TOOL`` print *before* a
held move, exactly as rs274 prints them).

How the interpreter uses it (one :class:`CutterCompensator` per run)::

    comp = CutterCompensator()
    # every canonical command the interpreter would emit, while comp.holding:
    out = comp.passthrough(cmd)             # [] (held) or [cmd]
    # G41/G42/G41.1/G42.1 (step 5 of the LinuxCNC order, after plane and units):
    out = comp.start(code, plane, d=d_word, l=l_word, tool=lookup, source=loc)
    # G40:
    out = comp.stop(source=loc)             # releases the last move; then arcs are refused
    # G0/G1 while comp.engaged (end = programmed end x y z a b c, start = current position):
    out = comp.straight(start, end, rapid=is_g0, source=loc)
    # G2/G3 while comp.engaged; centre and turn computed as without compensation from the
    # programmed start (``start``); centre in plane order (XY: x y, XZ: z x):
    out = comp.arc(start, end, centre, turn, source=loc)
    # M0 M1 M60 M2 M30, before their own commands (LinuxCNC ``convert_stop``):
    out = comp.flush()
    # after M2/M30:  comp.end_program()
    # every G20/G21:  comp.set_units(is_g20)
    # every straight motion (compensated or not):  comp.arc_not_allowed = False
    # before every arc:  comp.check_arc_allowed(loc)
    # operations LinuxCNC forbids while comp.on, keyed in FORBIDDEN (comp_rules):
    comp.require_off("tool change", loc)    # raises NGC-COMP-ACTIVE if comp.on
    # G33 while comp.engaged:  comp.straight(start, end, rapid=False, g33=True, source=loc)
    # M61 while comp.holding, after CHANGE_TOOL_NUMBER:  out = comp.release()

Positions in and out are program coordinates in current units; the interpreter keeps the
*programmed* position as its current point (LinuxCNC's ``find_ends`` does the same while
compensation is on), this object keeps the compensated one. Motions come out as
:class:`kernel.ir.canon.StraightTraverse`, :class:`~kernel.ir.canon.StraightFeed` and
:class:`~kernel.ir.canon.ArcFeed`, carrying the ``source`` of the block that produced them, in
rs274's order. Errors are :class:`kernel.diagnostics.Diagnostic` with ``NGC-COMP-*`` codes
(docs/errors.md, "Cutter radius compensation"). Held moves are dropped when an error stops
the run, as in rs274.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

from gcode.ngc import offset_geometry as geo
from gcode.ngc.comp.queue import HeldMove, MotionQueue, motion_command
from gcode.ngc.comp.rules import FORBIDDEN, LEFT, QUEUED_NAMES, RIGHT, ToolLookup, comp_setting
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

#: LinuxCNC's default ``CENTER_ARC_RADIUS_TOLERANCE`` (inch, mm).
SPIRAL_TOLERANCE = {True: 0.00005, False: 0.00127}
P2 = tuple[float, float]
P3 = tuple[float, float, float]  # plane order: first, second, normal axis


def _scaled(p: P3, factor: float) -> P3:
    """``p`` with every coordinate times ``factor`` (a change of length units)."""
    return (p[0] * factor, p[1] * factor, p[2] * factor)


class CutterCompensator:
    """LinuxCNC's cutter-compensation state and motion queue (see module docstring)."""

    def __init__(self, *, comments: bool = True) -> None:
        self.comments = comments
        self.side = 0  # LEFT, RIGHT or 0 (G40)
        self.radius = 0.0
        self.orientation = 0
        self.plane = canon.Plane.XY
        self.first_move = True
        self.inches = False  # length units (G20); rs274 starts in mm
        self._arc_not_allowed = False
        self._queue = MotionQueue()
        self._current = (0.0, 0.0, 0.0)  # compensated: first, second, normal
        self._programmed = (0.0, 0.0, 0.0)

    # ------------------------------------------------------------------ state
    @property
    def arc_not_allowed(self) -> bool:
        """Set by G40 after a compensated move: the next motion must be straight."""
        return self._arc_not_allowed

    @arc_not_allowed.setter
    def arc_not_allowed(self, value: bool) -> None:
        self._arc_not_allowed = value

    @property
    def on(self) -> bool:
        """G41/G42/G41.1/G42.1 in force (even with radius 0)."""
        return self.side != 0

    @property
    def engaged(self) -> bool:
        """Motions must go through :meth:`straight` / :meth:`arc`."""
        return self.side != 0 and self.radius > 0.0

    @contextmanager
    def suspended(self) -> Iterator[None]:
        """Moves made inside go uncompensated and leave the compensation state alone, as
        LinuxCNC's ``convert_g7x`` makes a lathe cycle's rapid to its start point with
        ``cutter_comp_side`` set to 0 for that move (since v2.9.3, commit f648d01c72)."""
        side = self.side
        self.side = 0
        try:
            yield
        finally:
            self.side = side

    @property
    def holding(self) -> bool:
        """A move is held: every other command must go through :meth:`passthrough`."""
        return bool(self._queue.items)

    def require_off(self, action: str, source: Location | None) -> None:
        """Raise NGC-COMP-ACTIVE if compensation is on: ``action`` is a key of
        :data:`FORBIDDEN` (LinuxCNC's message) or a phrase for "Cannot <action> with cutter
        radius compensation on"."""
        if self.side:
            message = FORBIDDEN.get(action, f"Cannot {action} with cutter radius compensation on")
            raise Diagnostic("NGC-COMP-ACTIVE", message, source)

    def check_arc_allowed(self, source: Location | None) -> None:
        """Before any G2/G3: LinuxCNC refuses an arc as the first move after G40."""
        if self.arc_not_allowed:
            raise Diagnostic(
                "NGC-COMP-ARC-AFTER-G40",
                "The move just after exiting cutter compensation mode must be straight, not an arc",
                source,
            )

    # ------------------------------------------------------------------ mode changes
    def start(
        self,
        code: str,
        plane: canon.Plane,
        *,
        d: float | None,
        l: float | None,  # noqa: E741 - the L word
        tool: ToolLookup,
        source: Location | None,
    ) -> list[canon.Command]:
        """G41 / G42 / G41.1 / G42.1 (LinuxCNC ``convert_cutter_compensation_on``).

        ``code`` is ``"G41"``, ``"G42"``, ``"G41.1"`` or ``"G42.1"``; ``d`` the D word, ``l``
        the L word (G41.1/G42.1 lathe orientation, G18 only). G41/G42 use the diameter of
        tool ``D`` (or of the tool in the spindle without D); G41.1/G42.1 use D as the
        diameter. A negative radius swaps the side.
        """
        if plane not in (canon.Plane.XY, canon.Plane.XZ):
            raise Diagnostic(
                "NGC-COMP-PLANE", "Cutter radius compensation allowed only in XY, XZ planes", source
            )
        if self.side:
            raise Diagnostic(
                "NGC-COMP-ALREADY-ON", "Cannot turn cutter radius comp on when on", source
            )
        side, radius, orientation = comp_setting(code, plane, d, l, tool, source)
        out = self._comment(
            "interpreter: cutter radius compensation on " + ("left" if side == LEFT else "right"),
            source,
        )
        self.side, self.radius, self.orientation, self.plane = side, radius, orientation, plane
        return out

    def change_radius(self, radius: float, source: Location | None) -> None:
        """Fanuc's and Haas's new D in offset mode (0i-MF operator's manual, "Tool radius
        compensation", change of the compensation value in offset mode; LinuxCNC refuses it):
        after the block at ``source`` that gave it, that block's held end moves from the old
        offset path to the new one (``radius``), so the tool slants from the old path to the
        new one along the block, and the radius changes."""
        if self.first_move or self.radius <= 0.0:
            self.radius = radius  # no compensated move yet: the start-up uses the new value
            return
        items = self._queue.items
        last = next((i for i in reversed(range(len(items))) if isinstance(items[i], HeldMove)), -1)
        held = items[last] if last >= 0 else None
        if (
            not isinstance(held, HeldMove)
            or held.is_arc
            or held.direction == (0.0, 0.0)
            or held.source is None
            or source is None
            or (held.source.file, held.source.line) != (source.file, source.line)
        ):
            raise Diagnostic(
                "FANUC-COMP-CHANGE",
                "a new D in offset mode is read on a straight move in the plane only",
                source,
            )
        p1, p2, _ = self._programmed
        k = radius / self.radius
        end = (p1 + (held.end[0] - p1) * k, p2 + (held.end[1] - p2) * k)
        items[last] = HeldMove(
            held.kind, end, held.normal, held.abc, held.source, direction=held.direction
        )
        self._current = (end[0], end[1], self._current[2])
        self.radius = radius

    def stop_offset(self) -> tuple[float, float, float] | None:
        """Before G40: where the tool is less where the program is, in X Y Z (None when no
        compensated move was made). rs274 re-reads its position from the tool's after a
        tool change, so a tool change right after G40 starts from the tool's point."""
        if not (self.side and self.radius > 0.0 and not self.first_move):
            return None
        d1 = self._current[0] - self._programmed[0]
        d2 = self._current[1] - self._programmed[1]
        if self.plane == canon.Plane.XZ:
            return (d2, 0.0, d1)
        return (d1, d2, 0.0)

    def stop(self, *, source: Location | None) -> list[canon.Command]:
        """G40 (LinuxCNC ``convert_cutter_compensation_off``): release the held move."""
        out = self._comment("interpreter: cutter radius compensation off", source)
        if self.side and self.radius > 0.0 and not self.first_move:
            out += self._move_endpoint_and_flush(self._current[:2], source)
            out += self._dequeue()
            self.arc_not_allowed = True
        self.side = 0
        self.first_move = True
        return out

    def flush(self, source: Location | None = None) -> list[canon.Command]:
        """Release everything held (LinuxCNC ``convert_stop`` for M0 M1 M60 M2 M30)."""
        out = self._move_endpoint_and_flush(self._current[:2], source)
        return out + self._dequeue()

    def release(self) -> list[canon.Command]:
        """Release the held commands as they are (after M61's ``CHANGE_TOOL_NUMBER``: the
        tool-change flag makes LinuxCNC empty its queue without joining the next corner)."""
        return self._dequeue()

    def end_program(self) -> None:
        """M2/M30 after :meth:`flush`: compensation off, next G41 starts afresh."""
        self.side = 0
        self.first_move = True

    def set_units(self, inches: bool) -> None:
        """G20/G21 (every time): held moves follow a change of units (``qc_scale``).

        The radius and the positions are converted as the interpreter converts its own;
        as in LinuxCNC, the held start point is scaled once per held command.
        """
        if inches == self.inches:
            return
        self.inches = inches
        if not self.side:
            return
        factor = 1 / 25.4 if inches else 25.4
        self.radius *= factor
        self._current = _scaled(self._current, factor)
        self._programmed = _scaled(self._programmed, factor)
        self._queue.scale(factor)

    # ------------------------------------------------------------------ other commands
    def passthrough(self, cmd: canon.Command) -> list[canon.Command]:
        """A non-motion command: held behind the queued move if LinuxCNC queues it."""
        if self._queue and cmd.NAME in QUEUED_NAMES:
            self._queue.push(cmd)
            return []
        return [cmd]

    # ------------------------------------------------------------------ motions
    def straight(
        self,
        start: Sequence[float],
        end: Sequence[float],
        *,
        rapid: bool,
        source: Location | None,
        g33: bool = False,
    ) -> list[canon.Command]:
        """G0/G1 with compensation (``convert_straight_comp1`` / ``comp2``).

        ``g33``: a G33 move while compensated. LinuxCNC then makes a plain compensated
        feed (no spindle synchronisation) where no corner arc is needed and rejects it as
        the first move, without motion in the plane, or at a convex corner.
        """
        p1, p2, pn = self._to_plane(end)
        abc = (float(end[3]), float(end[4]), float(end[5]))
        kind = "traverse" if rapid else "feed"
        if self.first_move:
            if g33:
                raise self._not_g0_g1(source)
            return self._straight_first(self._to_plane(start), (p1, p2, pn), abc, kind, source)
        return self._straight_next((p1, p2, pn), abc, kind, rapid, g33, source)

    def arc(
        self,
        start: Sequence[float],
        end: Sequence[float],
        centre: tuple[float, float],
        turn: int,
        *,
        source: Location | None,
    ) -> list[canon.Command]:
        """G2/G3 with compensation (``convert_arc_comp1`` / ``comp2``).

        ``centre`` and ``turn`` describe the programmed arc from the programmed start.
        """
        e1, e2, en = self._to_plane(end)
        abc = (float(end[3]), float(end[4]), float(end[5]))
        if self.first_move:
            return self._arc_first(self._to_plane(start), (e1, e2, en), centre, turn, abc, source)
        return self._arc_next((e1, e2, en), centre, turn, abc, source)

    # ------------------------------------------------------------------ straight moves
    def _straight_first(
        self, cur: P3, end: P3, abc: P3, kind: str, source: Location | None
    ) -> list[canon.Command]:
        c = (cur[0], cur[1])
        p = (end[0], end[1])
        if (length := math.hypot(p[0] - c[0], p[1] - c[1])) < self.radius:  # rs274 takes ==
            raise Diagnostic(
                "NGC-COMP-ENTRY-TOO-SHORT",
                "Length of cutter compensation entry move is not greater than the tool radius: "
                f"the move is {length:.4f} long in the plane, the tool radius {self.radius:.4f}",
                source,
            )
        comp_end, alpha = geo.entry_line_end(c, p, self.side, self.radius)
        self._queue.set_endpoint(c)
        self._queue.push(
            HeldMove(
                kind, comp_end, end[2], abc, source, direction=(math.cos(alpha), math.sin(alpha))
            )
        )
        self.first_move = False
        self._current = (comp_end[0], comp_end[1], end[2])
        self._programmed = end
        return []

    def _straight_next(
        self, end: P3, abc: P3, kind: str, rapid: bool, g33: bool, source: Location | None
    ) -> list[canon.Command]:
        cx, cy, cz = self._current
        op = (self._programmed[0], self._programmed[1])
        p = (end[0], end[1])
        out: list[canon.Command] = []
        new_end = (cx, cy)
        direction = (p[0] - op[0], p[1] - op[1])
        if p != op:
            beta, theta, alpha, gamma = geo.line_corner((cx, cy), op, p, self.side)
            new_end = geo.offset_point(p, alpha + gamma, self.radius)
            mid = geo.offset_point(op, alpha + gamma, self.radius)
            front = self._queue.front_arc()
            if beta < -geo.SMALL or beta > math.pi + geo.SMALL:
                concave = True
            else:
                # an "h" shape: over a round top then along a tangent side; LinuxCNC stays
                # on the outside of the round part
                concave = (
                    beta > math.pi - geo.SMALL
                    and bool(self._queue)
                    and front is not None
                    and (
                        (self.side == RIGHT and front.turn > 0)
                        or (self.side == LEFT and front.turn < 0)
                    )
                )
            if not concave and beta > geo.SMALL:
                if g33:
                    raise self._not_g0_g1(source)
                out += self._move_endpoint_and_flush((cx, cy), source)
                if rapid:
                    # no arc traverse: a straight rapid to the corner's far side
                    self._queue.push(HeldMove("traverse", mid, cz, abc, source))
                else:
                    corner = HeldMove(
                        "arc", mid, cz, abc, source, centre=op, turn=-1 if self.side == LEFT else 1
                    )
                    self._queue.push(corner)
                out += self._dequeue()
                self._queue.set_endpoint(mid)
            elif concave:
                if front is None:
                    retreat = geo.line_line_retreat(beta, self.radius)
                    meet = geo.offset_point((cx, cy), theta + gamma, retreat)
                else:
                    found = geo.arc_to_line_meet(
                        front.centre,
                        front.radius,
                        front.turn,
                        op,
                        p,
                        self.radius,
                        self.side,
                    )
                    if found is None:
                        raise Diagnostic(
                            "NGC-COMP-GOUGE",
                            "Arc to straight motion makes a corner the compensated tool "
                            "can't fit in without gouging",
                            source,
                        )
                    meet = found
                out += self._move_endpoint_and_flush(meet, source)
            else:  # tangent: colinear lines or tangent arc -> line
                out += self._dequeue()
                self._queue.set_endpoint((cx, cy))
            self._queue.push(HeldMove(kind, new_end, end[2], abc, source, direction=direction))
        else:  # no motion in the plane
            if g33:
                raise self._not_g0_g1(source)
            self._queue.push(HeldMove(kind, (cx, cy), end[2], abc, source, direction=(0.0, 0.0)))
        self._current = (new_end[0], new_end[1], end[2])
        self._programmed = end
        return out

    # ------------------------------------------------------------------ arcs
    def _arc_first(
        self, cur: P3, end: P3, centre: P2, turn: int, abc: P3, source: Location | None
    ) -> list[canon.Command]:
        c = (cur[0], cur[1])
        e = (end[0], end[1])
        if (length := math.hypot(e[0] - c[0], e[1] - c[1])) < self.radius:  # rs274 takes ==
            raise Diagnostic(
                "NGC-COMP-ENTRY-TOO-SHORT",
                "Radius of cutter compensation entry arc is not greater than the tool radius: "
                f"the arc ends {length:.4f} from its start, the tool radius {self.radius:.4f}",
                source,
            )
        inside = geo.tool_inside_arc(self.side, turn)
        if inside and (start_r := math.hypot(centre[0] - c[0], centre[1] - c[1])) <= self.radius:
            raise self._too_big(source, start_r)
        if inside:
            gamma = math.atan2(centre[1] - e[1], centre[0] - e[0])
        else:
            gamma = math.atan2(e[1] - centre[1], e[0] - centre[0])
        self.first_move = False
        self._programmed = end
        comp_end = geo.offset_point(e, gamma, self.radius)
        new_centre = geo.arc_entry_centre(c, comp_end, centre)
        if new_centre is None:
            raise self._too_big(source, math.hypot(centre[0] - e[0], centre[1] - e[1]))
        r_end = math.hypot(new_centre[0] - comp_end[0], new_centre[1] - comp_end[1])
        r_start = math.hypot(new_centre[0] - c[0], new_centre[1] - c[1])
        if abs(r_end - r_start) > SPIRAL_TOLERANCE[self.inches]:
            raise Diagnostic("NGC-COMP-BUG", "Bug in tool radius comp", source)
        if self.orientation not in (0, 9):
            # lathe tools: move the tool origin first, otherwise the arc is not an arc
            self._queue.push(HeldMove("feed", c, cur[2], abc, source))
            self._queue.set_endpoint(c)
        sweep = geo.find_turn(c, new_centre, turn, comp_end)
        self._queue.push(
            HeldMove(
                "arc", comp_end, end[2], abc, source, centre=new_centre, turn=turn, sweep=sweep
            )
        )
        self._current = (comp_end[0], comp_end[1], end[2])
        return []

    def _arc_next(
        self, end: P3, centre: P2, turn: int, abc: P3, source: Location | None
    ) -> list[canon.Command]:
        cx, cy, cz = self._current
        op = (self._programmed[0], self._programmed[1])
        e = (end[0], end[1])
        side, r = self.side, self.radius
        arc_radius = math.hypot(centre[0] - e[0], centre[1] - e[1])
        theta = math.atan2(cy - op[1], cx - op[0])
        theta = geo.plus_pi(theta, -0.5 if side == LEFT else 0.5)
        delta = math.atan2(centre[1] - op[1], centre[0] - op[0])
        alpha = geo.plus_pi(delta, -0.5 if turn > 0 else 0.5)
        beta = geo.normalise_beta(theta - alpha if side == LEFT else alpha - theta)
        inside = geo.tool_inside_arc(side, turn)
        if inside:
            gamma = math.atan2(centre[1] - e[1], centre[0] - e[0])
            if arc_radius <= r:
                raise self._too_big(source, arc_radius)
        else:
            gamma = math.atan2(e[1] - centre[1], e[0] - centre[0])
            delta = geo.plus_pi(delta, 1)
        new_end = geo.offset_point(e, gamma, r)
        sweep = geo.find_turn(op, centre, turn, e)
        main = HeldMove("arc", new_end, end[2], abc, source, centre=centre, turn=turn, sweep=sweep)
        out: list[canon.Command] = []
        small = geo.SMALL
        if beta < -small or beta > math.pi + small or (abs(beta - math.pi) < small and not inside):
            front = self._queue.front_arc()
            if front is None:  # line -> arc
                meet = geo.line_to_arc_meet(centre, arc_radius, r, beta, theta, turn, side)
                if meet is None:
                    raise Diagnostic(
                        "NGC-COMP-GOUGE",
                        "Arc move in concave corner cannot be reached by the tool without gouging",
                        source,
                    )
            else:  # arc -> arc
                old_r = front.radius
                new_r = arc_radius - r if inside else arc_radius + r
                cc = math.hypot(front.centre[1] - centre[1], front.centre[0] - centre[0])
                if old_r == 0 or cc == 0:
                    raise Diagnostic(
                        "NGC-COMP-SAME-CENTRE",
                        "Arc to arc motion is invalid because the arcs have the same center",
                        source,
                    )
                meet = geo.arc_to_arc_meet(
                    front.centre, old_r, front.turn, centre, new_r, turn, side
                )
                if meet is None:
                    raise Diagnostic(
                        "NGC-COMP-GOUGE",
                        "Arc to arc motion makes a corner the compensated tool can't fit in "
                        "without gouging",
                        source,
                    )
            out += self._move_endpoint_and_flush(meet, source)
            self._queue.push(main)
        elif beta > small:  # convex: corner arc, then the arc
            mid = geo.offset_point(op, delta, r)
            out += self._dequeue()
            self._queue.push(
                HeldMove("arc", mid, cz, abc, source, centre=op, turn=-1 if side == LEFT else 1)
            )
            out += self._dequeue()
            self._queue.set_endpoint(mid)
            self._queue.push(main)
        else:  # tangent
            out += self._dequeue()
            self._queue.set_endpoint((cx, cy))
            self._queue.push(main)
        self._programmed = end
        self._current = (new_end[0], new_end[1], end[2])
        return out

    @staticmethod
    def _not_g0_g1(source: Location | None) -> Diagnostic:
        return Diagnostic("NGC-COMP-G33", "Bug: code not g0 or g1", source)

    def _too_big(self, source: Location | None, arc_radius: float) -> Diagnostic:
        """NGC-COMP-TOOL-TOO-BIG with LinuxCNC's text, then the two radii compared."""
        return Diagnostic(
            "NGC-COMP-TOOL-TOO-BIG",
            "Tool radius not less than arc radius with comp: tool radius "
            f"{self.radius:.4f}, arc radius {arc_radius:.4f}",
            source,
        )

    # ------------------------------------------------------------------ the queue
    def _emit(self, q: HeldMove) -> canon.Command:
        return motion_command(q, self.plane, self.orientation, self.radius)

    def _dequeue(self) -> list[canon.Command]:
        return self._queue.release(self._emit)

    def _move_endpoint_and_flush(
        self, p: tuple[float, float], source: Location | None
    ) -> list[canon.Command]:
        return self._queue.move_endpoint_and_release(p, source, self._emit, self.inches)

    def _comment(self, text: str, source: Location | None) -> list[canon.Command]:
        if not self.comments:
            return []
        return self.passthrough(canon.Comment(text, source=source))

    def _to_plane(self, pos: Sequence[float]) -> tuple[float, float, float]:
        if self.plane == canon.Plane.XZ:
            return (float(pos[2]), float(pos[0]), float(pos[1]))
        return (float(pos[0]), float(pos[1]), float(pos[2]))
