"""STEP-NC -> canonical commands (stepnc.to_canon and stepnc.toolpaths)."""

from __future__ import annotations

import math
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc import gouge
from stepnc.model import load
from stepnc.to_canon import canon_from_file, canon_from_model
from stepnc.toolpaths.drilling import tip_length
from tests.data_paths import CORPUS_STEPNC

HERE = Path(__file__).resolve().parent
CORPUS = CORPUS_STEPNC
EX1, TOOLS = str(CORPUS / "ex1.stp"), str(CORPUS / "iso14649.tool_ex1")
EX1_RAW = (0.0, 0.0, -45.0, 100.0, 120.0, 5.0)  # book: block 100 x 120 x 50, face top Z=5
sys.path.insert(0, str(HERE / "stepnc"))
from programs import PROGRAMS  # noqa: E402


def nist_reference() -> list[canon.Command]:
    with open(CORPUS / "ex1.can") as fh:
        return [canon.parse_command(t) for t in canon.read_text(fh)]


def test_ex1_matches_nist_command_for_command():
    ours = list(canon_from_file(EX1, TOOLS, "nist"))
    theirs = nist_reference()
    assert len(ours) == len(theirs) == 538
    # compare as NIST prints them: CHANGE_TOOL shows the tool id, not our pocket number
    pairs = enumerate(zip(ours, theirs, strict=True))
    mismatches = [
        (i, a.to_text(), b.to_text()) for i, (a, b) in pairs if a.to_text() != b.to_text()
    ]
    assert mismatches == []
    assert [c.slot for c in ours if isinstance(c, canon.ChangeTool)] == [3, 4, 6, 3]


def test_ex1_every_motion_carries_its_workingstep_and_operation():
    model = load(EX1)
    for cmd in canon_from_model(model, None, "nist"):
        assert cmd.source is not None and cmd.source.file == EX1
        if isinstance(cmd, (canon.StraightFeed, canon.ArcFeed, canon.StraightTraverse)):
            ws = model.entity(cmd.source.workingstep)
            assert ws.type == "MACHINING_WORKINGSTEP"
            assert cmd.source.entity == ws.its_operation.id
            assert cmd.source.line > 0


def test_drill_tip_length_of_ex1_twist_drill():
    # ISO 14649-111 Fig. 2 via NIST: R tan(a) + r/tan((90+a+b)/2) cos(b), a=31, b=0.1, r=2
    tool = load(EX1).entity(44)
    expected = 10 * math.tan(math.radians(31)) + 2 / math.tan(math.radians(60.55)) * math.cos(
        math.radians(0.1)
    )
    assert tip_length(tool) == pytest.approx(expected, abs=1e-12)
    assert tip_length(tool) == pytest.approx(7.1378, abs=5e-5)  # ex1.can: -30 - 7.1378


def test_ex1_default_mode_puts_the_reduced_end_section_at_the_hole_bottom():
    nist = list(canon_from_file(EX1, TOOLS, "nist"))
    default = list(canon_from_file(EX1, TOOLS, "default"))

    def drill_feeds(cmds):
        return [
            round(c.z, 4)
            for c in cmds
            if isinstance(c, canon.StraightFeed) and c.source.workingstep == 11
        ]

    assert drill_feeds(nist) == [-9.1378, -15.1378, -37.1378, 10.0]
    assert drill_feeds(default) == [-9.1378, -29.1378, -37.1378, 10.0]  # 8 mm above bottom


def test_ex1_has_no_gouge_and_a_shifted_move_is_caught():
    model = load(EX1)
    cmds = list(canon_from_model(model, None, "nist"))
    assert all(not g for g in gouge.check(model, cmds, EX1_RAW).values())
    # push one finishing pass of the pocket 1 mm into the wall
    i = next(
        i
        for i, c in enumerate(cmds)
        if isinstance(c, canon.StraightFeed)
        and c.source.workingstep == 14
        and abs(c.x - 86.0) < 1e-9
    )
    cmds[i] = replace(cmds[i], x=87.0, source=cmds[i].source)
    found = gouge.check(model, cmds, EX1_RAW)
    assert [g.command for g in found[14]] == [i, i + 1]
    assert all(not found[ws] for ws in (10, 11, 12, 13))


