"""``--scheduler``: programs as tasks on a Dask cluster (issue 21).

The cluster path must give exactly what the local pool gives (one task function), keep one
row per program through time limits, corrupt files and a worker killed mid-batch, and
``--resume`` must skip only results newer than the program and the profile. Dask is an
optional extra (``cluster``); without it these tests skip.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import signal
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.check import Setup, check_file, load_context, run_checks
from cli.deadline import ProgramTimeout, deadline
from cli.inline import InlineProgram
from cli.main import cli
from cli.stream_out import LOG_PROGRESS_FROM, LineProgress, progress_wanted

HERE = Path(__file__).parent
PROGS = HERE / "check"
SHOP = str(PROGS / "shop.toml")
REAL = HERE / "realworld" / "ngc"

# 10^8 blocks of zig-zag moves: moves, and no loop goes round more than loop_passes
# (100,000) times in a row, so the loop guard lets it run; far past any time limit
HANG = (
    "G21 G90 F1000\n#2=0\nO200 while [#2 LT 1000]\n#1=0\nO100 while [#1 LT 99999]\n"
    "G1 X[#1 MOD 2]\n#1=[#1+1]\nO100 endwhile\n#2=[#2+1]\nO200 endwhile\nM2\n"
)


def cnc(*args: str) -> tuple[int, str]:
    res = CliRunner().invoke(cli, list(args), catch_exceptions=False)
    return res.exit_code, res.output


def programs() -> list[str]:
    """The rule test programs and the smallest real-world programs: a mixed batch."""
    real = sorted(REAL.glob("*.ngc"), key=lambda p: p.stat().st_size)[:12]
    return [str(p) for p in sorted(PROGS.glob("*.ngc"))] + [str(p) for p in real]


def without_times(report: str) -> dict[str, object]:
    """A JSON check report without its timings (the only thing that may differ)."""
    doc = json.loads(report)
    doc.pop("seconds", None)
    doc.get("summary", {}).pop("seconds", None)
    for f in doc["files"]:
        f.pop("seconds", None)
    return doc


@pytest.fixture(scope="module")
def cluster() -> Iterator[str]:
    """One LocalCluster (2 worker processes of 1 thread) for the module: its tcp address,
    which also exercises ``--scheduler ADDRESS`` of a cluster started elsewhere."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as lc:
        yield lc.scheduler_address


def test_deadline_stops_a_busy_loop_that_swallows_exceptions() -> None:
    t0 = time.perf_counter()
    with pytest.raises(ProgramTimeout), deadline(0.2):
        while True:
            with contextlib.suppress(Exception):  # what a careless handler would do
                sum(range(100))
    assert time.perf_counter() - t0 < 5
    with deadline(0.05):  # a block that ends in time: nothing raised, later or now
        pass
    time.sleep(0.2)


def test_deadline_raises_again_when_the_first_timeout_is_lost() -> None:
    """A timeout dropped once (Python drops an exception raised while a generator is
    being finalised) does not let the program run on: it is raised again."""
    lost = 0
    t0 = time.perf_counter()
    with pytest.raises(ProgramTimeout), deadline(0.1):
        while True:
            try:
                sum(range(100))
            except ProgramTimeout:
                if lost:
                    raise
                lost += 1
    assert lost == 1 and time.perf_counter() - t0 < 5
    time.sleep(0.7)  # no late re-raise once the block has ended


def test_parse_local_address() -> None:
    pytest.importorskip("distributed")
    from cli.fleet import parse_local

    assert parse_local("local:3") == 3
    assert parse_local("tcp://10.0.0.1:8786") is None
    code, out = cnc("check", "--scheduler", "local:0", str(PROGS / "CNC010.ngc"))
    assert code == 2 and "local:N" in out


def test_cluster_results_identical_to_local_pool(cluster: str) -> None:
    paths = programs()
    code_j, pool = cnc("check", "-m", SHOP, "-f", "json", "-j", "2", *paths)
    code_s, dask = cnc("check", "-m", SHOP, "-f", "json", "--scheduler", cluster, *paths)
    assert code_j == code_s
    a, b = without_times(pool), without_times(dask)
    assert [f["file"] for f in b["files"]] == paths  # input order, each program once
    assert a == b
    assert any(f["findings"] for f in a["files"])  # the batch has findings to compare


