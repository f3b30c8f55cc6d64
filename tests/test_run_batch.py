"""``cnc run``'s batch outputs (issue 18): ``index.html`` links every program's report,
``summary.json``'s totals are the sums of its rows, ``junit.xml`` validates against
Jenkins' schema, a program that failed shows its error and never a 0 cycle, progress is one
line per program without a terminal, and ``--resume`` gives the same outputs."""

from __future__ import annotations

import io
import json
from html.parser import HTMLParser
from pathlib import Path

import jsonschema
import pytest
import xmlschema
from click.testing import CliRunner
from rich.console import Console

from cli.batch import BatchProgress, print_summary, render_index, render_junit, summary_doc
from cli.main import cli
from cli.pipeline import RunResult

SCHEMAS = Path(__file__).parent / "schemas"
DOC_SCHEMAS = Path(__file__).resolve().parents[1] / "docs" / "schemas"


def _schema(name: str) -> dict:
    return json.loads((DOC_SCHEMAS / f"{name}.schema.json").read_text())


class _Index(HTMLParser):
    """Rows of index.html's table: the cells' text and the links of each row."""

    def __init__(self) -> None:
        super().__init__()
        self.rows: list[tuple[list[str], list[str]]] = []  # (cells, hrefs), body then foot
        self.scripts = 0
        self._cell: list[str] | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "tr":
            self.rows.append(([], []))
        elif tag in ("td", "th") and self.rows:
            self._cell = []
        elif tag == "a" and self.rows:
            self.rows[-1][1].append(dict(attrs)["href"] or "")
        elif tag == "script":
            self.scripts += 1

    def handle_data(self, data: str) -> None:
        if self._cell is not None:
            self._cell.append(data)

    def handle_endtag(self, tag: str) -> None:
        if tag in ("td", "th") and self._cell is not None:
            self.rows[-1][0].append("".join(self._cell))
            self._cell = None


def _programs(folder: Path) -> list[Path]:
    """Four short programs: clean, with a check error (no spindle), stopped by an
    interpreter error, and one that does not exist."""
    folder.mkdir()
    line = "STRAIGHT_FEED(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
    clean = folder / "clean.canon"
    clean.write_text(
        "USE_LENGTH_UNITS(CANON_UNITS_MM)\nSTART_SPINDLE_CLOCKWISE()\nSET_SPINDLE_SPEED(1000.0000)\n"
        f"SET_FEED_RATE(6000.0000)\n{line}PROGRAM_END()\n"
    )
    nospindle = folder / "nospindle.canon"
    nospindle.write_text(
        f"USE_LENGTH_UNITS(CANON_UNITS_MM)\nSET_FEED_RATE(6000.0000)\n{line}PROGRAM_END()\n"
    )
    broken = folder / "broken.ngc"
    broken.write_text("G21\nG1 X10 F100\nG2 X20 I3 J0\nM2\n")  # arc end off its circle
    return [clean, nospindle, broken, folder / "missing.ngc"]


@pytest.fixture(scope="module")
def batch(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[Path], str]:
    root = tmp_path_factory.mktemp("batch")
    progs = _programs(root / "progs")
    out = root / "out"
    res = CliRunner().invoke(cli, ["run", "-o", str(out), *map(str, progs)])
    assert res.exit_code == 2, res.output  # the missing file is an I/O error
    return out, progs, res.output


def test_index_links_every_program_with_a_report(batch: tuple[Path, list[Path], str]) -> None:
    out, progs, _ = batch
    page = _Index()
    page.feed((out / "index.html").read_text())
    head, *body, foot = page.rows
    assert head[0][:3] == ["program", "status", "cycle [m:s]"]
    assert [cells[0] for cells, _ in body] == [str(p) for p in progs]
    for (cells, links), prog in zip(body, progs, strict=True):
        if prog.exists():
            assert links == [f"{prog.stem}.report.json"] and (out / links[0]).is_file()
        else:
            assert links == [] and cells[1] == "io-error"
    assert foot[0][0].startswith("total: 4 programs") and foot[0][1] == "1 ok"
    assert page.scripts == 1  # the sorting script, inline


def test_failed_programs_show_their_error_not_a_zero_cycle(
    batch: tuple[Path, list[Path], str],
) -> None:
    out, _, output = batch
    page = _Index()
    page.feed((out / "index.html").read_text())
    cycles = {cells[0].rsplit("/", 1)[-1]: cells[2] for cells, _ in page.rows[1:-1]}
    assert cycles["broken.ngc"] == "NGC-ARC-RADIUS" or cycles["broken.ngc"].startswith("NGC-")
    assert cycles["missing.ngc"] == "IO-OPEN"
    assert ":" in cycles["clean.canon"] and cycles["clean.canon"] != "0:00.0"
    rows = {ln.split("│")[1].strip(): ln for ln in output.splitlines() if ln.count("│") > 3}
    assert "0:00" not in rows["broken.ngc"] and "IO-OPEN" in rows["missing.ngc"]
    assert "total" in rows  # the text table's total row
    summary = json.loads((out / "summary.json").read_text())
    by_name = {Path(p["program"]).name: p for p in summary["programs"]}
    assert by_name["broken.ngc"]["cycle_seconds"] is None
    assert "error[" in by_name["broken.ngc"]["error"]


