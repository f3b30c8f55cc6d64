"""Builders of the small ISO 14649 test programs in tests/stepnc/*.stp.

Each program is a 100 x 80 x 40 block (top at Z=0) with one setup, a security plane at
Z=50 and one or more workingsteps. ``regen.py`` writes them and their golden canonical
outputs; the tests re-read the files (the builders document how they were made).
"""

from __future__ import annotations

from collections.abc import Callable

from stepnc.part21 import format_value


class Program:
    """Accumulates Part 21 instances with automatic ids."""

    def __init__(self, title: str) -> None:
        self.title = title
        self.lines: list[str] = []
        self.next = 100
        self.workingsteps: list[int] = []
        self.features: dict[int, list[int]] = {}
        self.secplane = self.add("PLANE('SECURITY PLANE',{})", self.placement((0, 0, 50)))

    def add(self, text: str, *refs: object) -> int:
        ident = self.next
        self.next += 1
        self.lines.append(
            f"#{ident}=" + text.format(*(f"#{r}" if isinstance(r, int) else r for r in refs)) + ";"
        )
        return ident

    def point(self, p: tuple[float, ...]) -> int:
        return self.add("CARTESIAN_POINT('',({}))", ",".join(_r(v) for v in p))

    def direction(self, d: tuple[float, ...]) -> int:
        return self.add("DIRECTION('',({}))", ",".join(_r(v) for v in d))

    def placement(self, origin: tuple[float, ...], ref: tuple[float, ...] = (1, 0, 0)) -> int:
        return self.add(
            "AXIS2_PLACEMENT_3D('',{},{},{})",
            self.point(origin),
            self.direction((0, 0, 1)),
            self.direction(ref),
        )

    def plane_at(self, z: float) -> int:
        return self.add("PLANE('',{})", self.placement((0, 0, z)))

    def tlm(self, v: float) -> int:
        tol = self.add("PLUS_MINUS_VALUE(0.1,0.1,3)")
        return self.add(f"TOLERANCED_LENGTH_MEASURE({_r(v)},{{}})", tol)

    def tool(
        self,
        name: str,
        body: str,
        diameter: float,
        *,
        length: float = 60.0,
        top_angle: float | None = None,
        edge: float = 40.0,
        teeth: int = 4,
    ) -> int:
        angle = "$" if top_angle is None else _r(top_angle)
        dim = self.add(f"MILLING_TOOL_DIMENSION({_r(diameter)},{angle},$,{_r(edge)},$,$,$)")
        extra = ",$" if body in ("TAPERED_ENDMILL", "TAPERED_REAMER") else ""
        b = self.add(f"{body}({{}},{teeth},.RIGHT.,.F.,${extra})", dim)
        comp = self.add(f"CUTTING_COMPONENT({_r(length)},$,$,$,$)")
        return self.add(
            f"MILLING_CUTTING_TOOL('{name}',{{}},({{}}),{_r(length + 20)},$,$)", b, comp
        )

    def tech(self, feed: float = 0.02, spindle: float = -20.0) -> int:
        return self.add(f"MILLING_TECHNOLOGY({_r(feed)},.TCP.,$,{_r(spindle)},$,.F.,.F.,.F.,$)")

    def functions(self, coolant: bool = True, mist: bool = False) -> int:
        c, m = (".T." if coolant else ".F."), (".T." if mist else ".F.")
        return self.add(f"MILLING_MACHINE_FUNCTIONS({c},$,{m},.F.,$,(),.F.,$,$,())")

    def workingstep(self, name: str, feature: int, op: int) -> int:
        ws = self.add(
            f"MACHINING_WORKINGSTEP('{name}',{{}},{{}},{{}},$)", self.secplane, feature, op
        )
        self.workingsteps.append(ws)
        self.features.setdefault(feature, []).append(op)
        return ws

    def text(self, elements: list[int] | None = None) -> str:
        """The complete Part 21 file. Features get their operations list patched in."""
        block_place = self.placement((0, 0, -40))
        block = self.add("BLOCK('RAW',{},100.0,80.0,40.0)", block_place)
        wp_place = self.placement((0, 0, 0))
        tail = [
            f"#1=PROJECT('{self.title}',#2,(#3),$,$,$);",
            "#2=WORKPLAN('MAIN',({}),$,#4,$);".format(
                ",".join(f"#{e}" for e in (elements or self.workingsteps))
            ),
            f"#3=WORKPIECE('BLOCK',$,0.01,$,$,#{block},());",
            f"#4=SETUP('SETUP',$,#{self.secplane},(#5));",
            f"#5=WORKPIECE_SETUP(#3,#{wp_place},$,$,());",
        ]
        data = "\n".join(tail + self.lines)
        for feat, ops in self.features.items():
            data = data.replace(f"OPS{feat}_", ",".join(f"#{o}" for o in ops))
        return (
            "ISO-10303-21;\nHEADER;\n"
            f"FILE_DESCRIPTION(('{self.title}'),'2;1');\n"
            "FILE_NAME('','2026-01-01',(''),(''),'','','');\n"
            "FILE_SCHEMA(('MACHINING_SCHEMA','MILLING_SCHEMA'));\nENDSEC;\nDATA;\n"
            f"{data}\nENDSEC;\nEND-ISO-10303-21;\n"
        )

    # ------------------------------------------------------------ features
    def face(
        self, x: float, y: float, length: float, width: float, depth: float, along_y: bool = False
    ) -> int:
        place = self.placement((x, y, 0))
        path = self.add(
            "LINEAR_PATH($,{},{})",
            self.tlm(width if along_y else length),
            self.direction((0, 1, 0) if along_y else (1, 0, 0)),
        )
        prof = self.add(f"NUMERIC_PARAMETER('WIDTH',{_r(length if along_y else width)},'MM')")
        prof = self.add("LINEAR_PROFILE($,{})", prof)
        depth_plane = self.plane_at(-depth)
        return self.add(
            "PLANAR_FACE('FACE',#3,({}),{},{},{},{},$,())",
            f"OPS{self.next}_",
            place,
            depth_plane,
            path,
            prof,
        )

    def pocket(
        self,
        x: float,
        y: float,
        length: float,
        width: float,
        depth: float,
        radius: float,
        angle_ref: tuple[float, ...] = (1, 0, 0),
        circular: bool = False,
    ) -> int:
        place = self.placement((x, y, 0), angle_ref)
        if circular:
            boundary = self.add("CIRCULAR_CLOSED_PROFILE($,{})", self.tlm(length))
        else:
            boundary = self.add(
                "RECTANGULAR_CLOSED_PROFILE($,{},{})", self.tlm(width), self.tlm(length)
            )
        bottom = self.add("PLANAR_POCKET_BOTTOM_CONDITION()")
        depth_plane, corner = self.plane_at(-depth), self.tlm(radius)
        return self.add(
            "CLOSED_POCKET('POCKET',#3,({}),{},{},(),$,{},$,{},{})",
            f"OPS{self.next}_",
            place,
            depth_plane,
            bottom,
            corner,
            boundary,
        )

    def hole(self, x: float, y: float, diameter: float, depth: float, through: bool = False) -> int:
        place = self.placement((x, y, 0))
        bottom = self.add("THROUGH_BOTTOM_CONDITION()" if through else "FLAT_HOLE_BOTTOM()")
        depth_plane, dia = self.plane_at(-depth), self.tlm(diameter)
        return self.add(
            "ROUND_HOLE('HOLE',#3,({}),{},{},{},$,{})",
            f"OPS{self.next}_",
            place,
            depth_plane,
            dia,
            bottom,
        )

    def slot(
        self,
        x: float,
        y: float,
        length: float,
        width: float,
        depth: float,
        course: tuple[float, ...] = (1, 0, 0),
        ends: tuple[str, ...] = (),
    ) -> int:
        place = self.placement((x, y, 0))
        path = self.add("LINEAR_PATH($,{},{})", self.tlm(length), self.direction(course))
        shape = self.add("SQUARE_U_PROFILE($,{},$,$,$,$)", self.tlm(width))
        end_refs = ",".join(f"#{self.add(f'{e}()')}" for e in ends)
        depth_plane = self.plane_at(-depth)
        return self.add(
            f"SLOT('SLOT',#3,({{}}),{{}},{{}},{{}},{{}},({end_refs}))",
            f"OPS{self.next}_",
            place,
            depth_plane,
            path,
            shape,
        )

    def step(
        self, x: float, y: float, length: float, depth: float, along: tuple[float, ...]
    ) -> int:
        """Wall foot from (x, y) along ``along``; the material on its right is removed."""
        place = self.placement((x, y, 0))
        path = self.add("LINEAR_PATH($,{},{})", self.tlm(length), self.direction(along))
        depth_plane = self.plane_at(-depth)
        return self.add(
            "STEP('STEP',#3,({}),{},{},{},$)", f"OPS{self.next}_", place, depth_plane, path
        )

    def open_pocket(
        self, x: float, y: float, length: float, width: float, depth: float, radius: float
    ) -> int:
        """Open side on the feature's Y axis (x = 0), the pocket extending along +X."""
        place = self.placement((x, y, 0))
        w = width / 2
        pts = [self.point(p) for p in ((0, -w, 0), (length, -w, 0), (length, w, 0), (0, w, 0))]
        curve = self.add("POLYLINE('U',({}))".format(",".join(f"#{q}" for q in pts)))
        boundary = self.add("GENERAL_PROFILE($,{})", curve)
        bottom = self.add("PLANAR_POCKET_BOTTOM_CONDITION()")
        depth_plane, corner = self.plane_at(-depth), self.tlm(radius)
        return self.add(
            "OPEN_POCKET('OPEN POCKET',#3,({}),{},{},(),$,{},$,{},{},$)",
            f"OPS{self.next}_",
            place,
            depth_plane,
            bottom,
            corner,
            boundary,
        )


