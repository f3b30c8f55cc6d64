"""AP238 AIM files, conformance class 1: cutter-location toolpaths to canonical commands.

The test file (tests/stepnc/ap238/cc1_two_tools.stp) was written by hand from the AP238
ed. 3 AIM and its mapping specification (README.md there); its commands are checked
against the values written in it: the toolpath points, 500 mm/min and -3000 rev/min for the
first operation, 10 mm/s and -50 Hz for the second.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc.to_canon import canon_from_file

HERE = Path(__file__).resolve().parent / "stepnc" / "ap238"
CC1 = HERE / "cc1_two_tools.stp"


def _run(path: Path) -> list[canon.Command]:
    return list(canon_from_file(str(path), None, "default"))


def test_cc1_file_matches_its_golden_ir():
    golden = (HERE / "cc1_two_tools.can").read_text().splitlines()
    assert list(canon.write_text(_run(CC1))) == golden


def test_cc1_toolpaths_tools_feeds_and_speeds_are_the_files():
    cmds = _run(CC1)
    moves = [c for c in cmds if isinstance(c, (canon.StraightFeed, canon.ArcFeed))]
    ends = [
        (c.x, c.y, c.z) if isinstance(c, canon.StraightFeed) else (c.first_end, c.second_end)
        for c in moves
    ]
    assert ends == [
        (40.0, 0.0, -2.0),
        (50.0, 10.0),
        (50.0, 30.0, -2.0),
        (50.0, 30.0, 20.0),
        (25.0, 15.0, -5.0),
        (25.0, 15.0, 20.0),
    ]
    arc = next(c for c in moves if isinstance(c, canon.ArcFeed))
    assert (arc.first_axis, arc.second_axis, arc.rotation) == (40.0, 10.0, 1)
    rapids = [(c.x, c.y, c.z) for c in cmds if isinstance(c, canon.StraightTraverse)]
    assert (0.0, 0.0, -2.0) in rapids and (25.0, 15.0, 20.0) in rapids  # rapid and connect
    assert [c.name for c in cmds if isinstance(c, canon.ChangeTool)] == [
        "T10 END MILL 6",
        "T20 END MILL 3",
    ]
    assert [c.rate for c in cmds if isinstance(c, canon.SetFeedRate)] == [500.0, 600.0]
    assert [c.speed for c in cmds if isinstance(c, canon.SetSpindleSpeed)] == [3000.0]
    assert sum(isinstance(c, canon.StartSpindleClockwise) for c in cmds) == 2
    names = [type(c).__name__ for c in cmds]
    assert names.count("FloodOn") == 1 and names.index("FloodOn") < names.index("StraightFeed")
    assert names.index("FloodOff") < names.index("ChangeTool", names.index("FloodOn"))
    # every motion is located at its operation inside its workingstep
    for c in moves:
        assert c.source is not None and c.source.workingstep in (31, 32)


_NC = """#170=MACHINING_NC_FUNCTION('msg','display message','','');
#171=MACHINING_PROCESS_SEQUENCE_RELATIONSHIP('',$,#30,#170,1.5);
#172=ACTION_PROPERTY('message text','',#170);
#173=REPRESENTATION('',(#174),#20);
#174=DESCRIPTIVE_REPRESENTATION_ITEM('text','change the clamp');
#175=ACTION_PROPERTY_REPRESENTATION('','',#172,#173);
#176=MACHINING_NC_FUNCTION('stop','{}','','');
#177=MACHINING_PROCESS_SEQUENCE_RELATIONSHIP('',$,#30,#176,1.7);
ENDSEC;"""


def test_a_measure_may_be_a_complex_instance(tmp_path):
    path = tmp_path / "complex.stp"
    simple = "#54=MEASURE_REPRESENTATION_ITEM('feed speed',NUMERIC_MEASURE(500.),#10);"
    complex_ = (
        "#54=(MEASURE_REPRESENTATION_ITEM()MEASURE_WITH_UNIT(NUMERIC_MEASURE(500.),#10)"
        "REPRESENTATION_ITEM('feed speed'));"
    )
    assert simple in CC1.read_text()
    path.write_text(CC1.read_text().replace(simple, complex_))
    assert [c.rate for c in _run(path) if isinstance(c, canon.SetFeedRate)] == [500.0, 600.0]


def _with_nc(stop: str) -> str:
    end = "\nENDSEC;\nEND-ISO-10303-21;"
    return CC1.read_text().replace(end, "\n" + _NC.format(stop) + "\nEND-ISO-10303-21;")


def test_nc_functions_run_in_sequence_position_order(tmp_path):
    path = tmp_path / "nc.stp"
    path.write_text(_with_nc("program stop"))
    cmds = _run(path)
    names = [type(c).__name__ for c in cmds]
    msg = names.index("Message")
    stop = names.index("ProgramStop")
    tools = [i for i, n in enumerate(names) if n == "ChangeTool"]
    assert tools[0] < msg < stop < tools[1]
    assert cmds[msg].text == "change the clamp"
    path.write_text(_with_nc("set mark"))
    with pytest.raises(Diagnostic) as err:
        _run(path)
    assert err.value.code == "STEPNC-AP238" and "set mark" in err.value.message


@pytest.mark.parametrize(
    ("old", "new", "word"),
    [
        (
            "('side','cutter location trajectory'",
            "('side','cutter contact trajectory'",
            "cutter contact trajectory",
        ),
        ("NUMERIC_MEASURE(500.),#10", "NUMERIC_MEASURE(500.),#13", "length per time"),
        ("#30=MACHINING_WORKPLAN", "#30=MACHINING_NC_FUNCTION", "MACHINING_WORKPLAN"),
        ("SI_UNIT(.MILLI.,.METRE.)", "SI_UNIT($,.METRE.)", "length unit of 1000 mm"),
        ("#121=REPRESENTATION('',(#93),#20);", "#121=REPRESENTATION('',(#91),#20);", "AXIS2"),
        (
            "#100=ACTION_PROPERTY('basic curve','',#70);",
            "#100=ACTION_PROPERTY('tool axis','',#70);",
            "tool axis",
        ),
        (
            "#34=MACHINING_PROCESS_SEQUENCE_RELATIONSHIP('',$,#30,#32,2.);",
            "#34=MACHINING_PROCESS_SEQUENCE_RELATIONSHIP('',$,#30,#35,2.);",
            "FREEFORM_MILLING_OPERATION",
        ),
    ],
)
def test_what_class_1_does_not_cover_is_one_located_message(tmp_path, old, new, word):
    text = CC1.read_text()
    assert old in text
    bad = tmp_path / "bad.stp"
    bad.write_text(text.replace(old, new))
    with pytest.raises(Diagnostic) as err:
        _run(bad)
    assert err.value.code == "STEPNC-AP238"
    assert word in err.value.message
    assert err.value.location.line is not None


def test_cc1_file_has_no_check_error_on_the_default_machine():
    result = CliRunner().invoke(cli, ["check", "--format", "json", str(CC1)])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert [f for e in doc["files"] for f in e["findings"] if f["severity"] == "error"] == []


def test_a_reference_to_an_undefined_instance_is_located_at_its_referrer(tmp_path):
    """Even in an attribute class 1 does not follow: the file is broken, as in ISO 14649."""
    old = "#30=MACHINING_WORKPLAN('main workplan',$,'','');"
    text = CC1.read_text()
    assert old in text
    bad = tmp_path / "dangling.stp"
    bad.write_text(text.replace(old, "#30=MACHINING_WORKPLAN('main workplan',#999,'','');"))
    with pytest.raises(Diagnostic) as err:
        _run(bad)
    assert err.value.code == "P21-DANGLING-REF"
    assert "#999" in err.value.message and err.value.location.line == 30
