"""An independent 840D reader on our 840D output: CEAD-group's ``nc-gcode-interpreter``
(Rust, Sinumerik-flavoured; PyPI 0.1.9, the last release for Python 3.11), marked
``reference`` and skipped where it is not installed.

For every golden and corpus program, the 840D text the writer makes (ijk and r arc
formats) must parse in the peer, and the peer's path (its positions block by block,
without repeats) must be the path of end points our 840D reader gives (1e-4). The peer
keeps positions only (no arcs, no IR); version 0.1.9 reads neither ``AC()``/``IC()`` nor R
parameters, adds ``TRANS`` to its positions (the IR carries it as an offset), ignores
``ROT`` and does not convert positions at a change of units, so texts with TRANS, ROT or
G700, and the ijk-abs format, are left out.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from gcode.siemens.reader import interpret_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import options, programs, read_ir

peer = pytest.importorskip("nc_gcode_interpreter")
pytestmark = pytest.mark.reference

LEFT_OUT = ("TRANS", "ROT", "G700")
_PLANE_XYZ = {canon.Plane.XY: (0, 1, 2), canon.Plane.YZ: (1, 2, 0), canon.Plane.XZ: (2, 0, 1)}


def _path(points: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    """The points without consecutive repeats (within 1e-6)."""
    out: list[tuple[float, float, float]] = []
    for p in points:
        if not out or max(abs(a - b) for a, b in zip(p, out[-1], strict=True)) > 1e-6:
            out.append(p)
    return out


def _ours(commands: list[canon.Command]) -> list[tuple[float, float, float]]:
    """Our reader's motion end points (x, y, z), from the start point (0, 0, 0)."""
    points = [(0.0, 0.0, 0.0)]
    plane = canon.Plane.XY
    for c in commands:
        if isinstance(c, canon.SelectPlane):
            plane = c.plane
        elif isinstance(c, canon.StraightFeed | canon.StraightTraverse | canon.StraightProbe):
            points.append((c.x, c.y, c.z))
        elif isinstance(c, canon.ArcFeed):
            xyz = [0.0, 0.0, 0.0]
            f, s, n = _PLANE_XYZ[plane]
            xyz[f], xyz[s], xyz[n] = c.first_end, c.second_end, c.axis_end_point
            points.append((xyz[0], xyz[1], xyz[2]))
    return _path(points)


@pytest.mark.parametrize("arc_format", ["ijk", "r"])
@pytest.mark.parametrize("program", programs(), ids=lambda p: p.stem)
def test_peer_reads_our_840d_output_to_the_same_positions(program: Path, arc_format: str) -> None:
    ir = read_ir(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    try:
        lines = list(write(ir, "siemens840d", WriterOptions(arc_format=arc_format), report))
    except Diagnostic:
        pytest.skip("the writer refuses this program")
    text = "\n".join(lines)
    if any(c.code != "CONV-ARC-FORMAT" for c in report.changes) or any(
        word in text for word in LEFT_OUT
    ):
        pytest.skip("reported conversion, or a construct the peer does not position")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        df, _ = peer.nc_to_dataframe(text, extra_axes=["A", "B", "C"])
    ours = _ours(list(interpret_text(text + "\n", "conv.mpf", options(program))))
    columns = [df[k].to_list() if k in df.columns else [None] * len(df) for k in "XYZ"]
    theirs = _path(
        [(0.0, 0.0, 0.0)] + [tuple(v or 0.0 for v in row) for row in zip(*columns, strict=True)]
    )
    assert len(theirs) == len(ours)
    for a, b in zip(theirs, ours, strict=True):
        assert a == pytest.approx(b, abs=1e-4)
