"""Property tests: random pockets, faces and holes never gouge the finished part."""

from __future__ import annotations

import sys
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kernel.diagnostics import Diagnostic
from stepnc import gouge, part21
from stepnc.model import Model, validate
from stepnc.to_canon import canon_from_model

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "stepnc"))
from programs import Program, _mill, _pocket_op  # noqa: E402

STRATEGIES = [
    "CONTOUR_PARALLEL($,$,.CW.,.CONVENTIONAL.)",
    "CONTOUR_PARALLEL(0.3,.T.,.CCW.,.CLIMB.)",
    "BIDIRECTIONAL_MILLING(0.4,.T.,$,.LEFT.,$)",
    "CONTOUR_BIDIRECTIONAL(0.5,.T.,$,.RIGHT.,.CW.,.CONVENTIONAL.)",
    "$",
]
APPROACHES = [
    "$",
    "PLUNGE_TOOLAXIS($)",
    "PLUNGE_RAMP($,12.0)",
    "PLUNGE_ZIGZAG($,10.0,6.0)",
    "PLUNGE_HELIX($,2.0,6.0)",
]


def _run(p: Program) -> dict[int, list]:
    model = Model(part21.parse(p.text(), "prop.stp"))
    validate(model)
    return gouge.check(model, canon_from_model(model, None, "default"))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    length=st.floats(24, 80),
    aspect=st.floats(0.35, 1.0),
    corner=st.floats(0.0, 1.0),
    depth=st.floats(1.0, 15.0),
    tool=st.sampled_from([6.0, 8.0, 10.0]),
    strategy=st.sampled_from(STRATEGIES),
    approach=st.sampled_from(APPROACHES),
    finish=st.booleans(),
    axial=st.floats(1.0, 6.0),
    angle=st.floats(0.0, 3.1),
)
def test_random_pockets_never_gouge(
    length, aspect, corner, depth, tool, strategy, approach, finish, axial, angle
):
    import math

    width = round(max(length * aspect, tool + 1.0), 3)
    length = round(max(length, width), 3)
    radius = min(tool / 2 + 0.6 + corner * (width / 2 - tool / 2 - 0.6), width / 2)
    radius = math.floor(radius * 1000) / 1000
    p = Program("RANDOM POCKET")
    ref = (math.cos(angle), math.sin(angle), 0.0)
    feature = p.pocket(
        50, 40, round(length, 3), round(width, 3), round(depth, 3), round(radius, 3), angle_ref=ref
    )
    kind = "BOTTOM_AND_SIDE_FINISH_MILLING" if finish else "BOTTOM_AND_SIDE_ROUGH_MILLING"
    op = _pocket_op(
        p,
        kind,
        strategy,
        approach,
        tool=_mill(p, tool),
        axial=f"{axial:.3f}",
        radial="$",
        side="$" if finish else "0.5",
        bottom="$" if finish else "0.5",
    )
    p.workingstep("WS", feature, op)
    try:
        result = _run(p)
    except Diagnostic as d:  # honest refusals only: entries that do not fit
        assert d.code in ("STEPNC-ENTRY", "STEPNC-TOOL-CORNER", "STEPNC-TOOL-WIDTH"), str(d)
        assert radius - (0.0 if finish else 0.5) < tool / 2 + 1e-6 or d.code == "STEPNC-ENTRY"
        return
    assert result and all(not g for g in result.values())


@settings(max_examples=25, deadline=None)
@given(
    depth=st.floats(0.5, 4.0),
    along_y=st.booleans(),
    tool=st.sampled_from([8.0, 12.0, 16.0, 25.0]),
    strategy=st.sampled_from(
        [
            "BIDIRECTIONAL_MILLING(0.2,.T.,$,.LEFT.,$)",
            "BIDIRECTIONAL_MILLING(0.3,.T.,$,.RIGHT.,$)",
            "UNIDIRECTIONAL_MILLING(0.25,.T.,$,.CLIMB.)",
            "UNIDIRECTIONAL_MILLING($,$,$,.CONVENTIONAL.)",
        ]
    ),
)
def test_random_faces_never_gouge(depth, along_y, tool, strategy):
    """Plane milling overhangs the face ends (overcut), so, as NIST assumes, the face spans
    the whole block top; a smaller face would be gouged and is caught (see below)."""
    p = Program("RANDOM FACE")
    s = p.add(strategy)
    face = p.face(0, 0, 100, 80, round(depth, 3), along_y=along_y)
    op = p.add(
        "PLANE_FINISH_MILLING($,$,'F',5.0,$,{},{},{},$,$,$,{},1.0,$)",
        _mill(p, tool),
        p.tech(),
        p.functions(),
        s,
    )
    p.workingstep("WS", face, op)
    result = _run(p)
    assert result and all(not g for g in result.values())


def test_face_smaller_than_the_block_top_is_gouged_by_the_overcut():
    p = Program("SMALL FACE")
    s = p.add("BIDIRECTIONAL_MILLING(0.2,.T.,$,.LEFT.,$)")
    face = p.face(0, 0, 10, 10, 1.0)
    op = p.add(
        "PLANE_FINISH_MILLING($,$,'F',5.0,$,{},{},{},$,$,$,{},1.0,$)",
        _mill(p, 12.0),
        p.tech(),
        p.functions(),
        s,
    )
    ws = p.workingstep("WS", face, op)
    assert _run(p)[ws]
