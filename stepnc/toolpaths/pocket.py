"""Bottom-and-side rough and finish milling of closed pockets (ISO 14649-11 §4.2.6-4.2.8;
algorithm of NIST's ``mill_rectangular_pocket*``, ``mill_regular_pocket``,
``find_pocket_plunge_start*`` and ``enter_pocket_pass*``).

The pocket is a rectangle ``length x width`` (length along the feature's X axis) centred
on the feature origin, with vertical corner radius ``radius``, top at Z=0 and bottom at
``-depth``. Each layer is entered at the -X end of the (Voronoi) centre line by the
approach strategy (plunge along the tool axis, ramp, zigzag or helix, ISO 14649-11
§4.2.7) and cleared outward with contour-parallel loops; a circular closed profile is a
pocket whose length equals its width.
"""

from __future__ import annotations

import math

from stepnc.executor import ALLOW, TINY, UP
from stepnc.frames import Frame, coords, direction, frame_of
from stepnc.model import Entity, measure, tool_dimension
from stepnc.toolpaths.code import Code, check_count, place
from stepnc.toolpaths.passes import outside_in
from stepnc.toolpaths.pocket_entry import enter, plunge_start


def pocket_shape(ex, pocket: Entity) -> tuple[float, float, float, float, Frame]:  # noqa: ANN001
    """(length, width, depth, corner radius, profile frame) of a closed pocket whose boundary
    is a rectangle (RECTANGULAR_CLOSED_PROFILE, or a GENERAL_CLOSED_PROFILE polyline with
    four right-angled corners, as in ISO 14649-11 Example 1) or a circle. The profile frame
    puts the rectangle's centre at its origin with its long side along X."""
    depth = -float(pocket.depth.position.location.coordinates[2])
    if pocket.type == "ROUND_HOLE":
        return _round_hole_shape(ex, pocket, depth)
    boundary = pocket.feature_boundary
    frame = Frame()
    radius = measure(pocket.orthogonal_radius) if pocket.orthogonal_radius else 0.0
    if boundary.type == "RECTANGULAR_CLOSED_PROFILE":
        width = measure(boundary.profile_width)
        length = measure(boundary.profile_length)
        frame = frame_of(boundary.placement)
    elif boundary.type == "CIRCULAR_CLOSED_PROFILE":
        width = length = measure(boundary.diameter)
        radius = width / 2.0 if width else 0.0
        frame = frame_of(boundary.placement)
    else:
        rect = _polyline_rectangle(boundary)
        if rect is None:
            raise ex.error(
                "STEPNC-UNSUPPORTED",
                "pocket milling supports rectangular and circular closed profiles "
                "(a general profile must be a rectangular polyline)",
                pocket,
            )
        length, width, frame = rect
    if not width or width <= 0 or not length or length <= 0:
        raise ex.error(
            "STEPNC-POCKET",
            f"pocket profile needs a positive length and width (got length {length:g}, "
            f"width {width:g})",
            pocket,
        )
    if depth <= 0:
        raise ex.error(
            "STEPNC-POCKET",
            f"pocket depth plane must lie below its top (depth {depth:g})",
            pocket,
        )
    if width > length:
        # ISO 14649-10 does not order profile_length and profile_width; the clearing
        # strategies work along the long side, so turn the profile frame a quarter turn.
        length, width = width, length
        frame = Frame(frame.origin, frame.y, frame.z)
    if radius > width / 2.0 + TINY:
        raise ex.error(
            "STEPNC-POCKET",
            f"corner radius {radius:g} exceeds half the pocket width {width:g}",
            pocket,
        )
    return float(length), float(width), depth, float(radius or 0.0), frame


