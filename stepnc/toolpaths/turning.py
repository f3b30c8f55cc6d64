"""ISO 14649-12 turning workingsteps -> canonical commands for a 2-axis lathe (XZ plane).

X is the radius (the tool's distance from the spindle axis), Z the axis; Y stays 0. The
tool is a point at its reference (the nose of a turning tool, the middle of a grooving
insert's width): no nose-radius compensation. Our choices where ISO 14649-12 leaves the
toolpath open (docs/stepnc.md, "Turning"):

* contouring: layers parallel to the axis, from the free end towards the chuck (feed
  direction -Z, stepover -X), equal depths no deeper than the strategy's first
  ``cutting_depth`` (default 2 mm); after each layer the tool lifts ``lift_height`` (default
  1 mm) along +X and returns to the start at rapid; rough contouring leaves ``allowance``
  radially. Finish contouring follows the profile once and climbs the shoulder below it.
* facing: passes along -X from outside the stock to the face's inner radius, layers along
  -Z down to the face plus the allowance; lift along +Z.
* grooving: plunges along -X, as many as the insert width needs, evenly spaced across the
  groove; MULTISTEP_GROOVING_STRATEGY pecks ``cutting_depth`` deep and backs off
  ``retract_distance``; ``dwell`` at the bottom.
* the tool moves between cuts outside the raw bar (its radius + 2 mm) or above the free end
  (+2 mm); tool changes happen at the start position.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from kernel.ir import canon
from stepnc.executor import Executor
from stepnc.frames import Frame, direction
from stepnc.lathe import EPS, FREE, Profile, feature_frame, feature_limit, raw_bar
from stepnc.model import Entity
from stepnc.part21 import Typed
from stepnc.schema import TURNING_OPERATIONS

TURNING_OPS = TURNING_OPERATIONS
TURNING_TOOLS = frozenset(
    {"GENERAL_TURNING_TOOL", "GROOVING_TOOL", "TURNING_THREADING_TOOL", "KNURLING_TOOL"}
)
CLEAR = 2.0  # mm outside the raw bar / above the free end
LIFT = 1.0  # default lift height
DEPTH = 2.0  # default cutting depth
_FEATURES = {
    "FACING": ("REVOLVED_FLAT",),
    "CONTOURING": ("OUTER_DIAMETER", "GENERAL_REVOLUTION"),
    "GROOVING": ("GROOVE",),
    "CUTTING": ("GROOVE",),
}


@dataclass
class Lathe:
    """The turning state of a run: the stock left so far and the raw bar's radius."""

    stock: Profile
    raw_r: float

    @property
    def clear_x(self) -> float:
        return self.raw_r + CLEAR


def generate(ex: Executor, ws: Entity, feature: Entity, op: Entity, wp_frame: Frame) -> None:
    """Emit one turning workingstep."""
    if op.type.startswith("THREADING") or op.type == "KNURLING":
        raise ex.error(
            "STEPNC-UNSUPPORTED",
            f"{op.type}: threading and knurling need the THREAD and KNURL features, which "
            "this reader does not read",
            op,
        )
    family = op.type.split("_")[0]
    if feature.type not in _FEATURES[family]:
        raise ex.error(
            "STEPNC-OP-FEATURE",
            f"{op.type} cannot machine {feature.type} #{feature.id} "
            f"(it machines {' or '.join(_FEATURES[family])})",
            op,
        )
    for name in ("approach", "retract"):
        if getattr(op, name) is not None:
            raise ex.error(
                "STEPNC-STRATEGY",
                f"{op.type}: the {name} strategy of a turning operation is not read; give $",
                op,
            )
    lathe = ex.stock
    if not isinstance(lathe, Lathe):
        stock, raw_r = raw_bar(feature.model, wp_frame)
        lathe = Lathe(stock, raw_r)
        ex.stock = lathe
    if ex.plane is not canon.Plane.XZ:
        ex.emit(canon.SelectPlane(canon.Plane.XZ))
        ex.plane = canon.Plane.XZ
    _tool(ex, op.its_tool, lathe)
    _machine_functions(ex, op.its_machine_functions)
    _technology(ex, op.its_technology)
    fr = feature_frame(feature, wp_frame)
    allowance = float(op.allowance or 0.0)
    if allowance < 0:
        raise ex.error("STEPNC-TURNING", f"{op.type}: negative allowance", op)
    if family == "FACING":
        # a face's allowance is along the axis
        o = fr.origin
        goal = feature_limit(
            feature, Frame((o[0], o[1], o[2] + allowance), fr.x, fr.z), lathe.stock
        )
    else:
        goal = feature_limit(feature, fr, lathe.stock).offset(allowance)
    if family == "CONTOURING":
        _contouring(ex, lathe, feature, op, goal)
    elif family == "FACING":
        _facing(ex, lathe, feature, op, goal, fr.origin[2] + allowance)
    else:
        _grooving(ex, lathe, feature, op, goal, fr)
    lathe.stock = lathe.stock.minimum(goal)


