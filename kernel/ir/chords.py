"""Equivalence of a source and an output that replaced its arcs by straight chords, as arrays
(issue 15: ``cnc convert --to sandia``'s check).

The Sandia generic language has no arc command, so its writer turns every ``ARC_FEED`` into
``MoveTo`` chords within the tolerance: a 200,000-line CAM program reads back as 2.3
million straight feeds. :func:`kernel.ir.equivalence.first_difference` accepts such chords
by its ``_cover`` rule (each chord ends on the arc, within the tolerance, further along it,
the last on its end), one command object at a time; :func:`kernel.ir.equivalence.equivalent`
(motion for motion) cannot. :func:`chords_equivalent` builds both streams' motion tables
(``equivalence._Table``, the reader's runs as arrays) and walks them with the same rule in
a compiled kernel (:mod:`kernel.ir.chord_kernels`, built once through :mod:`kernel.aot`).

Like :func:`~kernel.ir.equivalence.equivalent` it says True only where ``first_difference``
finds nothing, and False where it cannot tell: any difference, anything but straight
motions and arcs covered by straight feeds (probes, curves, dwells, arcs in the output), a
motion seeing other units or spindle, tool or coolant state than its source (even where
the rule would map them), and every comparison within a few ulps of its bound (the
kernel's ``hypot`` need not be CPython's to the last bit). ``first_difference`` then
decides, and says what differs.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from kernel import aot
from kernel.ir import canon
from kernel.ir.equivalence import _AXES, EXACT, Moves, _mm, _State, _Table

#: the compiled kernel (kernel.aot: built once into the user's cache, JIT fallback)
KERNELS = aot.Kernels(
    "kernel.ir.chord_kernels", "_chords_aot", "chord comparison kernel", "CNC_CHORDS_JIT"
)


def chords_equivalent(
    source: Iterable[canon.Command | Moves],
    output: Iterable[canon.Command | Moves],
    tolerance: float,
    resolution: Mapping[canon.Units | None, float] | None = None,
) -> bool:
    """True when ``output`` (straight motions only) is equivalent to ``source`` by
    :func:`~kernel.ir.equivalence.first_difference`'s rule with ``tolerance`` (output
    length units) and ``resolution``; False where that rule must tell. Reads ``output``
    to its end unless the source holds what only the rule compares."""
    try:
        kernels = KERNELS.module()
    except ImportError:  # no compiled kernel and no numba: the rule decides
        return False
    states: dict[_State, int] = {}
    src = _Table(source, states)
    if not src.ok:
        return False
    out = _Table(output, states)
    if not out.ok or [e for _, e in src.events] != [e for _, e in out.events]:
        return False
    keys = sorted(states, key=states.__getitem__)
    rounding = resolution or {}
    seen: dict[tuple[object, ...], int] = {}
    key = np.array([seen.setdefault(k[:5] + k[6:], len(seen)) for k in keys], dtype=np.int64)
    mm = np.array([_mm(k[6]) for k in keys])
    written = np.array([rounding.get(k[6], 0.0) for k in keys]) * mm * (1 + 1e-6)
    exact = np.maximum(EXACT * mm, written + 1e-9)
    cover = tolerance * mm + exact
    axes = np.array([_AXES[k[5]] for k in keys], dtype=np.int64).reshape(len(keys), 3)
    ok, done = kernels.cover(
        np.ascontiguousarray(src.kind, dtype=np.int8),
        np.ascontiguousarray(src.values, dtype=np.float64),
        np.ascontiguousarray(src.feed, dtype=np.float64),
        np.ascontiguousarray(src.state, dtype=np.int64),
        np.ascontiguousarray(src.arcs, dtype=np.float64).reshape(-1, 3),
        np.ascontiguousarray(out.kind, dtype=np.int8),
        np.ascontiguousarray(out.values, dtype=np.float64),
        np.ascontiguousarray(out.feed, dtype=np.float64),
        np.ascontiguousarray(out.state, dtype=np.int64),
        key,
        mm,
        exact,
        cover,
        axes,
    )
    if not ok:
        return False
    # every event in the same place: after the output motions of the source's before it
    return all(
        (int(done[moves - 1]) if moves else 0) == at
        for (moves, _), (at, _) in zip(src.events, out.events, strict=True)
    )
