"""The compiled Part 21 scanner (stepnc/p21_scan.py, stepnc/p21_kernels.py) reads exactly as
the pure-Python reader does.

Reference: the pure-Python reader (``part21.SCAN_MIN_CHARS = None``), whose values, located
diagnostics and salvage are fixed by test_stepnc_part21.py and the real-file suites. Each
text here is read both ways, in strict and in collect mode, and everything the reader
returns is compared: instances in order with their values' types, lines and columns,
header, salvaged ids, the diagnostics (code, message, location) or the one raised. Also:
the AOT and JIT builds of the scanner fill identical arrays, and without kernels the reader
falls back to the pure-Python path.
"""

from __future__ import annotations

import os
import random
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from kernel import aot
from kernel.aot import cache_dir
from kernel.diagnostics import Diagnostic
from stepnc import p21_scan, part21
from stepnc.p21_values import Instance

ROOT = Path(__file__).resolve().parent
FILES = sorted({*ROOT.glob("stepnc/**/*.stp"), *ROOT.glob("data/corpus/stepnc/*.stp")})

HEAD = (
    "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n"
    "FILE_SCHEMA(('MACHINING_SCHEMA'));\nENDSEC;\nDATA;\n"
)
TAIL = "ENDSEC;\nEND-ISO-10303-21;\n"
#: instances the scanner takes and ones it leaves to the Python reader, side by side
MIX = (
    "#1=CARTESIAN_POINT('P1',(1.5,-2.,+3.E-2));\n"
    "/* a comment */ #2 = direction ( '' , ( 0. , 0. , 1. ) ) ;\n"
    "#3=AXIS2_PLACEMENT_3D('it''s',#1,#2,$);#4=A((),(()),((1,2),(3,(4,5))),*,.T.,.unset.);\n"
    "#5=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(2.0),#6);\n"
    "#6=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n"
    "#7=TEXT('a\\X2\\00E9\\X0\\ b, (c)');#8=BIN(\"0FF\");\n"
    "#9=B('multi\nline',(1,\n2),\n 3);\n"
    "#10=C(1,2/*inside*/);#11=D(1.5.3);#12=E(0010,007.50,-0.,1.E5,1.e-0);\n"
    "#123456789012=F(1);#13=G('x' );#14=H(#1 ,#2);\n"
    "#15=I((((((1))))));#16=J(1e5);#17=K(.A.B.);#18=L($1);\n"
)


def snapshot(text: str, collect: bool, scan: int | None, monkeypatch: pytest.MonkeyPatch) -> object:
    """Everything the reader gives for ``text`` with the scanner on (0) or off (None)."""
    monkeypatch.setattr(part21, "SCAN_MIN_CHARS", scan)
    diags: list[Diagnostic] | None = [] if collect else None
    try:
        f = part21.parse(text, "t.stp", diags)
    except Diagnostic as exc:
        return ("raised", exc.code, str(exc), exc.location)
    if scan is not None and len(f.instances):
        assert isinstance(f.instances, p21_scan.Instances)
    return (
        [
            (i.id, i.name, i.params, i.line, i.column, [type(v) for v in i.params])
            for i in f.instances.values()
        ],
        list(f.instances),
        f.header,
        sorted(f.salvaged),
        [(d.code, str(d), d.location) for d in diags or []],
    )


