"""Turn lcnc-tp recordings into goldens.json (run by hand; tests read only the JSON).

  python make_goldens.py WORK_DIR [WORK_DIR/lcnc ...]

WORK_DIR holds jobs.txt and ngc/ (made by the lcnc-tp harness' make_jobs.py from
programs.txt here) and one or more run_lcnc.sh output folders. For every job: LinuxCNC's
motion time is the number of servo periods (1 ms) from the first to the last period in which
a joint moved; the peak axis speed and acceleration are the largest first and second
differences of the commanded positions (and the 99.9th percentile of the acceleration,
which leaves out single-period spikes). Of several passes the full-length run with the
shortest time is kept (a non-realtime hiccup can only add time). The goldens already in
goldens.json that this work dir did not record are kept.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

PERIOD = 0.001


def analyse(samples: np.ndarray, rid: int) -> dict[str, object] | None:
    pos, ids = samples[:, 1:4], samples[:, 6].astype(int)
    idx = np.flatnonzero(ids == rid)
    if idx.size < 3:
        return None
    p = pos[max(idx[0] - 1, 0) : idx[-1] + 1]
    step = np.diff(p, axis=0)
    moving = np.flatnonzero(np.any(np.abs(step) > 1e-9, axis=1))
    if moving.size == 0:
        return None
    s, e = moving[0], moving[-1]
    v = step[s : e + 1] / PERIOD
    still = ~np.any(np.abs(step[s : e + 1]) > 1e-9, axis=1)
    # standstills of 20 periods or more inside the run: the planner's queue ran dry
    # (non-realtime milltask fell behind), not the planner's own doing
    edges = np.diff(np.concatenate([[0], still.astype(int), [0]]))
    runs = np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)
    a = np.diff(v, axis=0) / PERIOD
    after = pos[idx[-1] : idx[-1] + 50]
    if np.any(np.abs(np.diff(after, axis=0)) > 1e-9):
        return None  # cut short
    return {
        "time": round((e - s + 1) * PERIOD, 4),
        "peak_velocity": [round(float(x), 3) for x in np.abs(v).max(axis=0)],
        "peak_acceleration": [round(float(x), 2) for x in np.abs(a).max(axis=0)],
        "acceleration_p999": [round(float(x), 2) for x in np.percentile(np.abs(a), 99.9, 0)],
        "path_length": round(float(np.linalg.norm(step[s : e + 1], axis=1).sum()), 4),
        "stall_ms": int(runs[runs >= 20].sum()),
    }


def _num(record: dict[str, object], key: str) -> float:
    value = record[key]
    assert isinstance(value, (int, float))
    return float(value)


def main(argv: list[str]) -> None:
    work = Path(argv[0])
    outs = [Path(a) for a in argv[1:]] or [work / "lcnc"]
    jobs = {}
    for line in (work / "jobs.txt").read_text().splitlines():
        if line.strip():
            rid, rel = line.split()
            jobs[int(rid)] = Path(rel).name[:-4]
    best: dict[str, dict[str, object]] = {}
    for out in outs:
        for rd in sorted(out.glob("run_*")):
            if not rd.name[4:].isdigit() or not (rd / "samples.txt").exists():
                continue
            rid = int(rd.name[4:])
            try:
                data = np.loadtxt(rd / "samples.txt", ndmin=2)
            except ValueError:
                continue
            got = analyse(data, rid)
            if got is None:
                continue
            name = jobs[rid]
            old = best.get(name)
            longer = _num(got, "path_length") - _num(old, "path_length") if old else 1.0
            tol = 1e-3 * max(_num(got, "path_length"), 1.0)
            if (
                old is None
                or longer > tol
                or (abs(longer) <= tol and _num(got, "time") < _num(old, "time"))
            ):
                best[name] = got
    out = Path(__file__).with_name("goldens.json")
    # variants recorded before and not in this work dir are kept (programs added in a later
    # session are recorded on their own, the earlier recordings stay as they were)
    kept = json.loads(out.read_text())["goldens"] if out.exists() else {}
    kept.update(best)
    doc = {
        "source": "LinuxCNC 2.9 (Debian linuxcnc-uspace "
        "2.9.0~pre1+git20230208.f1270d6ed7-1+deb12u2) trajectory planner, "
        "simulator configuration, servo period 1 ms; machine.toml limits",
        "goldens": dict(sorted(kept.items())),
    }
    out.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"{len(best)} goldens recorded, {len(kept)} in all")


if __name__ == "__main__":
    main(sys.argv[1:])
