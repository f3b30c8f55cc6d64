"""Turn harness/run_lockstep.py's CSV output into goldens.json (run by hand; tests read only
the JSON).

  python make_goldens.py results_lockstep.csv [more.csv ...] [b=results_b.csv ...]

A run is kept when Grbl answered every line without an error; in lockstep mode the simulated
time does not depend on the host, so repeated runs agree to the tick (several CSVs may be
given: their times must then be equal, which is checked). ``SET=CSV`` is a run with
``run_lockstep.py --settings SET``: its goldens are named ``PROGRAM@SET`` and record the
profile ``machine_SET.toml``. A program that is not in ``ngc/`` is a real one of ``real/``
or else of ``tests/realworld/ngc`` (run there, under its own name): its golden records its
``file``.
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path


def main(argv: list[str]) -> None:
    here = Path(__file__).parent
    realworld = here.parent.parent / "realworld" / "ngc"
    best: dict[str, float] = {}
    extra: dict[str, dict[str, str]] = {}
    for arg in argv:
        setting, _, name = arg.rpartition("=")
        machine = f"machine_{setting}.toml" if setting else ""
        assert not machine or (here / machine).exists(), machine
        for row in csv.DictReader(Path(name).read_text().splitlines()):
            if "DID-NOT-FINISH" in row["notes"] or "TIMEOUT" in row["notes"]:
                continue
            if int(row["errors"]) > 0:
                continue
            base = Path(row["program"]).name
            stem = Path(base).stem
            prog = f"{stem}@{setting}" if setting else stem
            info: dict[str, str] = {}
            if not (here / "ngc" / f"{stem}.ngc").exists():
                if (here / "real" / base).exists():
                    info["file"] = f"real/{base}"
                else:
                    assert (realworld / base).exists(), base
                    info["file"] = f"../../realworld/ngc/{base}"
            if machine:
                info["machine"] = machine
            t = float(row["grbl_s"])
            if prog in best and best[prog] != t:
                raise SystemExit(f"{prog}: runs disagree ({best[prog]} s, {t} s)")
            best[prog] = t
            extra[prog] = info
    doc = {
        "source": "grbl-sim (Grbl 1.1h bfb67f0, grbl-sim 9bdd165) in lockstep mode via "
        "harness/run_lockstep.py; time = stepper-on simulated time + G4 dwells",
        "goldens": {p: {"time": t, **extra[p]} for p, t in sorted(best.items())},
    }
    Path(__file__).with_name("goldens.json").write_text(json.dumps(doc, indent=1) + "\n")
    print(f"{len(best)} goldens")


if __name__ == "__main__":
    main(sys.argv[1:])