@pytest.mark.slow
def test_time_limit_and_corrupt_file_are_one_row_each(cluster: str, tmp_path: Path) -> None:
    hang = tmp_path / "hang.ngc"
    hang.write_text(HANG)
    corrupt = tmp_path / "corrupt.ngc"
    corrupt.write_bytes(bytes(range(256)) * 8)
    good = str(PROGS / "clean.canon")
    args = ["check", "-f", "json", "--timeout", "4", str(hang), str(corrupt), good]
    code, out = cnc(*args, "--scheduler", cluster)
    doc = json.loads(out)
    rows = {Path(f["file"]).name: f for f in doc["files"]}
    assert list(rows) == ["hang.ngc", "corrupt.ngc", "clean.canon"] and code == 1
    [late] = rows["hang.ngc"]["findings"]
    assert late["code"] == "CHECK-TIMEOUT" and late["rule"] == "CNC001"
    assert [f["code"] for f in rows["corrupt.ngc"]["findings"]] == ["CHECK-BINARY"]
    assert all(f["code"] != "CHECK-TIMEOUT" for f in rows["clean.canon"]["findings"])
    # the local pool records the same rows
    code_j, out_j = cnc(*args, "-j", "2")
    assert without_times(out_j) == without_times(out)


def test_resume_skips_only_fresh_results(tmp_path: Path) -> None:
    a, b = tmp_path / "a.ngc", tmp_path / "b.ngc"
    a.write_text((PROGS / "CNC010.ngc").read_text())
    b.write_text((PROGS / "CNC001.ngc").read_text())
    profile = tmp_path / "shop.toml"
    profile.write_text(Path(SHOP).read_text())
    (tmp_path / "shop.tbl").write_text((PROGS / "shop.tbl").read_text())
    res = tmp_path / "results"
    base = ["check", "-m", str(profile), "-f", "json", "--results", str(res)]
    code, first = cnc(*base, str(a), str(b))
    assert code == 1, first
    stored = sorted(res.glob("*.json"))
    assert [p.name.split("-")[0] for p in stored] == ["a", "b"]

    def mark(stem: str) -> None:
        """Replace a stored result by a recognisable one, dated in the future."""
        [p] = res.glob(f"{stem}-*.json")
        doc = json.loads(p.read_text())
        doc["findings"] = [
            {"rule": "CNC999", "code": None, "severity": "note", "message": "from store"}
        ]
        p.write_text(json.dumps(doc))
        os.utime(p, (time.time() + 100, time.time() + 100))

    mark("a")
    mark("b")
    code, out = cnc(*base, "--resume", str(a), str(b))
    rules = {
        Path(f["file"]).name: [x["rule"] for x in f["findings"]] for f in json.loads(out)["files"]
    }
    assert rules == {"a.ngc": ["CNC999"], "b.ngc": ["CNC999"]}  # both resumed
    os.utime(b, (time.time() + 200, time.time() + 200))  # b edited after its result
    code, out = cnc(*base, "--resume", str(a), str(b))
    rules = {
        Path(f["file"]).name: [x["rule"] for x in f["findings"]] for f in json.loads(out)["files"]
    }
    assert rules["a.ngc"] == ["CNC999"] and rules["b.ngc"] != ["CNC999"]
    os.utime(profile, (time.time() + 300, time.time() + 300))  # the profile changed: all stale
    code, out = cnc(*base, "--resume", str(a), str(b))
    assert without_times(out) == without_times(first)
    code, out = cnc("check", "--resume", str(a))
    assert code == 2 and "--results" in out