# ------------------------------------------------------------------ tool and technology
def _tool(ex: Executor, tool: Entity, lathe: Lathe) -> None:
    if tool.type not in TURNING_TOOLS:
        raise ex.error(
            "STEPNC-OP-FEATURE", f"a turning operation needs a turning tool, not {tool.type}", tool
        )
    ident = str(tool.its_id)
    if ident == ex.tool_id:
        return
    pocket = ex.pocket_of(ident, tool)
    _leave(ex, lathe)
    ex.stop_for_tool_change()
    ex.emit(canon.ChangeTool(pocket, ident))
    ex.tool_id = ident


def _machine_functions(ex: Executor, mf: Entity) -> None:
    if mf.type != "TURNING_MACHINE_FUNCTIONS":
        raise ex.error(
            "STEPNC-OP-FEATURE", "a turning operation needs TURNING_MACHINE_FUNCTIONS", mf
        )
    mist = mf.coolant is True and str(mf.coolant_type) == "MIST"
    flood = mf.coolant is True and not mist
    if flood is not ex.flood:
        ex.emit(canon.FloodOn() if flood else canon.FloodOff())
        ex.flood = flood
    if mist is not ex.mist and (mist or ex.mist is True):
        ex.emit(canon.MistOn() if mist else canon.MistOff())
        ex.mist = mist


def _technology(ex: Executor, tech: Entity) -> None:
    if tech.type != "TURNING_TECHNOLOGY":
        raise ex.error("STEPNC-OP-FEATURE", "a turning operation needs TURNING_TECHNOLOGY", tech)
    if tech.its_adaptive_control is not None:
        raise ex.error("STEPNC-UNSUPPORTED", "adaptive control is not supported", tech)
    sel = tech.spindle_speed
    if sel.type == "CONST_CUTTING_SPEED":
        # m/s -> m/min (G96 S); rev/s -> rpm for the speed limit
        value = float(sel.speed) * 60.0
        css_max = abs(float(sel.max_speed)) * 60.0 if sel.max_speed is not None else 0.0
        if not ex.css or ex.css_max != css_max:
            ex.emit(canon.SetSpindleMode(css_max, True))
            ex.css, ex.css_max = True, css_max
            ex.speed = -1.0  # the S value changes meaning: always send it
    else:
        value = float(sel.rot_speed) * 60.0  # rev/s -> rpm
        if ex.css:
            ex.emit(canon.SetSpindleMode(0.0, False))
            ex.css = False
            ex.speed = -1.0
    # ISO 14649-10 §4.2.1: positive is counterclockwise
    if value > 0:
        ex.spin(value, canon.Direction.COUNTERCLOCKWISE)
    elif value < 0:
        ex.spin(-value, canon.Direction.CLOCKWISE)
    else:
        raise ex.error("STEPNC-NO-SPEED", "the turning technology gives spindle speed 0", tech)
    if tech.feed_per_revolution is not None:
        mode, feed = canon.FeedMode.UNITS_PER_REVOLUTION, float(tech.feed_per_revolution)
    elif tech.feedrate is not None:
        mode, feed = canon.FeedMode.UNITS_PER_MINUTE, float(tech.feedrate) * 60000.0
    else:
        raise ex.error(
            "STEPNC-NO-FEED", "the turning technology gives neither feedrate nor feed per rev", tech
        )
    if mode is not ex.feed_mode:
        ex.emit(canon.SetFeedMode(mode))
        ex.feed_mode = mode
        ex.feedrate = -1.0
    ex.set_feed(feed)