def same_both_ways(text: str, monkeypatch: pytest.MonkeyPatch) -> None:
    for collect in (False, True):
        scanned = snapshot(text, collect, 0, monkeypatch)
        assert scanned == snapshot(text, collect, None, monkeypatch), collect


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_every_corpus_file_reads_the_same_scanned(
    path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    same_both_ways(path.read_text(encoding="latin-1"), monkeypatch)


@pytest.mark.parametrize(
    "body",
    [
        MIX,
        MIX + MIX.replace("#", "#1"),  # more ids, some defined twice
        MIX + "#3=DUP(1);\n",  # a duplicate of a scanned instance
        "#1=A(1,,2);\n#2=B(x);\n#3=C(1);\n",  # salvage
        "#1=A(1,\n#2=B(2);\n#3=C(3);\n",  # unterminated
        "#1=A('never closed);\n#2=B(2);\n",
        "#1=A(1);\n#2=B(2)\n",  # no ';' and no ENDSEC
        # runs the scanner leaves (typed parameters, ids beyond its table) between its own
        "".join(f"#{i}=X(LENGTH({i}.5));\n#{i + 10**12}=P({i});\n" for i in range(1, 90))
        + "".join(f"#{i + 500}=Q({i}, #{i});\n" for i in range(1, 90))
        + "#7=DUP(7);\n",
    ],
)
def test_scanned_and_python_instances_mix_in_file_order(
    body: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    same_both_ways(HEAD + body + TAIL, monkeypatch)
    same_both_ways((HEAD + body + TAIL).replace("\n", "\r\n"), monkeypatch)


def test_mutated_files_read_the_same_scanned(monkeypatch: pytest.MonkeyPatch) -> None:
    """Random edits of a mixed file: every defect the Python reader reports, it reports
    at the same place with the scanner on."""
    rnd = random.Random(20)
    pieces = [*"#=(),;'$*.\n /\\\"09eE+-AZ_", "''", "/*", "*/", "#1", "\xa0", "(((", "#9" * 12]
    base = HEAD + MIX * 2 + TAIL
    for _ in range(40):
        text = list(base)
        for _ in range(rnd.randint(1, 3)):
            at = rnd.randrange(len(HEAD) - 6, len(text))
            op = rnd.random()
            if op < 0.4:
                text.insert(at, rnd.choice(pieces))
            elif op < 0.7:
                del text[at]
            else:
                text[at] = rnd.choice(pieces)
        same_both_ways("".join(text), monkeypatch)


def test_a_large_file_is_scanned_lazily_and_decodes_as_the_python_reader(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    rows = "".join(
        f"#{i}=CARTESIAN_POINT('P{i}',({i}.5,-{i}.25,0.));\n#{i + 1}=DIRECTION('',(0.,0.,1.));\n"
        for i in range(1, 8000, 2)
    )
    assert part21.SCAN_MIN_CHARS is not None
    assert len(HEAD + rows + TAIL) >= part21.SCAN_MIN_CHARS
    f = part21.parse(HEAD + rows + TAIL)
    assert isinstance(f.instances, p21_scan.Instances)
    assert f.instances._cache is None  # nothing decoded yet
    assert f[8000].params == ("", (0.0, 0.0, 1.0))
    assert (f[7999].name, f[7999].line, f[7999].column) == ("CARTESIAN_POINT", 7 + 7999, 1)
    same_both_ways(HEAD + rows + MIX.replace("#", "#9000") + TAIL, monkeypatch)


def test_the_table_behaves_as_a_dict(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(part21, "SCAN_MIN_CHARS", 0)
    text = HEAD + "#1=A(1);#2=B(2);#5=C('x');#3=D(3);\n" + TAIL
    f = part21.parse(text)
    table = f.instances
    assert isinstance(table, p21_scan.Instances)
    ref = dict(table.items())
    assert list(ref) == [1, 2, 5, 3] and table == ref
    new = Instance(2, "E", (), 9, 9)
    for m in (table, ref):
        m[2] = new  # replaced in place
        m[7] = Instance(7, "F", (), 9, 9)  # added at the end
        del m[5]
        assert 5 not in m and 2 in m and "x" not in m
    assert list(table) == list(ref) == [1, 2, 3, 7]
    assert list(table.values()) == list(ref.values()) and len(table) == len(ref) == 4
    assert table[2] is new and table.get(5) is None
    with pytest.raises(KeyError):
        table[5]


@pytest.mark.slow  # numba's JIT compile: several seconds
def test_aot_and_jit_scanners_fill_identical_arrays(monkeypatch: pytest.MonkeyPatch) -> None:
    aot = p21_scan.KERNELS.load_aot(cache_dir())
    if aot is None:
        pytest.skip("no AOT build of the Part 21 kernels (no C compiler)")
    jit = p21_scan.KERNELS.load_jit()
    text = HEAD + "".join(MIX.replace("#", f"#{k}") for k in range(1, 40)) + TAIL
    monkeypatch.setattr(part21, "SCAN_MIN_CHARS", 0)

    def run(module: ModuleType) -> list[list[int]]:
        monkeypatch.setattr(p21_scan.KERNELS, "_loaded", module)
        table = part21.parse(text, "t.stp", []).instances
        assert isinstance(table, p21_scan.Instances)
        rows = table._rows
        arrays = (table._ids, table._names, table._body_s, table._body_e, table._lines)
        return [[rows], *(a[:rows].tolist() for a in (*arrays, table._cols))]

    got = run(aot)
    assert got[0][0] > 50  # the scanner took rows between the Python reader's
    assert got == run(jit)


def test_without_kernels_the_python_reader_reads_everything(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def no_numba() -> ModuleType:
        raise ImportError("No module named 'numba'")

    monkeypatch.setattr(p21_scan.KERNELS, "_loaded", None)
    monkeypatch.setattr(p21_scan.KERNELS, "load_jit", no_numba)
    monkeypatch.setenv("CNC_P21_JIT", "1")
    monkeypatch.setattr(part21, "SCAN_MIN_CHARS", 0)
    f = part21.parse(HEAD + "#1=A(1);\n#2=B('x',(#1));\n" + TAIL)
    assert type(f.instances) is dict and f[2].params == ("x", (1,))


@pytest.mark.parametrize("shift", [-103, -101, -60, -1, 0, 1])
def test_a_long_number_across_the_digit_checks_pieces_is_found_whole(shift: int) -> None:
    """LIMIT-DIGITS (100 digits by default) is searched in 1 MiB pieces that overlap."""
    at = (1 << 20) + shift
    head = "ISO-10303-21;HEADER;ENDSEC;DATA;"
    text = head + " " * (at - len(head) - 5) + "#1=A(" + "1" * 101 + ");ENDSEC;END-ISO-10303-21;"
    with pytest.raises(Diagnostic) as exc:
        part21.parse(text)
    assert (exc.value.code, exc.value.location.line, exc.value.location.column) == (
        "LIMIT-DIGITS",
        1,
        at + 1,
    )


@pytest.mark.slow  # imports numba
def test_a_failed_build_falls_back_to_jit_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls = []

    def no_compiler(directory: Path, name: str) -> tuple[bool, str]:
        calls.append(name)
        return False, "error: command 'gcc' failed: No such file or directory"

    kernels = p21_scan.KERNELS
    monkeypatch.setattr(kernels, "build_aot", no_compiler)
    monkeypatch.setattr(aot, "cache_dir", lambda: tmp_path)
    monkeypatch.delenv("CNC_P21_JIT", raising=False)
    monkeypatch.setattr(kernels, "_loaded", None)
    assert kernels.mode() == "jit"
    assert kernels.module() is kernels.load_jit()
    assert (tmp_path / (kernels.aot_name() + ".failed")).read_text().startswith("error:")
    assert kernels.load_aot(tmp_path) is None  # remembered: no second build attempt
    assert len(calls) == 1


@pytest.mark.slow  # an interpreter
def test_loading_the_aot_module_imports_no_numba(tmp_path: Path) -> None:
    if p21_scan.KERNELS.load_aot(cache_dir()) is None:
        pytest.skip("no AOT build of the Part 21 kernels (no C compiler)")
    probe = (
        "import sys; from stepnc.p21_scan import KERNELS; "
        "print(KERNELS.module().__name__, 'numba' in sys.modules)"
    )
    env = dict(os.environ, CNC_CACHE_DIR=str(cache_dir()))
    env.pop("CNC_P21_JIT", None)
    out = subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.split() == [p21_scan.KERNELS.aot_name(), "False"]
