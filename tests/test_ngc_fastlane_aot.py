"""The fast lane's kernels compiled ahead of time (numba.pycc) behave exactly as the JIT ones.

Reference: the numba JIT build of the same source (gcode/ngc/lane/fastlane_kernels.py),
itself proven
against ``float()``, ``f"{v:.4f}"`` and the general interpreter by test_ngc_fastlane.py and
test_ngc_lane_equivalence.py. Also: a failed AOT build (no usable C compiler) falls back to
the JIT kernels, once, without output of its own, and loading a built module imports no
numba.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from click.testing import CliRunner

import gcode.ngc.interpreter as interp
from cli.canon import fast_text
from cli.main import cli
from gcode.ngc.lane import fastlane
from kernel import aot as aot_loader
from kernel.ir import canon

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent / "bench"))
from cam_program import write_program  # noqa: E402

TOOLS = ROOT / "golden" / "ngc" / "sim.tbl"


@pytest.fixture(scope="module")
def aot_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("aot-cache")


@pytest.fixture(scope="module")
def aot(aot_dir: Path) -> ModuleType:
    module = fastlane.load_aot(aot_dir)
    if module is None:
        failed = (aot_dir / (fastlane.aot_name() + ".failed")).read_text()
        if shutil.which("cc") is None and shutil.which("gcc") is None:
            pytest.skip(f"no C compiler for numba.pycc: {failed[-200:]}")
        pytest.fail(f"AOT build failed with a C compiler present: {failed}")
    return module


@pytest.fixture(scope="module")
def jit() -> ModuleType:
    return fastlane.load_jit()


@pytest.fixture(scope="module")
def cam_bytes(tmp_path_factory: pytest.TempPathFactory) -> np.ndarray:
    path = write_program(tmp_path_factory.mktemp("cam") / "cam.ngc", 20_000)
    return np.frombuffer(path.read_bytes(), dtype=np.uint8)


def _use(monkeypatch: pytest.MonkeyPatch, module: ModuleType) -> None:
    monkeypatch.setattr(fastlane.KERNELS, "_loaded", module)


def _runs(buf: np.ndarray, max_events: int) -> list[fastlane.Run]:
    """All runs over the buffer, stepping over each line the lane does not take."""
    out = []
    at, line = 0, 1
    state: tuple = ((0.0,) * 6, 0.0, True)
    while at < len(buf):
        pos, feed, trav = state
        run = fastlane.scan(
            buf, at, pos, feed, incremental=False, traverse=trav, first_line=line,
            max_events=max_events,
        )  # fmt: skip
        out.append(run)
        at += run.consumed
        line += run.lines
        state = (run.end_position, run.end_feed, run.end_traverse)
        if not run.lines:  # the general interpreter's line: skip it (G3 -> stay in G1 here)
            nl = bytes(buf[at : at + 200]).find(b"\n")
            at += nl + 1 if nl >= 0 else len(buf) - at
            line += 1
            state = (pos, max(feed, 1.0), False)
    return out


def _as_tuple(run: fastlane.Run) -> tuple:
    return (
        run.kind.tolist(),
        run.position.tolist(),
        run.feed.tolist(),
        run.line.tolist(),
        run.consumed,
        run.lines,
        run.end_position,
        run.end_feed,
        run.end_traverse,
    )


@pytest.mark.slow  # builds the AOT module with the C compiler (~15 s)
@pytest.mark.parametrize("max_events", [8192, 7])
def test_aot_and_jit_scan_a_cam_program_to_identical_runs(
    aot: ModuleType,
    jit: ModuleType,
    cam_bytes: np.ndarray,
    monkeypatch: pytest.MonkeyPatch,
    max_events: int,
) -> None:
    _use(monkeypatch, aot)
    by_aot = _runs(cam_bytes, max_events)
    _use(monkeypatch, jit)
    by_jit = _runs(cam_bytes, max_events)
    assert sum(len(r) for r in by_jit) > 19_000
    assert [_as_tuple(r) for r in by_aot] == [_as_tuple(r) for r in by_jit]


@pytest.mark.slow  # builds the AOT module with the C compiler (~15 s)
def test_aot_and_jit_format_identical_text_including_ties_and_huge_values(
    aot: ModuleType, jit: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(14649)
    special = [5e-5, -5e-5, 1.23445, -1.23445, 0.5, -0.0, 1e12, -3e13, 0.99995, 123456.78905]
    vals = np.concatenate([rng.normal(0, 2000, 12000), special, special])
    vals = np.resize(vals, (len(vals) // 6 + 1) * 6).reshape(-1, 6)
    kinds = np.resize(np.array([0, 1, 2], np.int8), len(vals))
    run = fastlane.Run(
        kinds, vals, vals[:, 0].copy(), np.arange(len(vals)), 0, 0, (0.0,) * 6, 0.0, False
    )
    expected = "".join(line + "\n" for line in canon.write_text(run.commands(), 99_990))
    _use(monkeypatch, aot)
    assert fastlane.events_text(run, 99_990) == expected
    _use(monkeypatch, jit)
    assert fastlane.events_text(run, 99_990) == expected
    raw_aot = aot.format(kinds, vals, run.feed, 3, fastlane._NAME_TABLE, fastlane._NAME_LEN)
    raw_jit = jit.format(kinds, vals, run.feed, 3, fastlane._NAME_TABLE, fastlane._NAME_LEN)
    assert raw_aot[0].tobytes() == raw_jit[0].tobytes()
    assert raw_aot[1].tolist() == raw_jit[1].tolist() and raw_aot[2] == raw_jit[2] > 0


@pytest.mark.slow  # builds the AOT module with the C compiler (~15 s)
def test_cnc_canon_prints_the_same_with_aot_and_jit_kernels(
    aot: ModuleType, jit: ModuleType, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    prog = write_program(tmp_path / "cam.ngc", 5_000)
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    texts = []
    for module in (aot, jit):
        _use(monkeypatch, module)
        result = CliRunner().invoke(cli, ["canon", str(prog), "--tool-table", str(TOOLS)])
        assert result.exit_code == 0, result.output
        texts.append(result.output)
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 1 << 60)  # the general path alone
    general = CliRunner().invoke(cli, ["canon", str(prog), "--tool-table", str(TOOLS)])
    assert texts[0] == texts[1] == general.output
    assert texts[0].count("\n") > 4_900


def test_a_failed_build_falls_back_to_jit_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, jit: ModuleType
) -> None:
    calls = []

    def no_compiler(directory: Path, name: str) -> tuple[bool, str]:
        calls.append(name)
        return False, "error: command 'gcc' failed: No such file or directory"

    monkeypatch.setattr(fastlane.KERNELS, "build_aot", no_compiler)
    monkeypatch.setattr(aot_loader, "cache_dir", lambda: tmp_path)
    monkeypatch.delenv("CNC_FASTLANE_JIT", raising=False)
    monkeypatch.setattr(fastlane.KERNELS, "_loaded", None)
    assert fastlane._kernels() is jit
    assert fastlane.kernel_mode() == "jit"
    assert (tmp_path / (fastlane.aot_name() + ".failed")).read_text().startswith("error:")
    run = fastlane.scan(
        np.frombuffer(b"G1 X1 F10\nY2\n", np.uint8), 0, (0.0,) * 6, 0.0,
        incremental=False, traverse=True, first_line=1,
    )  # fmt: skip
    assert fastlane.events_text(run, 1).splitlines()[-1] == (
        "    3 N..... STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)"
    )
    assert fastlane.load_aot(tmp_path) is None  # remembered: no second build attempt
    assert len(calls) == 1


def test_without_aot_module_or_numba_the_general_interpreter_does_everything(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def no_numba() -> ModuleType:
        raise ImportError("No module named 'numba'")

    prog = write_program(tmp_path / "cam.ngc", 300)
    expected = list(interp.interpret(prog, interp.InterpreterOptions(fast_lane=False)))
    monkeypatch.setattr(fastlane.KERNELS, "_loaded", None)
    monkeypatch.setattr(fastlane.KERNELS, "load_aot", lambda directory: None)
    monkeypatch.setattr(fastlane.KERNELS, "load_jit", no_numba)
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    chunks = list(interp.interpret_chunks(prog))
    assert all(isinstance(c, canon.Command) for c in chunks)
    assert chunks == expected


def test_a_build_without_a_working_compiler_reports_failure_and_leaves_no_module(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    monkeypatch.setenv("CXX", str(tmp_path / "no-such-cc"))
    name = fastlane.aot_name()
    ok, error = fastlane.KERNELS.build_aot(tmp_path, name)
    assert not ok and error
    assert [p.name for p in tmp_path.iterdir()] == []  # no module, no build leftovers


@pytest.mark.slow  # builds the AOT module with the C compiler (~15 s)
def test_loading_the_aot_module_imports_no_numba(
    aot: ModuleType, aot_dir: Path, tmp_path: Path
) -> None:
    probe = (
        "import sys; from gcode.ngc.lane import fastlane; k = fastlane._kernels(); "
        "print(k.__name__, 'numba' in sys.modules)"
    )
    shutil.copytree(aot_dir, tmp_path / "cnc-toolchain")
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path))
    env.pop("CNC_FASTLANE_JIT", None)
    out = subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.split() == [fastlane.aot_name(), "False"]


def test_inline_arc_text_is_exactly_the_ir_writers() -> None:
    """cli.canon formats ARC_FEED inline (the CAM bench's arcs); ints and bools in float
    fields, negative zeros and tiny negatives must print as kernel.ir.canon prints them."""
    rng = np.random.default_rng(3)
    arcs = [
        canon.ArcFeed(*rng.normal(0, 300, 4).tolist(), int(t), *rng.normal(0, 9, 4).tolist())
        for t in rng.integers(-3, 4, 300)
    ]
    arcs += [
        canon.ArcFeed(-0.0, -0.00004, 1e-9, -1e-5, -1, -0.0, 0.0, -0.0, 12345.67895),
        canon.ArcFeed(1, 2.0, 3.0, 4.0, 1, 5.0),  # an int where a float belongs
        canon.ArcFeed(1.0, 2.0, 3.0, 4.0, True, 5.0),  # a bool turn count
        canon.ArcFeed(1.0, 2.0, 3.0, 4.0, 1.0, 5.0),  # a float turn count
        canon.ArcFeed(float("nan"), float("inf"), 3.0, 4.0, 2, -float("inf")),
    ]
    assert list(fast_text(arcs, 9)) == list(canon.write_text(arcs, 9))
    assert list(fast_text(arcs, 9, linuxcnc=True)) == list(canon.write_text(arcs, 9))


@pytest.mark.parametrize(
    ("module", "notice"),
    [
        ("gcode.ngc.lane.fastlane", "building fast kernels, once, ~30 s"),
        pytest.param(
            "stepnc.p21_scan",
            "building fast Part 21 kernels, once, ~30 s",
            marks=pytest.mark.slow,  # two interpreters more
        ),
    ],
)
def test_the_one_off_build_is_announced_on_stderr_once(
    tmp_path: Path, module: str, notice: str
) -> None:
    """A user whose first command builds a front end's kernels (kernel.aot) is told so on
    stderr, before the wait; a later command (the build remembered) says nothing."""
    probe = (
        f"import sys; from pathlib import Path; from {module} import KERNELS; "
        "KERNELS.build_aot = lambda directory, name: (False, 'no compiler'); "
        "print(KERNELS.load_aot(Path(sys.argv[1])))"
    )
    env = dict(os.environ)
    env.pop("CNC_FASTLANE_JIT", None)
    env.pop("CNC_P21_JIT", None)
    runs = [
        subprocess.run(
            [sys.executable, "-c", probe, str(tmp_path)],
            env=env, capture_output=True, text=True, check=True,
        )
        for _ in range(2)
    ]  # fmt: skip
    assert runs[0].stdout.strip() == runs[1].stdout.strip() == "None"
    assert runs[0].stderr.startswith(notice)
    assert str(tmp_path) in runs[0].stderr
    assert runs[1].stderr == ""