def _r(v: float) -> str:
    return format_value(float(v))


def _mill(p: Program, d: float = 10.0) -> int:
    return p.tool(f"MILL {d:g}", "ENDMILL", d)


def _plane_op(
    p: Program, kind: str, strategy: int, axial: str = "2.0", allowance: str = "$"
) -> int:
    return p.add(
        f"{kind}($,$,'FACE OP',5.0,$,{{}},{{}},{{}},$,$,$,{{}},{axial},{allowance})",
        _mill(p, 16.0),
        p.tech(),
        p.functions(),
        strategy,
    )


def _pocket_op(
    p: Program,
    kind: str,
    strategy: str,
    approach: str = "$",
    *,
    tool: int | None = None,
    axial: str = "4.0",
    radial: str = "4.0",
    side: str = "$",
    bottom: str = "$",
) -> int:
    t = tool if tool is not None else _mill(p)
    strat = p.add(strategy) if strategy != "$" else "$"
    appr = p.add(approach) if approach != "$" else "$"
    return p.add(
        f"{kind}($,$,'POCKET OP',5.0,$,{{}},{{}},{{}},$,{{}},$,{{}},{axial},{radial},"
        f"{side},{bottom})",
        t,
        p.tech(),
        p.functions(),
        appr,
        strat,
    )


