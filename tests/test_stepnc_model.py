"""Schema validation (stepnc.model) and the book's broken Fig. 11.18 fragment."""

from __future__ import annotations

from pathlib import Path

import pytest

from kernel.diagnostics import Diagnostic, Severity
from stepnc import part21
from stepnc.model import Model, load, validate
from stepnc.to_canon import canon_from_file
from tests.data_paths import CORPUS_STEPNC

HERE = Path(__file__).resolve().parent
EX1 = CORPUS_STEPNC / "ex1.stp"
FIG = HERE / "stepnc" / "book_fig_11_18.stp"

# research/seed-book-stepnc.md §1.11.3: each defect row -> (entity, expected code).
FIG_DEFECTS = [
    (1, "STEPNC-ATTR-COUNT"),  # 3 fields, misplaced parenthesis
    (2, "STEPNC-ATTR-COUNT"),  # elements not in a list: 9 fields
    (10, "P21-UNTERMINATED"),  # truncated line swallows #11
    (18, "STEPNC-ATTR-TYPE"),  # its_boss written 0
    (28, "STEPNC-ATTR-COUNT"),  # 3 fields
    (28, "STEPNC-MISSING-HASH"),  # 59 without '#'
    (22, "P21-EMPTY-PARAM"),  # ',,'
    (22, "STEPNC-ATTR-COUNT"),  # 17 fields
    (42, "P21-EMPTY-PARAM"),
    (42, "P21-BARE-ENUM"),  # T, LEFT
    (42, "STEPNC-ATTR-COUNT"),  # 7 fields
    (41, "P21-BARE-ENUM"),
    (41, "P21-EMPTY-PARAM"),
    (41, "STEPNC-ATTR-COUNT"),  # 11 fields
    (50, "P21-BARE-ENUM"),
    (50, "P21-EMPTY-PARAM"),
    (50, "STEPNC-ATTR-COUNT"),  # 12 fields
    (29, "P21-BARE-ENUM"),  # F
    (4, "P21-BAD-REF"),  # $66
    (6, "STEPNC-ATTR-TYPE"),  # #7 not a list
    (7, "P21-KEYWORD-VALUE"),  # E='...'
    (7, "STEPNC-UNKNOWN-ENTITY"),  # PROPERTY_PARAMETER
    (9, "STEPNC-ATTR-TYPE"),  # 0 for ()
]
FIG_DANGLING = {
    16,
    17,
    19,
    20,
    21,
    23,
    35,
    37,
    43,
    62,
    65,
    66,
    67,
    68,
    69,
    71,
    74,
    84,
    121,
    122,
    123,
    124,
    125,
}


@pytest.fixture(scope="module")
def fig_diags() -> list[Diagnostic]:
    diags: list[Diagnostic] = []
    load(str(FIG), diags)
    return diags


def test_fig_11_18_strict_mode_stops_at_the_missing_semicolon():
    with pytest.raises(Diagnostic) as exc:
        load(str(FIG))
    assert (exc.value.code, exc.value.location.line) == ("P21-SYNTAX", 2)


def test_fig_11_18_each_listed_defect_has_one_precise_diagnostic(fig_diags):
    found = [(d.location.entity, d.code) for d in fig_diags]
    for defect in FIG_DEFECTS:
        assert found.count(defect) == 1, defect
    entity_level = [
        (e, c)
        for e, c in found
        if e is not None and c != "P21-DANGLING-REF" and c != "STEPNC-ORPHAN"
    ]
    assert sorted(entity_level) == sorted(FIG_DEFECTS)  # nothing beyond the list


def test_fig_11_18_file_structure_defects(fig_diags):
    file_level = [(d.code, d.location.line) for d in fig_diags if d.location.entity is None]
    assert file_level == [
        ("P21-SYNTAX", 2),  # ISO-10303-21 without ';'
        ("P21-HEADER", 3),  # '.....'
        ("P21-EOF", 37),  # DATA not closed by ENDSEC;
        ("P21-EOF", 37),  # no END-ISO-10303-21;
    ]


def test_fig_11_18_dangling_references_once_each(fig_diags):
    dangling = [d for d in fig_diags if d.code == "P21-DANGLING-REF"]
    named = {int(d.message.split()[0][1:]) for d in dangling}
    assert named == FIG_DANGLING and len(dangling) == len(FIG_DANGLING)


