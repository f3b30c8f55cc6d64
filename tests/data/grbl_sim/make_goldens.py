"""Turn harness/run_lockstep.py's CSV output into goldens.json (run by hand; tests read only
the JSON).

  python make_goldens.py results_lockstep.csv [more.csv ...]

A run is kept when Grbl answered every line without an error; in lockstep mode the simulated
time does not depend on the host, so repeated runs agree to the tick (several CSVs may be
given: their times must then be equal, which is checked). A program that is not in ``ngc/`` is
a real one of ``tests/realworld/ngc`` (run there, under its own name): its golden records
its ``file``.
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path


def main(argv: list[str]) -> None:
    here = Path(__file__).parent
    real = here.parent.parent / "realworld" / "ngc"
    best: dict[str, float] = {}
    files: dict[str, str] = {}
    for name in argv:
        for row in csv.DictReader(Path(name).read_text().splitlines()):
            if "DID-NOT-FINISH" in row["notes"] or "TIMEOUT" in row["notes"]:
                continue
            if int(row["errors"]) > 0:
                continue
            prog = Path(row["program"]).stem
            if not (here / "ngc" / f"{prog}.ngc").exists():
                assert (real / row["program"]).exists(), row["program"]
                files[prog] = f"../../realworld/ngc/{row['program']}"
            t = float(row["grbl_s"])
            if prog in best and best[prog] != t:
                raise SystemExit(f"{prog}: runs disagree ({best[prog]} s, {t} s)")
            best[prog] = t
    doc = {
        "source": "grbl-sim (Grbl 1.1h bfb67f0, grbl-sim 9bdd165) in lockstep mode via "
        "harness/run_lockstep.py; time = stepper-on simulated time + G4 dwells",
        "goldens": {
            p: {"time": t, **({"file": files[p]} if p in files else {})}
            for p, t in sorted(best.items())
        },
    }
    Path(__file__).with_name("goldens.json").write_text(json.dumps(doc, indent=1) + "\n")
    print(f"{len(best)} goldens")


if __name__ == "__main__":
    main(sys.argv[1:])