def _side_op(
    p: Program,
    kind: str,
    strategy: str,
    *,
    tool: int | None = None,
    axial: str = "$",
    radial: str = "$",
    side: str = "$",
) -> int:
    """SIDE_ROUGH/FINISH_MILLING: like bottom-and-side without the bottom allowance."""
    t = tool if tool is not None else _mill(p)
    strat = p.add(strategy) if strategy != "$" else "$"
    return p.add(
        f"{kind}($,$,'SIDE OP',5.0,$,{{}},{{}},{{}},$,$,$,{{}},{axial},{radial},{side})",
        t,
        p.tech(),
        p.functions(),
        strat,
    )


# ------------------------------------------------------------------ the programs
def face_bidir_x() -> Program:
    p = Program("FACE BIDIRECTIONAL +X LEFT")
    s = p.add("BIDIRECTIONAL_MILLING(0.25,.T.,{},.LEFT.,$)", p.direction((1, 0, 0)))
    p.workingstep("WS FACE", p.face(0, 0, 100, 80, 3), _plane_op(p, "PLANE_FINISH_MILLING", s))
    return p


def face_bidir_y_right() -> Program:
    p = Program("FACE BIDIRECTIONAL +Y RIGHT")
    s = p.add("BIDIRECTIONAL_MILLING(0.3,.T.,{},.RIGHT.,$)", p.direction((0, 1, 0)))
    p.workingstep(
        "WS FACE",
        p.face(0, 0, 100, 80, 2.5, along_y=True),
        _plane_op(p, "PLANE_FINISH_MILLING", s, axial="1.5"),
    )
    return p


def face_bidir_minus_x() -> Program:
    p = Program("FACE BIDIRECTIONAL -X")
    s = p.add("BIDIRECTIONAL_MILLING($,$,{},$,$)", p.direction((-1, 0, 0)))
    p.workingstep("WS FACE", p.face(0, 0, 100, 80, 2), _plane_op(p, "PLANE_FINISH_MILLING", s))
    return p


def face_unidir_conventional() -> Program:
    p = Program("FACE UNIDIRECTIONAL CONVENTIONAL")
    s = p.add("UNIDIRECTIONAL_MILLING(0.2,.T.,{},.CONVENTIONAL.)", p.direction((1, 0, 0)))
    p.workingstep("WS FACE", p.face(0, 0, 100, 80, 2), _plane_op(p, "PLANE_FINISH_MILLING", s))
    return p


def face_unidir_climb_minus_y() -> Program:
    p = Program("FACE UNIDIRECTIONAL CLIMB -Y")
    s = p.add("UNIDIRECTIONAL_MILLING(0.2,.T.,{},.CLIMB.)", p.direction((0, -1, 0)))
    p.workingstep(
        "WS FACE", p.face(0, 0, 100, 80, 2, along_y=True), _plane_op(p, "PLANE_FINISH_MILLING", s)
    )
    return p


