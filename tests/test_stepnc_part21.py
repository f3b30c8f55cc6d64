"""ISO 10303-21 reader and writer (stepnc.part21)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kernel.diagnostics import Diagnostic
from stepnc import part21
from stepnc.part21 import DERIVED, Binary, Enum, Instance, Part, Ref, Typed
from tests.data_paths import CORPUS_STEPNC

CORPUS = CORPUS_STEPNC
EX1 = CORPUS / "ex1.stp"


def wrap(data: str) -> str:
    return (
        f"ISO-10303-21;\nHEADER;\nFILE_NAME('x');\nENDSEC;\nDATA;\n{data}\nENDSEC;\n"
        "END-ISO-10303-21;\n"
    )


def test_values_of_every_kind_are_decoded():
    f = part21.parse(
        wrap(
            "#1=A(12,-3.5,1.E-3,'it''s',.T.,.LEFT.,\"0FF\",$,*,(1,(2,3)),#2,LENGTH_MEASURE(2.0));"
            "\n#2=B();"
        )
    )
    assert f[1].params == (
        12,
        -3.5,
        0.001,
        "it's",
        Enum("T"),
        Enum("LEFT"),
        Binary("0FF"),
        None,
        DERIVED,
        (1, (2, 3)),
        Ref(2),
        Typed("LENGTH_MEASURE", 2.0),
    )
    assert type(f[1].params[0]) is int and isinstance(f[1].params[10], Ref)


def test_string_escapes_x_x2_x4_and_backslash():
    f = part21.parse(wrap(r"#1=S('\X\E9t\X2\00E903A9\X0\ \X4\0001F600\X0\ a\\b');"))
    assert f[1].params == ("\xe9t\xe9\u03a9 \U0001f600 a\\b",)


def test_complex_instance_and_forward_reference():
    f = part21.parse(
        wrap(
            "#1=(REPRESENTATION_ITEM('a')GEOMETRIC_REPRESENTATION_ITEM()"
            "POINT_X(#5));\n#5=CARTESIAN_POINT('p',(0.,1.,2.));"
        )
    )
    assert f[1].name is None
    assert f[1].params == (
        Part("REPRESENTATION_ITEM", ("a",)),
        Part("GEOMETRIC_REPRESENTATION_ITEM", ()),
        Part("POINT_X", (Ref(5),)),
    )
    part21.check_references(f)  # #5 is defined after its use: no error


def test_header_entities_are_kept_in_order():
    f = part21.read_file(str(EX1))
    assert [h[0] for h in f.header] == ["FILE_DESCRIPTION", "FILE_NAME", "FILE_SCHEMA"]
    assert f.header[2][1] == (("MACHINING_SCHEMA", "MILLING_SCHEMA"),)


def test_ex1_has_all_instances_with_line_numbers():
    f = part21.read_file(str(EX1))
    assert len(f) == 105
    assert f[22].name == "BOTTOM_AND_SIDE_ROUGH_MILLING" and len(f[22].params) == 16
    assert (f[22].line, f[22].column) == (78, 1)  # comments before DATA counted


def test_writer_round_trips_ex1():
    f = part21.read_file(str(EX1))
    g = part21.parse("".join(part21.write(f)))
    assert g.instances == f.instances and g.header == f.header


_scalar = st.one_of(
    st.integers(-(10**12), 10**12),
    st.floats(allow_nan=False, allow_infinity=False, width=64),
    st.text(st.characters(blacklist_categories=("Cs",)), max_size=12),
    st.sampled_from([Enum("T"), Enum("F"), Enum("CW"), None, DERIVED, Binary("2A")]),
    st.integers(1, 50).map(Ref),
)
_value = st.recursive(_scalar, lambda inner: st.lists(inner, max_size=4).map(tuple), max_leaves=12)


@settings(max_examples=150, deadline=None)
@given(
    st.lists(
        st.tuples(st.sampled_from(["A", "B_C", "POINT"]), st.lists(_value, max_size=6).map(tuple)),
        min_size=1,
        max_size=5,
    )
)
def test_parse_of_write_is_identity(entities):
    f = part21.Part21File(header=[("FILE_NAME", ("n",))])
    for i, (name, params) in enumerate(entities, 1):
        f.instances[i] = Instance(i, name, params, 0, 0)
    g = part21.parse("".join(part21.write(f)))
    assert list(g.instances.values()) == list(f.instances.values())


@pytest.mark.parametrize(
    ("data", "code", "line", "column"),
    [
        ("#1=A(1,2;", "P21-SYNTAX", 6, 9),
        ("#1=A(1);\n#1=B(2);", "P21-DUPLICATE-ID", 7, 1),
        ("#1=A('unterminated);", "P21-STRING", 6, 6),
        ("#1=A(1 2);", "P21-SYNTAX", 6, 8),
    ],
)
def test_strict_errors_name_line_column_and_entity(data, code, line, column):
    with pytest.raises(Diagnostic) as exc:
        part21.parse(wrap(data), "t.stp")
    d = exc.value
    assert (d.code, d.location.line, d.location.column) == (code, line, column)
    assert d.location.entity == 1 and d.location.file == "t.stp"


def test_dangling_reference_is_reported_with_its_referrer():
    f = part21.parse(wrap("#1=A(#7);\n#2=B(#7,#8);"), "t.stp")
    diags: list[Diagnostic] = []
    part21.check_references(f, diags)
    assert [(d.code, d.location.entity) for d in diags] == [
        ("P21-DANGLING-REF", 1),
        ("P21-DANGLING-REF", 2),
    ]
    assert "#7 is referenced (by #1, #2)" in diags[0].message
    with pytest.raises(Diagnostic, match="#7"):
        part21.check_references(f)


def test_missing_sections_are_errors():
    with pytest.raises(Diagnostic) as exc:
        part21.parse("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=A();\n")
    assert exc.value.code == "P21-EOF"
    with pytest.raises(Diagnostic) as exc:
        part21.parse("HEADER;")
    assert exc.value.code == "P21-MAGIC"


_garbage = st.text(alphabet="#=();,.$*'\"ABCT_ 0123456789-\n/\\EX", max_size=80)


@settings(max_examples=300, deadline=None)
@given(_garbage)
def test_collect_mode_never_raises_on_garbage(junk):
    diags: list[Diagnostic] = []
    part21.parse(wrap(junk), "g.stp", diags)  # salvage: defects become diagnostics only
    assert all(isinstance(d, Diagnostic) for d in diags)


@settings(max_examples=300, deadline=None)
@given(_garbage)
def test_strict_mode_raises_only_diagnostics(junk):
    try:
        part21.parse(wrap(junk), "g.stp")
    except Diagnostic as d:
        assert d.code.startswith("P21-") and d.location.line >= 6


@pytest.mark.parametrize(("data", "column"), [("DATA(1 2);", 35), ("DATA(1;", 34)])
def test_a_defect_in_the_data_sections_parameters_is_located_and_the_section_still_read(
    data: str, column: int
) -> None:
    """Collect mode gave an internal exception (a traceback) here."""
    text = f"ISO-10303-21;HEADER;ENDSEC;{data}\n#1=A(1);ENDSEC;END-ISO-10303-21;"
    diags: list[Diagnostic] = []
    f = part21.parse(text, "f.stp", diags)
    assert [(d.code, d.location.line, d.location.column) for d in diags] == [
        ("P21-SYNTAX", 1, column)  # the '2', the ';'
    ]
    assert list(f.instances) == [1]
    with pytest.raises(Diagnostic) as exc:
        part21.parse(text, "f.stp")
    assert exc.value.code == "P21-SYNTAX"