def test_summary_totals_are_the_sums_of_the_rows(batch: tuple[Path, list[Path], str]) -> None:
    out, progs, _ = batch
    doc = json.loads((out / "summary.json").read_text())
    assert doc["schema"] == "cnc-run-summary" and doc["version"] == 1
    jsonschema.Draft202012Validator(_schema("run-summary-1")).validate(doc)
    report = json.loads((out / "clean.report.json").read_text())
    jsonschema.Draft202012Validator(_schema("run-report-1")).validate(report)
    assert report["times"]["tools"][0]["label"] == "(start)"  # no tool change in it
    rows, tot = doc["programs"], doc["totals"]
    assert [r["program"] for r in rows] == [str(p) for p in progs]
    assert tot["programs"] == len(rows) == 4
    known = [r["cycle_seconds"] for r in rows if r["cycle_seconds"] is not None]
    assert tot["cycle_seconds"] == pytest.approx(sum(known))
    for sev in ("error", "warning", "note"):
        assert tot["findings"][sev] == sum(r["findings"][sev] for r in rows)
    assert tot["status"] == {"ok": 1, "findings": 1, "error": 1, "io-error": 1}
    assert tot["seconds"] == pytest.approx(sum(r["seconds"] for r in rows))
    for stage, total in tot["stages"].items():
        assert total == pytest.approx(sum(r["stages"].get(stage, 0.0) for r in rows))


def test_junit_validates_with_a_case_per_program(batch: tuple[Path, list[Path], str]) -> None:
    out, progs, _ = batch
    schema = xmlschema.XMLSchema(str(SCHEMAS / "junit-10.xsd"))
    schema.validate(str(out / "junit.xml"))
    doc = schema.to_dict(str(out / "junit.xml"))
    suite = doc["testsuite"][0]
    cases = suite["testcase"]
    assert [c["@name"] for c in cases] == [str(p) for p in progs]
    assert (suite["@tests"], suite["@failures"], suite["@errors"]) == ("4", "2", "1")
    assert "failure" not in cases[0] and "failure" in cases[1] and "failure" in cases[2]
    assert "error" in cases[3]


def test_progress_is_one_line_per_program_without_a_terminal(
    batch: tuple[Path, list[Path], str],
) -> None:
    _, progs, output = batch
    lines = [ln for ln in output.splitlines() if ln.startswith("[")]
    assert [ln.split("]")[0] for ln in lines] == ["[1/4", "[2/4", "[3/4", "[4/4"]
    assert sorted(ln.rsplit("  ", 1)[-1] for ln in lines) == sorted(map(str, progs))


def test_resume_writes_the_same_batch_outputs(
    batch: tuple[Path, list[Path], str], tmp_path: Path
) -> None:
    out, progs, _ = batch
    first = json.loads((out / "summary.json").read_text())
    index = (out / "index.html").read_text()
    res = CliRunner().invoke(cli, ["-q", "run", "-o", str(out), "--resume", *map(str, progs)])
    assert res.exit_code == 2, res.output

    def steady(doc: dict) -> dict:  # what does not depend on the wall clock
        rows = [
            {k: v for k, v in r.items() if k not in ("seconds", "stages")} for r in doc["programs"]
        ]
        tot = {k: v for k, v in doc["totals"].items() if k not in ("seconds", "stages")}
        return {"programs": rows, "totals": tot}

    again = json.loads((out / "summary.json").read_text())
    assert steady(again) == steady(first)
    strip = [ln for ln in index.splitlines() if "wall time" not in ln]
    assert [
        ln for ln in (out / "index.html").read_text().splitlines() if "wall time" not in ln
    ] == strip


def test_an_existing_index_is_kept_without_force(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "index.html").write_text("keep me")
    prog = _programs(tmp_path / "p")[2]
    res = CliRunner().invoke(cli, ["run", "-o", str(out), str(prog)])
    assert res.exit_code == 2 and "IO-EXISTS" in res.output
    assert (out / "index.html").read_text() == "keep me"


def _result(name: str, status: str, cycle: float, message: str = "") -> RunResult:
    r = RunResult(f"/p/{name}", status=status, cycle_time=cycle, message=message)
    r.measured = status in ("ok", "findings")
    r.report = ""
    return r


def test_renderers_on_results_alone() -> None:
    """The batch files from results without any report on disk: no links, the total
    cycle in m:ss, and the progress line of a failed program naming its code."""
    results = [
        _result("a.ngc", "ok", 2037.6),
        _result("b.ngc", "error", 0.0, "/p/b.ngc:3:1: error[NGC-ARC-RADIUS]: arc radius"),
    ]
    page = render_index(results, "mill", 1.0, False)
    assert "<a " not in page and "33:58" in page and "NGC-ARC-RADIUS" in page
    doc = summary_doc(results, "mill", 1.0, False)
    assert doc["totals"]["cycle_hms"] == "33:58" and doc["programs"][1]["cycle_hms"] is None
    assert 'failures="1"' in render_junit(results, 1.0)
    buf = io.StringIO()
    with BatchProgress(2, Console(file=buf, width=200), quiet=False) as progress:
        for r in results:
            progress.finished(r)
    assert buf.getvalue().splitlines() == [
        "[1/2] ok           33:58  /p/a.ngc",
        "[2/2] error    NGC-ARC-RADIUS  /p/b.ngc",
    ]
    text = io.StringIO()
    print_summary(results, Console(file=text, width=200), 1.0)
    assert "-0.0" not in text.getvalue() and "33:58" in text.getvalue()
