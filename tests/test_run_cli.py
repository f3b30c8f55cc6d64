"""``cnc run``: the whole pipeline per program, a report each, a batch that survives failures."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import jsonschema
import pytest
from click.testing import CliRunner

from cli.main import cli

PROGS = Path(__file__).parent / "check"
SHOP = str(PROGS / "shop.toml")
SCHEMA = Path(__file__).resolve().parents[1] / "docs" / "schemas" / "run-report-1.schema.json"


def run(*args: str):
    return CliRunner().invoke(cli, ["run", *args], catch_exceptions=False)


def test_batch_with_a_corrupt_file_reports_it_and_completes_the_others(tmp_path: Path) -> None:
    good = tmp_path / "good.canon"
    shutil.copy(PROGS / "clean.canon", good)
    bad = tmp_path / "bad.ngc"
    bad.write_text("G21\nG1 X10 F100\nG2 X20 I3 J0\nM2\n")  # arc end off its circle
    out = tmp_path / "reports"
    res = run("-m", SHOP, "-o", str(out), str(good), str(bad))
    assert res.exit_code == 1
    assert "good.canon" in res.output and "bad.ngc" in res.output
    assert "1 ok, 1 with problems" in res.output
    good_doc = json.loads((out / "good.report.json").read_text())
    bad_doc = json.loads((out / "bad.report.json").read_text())
    assert good_doc["schema"] == "cnc-run-report" and good_doc["status"] == "ok"
    assert good_doc["measure"]["cycle"]["total"] > 0
    assert set(good_doc["servo"]) == {"following_error", "contour_error"}
    assert bad_doc["status"] == "error"
    schema = json.loads((SCHEMA).read_text())
    for doc in (good_doc, bad_doc):
        jsonschema.Draft202012Validator(schema).validate(doc)
    assert bad_doc["findings"][-1]["rule"] == "CNC001"
    assert bad_doc["findings"][-1]["line"] == 3


def test_cycle_time_of_a_known_move_matches_the_planner(tmp_path: Path) -> None:
    """One 100 mm feed at 600 mm/min is at least 10 s long (plus acceleration)."""
    prog = tmp_path / "line.canon"
    prog.write_text(
        "USE_LENGTH_UNITS(CANON_UNITS_MM)\nSET_FEED_RATE(600.0000)\n"
        "STRAIGHT_FEED(100.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\nPROGRAM_END()\n"
    )
    res = run("-o", str(tmp_path), str(prog))
    doc = json.loads((tmp_path / "line.report.json").read_text())
    total = doc["measure"]["cycle"]["total"]
    assert 10.0 <= total < 10.5, res.output


def test_parallel_run_writes_the_same_reports(tmp_path: Path) -> None:
    files = [str(PROGS / n) for n in ("clean.canon", "CNC504.canon", "CNC001.canon")]
    a, b = tmp_path / "a", tmp_path / "b"
    assert run("-m", SHOP, "-o", str(a), *files).exit_code == 1
    assert run("-m", SHOP, "-o", str(b), "-j", "2", *files).exit_code == 1
    for name in ("clean", "CNC504", "CNC001"):
        da = json.loads((a / f"{name}.report.json").read_text())
        db = json.loads((b / f"{name}.report.json").read_text())
        da.pop("seconds"), db.pop("seconds")
        assert da == db


def test_traces_on_request(tmp_path: Path) -> None:
    res = run("-m", SHOP, "-o", str(tmp_path), "--traces", "csv", str(PROGS / "clean.canon"))
    assert res.exit_code == 0
    header = (tmp_path / "clean_trace.csv").open().readline()
    assert header.startswith("t,segment,source_line") and "x_following_error" in header


class _Tags(HTMLParser):
    """Checks nesting of non-void elements and collects attribute URLs."""

    VOID = {"meta", "img", "br", "hr", "link", "input"}

    def __init__(self) -> None:
        super().__init__()
        self.stack: list[str] = []
        self.urls: list[str] = []
        self.errors: list[str] = []

    def handle_starttag(self, tag: str, attrs: list) -> None:
        self.urls += [v for k, v in attrs if k in ("src", "href") and v]
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag: str) -> None:
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(tag)


def test_html_report_is_self_contained_and_well_formed(tmp_path: Path) -> None:
    files = [str(PROGS / "clean.canon"), str(PROGS / "CNC001.canon")]
    res = run("-m", SHOP, "--html", "-o", str(tmp_path), *files)
    assert res.exit_code == 1
    for name, plots in (("clean", 4), ("CNC001", 0)):
        page = (tmp_path / f"{name}.report.html").read_text()
        p = _Tags()
        p.feed(page)
        assert p.errors == [] and p.stack == []
        images = [u for u in p.urls if u != "plotly.min.js"]
        assert images == []  # the trace charts are data the page's plotly.js draws
        charts = re.search(r'<script type="application/json" id="cnc-charts">(.*?)</script>', page)
        specs = json.loads(charts.group(1)) if charts else []
        assert len(specs) == plots  # XY path + one per axis for the simulated program
        assert [c["kind"] for c in specs] == ["xy", "axis", "axis", "axis"][:plots]
        # scripts: inline, or the batch's one plotly.js beside the pages; nothing fetched
        assert p.urls.count("plotly.min.js") == 1 and (tmp_path / "plotly.min.js").is_file()
        assert "http://" not in "".join(p.urls) and "https://" not in "".join(p.urls)
    clean = (tmp_path / "clean.report.html").read_text()
    assert "Cycle time" in clean and "No findings." in clean
    assert "CNC001/CANON-SYNTAX" in (tmp_path / "CNC001.report.html").read_text()


def test_html_report_opens_in_headless_chromium(tmp_path: Path) -> None:
    browser = next(
        (
            shutil.which(b)
            for b in ("chromium", "chromium-browser", "google-chrome")
            if shutil.which(b)
        ),
        None,
    )
    if browser is None:
        pytest.skip("no Chromium on this machine")
    run("-m", SHOP, "--html", "-o", str(tmp_path), str(PROGS / "clean.canon"))
    page = tmp_path / "clean.report.html"
    out = subprocess.run(
        [browser, "--headless", "--disable-gpu", "--no-sandbox", "--dump-dom", page.as_uri()],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert "Cycle time" in out.stdout and "data:image/png;base64," in out.stdout


@pytest.mark.slow
def test_hundred_programs_in_parallel_give_a_hundred_reports_and_a_summary(tmp_path: Path) -> None:
    progs = tmp_path / "progs"
    progs.mkdir()
    for i in range(100):
        src = PROGS / ("CNC001.canon" if i == 37 else "clean.canon")  # one broken program
        shutil.copy(src, progs / f"p{i:03d}.canon")
    out = tmp_path / "out"
    res = run("-m", SHOP, "-j", "2", "-o", str(out), str(progs))
    assert res.exit_code == 1
    assert "99 ok, 1 with problems" in res.output
    docs = [json.loads(p.read_text()) for p in sorted(out.glob("*.report.json"))]
    assert len(docs) == 100
    assert [d["status"] for d in docs].count("ok") == 99


def test_programs_with_the_same_name_keep_separate_reports(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    shutil.copy(PROGS / "clean.canon", a / "part.canon")
    shutil.copy(PROGS / "CNC504.canon", b / "part.canon")
    out = tmp_path / "out"
    run("-m", SHOP, "-o", str(out), str(a / "part.canon"), str(b / "part.canon"))
    first = json.loads((out / "part.report.json").read_text())
    second = json.loads((out / "part_2.report.json").read_text())
    assert first["program"].endswith("a/part.canon") and first["status"] == "ok"
    assert second["program"].endswith("b/part.canon") and second["status"] == "findings"
