"""Slot and step milling (stepnc/toolpaths/slot.py, step.py): the floor the tool sweeps
equals the feature's closed-form outline, layers reach the depth less the allowance, the
finished part has the closed-form volume, and impossible set-ups are located errors.
Golden IR, read-back and gouge checks of the programs run in test_stepnc_canon.py."""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc import geometry, gouge, part21
from stepnc.model import Model, load, validate
from stepnc.to_canon import canon_from_file, canon_from_model

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "stepnc"))

from programs import Program, _mill, _pocket_op, _side_op  # noqa: E402


def _commands(name: str) -> list[canon.Command]:
    model = load(str(HERE / "stepnc" / f"{name}.stp"))
    return list(canon_from_model(model, None, "default"))


def _bottom_path(cmds: list[canon.Command]) -> tuple[float, np.ndarray]:
    """(deepest Z, XY tool-centre samples every 0.1 mm of the moves at that Z)."""
    pos, pts = np.zeros(3), []
    feeds = [c for c in cmds if isinstance(c, (canon.StraightFeed, canon.ArcFeed))]
    bottom = min(c.z if isinstance(c, canon.StraightFeed) else c.axis_end_point for c in feeds)
    for c in cmds:
        if isinstance(c, (canon.StraightFeed, canon.ArcFeed)):
            s = gouge._samples(pos, c, 0.1)
            pts.append(s[np.abs(s[:, 2] - bottom) < 1e-9])
        if isinstance(c, (canon.StraightFeed, canon.StraightTraverse)):
            pos = np.array([c.x, c.y, c.z])
        elif isinstance(c, canon.ArcFeed):
            pos = np.array([c.first_end, c.second_end, c.axis_end_point])
    return bottom, np.concatenate(pts)[:, :2]


def _swept_area(path: np.ndarray, radius: float, cell: float = 0.05) -> float:
    """Area of the union of tool discs along ``path`` inside the 100 x 80 block."""
    gx, gy = np.meshgrid(np.arange(cell / 2, 100, cell), np.arange(cell / 2, 80, cell))
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    dist, _ = cKDTree(path).query(grid, distance_upper_bound=radius + 1e-9)
    return float(np.count_nonzero(np.isfinite(dist))) * cell * cell


@pytest.mark.parametrize(
    ("name", "radius", "area"),
    [
        # 45-degree slot, course 40, width 16 less 2 x 0.5 side allowance, radiused ends
        ("slot_radiused_ramp", 5.0, 40 * 15 + math.pi * 7.5**2),
        # open slot across the block: 100 x 16
        ("slot_open_finish", 5.0, 100 * 16),
        # course 70 to the block edge, width 10 = tool, radiused start (half disc)
        ("slot_side_full_width", 5.0, 70 * 10 + math.pi * 5**2 / 2),
        # step: Y < 20 less the 0.5 side allowance, over the block's 100 mm
        ("step_bidirectional", 6.0, 100 * 19.5),
        # step: X > 85, over the block's 80 mm, finish (no allowance)
        ("step_side_unidirectional", 5.0, 15 * 80),
        # open pocket 40 x 30 from the block edge, two corners of radius 8; the deepest
        # level is the finish side milling (8 mm tool) at full depth
        ("open_pocket_from_edge", 4.0, 40 * 30 - 2 * (1 - math.pi / 4) * 64),
    ],
)
def test_swept_floor_equals_the_feature_outline(name, radius, area):
    """Nothing is left on the floor and nothing beyond the outline is cut: the area swept
    by the tool at the deepest level equals the closed form (grid of 0.05 mm)."""
    _, path = _bottom_path(_commands(name))
    assert _swept_area(path, radius) == pytest.approx(area, rel=2e-3)