def test_fig_11_18_orphans_are_warnings(fig_diags):
    orphans = {
        (d.location.entity, d.record.severity) for d in fig_diags if d.code == "STEPNC-ORPHAN"
    }
    assert orphans == {(8, Severity.WARNING), (59, Severity.WARNING)}


def test_ex1_is_valid():
    diags: list[Diagnostic] = []
    load(str(EX1), diags)
    assert diags == []


def _ex1_variant(old: str, new: str) -> list[Diagnostic]:
    text = EX1.read_text(encoding="latin-1")
    assert old in text
    model = Model(part21.parse(text.replace(old, new, 1), "ex1v.stp"))
    diags: list[Diagnostic] = []
    validate(model, diags)
    return diags


def test_original_20mm_tool_cannot_reach_pocket_corners():
    # NIST change 11: a 20 mm endmill with 1 mm side allowance in a corner of radius 10
    diags = _ex1_variant("#30= MILLING_TOOL_DIMENSION(18.000,", "#30= MILLING_TOOL_DIMENSION(20.0,")
    corner = [d for d in diags if d.code == "STEPNC-TOOL-CORNER"]
    assert [d.location.workingstep for d in corner] == [13]  # rough only (finish has no side)
    assert corner[0].location.entity == 22


def test_original_bottom_fillet_below_tool_edge_radius():
    # NIST change 1: pocket fillet 1.0 (#35) smaller than the endmill edge radius 1.5 (#30)
    text = EX1.read_text(encoding="latin-1")
    text = text.replace(
        "#18= CLOSED_POCKET('POCKET1',#4,(#22,#23),#84,#65,(),$,#27,$,#37,#28);",
        "#18= CLOSED_POCKET('POCKET1',#4,(#22,#23),#84,#65,(),$,#27,#35,#37,"
        "#28);\n#35= TOLERANCED_LENGTH_MEASURE(1.000,#38);",
    )
    text = text.replace(
        "#30= MILLING_TOOL_DIMENSION(18.000, $,$, 29.0, 0.0, $,$);",
        "#30= MILLING_TOOL_DIMENSION(18.000, $,$, 29.0, 1.5, $,$);",
    )
    diags: list[Diagnostic] = []
    validate(Model(part21.parse(text, "v.stp")), diags)
    fillet = [d for d in diags if d.code == "STEPNC-FILLET-EDGE"]
    assert sorted(d.location.workingstep for d in fillet) == [13, 14]


def test_drill_wider_than_hole():
    diags = _ex1_variant(
        "#58= TOLERANCED_LENGTH_MEASURE(22.000,#56);", "#58= TOLERANCED_LENGTH_MEASURE(19.000,#56);"
    )
    assert {(d.code, d.location.workingstep) for d in diags} == {
        ("STEPNC-TOOL-HOLE", 11),
        ("STEPNC-TOOL-HOLE", 12),
    }


@pytest.mark.parametrize(
    ("old", "new", "code"),
    [
        (
            "#57= NUMERIC_PARAMETER('PROFILE LENGTH',100.000,'MM');",
            "#57= NUMERIC_PARAMETER('PROFILE LENGTH','100','MM');",
            "STEPNC-ATTR-TYPE",
        ),
        ("#60= PLUNGE_TOOLAXIS($);", "#60= PLUNGE_TOOLAXIS($,1.0);", "STEPNC-ATTR-COUNT"),
        ("#60= PLUNGE_TOOLAXIS($);", "#60= PLUNGE_SPIRAL($);", "STEPNC-UNKNOWN-ENTITY"),
        (
            "#10= MACHINING_WORKINGSTEP('WS FINISH PLANAR FACE1',#62,#16,#19,$);",
            "#10= MACHINING_WORKINGSTEP('WS FINISH PLANAR FACE1',#62,#39,#19,$);",
            "STEPNC-REF-TYPE",
        ),
        (
            "#29= TAPERED_ENDMILL(#30,4,.RIGHT.,.F.,$,$);",
            "#29= TAPERED_ENDMILL($,4,.RIGHT.,.F.,$,$);",
            "STEPNC-ATTR-MISSING",
        ),
        (
            "#29= TAPERED_ENDMILL(#30,4,.RIGHT.,.F.,$,$);",
            "#29= TAPERED_ENDMILL(#30,4,.UP.,.F.,$,$);",
            "STEPNC-ATTR-TYPE",
        ),
    ],
)
def test_schema_errors_are_located(old, new, code):
    diags = _ex1_variant(old, new)
    assert code in [d.code for d in diags]
    d = next(d for d in diags if d.code == code)
    assert d.location.entity is not None and d.location.line > 0


