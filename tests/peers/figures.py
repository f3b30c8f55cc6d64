"""Print what each peer checked: ``python -m tests.peers.figures`` (docs/readers/peers.md).

For each peer run: programs written and checked, programs the writer refused, blocks the
peer read, IR motions whose end point it compared, arc centres compared, the largest
deviation (mm), blocks excluded by name and programs where the peer disagrees.
"""

from __future__ import annotations

import tempfile
import time
from collections import Counter
from dataclasses import replace
from pathlib import Path

from tests.peers import pygcode_peer, toolpath_peer
from tests.peers.ir_motion import SIX, by_index, corpus, motions


def pygcode_rows() -> list[str]:
    rows = []
    for dialect, fmt in pygcode_peer.RUNS:
        t0 = time.perf_counter()
        n = refused = blocks = moves = arcs = feeds = cut = 0
        dev = 0.0
        excluded: Counter[str] = Counter()
        bad = []
        for w in corpus(dialect, replace(SIX, arc_format=fmt)):
            if w.tagged is None:
                refused += 1
                continue
            r = pygcode_peer.run(w.tagged, by_index(motions(w.ir)))
            n += 1
            blocks, moves, arcs, feeds = (
                blocks + r.blocks,
                moves + r.motions,
                arcs + r.arcs,
                feeds + r.feeds,
            )
            cut += r.comments_cut
            dev = max(dev, r.deviation)
            excluded.update(r.excluded)
            if r.problems:
                bad.append(w.program.stem)
        ex = ", ".join(f"{k} {v}" for k, v in sorted(excluded.items())) or "-"
        rows.append(
            f"| pygcode | {dialect} {fmt} | {n} ({refused} refused) | {blocks} | {moves} | "
            f"{arcs} | {feeds} | {dev:.1e} | {ex}; comments cut {cut} | {bad or '-'} | "
            f"{time.perf_counter() - t0:.1f} s |"
        )
    return rows


def toolpath_rows() -> list[str]:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (options, tol) in toolpath_peer.VARIANTS.items():
            t0 = time.perf_counter()
            written = [w for w in corpus("grbl", options)]
            runs = [w for w in written if w.tagged is not None]
            files = []
            for k, w in enumerate(runs):
                path = Path(tmp) / f"{k}.nc"
                path.write_text("\n".join(text for _, text in w.tagged or []) + "\n")
                files.append(path)
            records, blocks = toolpath_peer.run_node(files)
            total = Counter()
            dev = 0.0
            bad = []
            for k, w in enumerate(runs):
                assert w.tagged is not None
                r = toolpath_peer.compare(
                    w.tagged, by_index(motions(w.ir)), records.get(k, []), blocks[k], tol
                )
                total.update(blocks=r.blocks, motions=r.motions, arcs=r.arcs, probes=r.excluded)
                dev = max(dev, r.deviation)
                if r.problems:
                    bad.append(f"{w.program.stem}: {r.problems[0]}")
            rows.append(
                f"| gcode-toolpath | grbl {name} | {len(runs)} "
                f"({len(written) - len(runs)} refused) | {total['blocks']} | "
                f"{total['motions']} | {total['arcs']} | - | {dev:.1e} | "
                f"G38.x probes {total['probes']} | {bad or '-'} | "
                f"{time.perf_counter() - t0:.1f} s |"
            )
    return rows


def main() -> None:
    print(
        "| peer | output | programs | blocks | motions | arc centres | feeds | max dev (mm) "
        "| excluded | disagreements | time |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for row in pygcode_rows():
        print(row)
    missing = toolpath_peer.available()
    if missing:
        print(f"(gcode-toolpath not run: {missing})")
    else:
        for row in toolpath_rows():
            print(row)


if __name__ == "__main__":
    main()