def face_rough_default_allowance() -> Program:
    p = Program("FACE ROUGH DEFAULT ALLOWANCE")
    s = p.add("BIDIRECTIONAL_MILLING(0.2,.T.,$,.LEFT.,$)")
    p.workingstep(
        "WS FACE", p.face(0, 0, 100, 80, 3), _plane_op(p, "PLANE_ROUGH_MILLING", s, axial="$")
    )
    return p


def pocket_rough_default_helix() -> Program:
    p = Program("POCKET ROUGH DEFAULT ENTRY")
    p.workingstep(
        "WS ROUGH",
        p.pocket(50, 40, 60, 40, 12, 8),
        _pocket_op(p, "BOTTOM_AND_SIDE_ROUGH_MILLING", "$", side="0.5", bottom="0.5"),
    )
    return p


def pocket_finish_helix() -> Program:
    p = Program("POCKET FINISH HELIX")
    p.workingstep(
        "WS FINISH",
        p.pocket(50, 40, 60, 40, 10, 8),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_PARALLEL(0.5,.T.,.CW.,.CONVENTIONAL.)",
            "PLUNGE_HELIX($,4.0,5.0)",
            axial="5.0",
            radial="$",
        ),
    )
    return p


def pocket_ramp() -> Program:
    p = Program("POCKET RAMP ENTRY")
    p.workingstep(
        "WS ROUGH",
        p.pocket(50, 40, 70, 40, 9, 6),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            "PLUNGE_RAMP($,20.0)",
            axial="3.0",
            side="0.5",
            bottom="0.5",
        ),
    )
    return p


def pocket_zigzag() -> Program:
    p = Program("POCKET ZIGZAG ENTRY")
    p.workingstep(
        "WS ROUGH",
        p.pocket(50, 40, 70, 30, 8, 6),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            "PLUNGE_ZIGZAG($,15.0,8.0)",
            axial="4.0",
            side="0.5",
            bottom="0.5",
        ),
    )
    return p


def pocket_toolaxis_ccw_climb() -> Program:
    p = Program("POCKET TOOLAXIS CCW CLIMB")
    p.workingstep(
        "WS FINISH",
        p.pocket(50, 40, 60, 50, 6, 10),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_PARALLEL($,$,.CCW.,.CLIMB.)",
            "PLUNGE_TOOLAXIS($)",
            axial="3.0",
            radial="6.0",
        ),
    )
    return p


def pocket_bidirectional() -> Program:
    p = Program("POCKET BIDIRECTIONAL")
    s = "BIDIRECTIONAL_MILLING(0.4,.T.,#{},.LEFT.,$)"
    p.workingstep(
        "WS ROUGH",
        p.pocket(50, 40, 60, 40, 8, 10),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            s.format(p.direction((1, 0, 0))),
            "PLUNGE_RAMP($,15.0)",
            axial="4.0",
            radial="$",
            side="0.5",
            bottom="0.5",
        ),
    )
    return p


def pocket_contour_bidirectional_y() -> Program:
    p = Program("POCKET CONTOUR BIDIRECTIONAL ALONG Y")
    s = "CONTOUR_BIDIRECTIONAL(0.5,.T.,#{},.RIGHT.,.CCW.,.CLIMB.)"
    p.workingstep(
        "WS FINISH",
        p.pocket(50, 40, 70, 44, 6, 12),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            s.format(p.direction((0, 1, 0))),
            "PLUNGE_HELIX($,3.0,8.0)",
            axial="3.0",
            radial="4.0",
        ),
    )
    return p


def pocket_semicircle_ends() -> Program:
    p = Program("POCKET SEMICIRCLE ENDS")
    p.workingstep(
        "WS FINISH",
        p.pocket(50, 40, 70, 30, 5, 15),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            axial="5.0",
            radial="5.0",
        ),
    )
    return p


def pocket_circular() -> Program:
    p = Program("POCKET CIRCULAR")
    p.workingstep(
        "WS FINISH",
        p.pocket(50, 40, 40, 40, 6, 20, circular=True),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            axial="3.0",
            radial="5.0",
        ),
    )
    return p


def round_hole_milled() -> Program:
    """pocket_circular's 40 mm, 6 mm deep circle as a flat-bottomed ROUND_HOLE."""
    p = Program("ROUND HOLE MILLED")
    p.workingstep(
        "WS FINISH",
        p.hole(50, 40, 40, 6),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            axial="3.0",
            radial="5.0",
        ),
    )
    return p


