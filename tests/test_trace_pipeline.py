"""Traces: pipeline on samples built in closed form, writers, and ``cnc trace``."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest
from click.testing import CliRunner

from cli.main import cli
from kernel.axes.contour import circle_error
from kernel.diagnostics import Diagnostic
from kernel.interp.samples import Samples
from kernel.machine import DEFAULT_MACHINE, Machine, parse_machine
from kernel.path.segments import ARC, SEGMENT_DTYPE
from kernel.report.trace import Trace, column_dtypes, columns, setup
from kernel.report.trace_writers import open_writer

T = 0.001
R, F = 10.0, 100.0


def circle_samples(turns: float = 2.0) -> tuple[Samples, np.ndarray]:
    """A circle at constant feed, sampled in closed form, and its exact path row."""
    w = F / R
    n = int(round(turns * 2 * math.pi / w / T)) + 1
    t = np.arange(n) * T
    pos = np.column_stack([R * np.cos(w * t), R * np.sin(w * t), np.zeros(n)])
    vel = np.column_stack([-F * np.sin(w * t), F * np.cos(w * t), np.zeros(n)])
    acc = -w * w * np.column_stack([pos[:, 0], pos[:, 1], np.zeros(n)])
    seg = np.zeros(n, dtype=np.int64)
    s = Samples(T, t, pos, vel, acc, np.zeros_like(pos), seg, np.full(n, 7, dtype=np.int32))
    row = np.zeros(1, SEGMENT_DTYPE)
    row["kind"] = ARC
    row["start"][0, :3] = row["end"][0, :3] = (R, 0, 0)
    row["normal"], row["e1"], row["e2"] = (0, 0, 1), (1, 0, 0), (0, 1, 0)
    row["radius"] = row["radius_end"] = R
    row["sweep"] = 2 * math.pi * turns
    row["line"] = 7
    row["feed"] = F
    return s, row


def machine(toml_extra: str = "") -> Machine:
    return parse_machine(
        "[axes.x]\n[axes.y]\n[axes.z]\n[servo]\nkp = 30.0\nsettle = 0.2\n" + toml_extra
    )


def test_columns_schema_is_fixed():
    cols = columns(("x", "y", "z"))
    assert cols[:3] == ["t", "segment", "source_line"] and cols[-1] == "contour_error"
    assert "y_following_error" in cols and len(cols) == 3 + 3 * 7 + 1


def test_circle_trace_contour_error_matches_the_p_loop_and_tracker():
    s, row = circle_samples()
    m = machine()
    tr = Trace(s, setup(m, T), row, chunk=500)
    tables = list(tr.chunks())
    assert all(len(t["t"]) <= 500 for t in tables)
    cat = {k: np.concatenate([t[k] for t in tables]) for k in tables[0]}
    assert list(cat) == columns(("x", "y", "z"))
    assert len(cat["t"]) == tr.rows == len(s) + 200
    # P loop on a circle: each axis is a first-order lag (plus the drive), the radius
    # shrinks; the steady contour error equals the radial deficit of the actual path
    steady = slice(1000, len(s) - 1)
    rad = np.hypot(cat["x_act_pos"], cat["y_act_pos"])[steady]
    assert cat["contour_error"][steady] == pytest.approx(R - rad, abs=1e-9)
    assert tr.errors.contour.value == pytest.approx(np.nanmax(cat["contour_error"]))
    assert tr.errors.contour.line == 7
    fe = cat["x_following_error"]
    assert fe == pytest.approx(cat["x_cmd_pos"] - cat["x_act_pos"])
    # |following error| on a circle: |jw/(jw + Kv)| R for the P loop alone (the 4 ms
    # speed loop adds about 1.5 %)
    w = F / R
    lag = w * R / math.hypot(w, 30.0)
    assert np.hypot(fe, cat["y_following_error"])[steady].max() == pytest.approx(lag, rel=0.02)


def test_adcai_and_fine_interpolation_from_the_profile():
    s, row = circle_samples()
    coarse = Samples(
        0.004,
        s.t[::4] * 1,
        s.position[::4],
        s.velocity[::4],
        s.acceleration[::4],
        s.jerk[::4],
        s.segment[::4],
        s.source_line[::4],
    )
    coarse = Samples(
        0.004,
        np.arange(len(coarse)) * 0.004,
        coarse.position,
        coarse.velocity,
        coarse.acceleration,
        coarse.jerk,
        coarse.segment,
        coarse.source_line,
    )
    m = machine('period = 0.001\n[accdec]\ntype = "linear"\ntau = 0.048\n')
    tr = Trace(coarse, setup(m, 0.004), row)
    cmd = tr.commanded()
    assert cmd.period == pytest.approx(0.001)
    assert len(cmd) == (len(coarse) + 11) * 4 - 3  # 12-tap filter tail, 4 fine per coarse
    rows = sum(len(t["t"]) for t in tr.chunks())
    assert rows == tr.rows
    pred = tr.predicted()
    assert pred["accdec"] == "linear" and pred["tau"] == 0.048
    assert pred["max_arc_error"]["value"] == pytest.approx(circle_error("linear", F, R, 0.048))
    assert Trace(s, setup(machine(), T), row).predicted() is None


def test_bad_servo_period_is_a_diagnostic():
    s, row = circle_samples(0.1)
    with pytest.raises(Diagnostic) as err:
        Trace(s, setup(machine("period = 0.0003\n"), T), row).commanded()
    assert err.value.code == "SERVO-PERIOD"


def _write(fmt: str, path: str, known_rows: bool = False) -> list[dict[str, np.ndarray]]:
    s, row = circle_samples(0.3)
    tr = Trace(s, setup(machine(), T), row, chunk=256)
    names = columns(s.axes)
    if known_rows:
        w = open_writer(fmt, path, names, rows=tr.rows, dtypes=column_dtypes(s.axes))
    else:
        w = open_writer(fmt, path, names)
    tables = []
    for t in tr.chunks():
        w.write(t)
        tables.append(t)
    w.close()
    return tables


@pytest.mark.parametrize("known_rows", [False, True], ids=["two-pass", "direct"])
def test_npz_round_trip(tmp_path, known_rows):
    import zipfile

    path = str(tmp_path / "t.npz")
    tables = _write("npz", path, known_rows)
    with zipfile.ZipFile(path) as zf:
        assert zf.testzip() is None  # every CRC checks
    data = np.load(path)
    assert list(data.files) == columns(("x", "y", "z"))
    for k in ("t", "segment", "x_act_pos", "contour_error"):
        assert np.array_equal(data[k], np.concatenate([t[k] for t in tables]), equal_nan=True)
    assert data["segment"].dtype.kind == "i"
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".trace-")]


def test_csv_round_trip(tmp_path):
    path = str(tmp_path / "t.csv")
    tables = _write("csv", path)
    with open(path) as fh:
        header = fh.readline().strip().split(",")
    assert header == columns(("x", "y", "z"))
    data = np.genfromtxt(path, delimiter=",", skip_header=1)
    ref = np.concatenate([t["y_act_pos"] for t in tables])
    assert data[:, header.index("y_act_pos")] == pytest.approx(ref, rel=1e-8, abs=1e-12)
    assert data.shape[0] == ref.size


def test_parquet_without_pyarrow_and_existing_files_are_diagnostics(tmp_path):
    pytest.importorskip("numpy")
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        with pytest.raises(Diagnostic) as err:
            open_writer("parquet", str(tmp_path / "t.parquet"), ["t"])
        assert err.value.code == "IO-PARQUET"
    (tmp_path / "t.csv").write_text("keep")
    with pytest.raises(Diagnostic) as err:
        open_writer("csv", str(tmp_path / "t.csv"), ["t"])
    assert err.value.code == "IO-EXISTS"
    assert (tmp_path / "t.csv").read_text() == "keep"


PROGRAM = "G21 G90 G17\nG1 X20 F3000\nG1 Y20\nG2 X40 Y20 I10 J0\nG1 X0 Y0\nM2\n"


def test_cnc_trace_writes_traces_summary_and_plots(tmp_path):
    prog = tmp_path / "part.ngc"
    prog.write_text(PROGRAM)
    out = tmp_path / "out"
    runner = CliRunner()
    res = runner.invoke(cli, ["trace", str(prog), "-o", str(out), "--plot", "--format", "npz"])
    assert res.exit_code == 0, res.output
    names = sorted(os.listdir(out))
    assert names == sorted(
        [
            "part_trace.npz",
            "part_summary.json",
            "part_x.png",
            "part_y.png",
            "part_z.png",
            "part_xy.png",
        ]
    )
    summary = json.loads((out / "part_summary.json").read_text())
    assert summary["contour_error"]["line"] in (2, 3, 4, 5)
    # the default mill has balanced speed feedforward: following error = feed x the speed
    # loop's equivalent delay, 1/K_pn less half a drive sub-step (book eq. 5.39)
    delay = 1 / 250.0 - 0.001 / 4 / 2
    assert summary["following_error"]["x"]["value"] == pytest.approx(50 * delay, rel=1e-3)
    for png in ("part_x.png", "part_xy.png"):
        assert (out / png).read_bytes()[:4] == b"\x89PNG"
    before = (out / "part_summary.json").read_bytes()
    again = runner.invoke(cli, ["trace", str(prog), "-o", str(out)])  # summary would change
    assert again.exit_code == 2 and "IO-EXISTS" in again.output
    assert not (out / "part_trace.csv").exists()  # refused before writing anything
    assert (out / "part_summary.json").read_bytes() == before
    forced = runner.invoke(cli, ["trace", str(prog), "-o", str(out), "--force"])
    assert forced.exit_code == 0 and (out / "part_trace.csv").exists()


def test_cnc_trace_reports_program_errors_without_traceback(tmp_path):
    prog = tmp_path / "bad.ngc"
    prog.write_text("G1 X10\nM2\n")  # feed move with no feed rate
    res = CliRunner().invoke(cli, ["trace", str(prog), "-o", str(tmp_path / "o")])
    assert res.exit_code == 1
    assert "error[" in res.output and "Traceback" not in res.output


def test_default_machine_has_servo_parameters_for_every_axis():
    st = setup(DEFAULT_MACHINE, T)
    assert set(st.axes) == {"x", "y", "z"} and st.period is None


@pytest.mark.parametrize("chunk", [13, 300, 1_000_000])
def test_trace_does_not_depend_on_the_chunk_size(chunk):
    s, row = circle_samples(0.5)
    m = machine('feedforward = "torque"\ncurrent_time_constant = 0.0004\nvelocity_limit = 1000.0\n')
    ref = list(Trace(s, setup(m, T), row, chunk=256).chunks())
    got = list(Trace(s, setup(m, T), row, chunk=chunk).chunks())
    for name in columns(s.axes):
        a = np.concatenate([t[name] for t in ref])
        b = np.concatenate([t[name] for t in got])
        assert np.allclose(a, b, rtol=0, atol=1e-12, equal_nan=True), name


def test_cnc_trace_parquet_without_pyarrow_fails_before_simulating(tmp_path):
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        prog = tmp_path / "part.ngc"
        prog.write_text(PROGRAM)
        out = tmp_path / "o"
        res = CliRunner().invoke(cli, ["trace", str(prog), "-o", str(out), "--format", "parquet"])
        assert res.exit_code == 2 and "IO-PARQUET" in res.output
        assert not out.exists()
    else:  # pragma: no cover - pyarrow is not a dependency
        pytest.skip("pyarrow installed: Parquet output is available")


def test_parquet_round_trip_when_pyarrow_is_installed(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    path = str(tmp_path / "t.parquet")
    tables = _write("parquet", path)
    data = pq.read_table(path)
    assert data.column_names == columns(("x", "y", "z"))
    assert data.num_rows == sum(len(t["t"]) for t in tables)
    ref = np.concatenate([t["x_following_error"] for t in tables])
    assert np.array_equal(data.column("x_following_error").to_numpy(), ref)
    assert pq.ParquetFile(path).num_row_groups == len(tables)
