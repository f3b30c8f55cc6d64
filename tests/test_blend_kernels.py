"""The compiled blend-arc insertion (kernel.path.blend_kernels) makes the numpy
formulation's table (kernel.path.blend) byte for byte: on the LinuxCNC model's blend arcs
of golden programs, with every row kept and with the lines trimmed short left out."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gcode.readers import read
from kernel.machine import parse_machine
from kernel.path.blend import corner_trims, insert_blend_arcs, kept_after_blending
from kernel.plan.models import linuxcnc
from kernel.plan.models.lcnc_joins import ARC_JOIN
from kernel.plan.strategy import build

LCNC = Path(__file__).parent / "data" / "lcnc_tp"


def _corners(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A golden program's segment table and the LinuxCNC model's blend-arc corners, radii."""
    machine = parse_machine((LCNC / "machine.toml").read_text())
    built = build(list(read(LCNC / "ngc" / f"{name}.ngc", "rs274ngc")), machine)
    assert built.prepared is not None
    seg = built.path.segments
    src = np.clip(seg["source"], 0, len(built.prepared.term) - 1)
    term, tol = built.prepared.term[src], built.prepared.tolerance[src]
    lim = linuxcnc._limits(built.path, machine)
    j = linuxcnc._joins(seg, lim, term, tol, machine)
    corners = np.flatnonzero(j.kind == ARC_JOIN)
    return seg, corners, j.radius[corners]


@pytest.mark.parametrize(
    "name",
    [
        "real_fusion_1014.G64P",
        "own_sine_0p5_f3000.native",
        "real_estlcam_fixture.native",
        "own_tiny_segments.native",
    ],
)
def test_compiled_blend_arcs_make_the_same_table(name: str) -> None:
    seg, corners, r = _corners(name)
    assert corners.size > 10
    trims = corner_trims(seg, corners, r, True)
    for x, y in zip(trims, corner_trims(seg, corners, r), strict=True):
        assert np.array_equal(x, y)
    ref = insert_blend_arcs(seg, corners, r)
    ours = insert_blend_arcs(seg, corners, r, None, True, trims)
    assert ours.dtype == ref.dtype and ours.tobytes() == ref.tobytes()
    # a minimum length that drops some trimmed lines (and keeps others)
    lengths = np.sort(seg["length"][corners])
    for min_length in (1e-9, float(lengths[lengths.size // 3])):
        keep = kept_after_blending(seg, corners, r, min_length)
        assert np.array_equal(kept_after_blending(seg, corners, r, min_length, True, trims), keep)
        ref = insert_blend_arcs(seg, corners, r, keep)
        ours = insert_blend_arcs(seg, corners, r, keep, True)
        assert len(ours) == int(keep.sum()) and ours.tobytes() == ref.tobytes()