def _round_hole_shape(ex, hole: Entity, depth: float) -> tuple[float, float, float, float, Frame]:  # noqa: ANN001
    """A ROUND_HOLE milled with an end mill is a circular pocket of the hole's diameter
    (ISO 14649-10 round hole; bottom and side milling of ISO 14649-11). Only a flat
    bottom can be cut flat by the pocket strategies."""
    bottom = hole.bottom_condition
    kind = bottom.type if isinstance(bottom, Entity) else "no bottom condition"
    if kind not in ("FLAT_HOLE_BOTTOM", "THROUGH_BOTTOM_CONDITION"):
        raise ex.error(
            "STEPNC-UNSUPPORTED",
            f"milling round hole {hole.its_id!r} supports flat and through bottoms, not {kind}",
            hole,
        )
    if getattr(hole, "change_in_diameter", None) is not None:
        raise ex.error(
            "STEPNC-UNSUPPORTED",
            f"milling round hole {hole.its_id!r}: a tapered hole (change_in_diameter) "
            "cannot be milled as a pocket",
            hole,
        )
    diameter = measure(hole.diameter) or 0.0
    if diameter <= 0 or depth <= 0:
        raise ex.error(
            "STEPNC-POCKET",
            f"round hole {hole.its_id!r} needs a positive diameter and a depth plane below "
            f"its top (diameter {diameter:g}, depth {depth:g})",
            hole,
        )
    return diameter, diameter, depth, diameter / 2.0, Frame()


def _polyline_rectangle(boundary: Entity) -> tuple[float, float, Frame] | None:
    """(length, width, centred frame) of a closed four-corner polyline with right angles."""
    if boundary.type != "GENERAL_CLOSED_PROFILE":
        return None
    shape = boundary.closed_profile_shape
    if not isinstance(shape, Entity) or shape.type != "POLYLINE":
        return None
    place = frame_of(boundary.placement)
    pts = [place.point(coords(p)) for p in shape.points]
    if len(pts) == 5 and math.dist(pts[0], pts[4]) < TINY:
        pts = pts[:4]
    if len(pts) != 4 or any(abs(p[2] - pts[0][2]) > TINY for p in pts):
        return None
    edges = [(pts[(i + 1) % 4][0] - pts[i][0], pts[(i + 1) % 4][1] - pts[i][1]) for i in range(4)]
    for a, b in zip(edges, edges[1:] + edges[:1], strict=True):
        if abs(a[0] * b[0] + a[1] * b[1]) > TINY * max(1.0, math.hypot(*a) * math.hypot(*b)):
            return None
    e0, e1 = math.hypot(*edges[0]), math.hypot(*edges[1])
    long_edge = edges[0] if e0 >= e1 else edges[1]
    cx = sum(p[0] for p in pts) / 4
    cy = sum(p[1] for p in pts) / 4
    ux, uy = long_edge[0] / max(e0, e1), long_edge[1] / max(e0, e1)
    if ux < -TINY or (abs(ux) <= TINY and uy < 0):  # canonical: long side towards +X (+Y)
        ux, uy = -ux, -uy
    return max(e0, e1), min(e0, e1), Frame((cx, cy, pts[0][2]), (ux, uy, 0.0), (0.0, 0.0, 1.0))