def iso_example1_original() -> str:
    """ISO 14649-11 Example 1 as published: NIST's ex1.stp with every line NIST changed put
    back from its ORIGINAL comment (research/seed-book-stepnc.md §7.2)."""
    import re

    text = EX1.read_text(encoding="latin-1")
    originals = {}
    for m in re.finditer(r"/\*\s*(#(\d+)=.*?;)(.*?)\*/", text, re.DOTALL):
        if "SEMICIRCLE" not in m.group(3):
            originals[int(m.group(2))] = m.group(1)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.DOTALL)
    for ident, original in originals.items():
        text, n = re.subn(
            rf"#{ident}\s*=.*?;", lambda _m, o=original: o, text, count=1, flags=re.DOTALL
        )
        if n == 0:
            text = text.replace("ENDSEC;\n\nEND-ISO", f"{original}\nENDSEC;\n\nEND-ISO")
    return text


def test_iso_example1_original_is_rejected_for_the_reasons_nist_found():
    model = Model(part21.parse(iso_example1_original(), "iso_ex1.stp"))
    diags: list[Diagnostic] = []
    validate(model, diags)
    found = sorted((d.code, d.location.entity, d.location.workingstep) for d in diags)
    assert found == [
        ("STEPNC-ATTR-COUNT", 125, None),  # CUTTING_COMPONENT with 4 of 5 attributes
        ("STEPNC-ATTR-COUNT", 126, None),
        ("STEPNC-ATTR-COUNT", 127, None),
        ("STEPNC-FILLET-EDGE", 22, 13),  # bottom fillet 1.0 < tool edge radius 1.5
        ("STEPNC-FILLET-EDGE", 23, 14),
        ("STEPNC-TOOL-CORNER", 22, 13),  # 20 mm tool, corner 10, side allowance 1
    ]


def test_unset_placement_name_is_a_lenient_warning_and_the_file_runs(tmp_path):
    """A `$` in AXIS2_PLACEMENT_3D.name (mandatory in ISO 10303-42) names nothing the
    machine uses: a located STEPNC-LENIENT warning, and the commands are unchanged."""
    old, new = "#71= AXIS2_PLACEMENT_3D('SETUP1',", "#71= AXIS2_PLACEMENT_3D($,"
    diags = _ex1_variant(old, new)
    lenient = [d for d in diags if d.code == "STEPNC-LENIENT"]
    assert [d.record.severity for d in lenient] == [Severity.WARNING]
    assert lenient[0].location.entity == 71
    assert not [d for d in diags if d.record.severity is Severity.ERROR]
    variant = tmp_path / "ex1_unnamed.stp"
    variant.write_text(EX1.read_text(encoding="latin-1").replace(old, new, 1))
    ours = [c.to_text() for c in canon_from_file(str(variant), None)]
    assert ours == [c.to_text() for c in canon_from_file(str(EX1), None)]


def test_unset_mandatory_value_that_matters_is_still_an_error():
    diags = _ex1_variant(
        "#71= AXIS2_PLACEMENT_3D('SETUP1',#95,", "#71= AXIS2_PLACEMENT_3D('SETUP1',$,"
    )
    assert "STEPNC-ATTR-MISSING" in [d.code for d in diags]


AP238_AIM = """ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('AP238 AIM sample'),'2;1');
FILE_NAME('part.stp','2026-01-01',(''),(''),'','','');
FILE_SCHEMA(('INTEGRATED_CNC_SCHEMA'));
ENDSEC;
DATA;
#1=PRODUCT('part','part','',(#2));
#2=PRODUCT_CONTEXT('',#3,'');
#3=APPLICATION_CONTEXT('integrated cnc');
#4=MACHINING_WORKPLAN('main','','',$);
#5=MACHINING_WORKINGSTEP('ws1','','',$);
ENDSEC;
END-ISO-10303-21;
"""


def test_ap238_aim_file_gets_one_message_naming_the_form(tmp_path):
    path = tmp_path / "aim.stp"
    path.write_text(AP238_AIM)
    diags: list[Diagnostic] = []
    load(str(path), diags)
    assert [d.code for d in diags] == ["STEPNC-AP238"]
    assert "INTEGRATED_CNC_SCHEMA" in diags[0].message
    with pytest.raises(Diagnostic) as info:
        load(str(path))
    assert info.value.code == "STEPNC-AP238" and info.value.location.line == 1
