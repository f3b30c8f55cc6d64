"""Fanuc 0i-TF single cutting cycles G90, G92 and G94 (book Table 8.6: "single fixed cycles";
formats from Table A.1: ``G90/G92/G94 X(U) Z(W) R``).

Each cycle is four moves from the start point A = (x0, z0) and back to A:

* G90 (OD/ID cutting cycle A): (1) rapid in X to the cut start, (2) cut to the end point
  (X, Z), (3) feed out in X to x0, (4) rapid back in Z to z0. ``R`` is the taper: the radius
  of the cut start at z0 minus the radius at the end point (x_start = X + R), in radius
  whatever the diameter mode (Fanuc 0i: "R: taper amount, radius designation").
* G94 (face cutting cycle B): the same with the axes exchanged: (1) rapid in Z to Z + R,
  (2) cut to (X, Z), (3) feed back in Z to z0, (4) rapid in X to x0; ``R`` is the Z
  difference between the cut start (at x0) and the end point.
* G92 (threading cycle): as G90 but (2) is a spindle-synchronised thread pass with lead F
  and (3) is a rapid retract; no thread chamfer at the exit (parameter 5130 = 0).

The seeds list these cycles by name only (research/seed-book-interp.md §2.9); the motion
sequence is the Fanuc 0i-TF operator's manual behaviour stated above.
"""

from __future__ import annotations

from gcode.fanuc.turning.types import CycleWords, LatheMove, MoveList


def g90(w: CycleWords) -> list[LatheMove]:
    """G90 X(U) Z(W) [R] [F]: one longitudinal (straight or taper) cut."""
    x_end = w.end_x()
    z_end = w.end_z()
    x_cut = x_end + w.get("R", 0.0)
    out = MoveList(w.x0, w.z0)
    out.set_feed(w.get("F"))
    out.rapid(x_cut, w.z0)
    out.feed(x_end, z_end)
    out.feed(w.x0, z_end)
    out.rapid(w.x0, w.z0)
    return out.moves


def g94(w: CycleWords) -> list[LatheMove]:
    """G94 X(U) Z(W) [R] [F]: one face (straight or taper) cut."""
    x_end = w.end_x()
    z_end = w.end_z()
    z_cut = z_end + w.get("R", 0.0)
    out = MoveList(w.x0, w.z0)
    out.set_feed(w.get("F"))
    out.rapid(w.x0, z_cut)
    out.feed(x_end, z_end)
    out.feed(x_end, w.z0)
    out.rapid(w.x0, w.z0)
    return out.moves


def thread_lead(w: CycleWords) -> float:
    """The lead F of a threading cycle (required, positive)."""
    if not w.has("F"):
        raise w.error("FANUC-CYCLE-FEED", f"{w.cycle}: thread lead F missing")
    lead = w.params["F"]
    if lead <= 0.0:
        raise w.error("FANUC-CYCLE-FEED", f"{w.cycle}: thread lead F must be positive ({lead:g})")
    return lead


def g92(w: CycleWords) -> list[LatheMove]:
    """G92 X(U) Z(W) [R] F: one thread pass (F is the lead)."""
    x_end = w.end_x()
    z_end = w.end_z()
    lead = thread_lead(w)
    out = MoveList(w.x0, w.z0)
    out.rapid(x_end + w.get("R", 0.0), w.z0)
    out.thread(x_end, z_end, lead)
    out.rapid(w.x0, z_end)
    out.rapid(w.x0, w.z0)
    return out.moves