class Strategies:
    """Approach, retract and inside strategies, with NIST's defaults where $ is given."""

    def __init__(
        self, op: Entity, length: float, width: float, radius: float, diameter: float, finish: bool
    ) -> None:
        side = (
            float(op.allowance_side) if op.allowance_side is not None else 0.0 if finish else ALLOW
        )
        extra_w = width - (diameter + 2 * side)
        extra_l = length - (diameter + 2 * side)
        self.side = side
        self.ok = extra_w >= -TINY and radius - side >= diameter / 2.0 - TINY
        inside = op.its_machining_strategy
        self.rotation = "CW"
        self.cutmode = "CONVENTIONAL"
        self.along_y = False
        self.left = False
        if inside is not None:
            if inside.type not in ("CONTOUR_PARALLEL", "CONTOUR_SPIRAL"):
                self.inside_type = inside.type
            mode = getattr(inside, "cutmode", None) or getattr(inside, "spiral_cutmode", None)
            self.rotation = getattr(inside, "rotation_direction", None) or (
                "CCW" if mode == "CLIMB" else "CW"
            )
            self.cutmode = mode or ("CLIMB" if self.rotation == "CCW" else "CONVENTIONAL")
            feed_dir = getattr(inside, "feed_direction", None)
            if feed_dir is not None:
                d = direction(feed_dir)
                self.along_y = abs(d[1]) > abs(d[0])
            self.left = getattr(inside, "stepover_direction", None) == "LEFT"
        self.inside = inside
        self.outside_in = outside_in(self.rotation, self.cutmode)
        if op.radial_cutting_depth is not None:
            self.stepover = float(op.radial_cutting_depth)
        else:
            overlap = inside.overlap if inside is not None and inside.overlap is not None else 0.5
            self.stepover = diameter * (1 - float(overlap))
        approach = op.approach
        if approach is None:
            if extra_w < TINY:
                kind = (
                    ("PLUNGE_TOOLAXIS", ())
                    if extra_l < TINY
                    else ("PLUNGE_ZIGZAG", (10.0, min(extra_l, 3 * diameter)))
                )
            elif extra_w < 0.4 * diameter:
                kind = (
                    ("PLUNGE_HELIX", (extra_w / 2.0, 10.0))
                    if extra_l < 1.25 * extra_w
                    else ("PLUNGE_ZIGZAG", (10.0, min(extra_l, 3 * diameter)))
                )
            elif extra_w < 0.8 * diameter:
                kind = ("PLUNGE_HELIX", (extra_w / 2.0, 10.0))
            else:
                kind = ("PLUNGE_HELIX", (0.4 * diameter, 10.0))
            self.approach = kind
        else:
            t = approach.type
            args = {
                "PLUNGE_TOOLAXIS": (),
                "PLUNGE_RAMP": ("angle",),
                "PLUNGE_ZIGZAG": ("angle", "width"),
                "PLUNGE_HELIX": ("radius", "angle"),
            }[t]
            self.approach = (t, tuple(float(getattr(approach, a)) for a in args))
        retract = op.retract
        self.retract = "PLUNGE_TOOLAXIS" if retract is None else retract.type

    inside_type = "CONTOUR_PARALLEL"


def generate(ex, job) -> None:  # noqa: ANN001
    op, pocket = job.op, job.feature
    if pocket.type not in ("CLOSED_POCKET", "ROUND_HOLE"):
        raise ex.error(
            "STEPNC-OP-FEATURE",
            f"{op.type} is implemented for CLOSED_POCKET and ROUND_HOLE, not {pocket.type}",
            op,
        )
    finish = op.type.endswith("FINISH_MILLING")
    diameter = float(tool_dimension(op.its_tool).diameter)
    length, width, depth, radius, profile = pocket_shape(ex, pocket)
    st = Strategies(op, length, width, radius, diameter, finish)
    if not st.ok:
        raise ex.error(
            "STEPNC-TOOL-CORNER",
            f"a {diameter:g} mm tool does not fit pocket "
            f"{pocket.its_id!r} with side allowance {st.side:g}",
            op,
        )
    if st.inside_type not in ("CONTOUR_PARALLEL", *ZIGZAG):
        raise ex.error(
            "STEPNC-STRATEGY",
            f"pocket milling supports contour-parallel, bidirectional and contour-bidirectional "
            f"strategies, not {st.inside_type}",
            op,
        )
    if st.retract != "PLUNGE_TOOLAXIS":
        raise ex.error("STEPNC-STRATEGY", "pocket retract supports PLUNGE_TOOLAXIS only", op)
    code = Code()
    try:
        mill_pocket(code, length, width, depth, radius, diameter, op, st, finish)
    except ValueError as exc:
        raise ex.error("STEPNC-ENTRY", f"approach strategy: {exc}", op) from None
    frame = job.frame if profile == Frame() else job.frame.compose(profile)
    if not frame.vertical:
        raise ex.error(
            "STEPNC-PLACEMENT", "the pocket profile must lie in the feature's XY plane", op
        )
    ex.start_and_run(place(code, frame))