def test_run_resume_and_cluster_reports(cluster: str, tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text((PROGS / "CNC001.ngc").read_text())  # stops early: a fast report
    out_dir = tmp_path / "out"
    code, out = cnc("run", "-o", str(out_dir), "--scheduler", cluster, str(prog))
    report = out_dir / "p.report.json"
    doc = json.loads(report.read_text())
    assert doc["status"] == "error" and "NGC-ARC-RADIUS" in out
    os.utime(report, (time.time() + 100, time.time() + 100))
    doc["status"] = "findings"  # what the resumed summary must show: the stored report
    report.write_text(json.dumps(doc))
    os.utime(report, (time.time() + 100, time.time() + 100))
    code, out = cnc("run", "-o", str(out_dir), "--resume", str(prog))
    assert "findings" in out and "NGC-ARC-RADIUS" in out


def _generated(tmp_path: Path, n: int, lines: int) -> list[str]:
    out = []
    for k in range(n):
        p = tmp_path / f"gen{k:03d}.ngc"
        body = "".join(f"G1 X{(i * 7 + k) % 100} Y{(i * 13) % 90} F1000\n" for i in range(lines))
        p.write_text(f"G21 G90 G17\nT1 M6\nS1000 M3\n{body}M5\nM2\n")
        out.append(str(p))
    return out


@pytest.mark.slow
def _diagnostics_settings() -> tuple[object, ...]:
    import dask

    return (
        dask.config.get("distributed.worker.profile.enabled"),
        dask.config.get("distributed.admin.tick.interval"),
    )


def test_worker_killed_mid_batch_loses_nothing(tmp_path: Path) -> None:
    """On ``local:2`` as ``--scheduler`` starts it; its workers (separate processes) also
    got the cluster's settings: Dask's 10 ms stack sampler off, the tick slowed."""
    pytest.importorskip("distributed")
    from cli import fleet
    from cli.check import _lost

    paths = _generated(tmp_path, 16, 400)
    setup = Setup(load_context(SHOP, None, None), verbosity=-1)
    expected = [check_file(p, setup) for p in paths]
    with fleet.connect("local:2") as client:
        assert set(client.run(_diagnostics_settings).values()) == {(False, "500ms")}
        pids = list(client.run(os.getpid).values())
        seen: list[int] = []
        got = {}
        for i, res in fleet.map_stream(client, check_file, paths, setup, _lost):
            if not seen:
                os.kill(pids[0], signal.SIGKILL)  # a worker dies with tasks in flight
            seen.append(i)
            got[i] = res
        assert pids[0] not in client.run(os.getpid).values()  # the kill took effect
    assert sorted(seen) == list(range(len(paths)))  # each program exactly once
    assert [got[i].findings for i in range(len(paths))] == [r.findings for r in expected]


@pytest.mark.slow
def test_cli_local_cluster_matches_jobs() -> None:
    paths = programs()
    _, pool = cnc("check", "-m", SHOP, "-f", "json", "-j", "2", *paths)
    _, dask = cnc("check", "-m", SHOP, "-f", "json", "--scheduler", "local:2", *paths)
    assert without_times(pool) == without_times(dask)
    assert run_checks(paths[:3], Setup(load_context(SHOP, None, None), verbosity=-1), 1)


def test_batch_sizer_grows_to_the_target_and_shrinks_on_long_programs() -> None:
    pytest.importorskip("distributed")
    from cli.fleet import MAX_BATCH, TARGET_SECONDS, Sizer

    sizer = Sizer()
    assert sizer.size == 1  # the first task is one program: nothing is known yet
    sizes = []
    for _ in range(12):  # 1 ms programs: double each step up to the cap
        sizer.learn(sizer.size, sizer.size * 0.001)
        sizes.append(sizer.size)
    assert sizes[:4] == [2, 4, 8, 16] and sizes[-1] == min(MAX_BATCH, int(TARGET_SECONDS / 0.001))
    for _ in range(20):  # programs of 2 s each: one a task
        sizer.learn(sizer.size, sizer.size * 2.0)
    assert sizer.size == 1


def test_progress_is_a_line_per_n_programs_in_a_log() -> None:
    out = io.StringIO()
    progress = LineProgress(5, stream=out, every=2)
    for _ in range(5):
        progress.advance()
    progress.close()
    lines = out.getvalue().splitlines()
    assert [line.split(" ")[0] for line in lines] == ["2/5", "4/5", "5/5"]
    assert lines[-1].startswith("5/5 programs (100 %), ")
    assert not progress_wanted(5, 0, tty=False)  # a small batch in a script: quiet
    assert progress_wanted(5, 0, tty=True) and progress_wanted(5, 1, tty=False)
    assert progress_wanted(LOG_PROGRESS_FROM, 0, tty=False)
    assert not progress_wanted(LOG_PROGRESS_FROM, -1, tty=True)
    # the command: stderr is not a terminal here, -v asks for the lines
    paths = [str(PROGS / "CNC010.ngc"), str(PROGS / "clean.canon")]
    code, text = cnc("-v", "check", "-m", SHOP, *paths)
    assert "2/2 programs (100 %)" in text


def test_inline_program_gives_the_result_of_its_file(tmp_path: Path) -> None:
    setup = Setup(load_context(SHOP, None, None), verbosity=-1)
    src = PROGS / "CNC010.ngc"
    copy = tmp_path / "CNC010.ngc"
    copy.write_bytes(src.read_bytes())
    want = check_file(str(copy), setup)
    got = check_file(InlineProgram(str(copy), src.read_bytes()), setup)
    assert want.findings and got.findings == want.findings and got.file == want.file
    corrupt = check_file(InlineProgram("lib/bad.ngc", bytes(range(256)) * 4), setup)
    assert [(f.code, f.location.file) for f in corrupt.findings] == [
        ("CHECK-BINARY", "lib/bad.ngc")
    ]


def table_rows(path: Path) -> list[dict[str, object]]:
    """The rows of a ``--table`` file without the timings, by program (rows are written in
    the order results arrive)."""
    pq = pytest.importorskip("pyarrow.parquet")
    rows = pq.read_table(path).to_pylist()
    for r in rows:
        r.pop("seconds")
    return sorted(rows, key=lambda r: str(r["program"]))


def test_parquet_table_same_for_pool_and_cluster(cluster: str, tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    corrupt = tmp_path / "corrupt.ngc"
    corrupt.write_bytes(bytes(range(256)) * 8)
    paths = [str(PROGS / "CNC010.ngc"), str(PROGS / "CNC001.ngc"), str(corrupt)]
    paths.append(str(PROGS / "clean.canon"))
    a, b = tmp_path / "pool.parquet", tmp_path / "dask.parquet"
    code, out = cnc("check", "-m", SHOP, "-f", "json", "--table", str(a), *paths)
    cnc("check", "-m", SHOP, "-f", "json", "--scheduler", cluster, "--table", str(b), *paths)
    rows = table_rows(a)
    assert rows == table_rows(b)
    assert [r["program"] for r in rows] == sorted(paths)  # one row per program
    report = {f["file"]: f for f in json.loads(out)["files"]}
    for r in rows:  # the table says what the JSON report says
        f = report[r["program"]]
        assert r["rules"] == [x["rule"] for x in f["findings"]]
        assert r["errors"] == sum(x["severity"] == "error" for x in f["findings"])
    by_name = {Path(str(r["program"])).name: r for r in rows}
    assert by_name["corrupt.ngc"]["status"] == "error"
    assert by_name["clean.canon"]["status"] == "ok" and by_name["clean.canon"]["findings"] == []
    code, out = cnc("check", "--table", str(a), *paths)  # an existing table is kept
    assert code == 2 and "IO-EXISTS" in out


def test_generated_library_streams_as_bytes_through_the_cluster(cluster: str) -> None:
    distributed = pytest.importorskip("distributed")
    from cli import fleet
    from cli.check import _lost

    setup = Setup(load_context(SHOP, None, None), verbosity=-1)
    good = (PROGS / "CNC010.ngc").read_bytes()

    def library() -> Iterator[tuple[int, InlineProgram]]:
        for k in range(40):  # made on the fly: never a list, never a file on the client
            data = bytes(range(256)) if k == 7 else good
            yield k, InlineProgram(f"lib/p{k:03d}.ngc", data)

    with distributed.Client(cluster) as client:
        got = dict(fleet.stream(client, check_file, library(), setup, _lost))
    assert sorted(got) == list(range(40))
    assert [f.code for f in got[7].findings] == ["CHECK-BINARY"]
    want = check_file(InlineProgram("lib/p000.ngc", good), setup).findings
    assert got[0].findings == want and want
    assert all(got[k].file == f"lib/p{k:03d}.ngc" for k in got)


def kills_its_worker_on_13(item: int, shared: int) -> int:
    """A task function whose program 13 kills the worker process running it, every time."""
    if item == 13:
        os._exit(1)
    return item * shared


@pytest.mark.slow
def test_a_program_that_kills_every_worker_is_one_failed_row_not_its_batch() -> None:
    distributed = pytest.importorskip("distributed")
    import dask

    from cli import fleet

    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 2}),
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as lc,
        distributed.Client(lc) as client,
    ):
        got: dict[int, object] = {}
        pairs = ((k, k) for k in range(60))
        for i, res in fleet.stream(
            client, kills_its_worker_on_13, pairs, 3, lambda item, exc: f"lost {item}"
        ):
            assert i not in got  # each program once
            got[i] = res
    assert sorted(got) == list(range(60))
    assert got[13] == "lost 13"
    # the rest of its batch is not lost with it; Dask counts a death against the tasks
    # queued on the dying worker too, so a program queued beside it each time may be
    lost = [k for k in got if got[k] != 3 * k]
    assert all(got[k] == f"lost {k}" for k in lost) and len(lost) <= 3, lost