def pocket_groove_zigzag() -> Program:
    p = Program("POCKET AS WIDE AS THE TOOL")
    p.workingstep(
        "WS SLOT",
        p.pocket(50, 40, 60, 10, 6, 5),
        _pocket_op(p, "BOTTOM_AND_SIDE_FINISH_MILLING", "$", axial="2.0", radial="$"),
    )
    return p


def pocket_rotated() -> Program:
    p = Program("POCKET ROTATED 30 DEGREES")
    c, s = 0.8660254037844387, 0.5
    p.workingstep(
        "WS ROUGH",
        p.pocket(50, 40, 50, 30, 8, 6, angle_ref=(c, s, 0)),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "CONTOUR_PARALLEL(0.4,.T.,.CW.,.CONVENTIONAL.)",
            axial="4.0",
            radial="$",
            side="0.3",
            bottom="0.3",
        ),
    )
    return p


def _drill_tool(p: Program, d: float = 8.0) -> int:
    return p.tool(f"DRILL {d:g}", "TWIST_DRILL", d, top_angle=31.0, edge=60.0, teeth=2)


def drill_plain() -> Program:
    p = Program("DRILLING")
    op = p.add(
        "DRILLING($,$,'DRILL',3.0,$,{},{},{},$,$,$,$,$,$)",
        _drill_tool(p),
        p.tech(0.005, -25.0),
        p.functions(),
    )
    p.workingstep("WS DRILL", p.hole(30, 30, 8, 15), op)
    return p


def drill_reduced_feeds() -> Program:
    p = Program("DRILLING WITH DRILLING_TYPE_STRATEGY")
    s = p.add("DRILLING_TYPE_STRATEGY(0.8,0.5,2.0,0.6,0.4,4.0)")
    op = p.add(
        "DRILLING($,$,'DRILL',3.0,$,{},{},{},$,$,$,0.5,0.8,{})",
        _drill_tool(p),
        p.tech(0.005, -25.0),
        p.functions(),
        s,
    )
    p.workingstep("WS DRILL", p.hole(70, 40, 8, 40, through=True), op)
    return p


def multistep_drilling() -> Program:
    p = Program("MULTISTEP DRILLING")
    op = p.add(
        "MULTISTEP_DRILLING($,$,'PECK',3.0,$,{},{},{},$,$,$,$,$,$,1.0,5.0,4.0,0.2)",
        _drill_tool(p, 6.0),
        p.tech(0.004, -30.0),
        p.functions(),
    )
    p.workingstep("WS PECK", p.hole(30, 50, 6, 18), op)
    return p


def reaming_and_boring() -> Program:
    p = Program("REAMING AND BORING")
    hole = p.hole(40, 40, 10, 20, through=True)
    s = p.add("DRILLING_TYPE_STRATEGY(0.5,0.5,3.0,$,$,$)")
    ream = p.add(
        "REAMING($,$,'REAM',2.0,$,{},{},{},$,$,$,$,$,{},.F.,$,$)",
        p.tool("REAMER 10", "REAMER", 10.0, edge=70.0, teeth=6),
        p.tech(0.003, -8.0),
        p.functions(),
        s,
    )
    bore = p.add(
        "BORING($,$,'BORE',2.0,$,{},{},{},$,$,$,0.5,0.5,$,.T.,$,$)",
        p.tool("BORE 10", "ENDMILL", 10.0, edge=70.0),
        p.tech(0.002, -10.0),
        p.functions(False),
    )
    p.workingstep("WS REAM", hole, ream)
    p.workingstep("WS BORE", hole, bore)
    return p


def center_drill_countersink_tap() -> Program:
    p = Program("CENTRE DRILLING, COUNTERSINKING, TAPPING")
    hole = p.hole(60, 30, 8, 12)
    center = p.add(
        "CENTER_DRILLING($,$,'CENTRE',2.0,$,{},{},{},$,2.0,$,0.3,$,$)",
        p.tool("CENTRE 4", "CENTER_DRILL", 4.0, top_angle=60.0, edge=10.0, teeth=2),
        p.tech(0.003, -30.0),
        p.functions(),
    )
    sink = p.add(
        "COUNTER_SINKING($,$,'SINK',2.0,$,{},{},{},$,1.5,$,$,0.5,$)",
        p.tool("SINK 12", "COUNTERSINK", 8.0, top_angle=45.0, edge=10.0, teeth=3),
        p.tech(0.002, -15.0),
        p.functions(),
    )
    tap = p.add(
        "TAPPING($,$,'TAP',3.0,$,{},{},{},$,10.0,$,$,$,$,.T.)",
        p.tool("TAP M8", "TAP", 8.0, edge=20.0, teeth=3),
        p.tech(0.0125, -5.0),
        p.functions(),
    )
    for name, op in (("WS CENTRE", center), ("WS SINK", sink), ("WS TAP", tap)):
        p.workingstep(name, hole, op)
    return p