def mill_pocket(
    code: Code,
    length: float,
    width: float,
    depth: float,
    radius: float,
    diameter: float,
    op: Entity,
    st: Strategies,
    finish: bool,
) -> None:
    """NIST ``mill_rectangular_pocket``: allowances, pass depth, then the layer loop."""
    if op.allowance_bottom is not None:
        mill_depth = depth - float(op.allowance_bottom)
    else:
        mill_depth = depth - (0.0 if finish else ALLOW)
    side = st.side
    mill_length, mill_width = length - 2 * side, width - 2 * side
    extra_l, extra_w = mill_length - diameter, mill_width - diameter
    pass_depth = (
        float(op.axial_cutting_depth) if op.axial_cutting_depth is not None else diameter / 2.0
    )
    retract = float(op.retract_plane) if op.retract_plane is not None else UP
    if extra_w < TINY:
        if extra_l < TINY:
            code.feed(0, 0, retract)
            code.feed(0, 0, -mill_depth)
            code.feed(0, 0, retract)
        else:
            _cut_straight(code, mill_length, mill_depth, retract, pass_depth, st, diameter)
        return
    spiral = 1 if st.rotation == "CCW" else -1
    passes = 1 + int((mill_depth - TINY) / pass_depth)
    pass_depth = mill_depth / passes
    end1 = (mill_length - mill_width) / 2.0
    end2 = -end1
    z = -pass_depth
    r = radius - side
    tl, tw = mill_length - diameter, mill_width - diameter
    start = plunge_start(tl, tw, retract + pass_depth, st.approach)
    code.feed(start[0], start[1], retract)
    enter(code, st.approach, start, retract, end2, z)
    _layer(code, mill_length, mill_width, r, z, st, diameter, spiral)
    if passes > 1:
        start = plunge_start(tl, tw, pass_depth, st.approach)
    for _ in range(1, passes):
        x, y, _z = code.end()
        code.feed(x, y, z + pass_depth)
        code.traverse(start[0], start[1], z + pass_depth)
        code.feed(start[0], start[1], z)
        z -= pass_depth
        enter(code, st.approach, start, z + pass_depth, end2, z)
        _layer(code, mill_length, mill_width, r, z, st, diameter, spiral)
    x, y, _z = code.end()
    code.feed(x, y, retract)


def _layer(
    code: Code,
    length: float,
    width: float,
    radius: float,
    z: float,
    st: Strategies,
    diameter: float,
    spiral: int,
) -> None:
    end1 = (length - width) / 2.0
    stepover = st.stepover
    if st.inside_type in ZIGZAG:
        _zigzag(code, length, width, radius, z, st, diameter, spiral)
        return
    circular = width - 2 * radius < TINY and end1 < TINY
    if circular:
        loops = _circular(length, z, stepover, diameter, spiral)
    elif width - 2 * radius < TINY:
        loops = _semicircle_ends(length, width, z, stepover, diameter, spiral)
    else:
        loops = _regular(length, width, radius, z, stepover, diameter, spiral)
    if not circular:
        code.feed(end1, 0, z)  # along the centre line from the entry at its -X end
    # Each loop starts and ends at its own start point on the +X centre line, so the
    # loops can run inside out (material outside the loop) or outside in (inside it).
    for loop in reversed(loops) if st.outside_in else loops:
        code.extend(loop)
    check_count(len(code), "toolpath lines of one operation")


ZIGZAG = ("BIDIRECTIONAL_MILLING", "CONTOUR_BIDIRECTIONAL")


