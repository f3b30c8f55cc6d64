"""Drilling-type operations on a hole (ISO 14649-11 §4.2.12-4.2.13): drilling, centre
drilling, countersinking, multistep (peck) drilling, reaming, boring and tapping, with the
DRILLING_TYPE_STRATEGY reduced cut (spindle) and feed factors at the start and end of the
hole. Algorithms follow NIST's ``op_drilling``, ``op_reaming``, ``op_multistep_drilling``,
``op_center_drilling`` and ``find_cutting_depths``; the controlled point is the tool tip.

Drill tip length (NIST ``find_drill_tip_length`` after ISO 14649-111 §4.3.1 Fig. 2):
``h = R tan(a) + r / tan((90 + a + b) / 2) * cos(b)`` with R the drill radius, r the edge
radius, a the tool top angle and b the circumference angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import kernel.limits as limits
from kernel.ir import canon
from stepnc.executor import TINY, UP
from stepnc.model import Entity, tool_dimension


def tip_length(tool: Entity) -> float:
    dim = tool_dimension(tool)
    a = float(dim.tool_top_angle or 0.0)
    radius = float(dim.diameter) / 2.0
    h1 = radius * math.tan(math.radians(a))
    r = float(dim.edge_radius or 0.0)
    if r == 0.0:
        return h1
    b = float(dim.tool_circumference_angle or 0.0)
    arm = r / math.tan(math.radians((90.0 + a + b) / 2.0))
    return h1 + arm * math.cos(math.radians(b))


def _ratio(v: float | None) -> float | None:
    """positive_ratio_measure; values above 1 are read as percent (ISO 14649-11 Example 1
    writes 75.0 where NIST reads 0.75, research/seed-book-stepnc.md §7.2)."""
    if v is None:
        return None
    f = float(v)
    return f / 100.0 if f > 1.0 else f


@dataclass
class Depths:
    bottom: float
    start: float | None  # end of the reduced start section
    end: float | None  # beginning of the reduced end section


def cutting_depths(ex, job, tip: float, flute: float | None) -> Depths:  # noqa: ANN001
    op, feature = job.op, job.feature
    top = job.frame.origin[2]
    hole = -float(feature.depth.position.location.coordinates[2])
    if op.cutting_depth is not None:
        if op.overcut_length is not None:
            raise ex.error(
                "STEPNC-DRILL-DEPTH", "cutting_depth and overcut_length are exclusive", op
            )
        cut = float(op.cutting_depth)
    elif op.overcut_length is not None:
        cut = hole + float(op.overcut_length)
    else:
        cut = hole
    if cut <= 0:
        raise ex.error("STEPNC-DRILL-DEPTH", "cutting depth must be positive", op)
    if flute is not None and cut + tip > flute + TINY:
        raise ex.error(
            "STEPNC-FLUTE",
            f"hole depth {cut + tip:g} exceeds the tool's cutting edge length {flute:g}",
            op,
        )
    bottom = top - (cut + tip)
    start = end = None
    strat = op.its_machining_strategy
    if strat is not None and strat.type == "DRILLING_TYPE_STRATEGY":
        if strat.depth_of_start is not None:
            s = float(strat.depth_of_start)
            if s >= cut:
                raise ex.error(
                    "STEPNC-DRILL-DEPTH",
                    "depth_of_start must be less than the cutting depth",
                    strat,
                )
            start = top - (s + tip)
        if strat.depth_of_end is not None:
            e = float(strat.depth_of_end)
            if e >= cut:
                raise ex.error(
                    "STEPNC-DRILL-DEPTH", "depth_of_end must be less than the cutting depth", strat
                )
            # NIST measures depth_of_end from the top of the hole; the standard's reduced
            # end section lies depth_of_end above the bottom (docs/stepnc.md)
            end = top - (e + tip) if ex.mode == "nist" else bottom + e
            if start is not None and end > start:
                raise ex.error(
                    "STEPNC-DRILL-DEPTH",
                    "the reduced end section starts above the end of the reduced start section",
                    strat,
                )
    return Depths(bottom, start, end)


def _flute(tool: Entity) -> float | None:
    v = tool_dimension(tool).cutting_edge_length
    return float(v) if v is not None else None


def generate(ex, job) -> None:  # noqa: ANN001
    op = job.op
    kind = op.type
    if job.feature.type != "ROUND_HOLE":
        raise ex.error(
            "STEPNC-OP-FEATURE", f"{kind} is implemented for ROUND_HOLE, not {job.feature.type}", op
        )
    if job.feature.change_in_diameter is not None:
        raise ex.error(
            "STEPNC-UNSUPPORTED",
            f"{kind} of a tapered hole (change_in_diameter) is not implemented",
            op,
        )
    {
        "DRILLING": _drilling,
        "MULTISTEP_DRILLING": _multistep,
        "REAMING": _reaming,
        "BORING": _reaming,
        "CENTER_DRILLING": _plunge_once,
        "COUNTER_SINKING": _plunge_once,
        "TAPPING": _tapping,
    }.get(kind, _unsupported)(ex, job)


def _unsupported(ex, job) -> None:  # noqa: ANN001
    raise ex.error("STEPNC-UNSUPPORTED", f"{job.op.type} is not supported", job.op)


def _drilling(ex, job) -> None:  # noqa: ANN001
    op, tool, tech = job.op, job.op.its_tool, job.op.its_technology
    x, y, top = job.frame.origin
    tip = tip_length(tool)
    d = cutting_depths(ex, job, tip, _flute(tool))
    retract = top + (float(op.retract_plane) if op.retract_plane is not None else tip)
    ex.machine_functions(op.its_machine_functions)
    ex.technology_some(tech)
    strat = op.its_machining_strategy
    if d.start is not None:
        ex.handle_speed(tech, tool, _ratio(strat.reduced_cut_at_start))
        ex.handle_feed(tech, tool, _ratio(strat.reduced_feed_at_start))
    elif ex.mode == "default":
        # NIST starts the spindle only after reaching the retract plane
        ex.handle_speed(tech, tool, None)
        ex.handle_feed(tech, tool, None)
    ex.start_cut(x, y, retract)
    if d.start is not None:
        ex.feed_to(x, y, d.start)
    ex.handle_speed(tech, tool, None)
    ex.handle_feed(tech, tool, None)
    if d.end is not None:
        ex.feed_to(x, y, d.end)
        ex.handle_speed(tech, tool, _ratio(strat.reduced_cut_at_end))
        ex.handle_feed(tech, tool, _ratio(strat.reduced_feed_at_end))
    ex.feed_to(x, y, d.bottom)
    if op.dwell_time_bottom is not None:
        ex.emit(canon.Dwell(float(op.dwell_time_bottom)))
    ex.handle_feed(tech, tool, _ratio(op.feed_on_retract))
    ex.feed_to(x, y, retract)


def _technology(ex, job) -> None:  # noqa: ANN001
    ex.machine_functions(job.op.its_machine_functions)
    ex.technology(job.op.its_technology, job.op.its_tool)


def _reaming(ex, job) -> None:  # noqa: ANN001
    op = job.op
    _technology(ex, job)
    x, y, top = job.frame.origin
    d = cutting_depths(ex, job, 0.0, _flute(op.its_tool))
    retract = top + (float(op.retract_plane) if op.retract_plane is not None else UP)
    feed, speed = ex.feedrate, ex.speed
    base_feed, base_speed = feed, speed
    strat = op.its_machining_strategy
    ex.start_cut(x, y, retract)
    if d.start is not None:
        if strat.reduced_cut_at_start is not None:
            speed = base_speed * _ratio(strat.reduced_cut_at_start)
            ex.emit(canon.SetSpindleSpeed(speed))
        if strat.reduced_feed_at_start is not None:
            feed = base_feed * _ratio(strat.reduced_feed_at_start)
            ex.emit(canon.SetFeedRate(feed))
        ex.feed_to(x, y, d.start)
        if feed != base_feed:
            feed = base_feed
            ex.emit(canon.SetFeedRate(feed))
        if speed != base_speed:
            speed = base_speed
            ex.emit(canon.SetSpindleSpeed(speed))
    if d.end is not None:
        ex.feed_to(x, y, d.end)
        if strat.reduced_cut_at_end is not None:
            speed = base_speed * _ratio(strat.reduced_cut_at_end)
            ex.emit(canon.SetSpindleSpeed(speed))
        if strat.reduced_feed_at_end is not None:
            feed = base_feed * _ratio(strat.reduced_feed_at_end)
            ex.emit(canon.SetFeedRate(feed))
    ex.feed_to(x, y, d.bottom)
    retract_feed = base_feed * (_ratio(op.feed_on_retract) or 1.0)
    if feed != retract_feed:
        feed = retract_feed
        ex.emit(canon.SetFeedRate(feed))
    if op.dwell_time_bottom is not None:
        ex.emit(canon.Dwell(float(op.dwell_time_bottom)))
    if op.spindle_stop_at_bottom is True:
        ex.emit(canon.StopSpindleTurning())
        ex.emit(canon.SetSpindleSpeed(0.0))
        speed = 0.0
        ex.spindle = canon.Direction.STOPPED
    ex.feed_to(x, y, retract)
    ex.feedrate, ex.speed = feed, speed


def _multistep(ex, job) -> None:  # noqa: ANN001
    op, tool = job.op, job.op.its_tool
    _technology(ex, job)
    x, y, top = job.frame.origin
    tip = tip_length(tool)
    first = float(op.first_depth)
    d = cutting_depths(ex, job, tip, _flute(tool))
    peck = float(op.depth_of_step)
    if peck <= 0:
        raise ex.error("STEPNC-DRILL-DEPTH", "depth_of_step must be positive", op)
    retract = top + (float(op.retract_plane) if op.retract_plane is not None else tip)
    retract_feed = _ratio(op.feed_on_retract) or 1.0
    dwell = float(op.dwell_time_step) if op.dwell_time_step is not None else 0.0
    back = float(op.retract_distance)
    ex.start_cut(x, y, retract)
    depth = top - (first + tip)
    pecks = (depth - d.bottom) / peck
    limit = limits.current().cycle_passes
    if not pecks < limit:  # a 1e-7 mm step: refused before the first peck
        raise limits.count_error("pecks of the drilling", pecks, limit, "cycle_passes", op.where())
    while True:
        last = depth <= d.bottom + TINY
        if last:
            depth = d.bottom
            dwell = float(op.dwell_time_bottom) if op.dwell_time_bottom is not None else 0.0
        ex.feed_to(x, y, depth)
        if dwell:
            ex.emit(canon.Dwell(dwell))
        if retract_feed != 1.0:
            ex.emit(canon.SetFeedRate(retract_feed * ex.feedrate))
        ex.feed_to(x, y, retract if last or back <= 0 else depth + back)
        if retract_feed != 1.0:
            ex.emit(canon.SetFeedRate(ex.feedrate))
        if last:
            break
        depth -= peck
    ex.x, ex.y, ex.z = x, y, retract


def _plunge_once(ex, job) -> None:  # noqa: ANN001
    """Centre drilling and countersinking: one plunge to the cutting depth and back."""
    op = job.op
    _technology(ex, job)
    x, y, top = job.frame.origin
    if op.cutting_depth is not None:
        cut = float(op.cutting_depth)
    else:
        cut = -float(job.feature.depth.position.location.coordinates[2])
    if cut <= 0:
        raise ex.error("STEPNC-DRILL-DEPTH", "cutting depth must be positive", op)
    flute = _flute(op.its_tool)
    if flute is not None and cut > flute + TINY:
        raise ex.error(
            "STEPNC-FLUTE", f"cutting depth {cut:g} exceeds the cutting edge length {flute:g}", op
        )
    retract = top + (float(op.retract_plane) if op.retract_plane is not None else UP)
    ex.start_cut(x, y, retract)
    ex.feed_to(x, y, top - cut)
    factor = _ratio(op.feed_on_retract)
    if factor is not None and factor != 1.0:
        ex.set_feed(factor * ex.feedrate)
    if op.dwell_time_bottom is not None:
        ex.emit(canon.Dwell(float(op.dwell_time_bottom)))
    ex.feed_to(x, y, retract)


def _tapping(ex, job) -> None:  # noqa: ANN001
    """Feed in, reverse the spindle at the bottom, feed out, restore the direction."""
    op = job.op
    _technology(ex, job)
    x, y, top = job.frame.origin
    d = cutting_depths(ex, job, 0.0, _flute(op.its_tool))
    retract = top + (float(op.retract_plane) if op.retract_plane is not None else UP)
    ex.start_cut(x, y, retract)
    ex.feed_to(x, y, d.bottom)
    if op.dwell_time_bottom is not None:
        ex.emit(canon.Dwell(float(op.dwell_time_bottom)))
    forward = ex.spindle
    ex.emit(canon.StopSpindleTurning())
    if forward is canon.Direction.COUNTERCLOCKWISE:
        ex.emit(canon.StartSpindleClockwise())
    else:
        ex.emit(canon.StartSpindleCounterclockwise())
    ex.feed_to(x, y, retract)
    ex.emit(canon.StopSpindleTurning())
    ex.emit(
        canon.StartSpindleCounterclockwise()
        if forward is canon.Direction.COUNTERCLOCKWISE
        else canon.StartSpindleClockwise()
    )