@pytest.mark.parametrize(
    ("name", "depth", "layers"),
    [
        ("slot_radiused_ramp", -8.5, 3),  # 9 less 0.5 bottom allowance, axial 3
        ("slot_open_finish", -6.0, 2),
        ("slot_side_full_width", -5.0, 1),  # side milling: axial = edge length 40
        ("step_bidirectional", -9.7, 3),  # 10 less 0.3, axial 4
        ("step_side_unidirectional", -12.0, 2),
        ("open_pocket_from_edge", -8.0, 1),  # rough to -7.5 in 2 layers, finish to -8 in 1
    ],
)
def test_layers_are_equal_and_reach_depth_less_allowance(name, depth, layers):
    bottom, _ = _bottom_path(cmds := _commands(name))
    assert bottom == pytest.approx(depth, abs=1e-9)
    levels = {round(c.z, 6) for c in cmds if isinstance(c, canon.StraightFeed) and c.z < 0}
    levels |= {round(c.axis_end_point, 6) for c in cmds if isinstance(c, canon.ArcFeed)}
    expected = {round(depth * k / layers, 6) for k in range(1, layers + 1)}
    assert expected <= levels
    assert all(z in expected for z in levels if z < 0 and name.startswith("step"))


def test_every_slot_and_step_move_carries_its_workingstep():
    for name in ("slot_radiused_ramp", "step_bidirectional"):
        model = load(str(HERE / "stepnc" / f"{name}.stp"))
        ws = next(model.all("MACHINING_WORKINGSTEP"))
        op = ws.its_operation
        moves = [
            c
            for c in canon_from_model(model, None, "default")
            if isinstance(c, (canon.StraightFeed, canon.ArcFeed))
        ]
        assert moves and all(
            c.source.workingstep == ws.id and c.source.entity == op.id for c in moves
        )