def _zigzag(
    code: Code,
    length: float,
    width: float,
    radius: float,
    z: float,
    st: Strategies,
    diameter: float,
    spiral: int,
) -> None:
    """Bidirectional strokes over the region the tool centre may reach (the pocket offset by
    the tool radius: a rectangle with corner radius ``radius - r``), parallel to the feed
    direction; CONTOUR_BIDIRECTIONAL adds one contour pass along that region's boundary
    (ISO 14649-11 §4.2.8.1 bidirectional and contour-bidirectional milling)."""
    r = diameter / 2.0
    hx, hy = length / 2.0 - r, width / 2.0 - r
    rc = max(radius - r, 0.0)
    if st.along_y:  # strokes along Y: work in (u, v) = (y, -x), a rotation by +90 degrees
        hu, hv = hy, hx

        def put(u: float, v: float) -> None:
            code.feed(-v, u, z)

        def put_arc(u: float, v: float, cu: float, cv: float, turns: int) -> None:
            code.arc(-v, u, -cv, cu, turns, z)
    else:
        hu, hv = hx, hy

        def put(u: float, v: float) -> None:
            code.feed(u, v, z)

        def put_arc(u: float, v: float, cu: float, cv: float, turns: int) -> None:
            code.arc(u, v, cu, cv, turns, z)

    def along_edge(p: tuple[float, float], q: tuple[float, float]) -> None:
        """From stroke end ``p`` to stroke end ``q`` on the same side, following the
        boundary of the tool-centre region (its straight side and corner arcs)."""
        side = 1.0 if p[0] > 0 else -1.0
        knee = hv - rc  # |v| where the corner arc begins
        pts = [p]
        for vk in sorted({-knee, knee}, reverse=q[1] < p[1]):
            if min(p[1], q[1]) < vk < max(p[1], q[1]):
                pts.append((side * hu, vk))
        pts.append(q)
        for a, b in zip(pts, pts[1:], strict=False):
            mid = (a[1] + b[1]) / 2.0
            if abs(mid) > knee + TINY and rc > TINY:
                cu, cv = side * (hu - rc), math.copysign(knee, mid)
                cross = (a[0] - cu) * (b[1] - cv) - (a[1] - cv) * (b[0] - cu)
                put_arc(b[0], b[1], cu, cv, 1 if cross > 0 else -1)
            else:
                put(*b)

    n = max(1, math.ceil((2 * hv - TINY) / st.stepover)) if hv > TINY else 0
    check_count(n, "zigzag strokes of the pocket")
    sign = 1.0 if st.left else -1.0
    vs = [sign * (-hv + 2 * hv * k / n) for k in range(n + 1)] if n else [0.0]
    forward = True
    prev: tuple[float, float] | None = None  # start of the previous stroke
    last: tuple[float, float] | None = None  # end of the previous stroke
    for v in vs:
        dv = abs(v) - (hv - rc)
        extent = hu - rc + math.sqrt(max(rc * rc - dv * dv, 0.0)) if dv > 0 else hu
        a, b = (-extent, extent) if forward else (extent, -extent)
        if last is None:
            put(a, v)
        else:
            along_edge(last, (a, v))
        put(b, v)
        if prev is not None and abs(prev[0] - b) > TINY:
            # a rounded corner between this stroke's end and the previous stroke's start:
            # sweep it along the boundary and back, or a corner wedge stays uncut
            along_edge((b, v), prev)
            along_edge(prev, (b, v))
        prev, last = (a, v), (b, v)
        forward = not forward
    if st.inside_type == "CONTOUR_BIDIRECTIONAL":
        end1 = (length - width) / 2.0
        c = width / 2.0 - radius
        off = hy
        code.feed(end1 + off, 0.0, z)
        _loop(code, end1, -end1, c, off, off - c, spiral, z)


def _loop(
    code: Code, end1: float, end2: float, c: float, off: float, r_now: float, s: int, z: float
) -> None:
    """One closed loop at ``off`` around the centre line, starting and ending at
    (end1 + off, 0): square corners while ``r_now`` <= 0, else arcs (NIST pocket loop)."""
    if r_now < TINY:
        code.feed(end1 + off, off * s, z)
        code.feed(end2 - off, off * s, z)
        code.feed(end2 - off, -off * s, z)
        code.feed(end1 + off, -off * s, z)
        code.feed(end1 + off, 0, z)
    else:
        code.feed(end1 + off, c * s, z)
        code.arc(end1 + c, off * s, end1 + c, c * s, s, z)
        code.feed(end2 - c, off * s, z)
        code.arc(end2 - off, c * s, end2 - c, c * s, s, z)
        code.feed(end2 - off, -c * s, z)
        code.arc(end2 - c, -off * s, end2 - c, -c * s, s, z)
        code.feed(end1 + c, -off * s, z)
        code.arc(end1 + off, -c * s, end1 + c, -c * s, s, z)
        code.feed(end1 + off, 0, z)