# ------------------------------------------------------------------ strategy
@dataclass(frozen=True)
class _Strategy:
    depth: float
    lift: float
    retract: float | None  # multistep grooving back-off


_DEFAULT_DIRECTIONS = {
    # family: attribute -> (radial, axial) unit direction
    "CONTOURING": {
        "feed_direction": (0.0, -1.0),
        "back_path_direction": (0.0, 1.0),
        "lift_direction": (1.0, 0.0),
        "stepover_direction": (-1.0, 0.0),
    },
    "FACING": {
        "feed_direction": (-1.0, 0.0),
        "back_path_direction": (1.0, 0.0),
        "lift_direction": (0.0, 1.0),
        "stepover_direction": (0.0, -1.0),
    },
    "GROOVING": {"grooving_direction": (-1.0, 0.0)},
}


def _strategy(ex: Executor, op: Entity, family: str) -> _Strategy:
    st = op.its_machining_strategy
    if st is None:
        return _Strategy(DEPTH, LIFT, None)
    allowed = (
        ("GROOVING_STRATEGY", "MULTISTEP_GROOVING_STRATEGY")
        if family in ("GROOVING", "CUTTING")
        else ("UNIDIRECTIONAL_TURNING",)
    )
    if st.type not in allowed:
        raise ex.error(
            "STEPNC-STRATEGY",
            f"{st.type} #{st.id} is not implemented for {op.type} (only {', '.join(allowed)})",
            st,
        )
    key = "GROOVING" if family in ("GROOVING", "CUTTING") else family
    for name, want in _DEFAULT_DIRECTIONS[key].items():
        d = getattr(st, name)
        if d is None:
            continue
        x, _, z = direction(d)
        if math.hypot(x - want[0], z - want[1]) > 1e-6:
            raise ex.error(
                "STEPNC-STRATEGY",
                f"{st.type} #{st.id}: {name} ({x:g}, {z:g}) in (X, Z) is not implemented; "
                f"the generator cuts along ({want[0]:g}, {want[1]:g})",
                st,
            )
    depths = st.cutting_depth or ()
    depth = float(depths[0]) if depths else DEPTH
    if depth <= 0:
        raise ex.error("STEPNC-STRATEGY", f"{st.type} #{st.id}: cutting depth must be > 0", st)
    lift = float(st.lift_height) if getattr_opt(st, "lift_height") is not None else LIFT
    retract = float(st.retract_distance) if st.type == "MULTISTEP_GROOVING_STRATEGY" else None
    return _Strategy(depth, lift, retract)


def getattr_opt(e: Entity, name: str) -> object:
    """An attribute the entity may not have (None then)."""
    try:
        return getattr(e, name)
    except AttributeError:
        return None


# ------------------------------------------------------------------ motion
def _rapid(ex: Executor, x: float, z: float) -> None:
    if abs(ex.x - x) > EPS or abs(ex.z - z) > EPS or abs(ex.y) > EPS:
        ex.emit(canon.StraightTraverse(x, 0.0, z))
        ex.x, ex.y, ex.z = x, 0.0, z


def _feed(ex: Executor, x: float, z: float) -> None:
    if abs(ex.x - x) <= EPS and abs(ex.z - z) <= EPS:
        return
    ex.emit(canon.StraightFeed(x, 0.0, z))
    ex.x, ex.y, ex.z = x, 0.0, z


def _approach(ex: Executor, lathe: Lathe, x: float, z: float) -> None:
    """To ``(x, z)`` (a point in the air): out beyond the raw bar, along Z, then in."""
    if abs(ex.z - z) > EPS or abs(ex.y) > EPS:
        if ex.x < lathe.clear_x:
            _rapid(ex, lathe.clear_x, ex.z)
        _rapid(ex, max(ex.x, lathe.clear_x), z)
    _rapid(ex, x, z)