def _freeform(p: Program, toolpaths: list[int], feature: int, name: str = "WS PATH") -> int:
    tpl = p.add("TOOLPATH_LIST(({}))".format(",".join(f"#{t}" for t in toolpaths)))
    op = p.add(
        "FREEFORM_OPERATION({},$,'EXPLICIT',5.0,$,{},{},{},$,$,$,$)",
        tpl,
        _mill(p, 6.0),
        p.tech(0.01, -30.0),
        p.functions(),
    )
    return p.workingstep(name, feature, op)


def explicit_polyline() -> Program:
    p = Program("EXPLICIT POLYLINE")
    pts = [(-10, -5, 2), (-10, -5, -2), (10, -5, -2), (10, 5, -2), (-10, 5, -2), (-10, -5, -2)]
    poly = p.add("POLYLINE('',({}))".format(",".join(f"#{p.point(q)}" for q in pts)))
    up = p.add("POLYLINE('',({},{}))", p.point((-10, -5, -2)), p.point((-10, -5, 3)))
    t1 = p.add("CUTTER_LOCATION_TRAJECTORY(.T.,.TRAJECTORY_PATH.,$,$,$,.T.,{},$,$)", poly)
    t2 = p.add("CUTTER_LOCATION_TRAJECTORY(.T.,.CONNECT.,$,$,$,.T.,{},$,$)", up)
    _freeform(p, [t1, t2], p.pocket(50, 40, 40, 30, 5, 3))
    return p


def explicit_segment_technology() -> Program:
    p = Program("EXPLICIT SEGMENT TECHNOLOGY")
    a, b, c, d = (p.point(q) for q in ((-10, 0, 2), (-10, 0, -2), (10, 0, -2), (10, 8, -2)))
    slow = p.tech(0.002, -10.0)
    segs = []
    for pts, tech in (((a, b), "$"), ((b, c), slow), ((c, d), "$")):
        poly = p.add("POLYLINE('',({},{}))", *pts)
        segs.append(
            p.add("CUTTER_LOCATION_TRAJECTORY(.T.,.TRAJECTORY_PATH.,$,{},$,.T.,{},$,$)", tech, poly)
        )
    _freeform(p, segs, p.pocket(50, 40, 40, 30, 5, 3))
    return p


def explicit_arcs_and_helix() -> Program:
    p = Program("EXPLICIT ARC AND HELIX")
    centre = p.placement((0, 0, 0))
    circle = p.add("CIRCLE('',{},8.0)", centre)
    helix = p.add("HELIX('',{},8.0,-1.0)", centre)
    a, b = p.point((8, 0, -1)), p.point((-8, 0, -1))
    arc = p.add("TRIMMED_CURVE('',{},({}),({}),.T.,.CARTESIAN.)", circle, a, b)
    down = p.add("TRIMMED_CURVE('',{},({}),({}),.F.,.CARTESIAN.)", helix, b, p.point((-8, 0, -3)))
    seg1 = p.add("COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,{})", arc)
    seg2 = p.add("COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,{})", down)
    comp = p.add("COMPOSITE_CURVE('',({},{}),.F.)", seg1, seg2)
    line = p.add(
        "LINE('',{},{})", p.point((0, 0, 0)), p.add("VECTOR('',{},1.0)", p.direction((1, 0, 0)))
    )
    plunge = p.add(
        "TRIMMED_CURVE('',{},({}),({}),.T.,.CARTESIAN.)",
        line,
        p.point((8, 0, 2)),
        p.point((8, 0, -1)),
    )
    t0 = p.add("CUTTER_LOCATION_TRAJECTORY(.T.,.TRAJECTORY_PATH.,$,$,$,.T.,{},$,$)", plunge)
    t1 = p.add("CUTTER_LOCATION_TRAJECTORY(.T.,.TRAJECTORY_PATH.,$,$,$,.T.,{},$,$)", comp)
    stop = p.add("FEEDSTOP(.T.,.TRAJECTORY_PATH.,$,$,$,0.5)")
    _freeform(p, [t0, t1, stop], p.pocket(50, 40, 30, 30, 4, 15, circular=True))
    return p