def test_unknown_tool_in_tool_file_is_a_located_error(tmp_path):
    tf = tmp_path / "t.tool"
    tf.write_text("POCKET FMS TLO DIAM\n\n3 'MILL 18MM' 50.0 18.0 0\n")
    with pytest.raises(Diagnostic) as exc:
        list(canon_from_file(EX1, str(tf)))
    assert exc.value.code == "STEPNC-TOOL-MISSING" and exc.value.location.workingstep == 11


# ------------------------------------------------------------------ own programs
@pytest.fixture(scope="module", params=sorted(PROGRAMS))
def program(request):
    name = request.param
    model = load(str(HERE / "stepnc" / f"{name}.stp"))
    return name, model, list(canon_from_model(model, None, "default"))


def test_program_matches_its_golden_ir(program):
    name, _, cmds = program
    golden = (HERE / "stepnc" / f"{name}.can").read_text().splitlines()
    ours = list(canon.write_text(cmds))
    assert ours == golden


def test_program_golden_ir_reads_back_as_the_same_commands(program):
    name, _, cmds = program
    with open(HERE / "stepnc" / f"{name}.can") as fh:
        back = list(canon.read_commands(fh))
    assert [c.to_text() for c in back] == [c.to_text() for c in cmds]


def test_program_never_gouges_the_finished_part(program):
    name, model, cmds = program
    result = gouge.check(model, cmds)
    assert result and all(not v for v in result.values()), name


def test_program_cuts_only_below_the_security_plane_and_ends(program):
    _, _, cmds = program
    assert isinstance(cmds[-1], canon.ProgramEnd)
    for c in cmds:
        if isinstance(c, canon.StraightFeed):
            assert c.z <= 50.0 + 1e-9


def _feeds(cmds, ws=None):
    return [
        c
        for c in cmds
        if isinstance(c, (canon.StraightFeed, canon.ArcFeed))
        and (ws is None or c.source.workingstep == ws)
    ]


def _z(c):
    return c.z if isinstance(c, canon.StraightFeed) else c.axis_end_point


@pytest.mark.parametrize(
    ("name", "depth"),
    [
        ("face_bidir_x", -3.0),
        ("face_bidir_y_right", -2.5),
        ("face_rough_default_allowance", -2.8),
        ("pocket_rough_default_helix", -11.5),
        ("pocket_finish_helix", -10.0),
        ("pocket_ramp", -8.5),
        ("pocket_zigzag", -7.5),
        ("pocket_toolaxis_ccw_climb", -6.0),
        ("pocket_semicircle_ends", -5.0),
        ("pocket_circular", -6.0),
        ("pocket_groove_zigzag", -6.0),
        ("pocket_rotated", -7.7),
        ("drill_plain", -15 - 4 * math.tan(math.radians(31))),
        ("multistep_drilling", -18 - 3 * math.tan(math.radians(31))),
    ],
)
def test_deepest_cut_is_the_feature_depth_less_allowance(name, depth):
    model = load(str(HERE / "stepnc" / f"{name}.stp"))
    cmds = list(canon_from_model(model, None, "default"))
    assert min(_z(c) for c in _feeds(cmds)) == pytest.approx(depth, abs=1e-9)


def test_facing_strips_cover_the_whole_face():
    """Every point of the 100 x 80 face is within the tool radius of a cut at full depth."""
    for name in (
        "face_bidir_x",
        "face_bidir_y_right",
        "face_bidir_minus_x",
        "face_unidir_conventional",
        "face_unidir_climb_minus_y",
    ):
        model = load(str(HERE / "stepnc" / f"{name}.stp"))
        cmds = list(canon_from_model(model, None, "default"))
        bottom = min(c.z for c in _feeds(cmds))
        pos, segs = None, []
        for c in cmds:
            if isinstance(c, (canon.StraightFeed, canon.StraightTraverse)):
                if (
                    isinstance(c, canon.StraightFeed)
                    and pos
                    and abs(c.z - bottom) < 1e-9
                    and abs(pos[2] - bottom) < 1e-9
                ):
                    segs.append((pos[:2], (c.x, c.y)))
                pos = (c.x, c.y, c.z)
        gx, gy = np.meshgrid(np.linspace(0, 100, 41), np.linspace(0, 80, 33))
        pts = np.column_stack([gx.ravel(), gy.ravel()])
        best = np.full(len(pts), np.inf)
        for a, b in segs:
            a, b = np.array(a), np.array(b)
            t = np.clip(((pts - a) @ (b - a)) / max((b - a) @ (b - a), 1e-12), 0, 1)
            best = np.minimum(best, np.linalg.norm(pts - (a + t[:, None] * (b - a)), axis=1))
        assert best.max() <= 8.0 + 1e-9, name  # 16 mm tool


