"""The turning test programs (ISO 14649-12), written as Part 21 text.

Each program is a bar on the spindle (Z) axis and a list of workingsteps. The dimensions
come from the book's turning example (§11.5.2: an end face, a cylinder and a cone; depth of
cut 3 mm, lift height 2 mm, 0.3 mm/rev) and from plain shaft parts; README.md gives each
program's hand-derived passes and volume. ``render(name)`` writes one program.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class _File:
    lines: list[str] = field(default_factory=list)
    n: int = 0

    def add(self, text: str) -> str:
        self.n += 1
        self.lines.append(f"#{self.n}={text};")
        return f"#{self.n}"


def _num(v: float) -> str:
    s = repr(float(v))
    return s[:-1] if s.endswith(".0") else s


@dataclass(frozen=True)
class Op:
    """One workingstep: operation entity, feature kind and its data, technology."""

    op: str  # FACING_ROUGH, CONTOURING_FINISH, GROOVING_ROUGH, CUTTING_IN, ...
    feature: tuple  # ("face", z) / ("od", z, diameter, length) / ("groove", z, width, r)
    # / ("rev", z, [(r, z), ...])
    tool: str = "T1"  # T1 general turning tool, G3/G2 grooving tools of width 3/2
    allowance: float | None = None
    strategy: str = "$"  # Part 21 text of the strategy, built by the helpers below
    feed_per_rev: float | None = 0.3
    feedrate: float | None = None  # m/s
    speed: str = "CONST_SPINDLE_SPEED(10.)"
    coolant: str = ".T.,$"  # coolant, coolant_type
    dwell: str = "$"


def unidirectional(depth: float | None = None, lift: float | None = None) -> str:
    d = f"({_num(depth)})" if depth is not None else "()"
    h = _num(lift) if lift is not None else "$"
    return f"UNIDIRECTIONAL_TURNING($,$,{d},$,$,$,$,$,{h},$,$)"


def multistep_grooving(depth: float, back: float) -> str:
    return f"MULTISTEP_GROOVING_STRATEGY($,$,({_num(depth)}),$,$,$,{_num(back)})"


@dataclass(frozen=True)
class Program:
    raw: tuple[float, float, float]  # z of the chuck end, length, radius
    steps: tuple[Op, ...]


_TOOLS = {
    "T1": "GENERAL_TURNING_TOOL('T1',120.,45.,$,$,$,{edge},.RIGHT.)",
    "T2": "GENERAL_TURNING_TOOL('T2',120.,45.,$,$,$,{edge},.RIGHT.)",
    "G3": "GROOVING_TOOL('G3',100.,20.,$,$,$,{edge},.NEUTRAL.,3.,8.,$,$,$)",
    "G2": "GROOVING_TOOL('G2',100.,20.,$,$,$,{edge},.NEUTRAL.,2.,6.,$,$,$)",
    "TH": "TURNING_THREADING_TOOL('TH',100.,20.,$,$,$,{edge},.RIGHT.,1.5,.RIGHT.,"
    ".EXTERNAL.,.FULL_PROFILE.,'ISO metric')",
}


def render(name: str, prog: Program | None = None) -> str:
    prog = PROGRAMS[name] if prog is None else prog
    f = _File()
    origin = f.add("CARTESIAN_POINT('origin',(0.,0.,0.))")
    zdir = f.add("DIRECTION('axis',(0.,0.,1.))")
    xdir = f.add("DIRECTION('ref',(1.,0.,0.))")
    place0 = f.add(f"AXIS2_PLACEMENT_3D('setup',{origin},{zdir},{xdir})")
    z0, length, radius = prog.raw
    rawpt = f.add(f"CARTESIAN_POINT('bar start',(0.,0.,{_num(z0)}))")
    rawpl = f.add(f"AXIS2_PLACEMENT_3D('bar',{rawpt},{zdir},{xdir})")
    cyl = f.add(f"RIGHT_CIRCULAR_CYLINDER('raw bar',{rawpl},{_num(length)},{_num(radius)})")
    secpt = f.add(f"CARTESIAN_POINT('security',(0.,0.,{_num(z0 + length + 10)}))")
    secpl = f.add(f"AXIS2_PLACEMENT_3D('security',{secpt},{zdir},{xdir})")
    plane = f.add(f"PLANE('security plane',{secpl})")
    edge = f.add("CUTTING_EDGE_PROPERTIES($,$,$,10.,110.,$,25.,(),$,$)")
    tools: dict[str, str] = {}
    ws_refs: list[str] = []
    pending: list[tuple[str, str, list[str]]] = []  # feature text, op refs
    # the workpiece is referenced by the features: reserve its id
    f.n += 1
    wp = f"#{f.n}"
    wp_index = len(f.lines)
    f.lines.append("")
    for step in prog.steps:
        if step.tool not in tools:
            tools[step.tool] = f.add(_TOOLS[step.tool].format(edge=edge))
        speed = f.add(step.speed)
        fpr = _num(step.feed_per_rev) if step.feed_per_rev is not None else "$"
        frt = _num(step.feedrate) if step.feedrate is not None else "$"
        tech = f.add(f"TURNING_TECHNOLOGY({frt},.TCP.,{speed},{fpr},.F.,.F.,.F.,$)")
        mf = f.add(f"TURNING_MACHINE_FUNCTIONS({step.coolant},$,(),$,$,$,(),$,$,$)")
        strat = f.add(step.strategy) if step.strategy != "$" else "$"
        allow = _num(step.allowance) if step.allowance is not None else "$"
        common = f"$,$,'{step.op.lower()}',$,$,{tools[step.tool]},{tech},{mf},$,$,{strat}"
        if step.op.startswith("GROOVING") or step.op == "CUTTING_IN":
            op = f.add(f"{step.op}({common},{step.dwell},{allow})")
        else:
            op = f.add(f"{step.op}({common},{allow})")
        pending.append((step.feature, op, []))
    # one feature per distinct feature tuple, carrying all its operations
    features: dict[tuple, tuple[str, list[str]]] = {}
    for feat, op, _ in pending:
        features.setdefault(feat, ("", []))[1].append(op)
    feat_ref: dict[tuple, str] = {}
    for feat, (_, ops) in features.items():
        kind, zf = feat[0], feat[1]
        pt = f.add(f"CARTESIAN_POINT('feature',(0.,0.,{_num(zf)}))")
        pl = f.add(f"AXIS2_PLACEMENT_3D('feature',{pt},{zdir},{xdir})")
        opl = "(" + ",".join(ops) + ")"
        if kind == "face":
            lp_len = f.add(f"NUMERIC_PARAMETER('length',{_num(radius + 5)},'mm')")
            lp = f.add(f"LINEAR_PROFILE($,{lp_len})")
            feat_ref[feat] = f.add(f"REVOLVED_FLAT('end face',{wp},{opl},{pl},$,0.,{lp})")
        elif kind == "od":
            _, _, dia, flen = feat
            feat_ref[feat] = f.add(
                f"OUTER_DIAMETER('diameter {_num(dia)}',{wp},{opl},{pl},{_num(dia)},{_num(flen)},$)"
            )
        elif kind == "cone":
            _, _, dia, flen, final = feat
            taper = f.add(f"DIAMETER_TAPER({_num(final)})")
            feat_ref[feat] = f.add(
                f"OUTER_DIAMETER('cone',{wp},{opl},{pl},{_num(dia)},{_num(flen)},{taper})"
            )
        elif kind == "groove":
            _, _, width, r = feat
            w = f.add(f"TOLERANCED_LENGTH_MEASURE({_num(width)},$)")
            sweep = f.add(f"SQUARE_U_PROFILE($,{w},$,$,$,$)")
            feat_ref[feat] = f.add(f"GROOVE('groove',{wp},{opl},{pl},$,{_num(r)},{sweep})")
        else:
            pts = [f.add(f"CARTESIAN_POINT('',({_num(r)},0.,{_num(z - zf)}))") for r, z in feat[2]]
            poly = f.add(f"POLYLINE('outline',({','.join(pts)}))")
            gp = f.add(f"GENERAL_PROFILE($,{poly})")
            feat_ref[feat] = f.add(f"GENERAL_REVOLUTION('revolution',{wp},{opl},{pl},$,0.,{gp})")
    for i, (feat, op, _) in enumerate(pending):
        ws_refs.append(f.add(f"MACHINING_WORKINGSTEP('WS{i + 1}',{plane},{feat_ref[feat]},{op},$)"))
    f.lines[wp_index] = f"{wp}=WORKPIECE('bar',$,0.01,$,$,{cyl},());"
    wps = f.add(f"WORKPIECE_SETUP({wp},{place0},$,$,())")
    setup = f.add(f"SETUP('setup',{place0},{plane},({wps}))")
    plan = f.add(f"WORKPLAN('main',({','.join(ws_refs)}),$,{setup},$)")
    f.add(f"PROJECT('{name}',{plan},({wp}),$,$,$)")
    head = (
        "ISO-10303-21;\nHEADER;\n"
        f"FILE_DESCRIPTION(('cnc-toolchain turning test program {name}'),'2;1');\n"
        f"FILE_NAME('{name}.stp','2026-12-02T00:00:00',('cnc-toolchain'),(''),'','','');\n"
        "FILE_SCHEMA(('MACHINING_SCHEMA'));\nENDSEC;\nDATA;\n"
    )
    return head + "\n".join(f.lines) + "\nENDSEC;\nEND-ISO-10303-21;\n"


_FACE = ("face", 0.0)
_OD40 = ("od", 0.0, 40.0, 30.0)
#: the book's cone (§11.5.2) as a general revolution: radius 15 at the end face growing to
#: 25 over 20 mm, then the cylinder of radius 25 to 40 mm from the end
_CONE = ("rev", 0.0, ((15.0, 0.0), (25.0, -20.0), (25.0, -40.0)))

PROGRAMS: dict[str, Program] = {
    "face_rough_finish": Program(
        (-80.0, 82.0, 25.0),
        (
            Op("FACING_ROUGH", _FACE, allowance=0.2, strategy=unidirectional(1.0, 0.5)),
            Op("FACING_FINISH", _FACE),
        ),
    ),
    "od_rough": Program(
        (-80.0, 80.0, 25.0),
        (Op("CONTOURING_ROUGH", _OD40, allowance=0.5, strategy=unidirectional(2.0)),),
    ),
    "od_rough_finish": Program(
        (-80.0, 80.0, 25.0),
        (
            Op("CONTOURING_ROUGH", _OD40, allowance=0.5, strategy=unidirectional(2.0)),
            Op("CONTOURING_FINISH", _OD40, feed_per_rev=0.1),
        ),
    ),
    "book_face_cylinder_cone": Program(
        (-100.0, 102.0, 30.0),
        (
            Op("FACING_ROUGH", _FACE, allowance=0.0, strategy=unidirectional(3.0, 2.0)),
            Op("CONTOURING_ROUGH", _CONE, allowance=0.0, strategy=unidirectional(3.0, 2.0)),
            Op(
                "CONTOURING_ROUGH",
                ("od", -40.0, 50.0, 30.0),
                allowance=0.0,
                strategy=unidirectional(3.0, 2.0),
            ),
        ),
    ),
    # the book's part with the cone as ISO 14649 writes it: an outer diameter whose
    # reduced_size is a diameter taper
    "book_tapered_outer_diameter": Program(
        (-100.0, 102.0, 30.0),
        (
            Op("FACING_ROUGH", _FACE, allowance=0.0, strategy=unidirectional(3.0, 2.0)),
            Op(
                "CONTOURING_ROUGH",
                ("cone", 0.0, 30.0, 20.0, 50.0),
                allowance=0.0,
                strategy=unidirectional(3.0, 2.0),
            ),
            Op(
                "CONTOURING_ROUGH",
                ("od", -20.0, 50.0, 50.0),
                allowance=0.0,
                strategy=unidirectional(3.0, 2.0),
            ),
        ),
    ),
    "stepped_shaft": Program(
        (-80.0, 80.0, 25.0),
        (
            Op(
                "CONTOURING_ROUGH",
                ("od", 0.0, 40.0, 50.0),
                allowance=0.0,
                strategy=unidirectional(2.5),
            ),
            Op(
                "CONTOURING_ROUGH",
                ("od", 0.0, 30.0, 20.0),
                allowance=0.0,
                strategy=unidirectional(2.5),
            ),
        ),
    ),
    "taper_rough_finish": Program(
        (-60.0, 60.0, 25.0),
        (
            Op(
                "CONTOURING_ROUGH",
                ("rev", 0.0, ((15.0, 0.0), (25.0, -40.0))),
                allowance=0.5,
                strategy=unidirectional(3.0),
            ),
            Op("CONTOURING_FINISH", ("rev", 0.0, ((15.0, 0.0), (25.0, -40.0))), feed_per_rev=0.1),
        ),
    ),
    "chamfer_shoulder_finish": Program(
        (-60.0, 60.0, 25.0),
        (
            Op(
                "CONTOURING_ROUGH",
                (
                    "rev",
                    0.0,
                    ((10.0, 0.0), (12.0, -2.0), (12.0, -20.0), (18.0, -20.0), (18.0, -35.0)),
                ),
                allowance=0.0,
                strategy=unidirectional(4.0, 1.5),
            ),
            Op(
                "CONTOURING_FINISH",
                (
                    "rev",
                    0.0,
                    ((10.0, 0.0), (12.0, -2.0), (12.0, -20.0), (18.0, -20.0), (18.0, -35.0)),
                ),
                feed_per_rev=0.08,
            ),
        ),
    ),
    "groove_cut_in": Program(
        (-60.0, 60.0, 25.0),
        (
            Op(
                "CUTTING_IN",
                ("groove", -20.0, 3.0, 20.0),
                tool="G3",
                feed_per_rev=0.05,
                dwell="0.5",
            ),
        ),
    ),
    "groove_multistep_rough_finish": Program(
        (-60.0, 60.0, 25.0),
        (
            Op(
                "GROOVING_ROUGH",
                ("groove", -30.0, 8.0, 18.0),
                tool="G3",
                allowance=0.2,
                feed_per_rev=0.05,
                strategy=multistep_grooving(2.0, 0.5),
            ),
            Op("GROOVING_FINISH", ("groove", -30.0, 8.0, 18.0), tool="G3", feed_per_rev=0.03),
        ),
    ),
    "css_feed_per_minute_mist": Program(
        (-50.0, 50.0, 20.0),
        (
            Op(
                "CONTOURING_ROUGH",
                ("od", 0.0, 32.0, 25.0),
                allowance=0.0,
                strategy=unidirectional(2.0),
                feed_per_rev=None,
                feedrate=0.005,
                speed="CONST_CUTTING_SPEED(3.,50.)",
                coolant=".T.,.MIST.",
            ),
        ),
    ),
    "shaft_two_tools": Program(
        (-70.0, 72.0, 25.0),
        (
            Op("FACING_ROUGH", _FACE, allowance=0.0, strategy=unidirectional(1.0)),
            Op(
                "CONTOURING_ROUGH",
                ("od", 0.0, 36.0, 40.0),
                allowance=0.3,
                strategy=unidirectional(3.0),
            ),
            Op("CONTOURING_FINISH", ("od", 0.0, 36.0, 40.0), feed_per_rev=0.1),
            Op(
                "CUTTING_IN",
                ("groove", -25.0, 2.0, 15.0),
                tool="G2",
                feed_per_rev=0.04,
                speed="CONST_SPINDLE_SPEED(-8.)",
            ),
        ),
    ),
}

#: programs that must be refused, with the code and a word of the message
REFUSED: dict[str, tuple[Program, str, str]] = {
    "threading": (
        Program(
            (-60.0, 60.0, 20.0),
            (Op("THREADING_ROUGH", ("od", 0.0, 40.0, 20.0), tool="TH", allowance=0.0),),
        ),
        "STEPNC-UNSUPPORTED",
        "THREADING_ROUGH",
    ),
    "undercut": (
        Program(
            (-60.0, 60.0, 25.0),
            (
                Op(
                    "CONTOURING_ROUGH",
                    ("rev", 0.0, ((20.0, 0.0), (10.0, -10.0), (20.0, -20.0))),
                    allowance=0.0,
                ),
            ),
        ),
        "STEPNC-TURNING",
        "undercut",
    ),
}