def explicit_bspline() -> Program:
    p = Program("EXPLICIT B-SPLINE")
    ctrl = [(-15, -5, -1), (-5, 8, -1), (5, -8, -1), (15, 5, -1)]
    pts = ",".join(f"#{p.point(q)}" for q in ctrl)
    spline = p.add(
        f"B_SPLINE_CURVE_WITH_KNOTS('',3,({pts}),.UNSPECIFIED.,.F.,.F.,(4,4),"
        "(0.0,1.0),.PIECEWISE_BEZIER_KNOTS.)"
    )
    t = p.add("CUTTER_LOCATION_TRAJECTORY(.T.,.TRAJECTORY_PATH.,$,$,$,.T.,{},$,$)", spline)
    _freeform(p, [t], p.pocket(50, 40, 50, 40, 3, 5))
    return p


def workplan_structures() -> Program:
    p = Program("PROGRAM STRUCTURES AND NC FUNCTIONS")
    s = p.add("BIDIRECTIONAL_MILLING(0.2,.T.,$,.LEFT.,$)")
    face_ws = p.workingstep(
        "WS FACE", p.face(0, 0, 100, 80, 1), _plane_op(p, "PLANE_FINISH_MILLING", s, axial="1.0")
    )
    drill = _drill_tool(p, 6.0)
    ws_a = p.workingstep(
        "WS HOLE A",
        p.hole(20, 20, 6, 10),
        p.add(
            "DRILLING($,$,'A',3.0,$,{},{},{},$,$,$,$,$,$)",
            drill,
            p.tech(0.004, -25.0),
            p.functions(),
        ),
    )
    ws_b = p.workingstep(
        "WS HOLE B",
        p.hole(80, 60, 6, 10),
        p.add(
            "DRILLING($,$,'B',3.0,$,{},{},{},$,$,$,$,$,$)",
            drill,
            p.tech(0.004, -25.0),
            p.functions(),
        ),
    )
    msg = p.add("DISPLAY_MESSAGE('MSG','CHECK THE FACE')")
    stop = p.add("OPTIONAL_STOP('OPT')")
    load = p.add("LOAD_TOOL('LOAD',{})", drill)
    nonseq = p.add("NON_SEQUENTIAL('HOLES',({},{}))", ws_a, ws_b)
    sel = p.add("SELECTIVE('CHOICE',({},{}))", ws_b, ws_a)
    unload = p.add("UNLOAD_TOOL('UNLOAD',$)")
    end = p.add("PROGRAM_STOP('STOP')")
    p.elements = [face_ws, msg, stop, load, nonseq, sel, unload, end]  # type: ignore[attr-defined]
    return p


def two_tools_face_and_pocket() -> Program:
    p = Program("FACE THEN POCKET THEN HOLE")
    s = p.add("BIDIRECTIONAL_MILLING(0.2,.T.,$,.LEFT.,$)")
    p.workingstep("WS FACE", p.face(0, 0, 100, 80, 2), _plane_op(p, "PLANE_FINISH_MILLING", s))
    p.workingstep(
        "WS POCKET",
        p.pocket(35, 40, 40, 30, 8, 6),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            axial="4.0",
            radial="4.0",
            side="0.5",
            bottom="0.5",
        ),
    )
    p.workingstep(
        "WS HOLE",
        p.hole(80, 40, 8, 12),
        p.add(
            "DRILLING($,$,'D',3.0,$,{},{},{},$,$,$,$,$,$)",
            _drill_tool(p),
            p.tech(0.005, -25.0),
            p.functions(),
        ),
    )
    return p


def slot_radiused_ramp() -> Program:
    """A closed slot at 45 degrees: radiused ends, rough with allowances, ramp entry."""
    p = Program("SLOT RADIUSED ROUGH RAMP")
    p.workingstep(
        "WS SLOT",
        p.slot(25, 20, 40, 16, 9, course=(1, 1, 0)),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "$",
            "PLUNGE_RAMP($,15.0)",
            axial="3.0",
            radial="2.0",
            side="0.5",
            bottom="0.5",
        ),
    )
    return p


def slot_open_finish() -> Program:
    """A through slot across the block (open ends), finish, contour-bidirectional CCW."""
    p = Program("SLOT OPEN FINISH")
    p.workingstep(
        "WS SLOT",
        p.slot(0, 40, 100, 16, 6, ends=("OPEN_SLOT_END_TYPE", "OPEN_SLOT_END_TYPE")),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_BIDIRECTIONAL($,$,$,$,.CCW.,$)",
            axial="3.0",
            radial="4.0",
        ),
    )
    return p


def slot_contour_parallel() -> Program:
    """slot_radiused_ramp's closed 45 degree slot cleared by contour-parallel loops (CW,
    conventional: from the centre line out), plunging along the tool axis."""
    p = Program("SLOT CONTOUR PARALLEL")
    p.workingstep(
        "WS SLOT",
        p.slot(25, 20, 40, 16, 9, course=(1, 1, 0)),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
            "PLUNGE_TOOLAXIS($)",
            axial="3.0",
            radial="2.0",
            side="0.5",
            bottom="0.5",
        ),
    )
    return p


