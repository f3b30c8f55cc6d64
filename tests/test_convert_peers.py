"""Our writers' output read by independent peer readers (docs/readers/peers.md).

* **pygcode 0.2.1** (default suite; a dev dependency): every golden and corpus program our
  interpreter reads, written as Grbl, Fanuc, Haas and NIST RS274/NGC v3, is parsed block by
  block by pygcode and run on its ``Machine``; after each IR motion pygcode's position is
  the IR's end point within 1e-4 mm, its centre words give the IR's arc centre, its G2/G3
  the IR's turning sense, its F the IR's feed. What pygcode cannot read is excluded by
  name (``tests/peers/pygcode_peer.py``), and only where the dialect defines it.
* **cncjs's gcode-toolpath** (npm; marked ``reference``, skipped unless ``node`` and the
  module are found, ``CNC_PEERS_NODE_PATH`` or /tmp/peers/node_modules): the Grbl output
  of the whole corpus, IJK and R arcs, with six decimals (1e-4 mm) and in the default
  format (within its rounding): end points, arc centres by the peer's own arithmetic.
"""

from __future__ import annotations

import tempfile
from collections import Counter
from dataclasses import replace
from pathlib import Path

import pytest
from pygcode import Machine

from gcode.ngc.interpreter import interpret_text
from gcode.registry import get_dialect
from gcode.write.spec import Dialect
from tests.convert_support import programs
from tests.peers import pygcode_peer, toolpath_peer
from tests.peers.ir_motion import SIX, by_index, corpus, motions, tagged_lines

#: fewest programs a run must check (the corpus has 241; some targets refuse a few)
MIN_PROGRAMS = {"grbl": 220, "fanuc": 235, "haas": 230, "nist_v3": 230}


def allowed_exclusions(d: Dialect) -> set[str]:
    """The pygcode exclusions a dialect can need: constructs that dialect defines."""
    defined = {
        "G06.2 NURBS": d.nurbs == "g06.2",
        "G31 skip": d.probe == "G31",
        "G52 local offset": (d.local_offset or "").startswith("G52"),
        "G68/G69 rotation": "G68" in (d.xy_rotation or ""),
        "G09 exact stop": d.exact_stop in ("G09", "G9"),
        "G04 X dwell": d.dwell is not None and d.dwell[1] == "X",
        "M19 angle": "{angle}" in (d.orient or ""),
        "G43.1 Z": (d.tool_length or "").startswith("G43.1"),
    }
    return {name for name, yes in defined.items() if yes}


#: the pygcode runs of the default run (a few seconds each); the rest marked slow
_PYGCODE_QUICK = {("grbl", "r"), ("fanuc", "ijk")}


@pytest.mark.parametrize(
    ("dialect", "arc_format"),
    [
        pytest.param(d, f, marks=() if (d, f) in _PYGCODE_QUICK else pytest.mark.slow)
        for d, f in pygcode_peer.RUNS
    ],
)
def test_pygcode_reads_every_block_and_stands_at_every_ir_end_point(
    dialect: str, arc_format: str
) -> None:
    problems: dict[str, list[str]] = {}
    excluded: Counter[str] = Counter()
    checked = motions_compared = arcs = 0
    for w in corpus(dialect, replace(SIX, arc_format=arc_format)):
        if w.tagged is None:
            assert w.refusal.startswith("CONV-"), w.refusal
            continue
        result = pygcode_peer.run(w.tagged, by_index(motions(w.ir)))
        checked += 1
        motions_compared += result.motions
        arcs += result.arcs
        excluded.update(result.excluded)
        assert result.blocks + sum(result.excluded.values()) == len(w.tagged)
        if result.problems:
            problems[w.program.name] = result.problems[:5]
    assert problems == {}
    assert set(excluded) <= allowed_exclusions(get_dialect(dialect)), excluded
    assert checked >= MIN_PROGRAMS[dialect]
    assert motions_compared > 2500 and arcs > 750


# One block per exclusion rule: pygcode 0.2.1 rejects it or moves where the control does not.
RULE_EXAMPLES = {
    "G06.2 NURBS": "G06.2 P3 K0. X0. Y0. R1.",
    "G31 skip": "G31 X1. F50.",
    "G52 local offset": "G52 X10. Y10.",
    "G68/G69 rotation": "G68 X0 Y0 R30.",
    "G09 exact stop": "G09",
    "G04 X dwell": "G04 X1.5",
    "M19 angle": "M19 P90.",
    "G43.1 Z": "G43.1 Z5.",
}


@pytest.mark.parametrize("rule", pygcode_peer.RULES, ids=lambda r: r.name)
def test_each_pygcode_exclusion_names_a_block_pygcode_misreads(rule: pygcode_peer.Rule) -> None:
    text = RULE_EXAMPLES[rule.name]
    words = [(w, float(v)) for w, v in pygcode_peer.WORD.findall(text)]
    assert rule.matches(words)
    machine = Machine()
    machine.process_str("G1 X0 Y0 Z0 F100")
    try:
        machine.process_str(text)
    except Exception:  # noqa: BLE001 - a rejection is what the rule says
        return
    assert machine.pos.values != {"X": 0.0, "Y": 0.0, "Z": 0.0}, "pygcode reads it right"