def test_drilling_strategy_reduces_feed_and_speed_at_start_and_end():
    model = load(str(HERE / "stepnc" / "drill_reduced_feeds.stp"))
    cmds = list(canon_from_model(model, None, "default"))
    seen, feed, speed = [], None, None
    for c in cmds:
        if isinstance(c, canon.SetFeedRate):
            feed = c.rate
        elif isinstance(c, canon.SetSpindleSpeed):
            speed = c.speed
        elif isinstance(c, canon.StraightFeed):
            seen.append((round(c.z, 4), feed, speed))
    full_feed, full_speed = 0.005 * 60000, 25 * 60
    tip = 4 * math.tan(math.radians(31))
    assert seen == [
        (round(-2 - tip, 4), 0.5 * full_feed, 0.8 * full_speed),
        (round(-40 - tip + 4, 4), full_feed, full_speed),
        (round(-40 - tip, 4), 0.4 * full_feed, 0.6 * full_speed),
        (3.0, 0.8 * full_feed, 0.6 * full_speed),  # feed_on_retract 0.8
    ]


def test_workplan_structures_and_nc_functions_in_order():
    model = load(str(HERE / "stepnc" / "workplan_structures.stp"))
    names = [
        c.NAME
        for c in canon_from_model(model, None, "default")
        if c.NAME
        in ("MESSAGE", "OPTIONAL_PROGRAM_STOP", "CHANGE_TOOL", "PROGRAM_STOP", "PROGRAM_END")
    ]
    assert names == [
        "CHANGE_TOOL",
        "MESSAGE",
        "OPTIONAL_PROGRAM_STOP",
        "CHANGE_TOOL",
        "CHANGE_TOOL",
        "PROGRAM_STOP",
        "PROGRAM_END",
    ]


def test_bspline_toolpath_becomes_one_nurbs_feed():
    model = load(str(HERE / "stepnc" / "explicit_bspline.stp"))
    nurbs = [c for c in canon_from_model(model, None, "default") if isinstance(c, canon.NurbsFeed)]
    assert len(nurbs) == 1 and nurbs[0].order == 4
    assert nurbs[0].points[0][:2] == (35.0, 35.0) and nurbs[0].knots == (0.0,) * 4 + (1.0,) * 4


def test_helix_turns_follow_pitch_and_direction():
    model = load(str(HERE / "stepnc" / "explicit_arcs_and_helix.stp"))
    arcs = [c for c in canon_from_model(model, None, "default") if isinstance(c, canon.ArcFeed)]
    assert [(a.rotation, a.axis_end_point) for a in arcs] == [(1, -1.0), (2, -3.0)]


@pytest.mark.parametrize(
    ("name", "length", "width", "radius", "allowance"),
    [
        ("pocket_finish_helix", 60, 40, 8, 0.0),
        ("pocket_toolaxis_ccw_climb", 60, 50, 10, 0.0),
        ("pocket_semicircle_ends", 70, 30, 15, 0.0),
        ("pocket_circular", 40, 40, 20, 0.0),
        ("pocket_contour_bidirectional_y", 70, 44, 12, 0.0),
        # zigzag without a contour pass leaves cusps of 5 - sqrt(25 - 2.9^2) = 0.93 mm at
        # the walls between stroke ends (stepover 5.8): counted as allowance here
        ("pocket_bidirectional", 60, 40, 10, 0.5 + 0.93),
        ("pocket_rough_default_helix", 60, 40, 8, 0.5),
    ],
)
def test_pocket_floor_is_cleared(name, length, width, radius, allowance):
    """Every floor point of the pocket (less the side allowance) is within the tool radius
    (5 mm) of a cutting move at the deepest level: nothing is left standing."""
    model = load(str(HERE / "stepnc" / f"{name}.stp"))
    _assert_floor_cleared(
        list(canon_from_model(model, None, "default")), length, width, radius, allowance, name
    )


