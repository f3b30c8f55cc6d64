#!/usr/bin/env bash
# Build grbl-sim (Grbl 1.1h's planner, stepper and G-code parser compiled for a PC, the 16 MHz
# AVR timers simulated tick by tick) with this folder's two patches to grbl-sim.
# Usage: build.sh GRBL_CHECKOUT GRBL_SIM_CHECKOUT BUILD_DIR   -> BUILD_DIR/grbl/grbl-sim/grbl_sim.exe
#   GRBL_CHECKOUT     : https://github.com/gnea/grbl at bfb67f0c7963fe3ce4aaf8a97f9009ea5a8db36e
#   GRBL_SIM_CHECKOUT : https://github.com/grbl/grbl-sim at 9bdd1654c7eb6cacf03e35340b38c962bcebe013
# Grbl's own sources are compiled unmodified; nothing is fetched.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
[ $# -eq 3 ] || { sed -n 2,7p "$0"; exit 2; }
GRBL=$(cd "$1" && pwd); SIM=$(cd "$2" && pwd); BUILD=$3
[ -f "$GRBL/grbl/planner.c" ] || { echo "no grbl/planner.c under $GRBL" >&2; exit 1; }
[ -f "$SIM/simulator.c" ] || { echo "no simulator.c under $SIM" >&2; exit 1; }
rm -rf "$BUILD/grbl"; mkdir -p "$BUILD"
cp -r "$GRBL/grbl" "$BUILD/grbl"                 # grbl-sim's Makefile expects Grbl in ..
mkdir -p "$BUILD/grbl/grbl-sim"
(cd "$SIM" && tar cf - --exclude=.git .) | (cd "$BUILD/grbl/grbl-sim" && tar xf -)
cd "$BUILD/grbl/grbl-sim"
patch -p1 --quiet < "$HERE/grbl-sim-oracle.patch"     # pipe-friendly stdin, SIMSTATS line
patch -p1 --quiet < "$HERE/grbl-sim-lockstep.patch"   # lockstep scheduling, RX ring fix
# gcc >= 10 defaults to -fno-common, which grbl-sim's tentative definitions need
make -j2 new PLATFORM=LINUX FLAGS="-g -O2 -fcommon -w" >build.log 2>&1 || { tail -40 build.log; exit 1; }
ls -l grbl_sim.exe