def _leave(ex: Executor, lathe: Lathe) -> None:
    """Back to the start position (tool changes): out, then along Z, then across."""
    home_x, home_z = ex.home
    if abs(ex.x - home_x) <= EPS and abs(ex.z - home_z) <= EPS:
        return
    if ex.x < lathe.clear_x and ex.z < lathe.stock.top() + CLEAR:
        _rapid(ex, lathe.clear_x, ex.z)
    _rapid(ex, ex.x, home_z)
    _rapid(ex, home_x, home_z)


# ------------------------------------------------------------------ generators
def _feature_range(goal: Profile) -> tuple[float, float]:
    finite = [s for s in goal.segs if s[2] < FREE and s[3] < FREE]
    return finite[0][0], finite[-1][1]


def _contouring(ex: Executor, lathe: Lathe, feature: Entity, op: Entity, goal: Profile) -> None:
    stock = lathe.stock
    z_lo, z_hi = _feature_range(goal)
    z_top = stock.top()
    zs = min(z_hi, z_top)
    finite = [s for s in goal.segs if z_lo - EPS <= s[0] and s[1] <= z_hi + EPS]
    # no undercut: the radius may only grow towards the chuck (the peak and valley split of
    # the book's §8.6.2 is not implemented)
    prev_r: float | None = None
    for za, zb, ra, rb in reversed(finite):
        if rb > ra + 1e-9 or (prev_r is not None and rb < prev_r - 1e-9):
            raise ex.error(
                "STEPNC-TURNING",
                f"{feature.type} #{feature.id} has an undercut at Z={za:g}..{zb:g} (the radius "
                "shrinks towards the chuck); rough turning of undercuts is not implemented",
                feature,
            )
        prev_r = ra
    r_top = goal.piece(zs - min(1e-6, (zs - z_lo) / 2), zs)[1]
    if stock.max_r(zs, z_top) > r_top + 1e-6 and z_top > zs + EPS:
        raise ex.error(
            "STEPNC-TURNING",
            f"{feature.type} #{feature.id}: material between it and the free end (Z={z_top:g}) "
            "stands above its radius; turn that first",
            feature,
        )
    big = stock.max_r(z_lo, zs)
    z_start = z_top + CLEAR
    if op.type == "CONTOURING_ROUGH":
        r_min = min(min(s[2], s[3]) for s in finite)
        if big <= r_min + EPS:
            return
        strat = _strategy(ex, op, "CONTOURING")
        n = math.ceil((big - r_min) / strat.depth - 1e-9)
        step = (big - r_min) / n
        first = True
        for k in range(1, n + 1):
            rho = big - k * step if k < n else r_min
            z_end = _descend(goal, rho, zs, z_lo)
            if z_end >= zs - EPS:
                continue
            if first:
                _approach(ex, lathe, rho, z_start)
                first = False
            else:
                _rapid(ex, rho, z_start)
            _feed(ex, rho, z_end)
            _rapid(ex, rho + strat.lift, z_end)
            _rapid(ex, rho + strat.lift, z_start)
        _rapid(ex, lathe.clear_x, ex.z)
    # finish, and after roughing the pass along the profile that removes the steps the
    # layers leave (as G71's last pass does)
    _approach(ex, lathe, r_top, z_start)
    _feed(ex, r_top, zs)
    for za, zb, ra, rb in reversed(finite):
        if zb > zs + EPS:
            if za >= zs - EPS:
                continue
            rb = ra + (rb - ra) * (zs - za) / (zb - za)
            zb = zs
        _feed(ex, rb, zb)
        _feed(ex, ra, za)
    below = stock.max_r(z_lo - 1e-6, z_lo - 1e-6) if z_lo > stock.z_lo + EPS else 0.0
    if below > ex.x + EPS:
        _feed(ex, below, z_lo)
    _rapid(ex, lathe.clear_x, ex.z)


def _descend(goal: Profile, rho: float, z_from: float, z_lo: float) -> float:
    """Going from ``z_from`` towards the chuck at radius ``rho``: where the profile rises
    to it (the end of the layer)."""
    for za, zb, ra, rb in reversed(goal.segs):
        if za >= z_from - EPS:
            continue
        hi = min(zb, z_from)
        r_hi = ra + (rb - ra) * (hi - za) / (zb - za)
        if r_hi > rho + 1e-9:
            return hi
        if ra > rho + 1e-9:
            return za + (rho - ra) * (zb - za) / (rb - ra)
    return z_lo