def _assert_floor_cleared(cmds, length, width, radius, allowance, name):
    path = _bottom_path(cmds)
    hl, hw = length / 2 - allowance - 0.25, width / 2 - allowance - 0.25
    r = radius - allowance - 0.25  # the outline 0.25 mm inside the walls
    gx, gy = np.meshgrid(np.linspace(-hl, hl, 61), np.linspace(-hw, hw, 41))
    q = np.column_stack([gx.ravel(), gy.ravel()])
    cx = np.maximum(np.abs(q[:, 0]) - (hl - r), 0)
    cy = np.maximum(np.abs(q[:, 1]) - (hw - r), 0)
    q = q[cx * cx + cy * cy <= r * r] + [50.0, 40.0]  # inside the rounded outline
    d = np.min(np.linalg.norm(q[:, None, :] - path[None, :, :], axis=2), axis=1)
    assert d.max() <= 5.0 + 0.1, name


def test_rectangular_polyline_boundary_mills_like_the_rectangular_profile(tmp_path):
    """ISO Example 1's pocket boundary is a GENERAL_CLOSED_PROFILE polyline (NIST replaced
    it by a RECTANGULAR_CLOSED_PROFILE); the same rectangle gives the same commands."""
    text = (
        Path(EX1)
        .read_text(encoding="latin-1")
        .replace(
            "#28= RECTANGULAR_CLOSED_PROFILE($, #122, #121);",
            "#28= GENERAL_CLOSED_PROFILE($,#59);\n"
            "#59= POLYLINE('CONTOUR OF POCKET1',(#131,#132,#133,#134,#131));\n"
            "#131= CARTESIAN_POINT('P1',(40.0,-25.0,0.0));\n"
            "#132= CARTESIAN_POINT('P2',(40.0,25.0,0.0));\n"
            "#133= CARTESIAN_POINT('P3',(-40.0,25.0,0.0));\n"
            "#134= CARTESIAN_POINT('P4',(-40.0,-25.0,0.0));",
        )
    )
    poly = tmp_path / "poly.stp"
    poly.write_text(text)
    ours = [c.to_text() for c in canon_from_file(str(poly), TOOLS)]
    assert ours == [c.to_text() for c in nist_reference()]


def test_segment_technology_applies_to_its_segment_only():
    model = load(str(HERE / "stepnc" / "explicit_segment_technology.stp"))
    feed, seen = None, []
    for c in canon_from_model(model, None, "default"):
        if isinstance(c, canon.SetFeedRate):
            feed = c.rate
        elif isinstance(c, canon.StraightFeed):
            seen.append(feed)
    assert seen == [600.0, 120.0, 600.0]  # 0.01 m/s, the segment's 0.002 m/s, back


def test_pocket_wider_than_long_mills_like_the_turned_long_pocket(tmp_path):
    """ISO 14649-10 does not order a RECTANGULAR_CLOSED_PROFILE's width and length: a 30
    long, 70 wide pocket is the 70 x 30 pocket turned a quarter turn, so it is milled by
    the same commands as the long pocket placed with its X axis along +Y."""
    source = (HERE / "stepnc" / "pocket_zigzag.stp").read_text()
    assert "#110=TOLERANCED_LENGTH_MEASURE(30.0,#109);" in source
    wide = source.replace(
        "#110=TOLERANCED_LENGTH_MEASURE(30.0,#109);", "#110=TOLERANCED_LENGTH_MEASURE(70.0,#109);"
    ).replace(
        "#112=TOLERANCED_LENGTH_MEASURE(70.0,#111);", "#112=TOLERANCED_LENGTH_MEASURE(30.0,#111);"
    )
    turned = source.replace(
        "#107=DIRECTION('',(1.0,0.0,0.0));", "#107=DIRECTION('',(0.0,1.0,0.0));"
    )
    (tmp_path / "wide.stp").write_text(wide)
    (tmp_path / "turned.stp").write_text(turned)
    wide_cmds = [c.to_text() for c in canon_from_file(str(tmp_path / "wide.stp"), None)]
    turned_cmds = [c.to_text() for c in canon_from_file(str(tmp_path / "turned.stp"), None)]
    assert wide_cmds == turned_cmds
    feeds = [
        c
        for c in canon_from_file(str(tmp_path / "wide.stp"), None)
        if isinstance(c, canon.StraightFeed)
    ]
    xs = [c.x for c in feeds]
    ys = [c.y for c in feeds]
    # a 10 mm tool, 0.5 mm side allowance in a 30 (X) x 70 (Y) pocket centred at (50, 40)
    assert max(xs) - min(xs) <= 30 - 10 - 2 * 0.5 + 1e-6
    assert max(ys) - min(ys) > 30