def test_pygcode_cuts_a_block_at_a_semicolon_inside_a_comment() -> None:
    with pytest.raises(Exception):  # noqa: B017,PT011 - whatever pygcode raises
        Machine().process_str("(tool change; next corner)")


PROGRAM = """G21 G90 G17
G0 X0 Y0 Z5
G1 Z-1 F120
G1 X20 Y0
G3 X20 Y20 I0 J10
G2 X0 Y20 R10 F80
G18 G2 Z-3 X-2 K-1 I-1
G19 G3 Y25 Z-1 J2.5 K1
G17 G20 G1 X0.5
M2
"""


def _mutated(old: str, new: str, dialect: str = "grbl") -> list[str]:
    ir = list(interpret_text(PROGRAM, "peer.ngc"))
    tagged = tagged_lines(ir, dialect, SIX)
    hits = [i for i, (_, text) in enumerate(tagged) if old in text]
    assert hits, f"{old!r} not in {[t for _, t in tagged]}"
    index, text = tagged[hits[0]]
    tagged[hits[0]] = (index, text.replace(old, new, 1))
    return pygcode_peer.run(tagged, by_index(motions(ir))).problems


def test_pygcode_check_passes_the_unaltered_program() -> None:
    for dialect in ("grbl", "fanuc", "haas", "nist_v3"):
        assert _mutated("G21", "G21", dialect) == []


@pytest.mark.parametrize(
    ("old", "new", "found"),
    [
        ("X20", "X20.001", "X=20.001"),  # an end point
        ("J10", "J10.01", "centre"),  # an arc centre
        ("G3 X20", "G2 X20", "rotation"),  # the turning sense
        ("F120", "F12", "F=12"),  # the feed
        ("G21", "G20", "X="),  # the units word
        ("G18", "G17", "plane"),  # the plane
    ],
)
def test_pygcode_check_catches_a_wrong_block(old: str, new: str, found: str) -> None:
    problems = _mutated(old, new)
    assert any(found in p for p in problems), problems


def test_pygcode_fanuc_feed_after_a_thread_is_the_programmed_feed() -> None:
    """Fanuc's F is one modal word: the G33 lead replaces the feed, so the writer restates
    F on the next G01 (a bug pygcode found; docs/readers/peers.md)."""
    text = "G21 G90 G17\nS200 M3\nG1 X0 Y0 Z2 F300\nG33 Z-10 K1.5\nG1 X5\nM2\n"
    ir = list(interpret_text(text, "thread.ngc"))
    result = pygcode_peer.run(tagged_lines(ir, "fanuc", SIX), by_index(motions(ir)))
    assert result.problems == []


# ----------------------------------------------------------------------- gcode-toolpath
VARIANTS = toolpath_peer.VARIANTS
KNOWN: dict[tuple[str, str], str] = {}  # (variant, program stem): why the peer disagrees
_missing = toolpath_peer.available()


@pytest.fixture(scope="module")
def toolpath_results() -> dict[str, dict[str, toolpath_peer.ToolpathResult | str]]:
    """Per variant and program stem: the peer's result, or the writer's refusal."""
    out: dict[str, dict[str, toolpath_peer.ToolpathResult | str]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, (options, tolerance) in VARIANTS.items():
            written = list(corpus("grbl", options))
            files, runs = [], []
            for w in written:
                if w.tagged is not None:
                    path = Path(tmp) / f"{name}-{len(files)}.nc"
                    path.write_text("\n".join(text for _, text in w.tagged) + "\n")
                    files.append(path)
                    runs.append(w)
            records, blocks = toolpath_peer.run_node(files)
            out[name] = {w.program.stem: w.refusal for w in written if w.tagged is None}
            for k, w in enumerate(runs):
                assert w.tagged is not None
                out[name][w.program.stem] = toolpath_peer.compare(
                    w.tagged, by_index(motions(w.ir)), records.get(k, []), blocks[k], tolerance
                )
    return out


def _toolpath_params() -> list:
    params = []
    for variant in VARIANTS:
        for p in programs():
            reason = KNOWN.get((variant, p.stem))
            marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
            params.append(pytest.param(variant, p.stem, marks=marks, id=f"{variant}-{p.stem}"))
    return params


@pytest.mark.reference
@pytest.mark.skipif(_missing is not None, reason=_missing or "")
@pytest.mark.parametrize(("variant", "stem"), _toolpath_params())
def test_gcode_toolpath_reads_our_grbl_output_as_the_ir_moves(
    toolpath_results: dict, variant: str, stem: str
) -> None:
    result = toolpath_results[variant].get(stem)
    if result is None:
        pytest.skip("our interpreter rejects this program")
    if isinstance(result, str):
        assert result.startswith("CONV-"), result
        return
    assert result.problems == []
    assert result.blocks > 0