def _facing(
    ex: Executor, lathe: Lathe, feature: Entity, op: Entity, goal: Profile, z_face: float
) -> None:
    stock = lathe.stock
    z_top = stock.top()
    if z_top <= z_face + EPS:
        return
    r_in = goal.segs[-1][3]
    big = stock.max_r(z_face, z_top)
    if op.type == "FACING_FINISH":
        levels = [z_face]
        lift = LIFT
    else:
        strat = _strategy(ex, op, "FACING")
        lift = strat.lift
        n = math.ceil((z_top - z_face) / strat.depth - 1e-9)
        step = (z_top - z_face) / n
        levels = [z_top - k * step if k < n else z_face for k in range(1, n + 1)]
    x_out = big + CLEAR
    for z in levels:
        if ex.x < x_out - EPS and abs(ex.z - z) > EPS and ex.z > z:
            _rapid(ex, x_out, ex.z)
        _approach(ex, lathe, x_out, z)
        _feed(ex, r_in, z)
        _rapid(ex, r_in, z + lift)
    _rapid(ex, x_out, ex.z)


def _grooving(
    ex: Executor, lathe: Lathe, feature: Entity, op: Entity, goal: Profile, fr: Frame
) -> None:
    tool = op.its_tool
    if tool.type != "GROOVING_TOOL":
        raise ex.error("STEPNC-OP-FEATURE", f"{op.type} needs a GROOVING_TOOL", op)
    width = float(tool.cutting_width)
    z_lo, z_hi = _feature_range(goal)
    groove = z_hi - z_lo
    if width > groove + 1e-9 or width <= 0:
        raise ex.error(
            "STEPNC-TOOL-WIDTH",
            f"grooving tool {tool.its_id!r} of width {width:g} does not fit groove "
            f"{feature.its_id!r} of width {groove:g}",
            op,
        )
    bottom = goal.segs[[i for i, s in enumerate(goal.segs) if s[2] < FREE][0]][2]
    stock = lathe.stock
    big = stock.max_r(z_lo, z_hi)
    if big <= bottom + EPS:
        return
    strat = _strategy(ex, op, "GROOVING")
    if groove - width <= 1e-9:
        centres = [(z_lo + z_hi) / 2]
    else:
        n = math.ceil((groove - width) / width - 1e-9) + 1
        gap = (groove - width) / (n - 1)
        centres = [z_hi - width / 2 - j * gap for j in range(n)]
    x_out = big + CLEAR
    dwell = _dwell(op, ex)
    for zc in centres:
        _approach(ex, lathe, x_out, zc)
        if strat.retract is None:
            _feed(ex, bottom, zc)
        else:
            at = big
            while at > bottom + EPS:
                nxt = max(bottom, at - strat.depth)
                _feed(ex, nxt, zc)
                if nxt > bottom + EPS:
                    _rapid(ex, nxt + strat.retract, zc)
                at = nxt
        if dwell > 0:
            ex.emit(canon.Dwell(dwell))
        _rapid(ex, x_out, zc)


def _dwell(op: Entity, ex: Executor) -> float:
    """Seconds at the groove bottom: a time, or DWELL_REVOLUTION(n) at the current speed."""
    raw = op.raw("dwell")
    if raw is None:
        return 0.0
    if isinstance(raw, Typed) and raw.name == "DWELL_REVOLUTION":
        if ex.css or ex.speed <= 0:
            raise ex.error(
                "STEPNC-UNSUPPORTED", "a dwell in revolutions needs a constant spindle speed", op
            )
        revs = raw.value
        if not isinstance(revs, (int, float)):
            raise ex.error("STEPNC-ATTR-TYPE", f"{op.type}.dwell must be a number", op)
        return float(revs) * 60.0 / ex.speed
    value = op.dwell
    if not isinstance(value, (int, float)):
        raise ex.error("STEPNC-ATTR-TYPE", f"{op.type}.dwell must be a number of seconds", op)
    return float(value)


__all__ = ["TURNING_OPS", "Lathe", "generate"]