def _outside_in_variant(name: str, tmp_path: Path) -> Path:
    """The program with its CONTOUR_PARALLEL cutmode flipped: same rotation, the material
    now on the other side of the loops (CCW conventional / CW climb: outside in)."""
    text = (HERE / "stepnc" / f"{name}.stp").read_text()
    flipped = text.replace(".CCW.,.CLIMB.)", ".CCW.,.CONVENTIONAL.)").replace(
        ".CW.,.CONVENTIONAL.)", ".CW.,.CLIMB.)"
    )
    assert flipped != text
    out = tmp_path / f"{name}_outside_in.stp"
    out.write_text(flipped)
    return out


def _loop_starts(cmds, centre_x, centre_y):
    """The +X points of the centre line (y = centre) that feeds reach at the bottom Z, in
    order, consecutive repeats merged: the end of the lead-in along the centre line (not
    in a circular pocket), then where each loop starts."""
    bottom = min(_z(c) for c in _feeds(cmds))
    xs: list[float] = []
    for c in cmds:
        if not isinstance(c, canon.StraightFeed) or abs(c.z - bottom) > 1e-9:
            continue
        on_line = abs(c.y - centre_y) < 1e-9 and c.x > centre_x + 1e-9
        if on_line and (not xs or abs(xs[-1] - c.x) > 1e-9):
            xs.append(c.x)
    return xs


@pytest.mark.parametrize(
    ("name", "length", "width", "radius"),
    [
        ("pocket_toolaxis_ccw_climb", 60, 50, 10),
        ("pocket_semicircle_ends", 70, 30, 15),
        ("pocket_circular", 40, 40, 20),
        ("pocket_finish_helix", 60, 40, 8),
    ],
)
def test_outside_in_contour_parallel_clears_the_same_floor_with_loops_reversed(
    tmp_path, name, length, width, radius
):
    """ISO 14649-11 CONTOUR_PARALLEL: CCW conventional (and CW climb) keeps the uncut
    material inside the loop, so the loops run from the outermost in. The floor is still
    cleared everywhere, every arc turns in the given rotation, and the loops are those of
    the inside-out program in the opposite order."""
    inside_out = list(canon_from_file(str(HERE / "stepnc" / f"{name}.stp"), None, "default"))
    outside_in = list(canon_from_file(str(_outside_in_variant(name, tmp_path)), None, "default"))
    _assert_floor_cleared(outside_in, length, width, radius, 0.0, name)
    turns_in = {c.rotation for c in inside_out if isinstance(c, canon.ArcFeed) and c.rotation}
    turns_out = {c.rotation for c in outside_in if isinstance(c, canon.ArcFeed) and c.rotation}
    assert turns_out == turns_in  # the rotation direction is the one the file gives
    cuts_in = sorted(c.to_text() for c in inside_out if isinstance(c, canon.ArcFeed))
    cuts_out = sorted(c.to_text() for c in outside_in if isinstance(c, canon.ArcFeed))
    assert cuts_out == cuts_in  # the same loops ...
    starts_in = _loop_starts(inside_out, 50.0, 40.0)
    starts_out = _loop_starts(outside_in, 50.0, 40.0)
    if starts_out[0] < starts_out[1]:  # the lead-in along the centre line comes first
        lead_in = starts_out.pop(0)
        assert starts_in[0] == lead_in
        starts_in = starts_in[1:]
    assert len(starts_in) >= 2
    assert starts_in == sorted(starts_in)  # ... inside out: growing loops
    assert starts_out == sorted(starts_in, reverse=True)  # outside in: the same, shrinking


def test_milled_round_hole_is_cut_as_the_circular_pocket_of_its_diameter():
    """BOTTOM_AND_SIDE milling of a flat-bottomed ROUND_HOLE (a milled hole) removes the
    same cylinder as a CLOSED_POCKET with a CIRCULAR_CLOSED_PROFILE of that diameter, so
    the commands are the same."""
    hole = [
        c.to_text()
        for c in canon_from_file(str(HERE / "stepnc" / "round_hole_milled.stp"), None, "default")
    ]
    circle = [
        c.to_text()
        for c in canon_from_file(str(HERE / "stepnc" / "pocket_circular.stp"), None, "default")
    ]
    assert hole == circle
    _assert_floor_cleared(
        list(canon_from_file(str(HERE / "stepnc" / "round_hole_milled.stp"), None, "default")),
        40,
        40,
        20,
        0.0,
        "round_hole_milled",
    )