def slot_open_contour_parallel_outside_in() -> Program:
    """An open through slot cleared by contour-parallel loops CCW with conventional
    cutting: the material inside the loops, so from the outermost loop in."""
    p = Program("SLOT OPEN CONTOUR PARALLEL OUTSIDE IN")
    p.workingstep(
        "WS SLOT",
        p.slot(0, 40, 100, 16, 6, ends=("OPEN_SLOT_END_TYPE", "OPEN_SLOT_END_TYPE")),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "CONTOUR_PARALLEL($,$,.CCW.,.CONVENTIONAL.)",
            axial="3.0",
            radial="4.0",
        ),
    )
    return p


def slot_side_full_width() -> Program:
    """Side milling of a slot as wide as the tool (one stroke, one layer), one open end."""
    p = Program("SLOT SIDE FULL WIDTH")
    p.workingstep(
        "WS SLOT",
        p.slot(30, 60, 70, 10, 5, ends=("RADIUSED_SLOT_END_TYPE", "OPEN_SLOT_END_TYPE")),
        _side_op(p, "SIDE_FINISH_MILLING", "BIDIRECTIONAL_MILLING($,$,$,$,$)"),
    )
    return p


def step_bidirectional() -> Program:
    """A step along the front edge (Y < 20 removed, 10 deep), rough bottom-and-side."""
    p = Program("STEP BIDIRECTIONAL")
    p.workingstep(
        "WS STEP",
        p.step(0, 20, 100, 10, (1, 0, 0)),
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "$",
            tool=_mill(p, 12.0),
            axial="4.0",
            radial="5.0",
            side="0.5",
            bottom="0.3",
        ),
    )
    return p


def step_side_unidirectional() -> Program:
    """Side finish milling of a step along the right edge (X > 85 removed, 12 deep)."""
    p = Program("STEP SIDE UNIDIRECTIONAL")
    p.workingstep(
        "WS STEP",
        p.step(85, 0, 80, 12, (0, 1, 0)),
        _side_op(
            p,
            "SIDE_FINISH_MILLING",
            "UNIDIRECTIONAL_MILLING($,$,$,.CLIMB.)",
            axial="6.0",
            radial="6.0",
        ),
    )
    return p


def open_pocket_from_edge() -> Program:
    """A 40 x 30 open pocket at the block's -X edge, corner radius 8, rough, then finish
    side milling of its walls with a smaller tool (contour-bidirectional, CCW)."""
    p = Program("OPEN POCKET FROM THE EDGE")
    feature = p.open_pocket(0, 40, 40, 30, 8, 8)
    p.workingstep(
        "WS ROUGH",
        feature,
        _pocket_op(
            p,
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "$",
            axial="4.0",
            radial="4.0",
            side="0.5",
            bottom="0.5",
        ),
    )
    p.workingstep(
        "WS FINISH WALLS",
        feature,
        _side_op(
            p,
            "SIDE_FINISH_MILLING",
            "CONTOUR_BIDIRECTIONAL($,$,$,$,.CCW.,$)",
            tool=_mill(p, 8.0),
            radial="3.0",
        ),
    )
    return p


PROGRAMS: dict[str, Callable[[], Program]] = {
    f.__name__: f
    for f in (
        face_bidir_x,
        face_bidir_y_right,
        face_bidir_minus_x,
        face_unidir_conventional,
        face_unidir_climb_minus_y,
        face_rough_default_allowance,
        pocket_rough_default_helix,
        pocket_finish_helix,
        pocket_ramp,
        pocket_zigzag,
        pocket_toolaxis_ccw_climb,
        pocket_bidirectional,
        pocket_contour_bidirectional_y,
        pocket_semicircle_ends,
        pocket_circular,
        round_hole_milled,
        pocket_groove_zigzag,
        pocket_rotated,
        drill_plain,
        drill_reduced_feeds,
        multistep_drilling,
        reaming_and_boring,
        center_drill_countersink_tap,
        explicit_polyline,
        explicit_segment_technology,
        explicit_arcs_and_helix,
        explicit_bspline,
        workplan_structures,
        two_tools_face_and_pocket,
        slot_radiused_ramp,
        slot_open_finish,
        slot_contour_parallel,
        slot_open_contour_parallel_outside_in,
        slot_side_full_width,
        step_bidirectional,
        step_side_unidirectional,
        open_pocket_from_edge,
    )
}


def render(name: str) -> str:
    p = PROGRAMS[name]()
    return p.text(getattr(p, "elements", None))