def test_unidirectional_climb_cuts_against_the_path_direction():
    """Step wall along +Y with the material at X > 85: every cutting stroke runs -Y."""
    strokes = [
        c
        for c in _commands("step_side_unidirectional")
        if isinstance(c, canon.StraightFeed) and c.z < 0
    ]
    ys = [round(c.y, 9) for c in strokes]
    assert ys[1::2] == [-6.0] * (len(ys) // 2) and ys[0::2] == [86.0] * (len(ys) // 2)


@pytest.mark.parametrize(
    ("name", "removed"),
    [
        ("slot_side_full_width", (70 * 10 + math.pi * 25 / 2) * 5),
        ("step_bidirectional", 100 * 20 * 10),
        ("slot_radiused_ramp", (40 * 16 + math.pi * 64) * 9),
        ("open_pocket_from_edge", (40 * 30 - 2 * (1 - math.pi / 4) * 64) * 8),
    ],
)
def test_finished_part_is_block_minus_the_feature(name, removed):
    part = geometry.finished_part(load(str(HERE / "stepnc" / f"{name}.stp")))
    assert geometry.volume(part) == pytest.approx(100 * 80 * 40 - removed, rel=1e-6)


def _write(tmp_path: Path, p: Program) -> str:
    path = tmp_path / "p.stp"
    path.write_text(p.text())
    return str(path)


def test_tool_wider_than_the_slot_is_a_located_error(tmp_path):
    p = Program("SLOT TOO NARROW")
    ws = p.workingstep(
        "WS SLOT",
        p.slot(30, 40, 40, 10, 5),
        _side_op(p, "SIDE_ROUGH_MILLING", "$", tool=_mill(p, 10.0)),  # 0.2 allowance each side
    )
    with pytest.raises(Diagnostic) as exc:
        list(canon_from_file(_write(tmp_path, p)))
    assert exc.value.code == "STEPNC-TOOL-WIDTH" and exc.value.location.workingstep == ws


def test_unsupported_slot_strategy_is_a_located_error(tmp_path):
    p = Program("SLOT CONTOUR SPIRAL")
    ws = p.workingstep(
        "WS SLOT",
        p.slot(30, 40, 40, 16, 5),
        _pocket_op(p, "BOTTOM_AND_SIDE_FINISH_MILLING", "CONTOUR_SPIRAL($,$,.CW.,$)"),
    )
    with pytest.raises(Diagnostic) as exc:
        list(canon_from_file(_write(tmp_path, p)))
    assert exc.value.code == "STEPNC-STRATEGY" and exc.value.location.workingstep == ws


def test_closed_slot_moved_into_the_wall_is_caught_by_the_gouge_check(tmp_path):
    """The gouge check knows the slot's volume: the same toolpath against a slot whose
    radiused end is 3 mm shorter gouges the end wall."""
    good = (HERE / "stepnc" / "slot_side_full_width.stp").read_text()
    model = load(str(HERE / "stepnc" / "slot_side_full_width.stp"))
    cmds = list(canon_from_model(model, None, "default"))
    path = tmp_path / "short.stp"
    path.write_text(
        good.replace("CARTESIAN_POINT('',(30.0,60.0,0.0))", "CARTESIAN_POINT('',(33.0,60.0,0.0))")
    )
    shifted = load(str(path))
    found = gouge.check(shifted, cmds)
    assert any(found.values())


def test_open_pocket_rough_layers_leave_the_allowances():
    """Rough workingstep: floor at 8 - 0.5 in two equal layers, strokes stop 0.5 mm plus
    the tool radius before the back wall (X = 40) and side walls (Y = 25, 55)."""
    model = load(str(HERE / "stepnc" / "open_pocket_from_edge.stp"))
    rough = next(model.all("MACHINING_WORKINGSTEP")).id
    moves = [
        c
        for c in canon_from_model(model, None, "default")
        if isinstance(c, canon.StraightFeed) and c.source.workingstep == rough and c.z < 0
    ]
    assert {round(c.z, 9) for c in moves} == {-3.75, -7.5}
    assert max(c.x for c in moves) == pytest.approx(40 - 0.5 - 5)
    assert min(c.y for c in moves) == pytest.approx(25 + 0.5 + 5)
    assert max(c.y for c in moves) == pytest.approx(55 - 0.5 - 5)
    assert min(c.x for c in moves) == pytest.approx(-6.0)  # enters beside the block


def test_validation_reports_a_tool_wider_than_the_slot(tmp_path):
    """Collect mode (cnc stepnc check) finds the misfit without generating toolpaths."""
    p = Program("SLOT TOO NARROW FOR THE TOOL")
    ws = p.workingstep(
        "WS SLOT",
        p.slot(30, 40, 40, 10, 5),
        _pocket_op(p, "BOTTOM_AND_SIDE_FINISH_MILLING", "$", tool=_mill(p, 12.0)),
    )
    found: list[Diagnostic] = []
    load(_write(tmp_path, p), found)
    assert [(d.code, d.location.workingstep) for d in found] == [("STEPNC-TOOL-WIDTH", ws)]


@settings(max_examples=20, deadline=None)
@given(
    length=st.floats(5.0, 40.0),
    width=st.floats(6.0, 30.0),
    tool_share=st.floats(0.3, 1.0),
    angle=st.floats(0.0, 2 * math.pi),
    depth=st.floats(1.0, 12.0),
    axial=st.floats(1.0, 6.0),
    radial=st.floats(0.5, 8.0),
    finish=st.booleans(),
    strategy=st.sampled_from(
        ["$", "BIDIRECTIONAL_MILLING($,$,$,$,$)", "CONTOUR_BIDIRECTIONAL($,$,$,$,.CCW.,$)"]
    ),
)
def test_random_closed_slots_never_gouge_and_clear_the_floor(
    length, width, tool_share, angle, depth, axial, radial, finish, strategy
):
    """Any closed slot (radiused ends) centred in the block at any angle: gouge-free, and
    with a contour pass every floor point inside the outline less the allowance is within
    the tool radius of the path at the deepest level."""
    side = 0.0 if finish else 0.5
    length, width, depth = round(length, 3), round(width, 3), round(depth, 3)
    tool = round(max(2.0, tool_share * (width - 2 * side)), 3)
    d = (math.cos(angle), math.sin(angle))
    p = Program("RANDOM SLOT")
    kind = "BOTTOM_AND_SIDE_FINISH_MILLING" if finish else "BOTTOM_AND_SIDE_ROUGH_MILLING"
    x0, y0 = 50 - d[0] * length / 2, 40 - d[1] * length / 2
    feature = p.slot(round(x0, 4), round(y0, 4), length, width, depth, course=(*d, 0.0))
    op = _pocket_op(
        p,
        kind,
        strategy,
        tool=_mill(p, tool),
        axial=f"{axial:.3f}",
        radial=f"{radial:.3f}",
        side=f"{side}",
        bottom=f"{side}",
    )
    p.workingstep("WS", feature, op)
    model = Model(part21.parse(p.text(), "slot.stp"))
    validate(model)
    cmds = list(canon_from_model(model, None, "default"))
    result = gouge.check(model, cmds)
    assert result and all(not g for g in result.values())
    if strategy.startswith("BIDIRECTIONAL"):
        return  # cusps stay in the radiused ends between stroke ends (documented)
    _, path = _bottom_path(cmds)
    # floor points: the stadium shrunk by the allowance and 0.05 mm, on a 0.25 mm grid
    half = width / 2 - side - 0.05
    u, v = np.meshgrid(np.arange(-half, length + half, 0.25), np.arange(-half, half, 0.25))
    u, v = u.ravel(), v.ravel()
    du = np.maximum(np.maximum(-u, u - length), 0.0)
    keep = du * du + v * v <= half * half
    pts = np.column_stack(
        [x0 + u[keep] * d[0] - v[keep] * d[1], y0 + u[keep] * d[1] + v[keep] * d[0]]
    )
    dist, _ = cKDTree(path).query(pts)
    assert dist.max() <= tool / 2 + 0.02


@settings(max_examples=20, deadline=None)
@given(
    length=st.floats(8.0, 50.0),
    width=st.floats(10.0, 40.0),
    corner_share=st.floats(0.0, 1.0),
    tool_share=st.floats(0.2, 0.9),
    depth=st.floats(1.0, 10.0),
    radial=st.floats(0.5, 8.0),
    finish=st.booleans(),
)
def test_random_open_pockets_never_gouge_and_clear_the_floor(
    length, width, corner_share, tool_share, depth, radial, finish
):
    """Open pockets from the block's -X edge: gouge-free, and every floor point of the
    rounded outline less the allowance is within the tool radius of the deepest path."""
    side = 0.0 if finish else 0.5
    length, width, depth = round(length, 3), round(width, 3), round(depth, 3)
    tool = round(max(2.0, tool_share * min(width - 2 * side, length - side)), 3)
    rmin = tool / 2 + side
    corner = rmin + corner_share * (min(width / 2, length) - rmin)
    corner = max(math.floor(corner * 1000) / 1000, math.ceil(rmin * 1000 + 1) / 1000)
    p = Program("RANDOM OPEN POCKET")
    kind = "BOTTOM_AND_SIDE_FINISH_MILLING" if finish else "BOTTOM_AND_SIDE_ROUGH_MILLING"
    feature = p.open_pocket(0, 40, length, width, depth, corner)
    op = _pocket_op(
        p,
        kind,
        "$",
        tool=_mill(p, tool),
        radial=f"{radial:.3f}",
        side=f"{side}",
        bottom=f"{side}",
    )
    p.workingstep("WS", feature, op)
    model = Model(part21.parse(p.text(), "open.stp"))
    validate(model)
    cmds = list(canon_from_model(model, None, "default"))
    result = gouge.check(model, cmds)
    assert result and all(not g for g in result.values())
    _, path = _bottom_path(cmds)
    hw, back, c = width / 2 - side - 0.05, length - side - 0.05, corner - side - 0.05
    x, y = np.meshgrid(np.arange(0.0, back, 0.25), np.arange(-hw, hw, 0.25))
    x, y = x.ravel(), y.ravel()
    ex = np.maximum(x - (back - c), 0.0)
    ey = np.maximum(np.abs(y) - (hw - c), 0.0)
    keep = ex * ex + ey * ey <= c * c
    dist, _ = cKDTree(path).query(np.column_stack([x[keep], y[keep] + 40.0]))
    assert dist.max() <= tool / 2 + 0.02


@settings(max_examples=20, deadline=None)
@given(
    edge=st.sampled_from(["+X", "+Y", "-X", "-Y"]),
    reach=st.floats(3.0, 30.0),
    tool=st.sampled_from([4.0, 6.0, 10.0, 16.0]),
    depth=st.floats(1.0, 15.0),
    radial=st.floats(0.5, 10.0),
    side_op=st.booleans(),
    strategy=st.sampled_from(
        ["$", "UNIDIRECTIONAL_MILLING($,$,$,.CLIMB.)", "UNIDIRECTIONAL_MILLING($,$,$,$)"]
    ),
)
def test_random_steps_never_gouge_and_clear_the_floor(
    edge, reach, tool, depth, radial, side_op, strategy
):
    """A step along any block edge: gouge-free, and the whole floor strip (reach less the
    allowance, over the block) is within the tool radius of the deepest path."""
    reach, depth = round(reach, 3), round(depth, 3)
    start, along, length = {
        "+X": ((0, reach), (1, 0, 0), 100),
        "+Y": ((100 - reach, 0), (0, 1, 0), 80),
        "-X": ((100, 80 - reach), (-1, 0, 0), 100),
        "-Y": ((reach, 80), (0, -1, 0), 80),
    }[edge]
    p = Program("RANDOM STEP")
    feature = p.step(*start, length, depth, along)
    if side_op:
        op = _side_op(p, "SIDE_ROUGH_MILLING", strategy, tool=_mill(p, tool), radial=f"{radial}")
    else:
        op = _pocket_op(
            p, "BOTTOM_AND_SIDE_FINISH_MILLING", strategy, tool=_mill(p, tool), radial=f"{radial}"
        )
    p.workingstep("WS", feature, op)
    model = Model(part21.parse(p.text(), "step.stp"))
    validate(model)
    cmds = list(canon_from_model(model, None, "default"))
    result = gouge.check(model, cmds)
    assert result and all(not g for g in result.values())
    _, path = _bottom_path(cmds)
    keep = reach - (0.2 if side_op else 0.0) - 0.05  # rough side milling leaves 0.2
    gx, gy = np.meshgrid(np.arange(0.05, 100, 0.25), np.arange(0.05, 80, 0.25))
    x, y = gx.ravel(), gy.ravel()
    inside = {
        "+X": y < keep,
        "+Y": x > 100 - keep,
        "-X": y > 80 - keep,
        "-Y": x < keep,
    }[edge]
    dist, _ = cKDTree(path).query(np.column_stack([x[inside], y[inside]]))
    assert dist.max() <= tool / 2 + 0.02


def test_slot_with_bottom_radii_is_refused_in_its_workingstep(tmp_path):
    """The generator mills flat floors only; the refusal names the workingstep."""
    p = Program("SLOT BOTTOM RADIUS")
    ws = p.workingstep(
        "WS SLOT",
        p.slot(30, 40, 40, 16, 5, ends=("OPEN_SLOT_END_TYPE",)),
        _pocket_op(p, "BOTTOM_AND_SIDE_FINISH_MILLING", "$"),
    )
    # first_radius := the width measure (8 mm fillets would need a ball or bull-nose tool)
    text = re.sub(r"SQUARE_U_PROFILE\(\$,(#\d+),\$", r"SQUARE_U_PROFILE($,\1,\1", p.text())
    path = tmp_path / "p.stp"
    path.write_text(text)
    with pytest.raises(Diagnostic) as exc:
        list(canon_from_file(str(path)))
    assert exc.value.code == "STEPNC-UNSUPPORTED" and exc.value.location.workingstep == ws