def test_milled_round_hole_with_a_conical_bottom_is_refused_naming_it(tmp_path):
    text = (HERE / "stepnc" / "round_hole_milled.stp").read_text()
    assert "FLAT_HOLE_BOTTOM()" in text
    path = tmp_path / "cone.stp"
    path.write_text(text.replace("FLAT_HOLE_BOTTOM()", "CONICAL_HOLE_BOTTOM(118.0,$)"))
    with pytest.raises(Diagnostic) as info:
        list(canon_from_file(str(path), None, "default"))
    assert info.value.code == "STEPNC-UNSUPPORTED"
    assert "CONICAL_HOLE_BOTTOM" in info.value.message
    assert info.value.location.entity is not None


def _bottom_path(cmds):
    """Sample points (XY) of the cutting moves at the deepest Z."""
    bottom = min(_z(c) for c in _feeds(cmds))
    pos, pts = np.zeros(3), []
    for c in cmds:
        if isinstance(c, (canon.StraightFeed, canon.ArcFeed)):
            s = gouge._samples(pos, c, 0.2)
            pts.append(s[np.abs(s[:, 2] - bottom) < 1e-9])
        if isinstance(c, (canon.StraightFeed, canon.StraightTraverse)):
            pos = np.array([c.x, c.y, c.z])
        elif isinstance(c, canon.ArcFeed):
            pos = np.array([c.first_end, c.second_end, c.axis_end_point])
    return np.concatenate(pts)[:, :2]


@pytest.mark.parametrize(
    ("name", "start", "end", "half_width"),
    [
        # closed 45 degree slot: course from (25, 20), 40 long; width 16 less 0.5 allowance
        ("slot_contour_parallel", (25.0, 20.0), (25 + 40 / 2**0.5, 20 + 40 / 2**0.5), 7.5),
        # open through slot along X at Y 40, width 16, finish: the floor inside the block
        ("slot_open_contour_parallel_outside_in", (0.0, 40.0), (100.0, 40.0), 8.0),
    ],
)
def test_contour_parallel_slot_clears_its_floor(name, start, end, half_width):
    """Every floor point of the slot (a stadium around its course, less the side
    allowance; an open slot within the block) is within the 5 mm tool radius of a cut at
    the deepest level."""
    path = _bottom_path(
        list(canon_from_file(str(HERE / "stepnc" / f"{name}.stp"), None, "default"))
    )
    a, b = np.array(start), np.array(end)
    u = (b - a) / np.linalg.norm(b - a)
    v = np.array([-u[1], u[0]])
    length = float(np.linalg.norm(b - a))
    s, t = np.meshgrid(
        np.linspace(-half_width, length + half_width, 121), np.linspace(-half_width, half_width, 41)
    )
    q = a + s.ravel()[:, None] * u + t.ravel()[:, None] * v
    along = np.clip(s.ravel(), 0.0, length)
    inside = np.hypot(s.ravel() - along, t.ravel()) <= half_width - 0.25
    if "open" in name:
        inside = (s.ravel() >= 0) & (s.ravel() <= length) & (np.abs(t.ravel()) <= half_width - 0.25)
    q = q[inside]
    d = np.min(np.linalg.norm(q[:, None, :] - path[None, :, :], axis=2), axis=1)
    assert d.max() <= 5.0 + 0.1


def test_contour_parallel_slot_loops_turn_as_the_strategy_says():
    """CW conventional: the loops run clockwise (arcs CW), the innermost (the centre line)
    first; CCW conventional on the open slot: the outermost loop first, counterclockwise."""
    closed = list(
        canon_from_file(str(HERE / "stepnc" / "slot_contour_parallel.stp"), None, "default")
    )
    assert {c.rotation for c in closed if isinstance(c, canon.ArcFeed)} == {-1}
    open_ = [
        c
        for c in canon_from_file(
            str(HERE / "stepnc" / "slot_open_contour_parallel_outside_in.stp"), None, "default"
        )
        if isinstance(c, canon.StraightFeed)
    ]
    bottom_first = [c for c in open_ if abs(c.z - open_[0].z) < 1e-9 and c.z < 0][:5]
    xs = [(round(c.x, 4), round(c.y, 4)) for c in bottom_first]
    # the first loop is the outermost (|y - 40| = 3: 8 - 5 tool radius), turning CCW
    assert xs[:4] == [(-6.0, 37.0), (106.0, 37.0), (106.0, 43.0), (-6.0, 43.0)]