def _passes(total: float, stepover: float) -> tuple[int, float]:
    check_count(1 + (total - TINY) / stepover, "passes of the pocket")
    n = 1 + int((total - TINY) / stepover)
    return n, total / n


def _regular(
    length: float,
    width: float,
    radius: float,
    z: float,
    stepover: float,
    diameter: float,
    s: int,
) -> list[Code]:
    """Rectangular loops around the centre line, innermost first, with corner arcs once
    they fit; each begins with the feed to its start point."""
    n, stepover = _passes((width - diameter) / 2.0, stepover)
    end1 = (length - width) / 2.0
    end2 = -end1
    c = width / 2.0 - radius
    r_now, off = -c, 0.0
    loops = Code()
    starts = []
    for _ in range(n):
        r_now += stepover
        off += stepover
        starts.append(len(loops))
        loops.feed(end1 + off, 0, z)
        _loop(loops, end1, end2, c, off, r_now, s, z)
    return _split(loops, starts)


def _semicircle_ends(
    length: float, width: float, z: float, stepover: float, diameter: float, s: int
) -> list[Code]:
    """Loops of two straight sides and two half circles, innermost first."""
    n, stepover = _passes((width - diameter) / 2.0, stepover)
    end1 = (length - width) / 2.0
    end2 = -end1
    r = 0.0
    loops = Code()
    starts = []
    for _ in range(n):
        r += stepover
        starts.append(len(loops))
        loops.feed(end1 + r, 0, z)
        loops.arc(end1, r * s, end1, 0, s, z)
        loops.feed(end2, r * s, z)
        loops.arc(end2, -r * s, end2, 0, s, z)
        loops.feed(end1, -r * s, z)
        loops.arc(end1 + r, 0, end1, 0, s, z)
    return _split(loops, starts)


def _circular(length: float, z: float, stepover: float, diameter: float, s: int) -> list[Code]:
    """Full circles about the centre, innermost first."""
    n, stepover = _passes((length - diameter) / 2.0, stepover)
    r = 0.0
    loops = Code()
    starts = []
    for _ in range(n):
        r += stepover
        starts.append(len(loops))
        loops.feed(r, 0, z)
        loops.arc(r, 0, 0, 0, s, z)
    return _split(loops, starts)


def _split(lines: Code, starts: list[int]) -> list[Code]:
    """``lines`` cut at ``starts`` into its loops (written into one Code first so that its
    line budget, kernel.limits' ``toolpath_passes``, applies to them all)."""
    ends = [*starts[1:], len(lines)]
    return [Code(lines[a:b]) for a, b in zip(starts, ends, strict=True)]


def _cut_straight(
    code: Code,
    length: float,
    depth: float,
    retract: float,
    pass_depth: float,
    st: Strategies,
    diameter: float,
) -> None:
    """A groove as wide as the tool along the X axis (NIST ``cut_straight``)."""
    if st.approach[0] == "PLUNGE_HELIX":
        raise ValueError("no room for a helix in a pocket as wide as the tool")
    passes = 1 + int((depth - TINY) / pass_depth)
    pass_depth = depth / passes
    end1 = (length - diameter) / 2.0
    end2 = -end1
    z = -pass_depth
    start = plunge_start(length - diameter, 0.0, retract + pass_depth, st.approach)
    code.feed(start[0], start[1], retract)
    enter(code, st.approach, start, retract, end2, z)
    code.feed(end1, 0, z)
    if passes > 1:
        start = plunge_start(length - diameter, 0.0, pass_depth, st.approach)
    for _ in range(1, passes):
        if abs(end1 - start[0]) > TINY or abs(start[1]) > TINY:
            code.feed(end1, 0, z + pass_depth)
            code.traverse(start[0], start[1], z + pass_depth)
            code.feed(start[0], start[1], z)
        z -= pass_depth
        enter(code, st.approach, start, z + pass_depth, end2, z)
        code.feed(end1, 0, z)
    code.feed(end1, 0, retract)
