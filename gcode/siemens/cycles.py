"""Drilling cycles of the 840D expanded into moves (SINUMERIK 840D sl cycles manual,
"Drilling, centering - CYCLE81" and "Drilling, counterboring - CYCLE82").

``CYCLE81(RTP, RFP, SDIS, DP, DPR)`` and ``CYCLE82(RTP, RFP, SDIS, DP, DPR, DTB)`` drill at
the current position along the applicate (the axis normal to the active plane; Z in G17):

1. G0 to the reference plane plus the safety distance, ``RFP + SDIS``;
2. G1 to the final depth at the feed programmed before the call: ``RFP - DPR`` when DPR is
   given (DPR wins over DP, as the manual states), else ``DP``;
3. CYCLE82 only: dwell ``DTB`` seconds at depth;
4. G0 back to the retraction plane ``RTP``.

Omitted parameters are 0. ``MCALL CYCLE81(...)`` repeats the cycle after every following
block that moves, until ``MCALL`` alone.

Two setting cycles that CAM output for the 840D calls in nearly every program are read
without moves (cycles manual, "High speed settings - CYCLE832" and "Swiveling - CYCLE800"):
``CYCLE832(TOL, ...)`` sets continuous-path mode with blending within the path tolerance
TOL (as G642 with that tolerance), and ``CYCLE832()`` (no tolerance: the deselection) the
exact stop G60; ``CYCLE800()`` (no parameters: swivel off) and a ``CYCLE800`` that states
its offsets and angles (parameters 5 to 13) all 0 leave the work plane as it is (the
retraction it may order first moves to machine-data positions the IR cannot know, and is
left out). Any other swivel, and every other cycle, is refused (SIEM-CYCLE-UNSUPPORTED).
"""

from __future__ import annotations

from gcode.siemens import motion
from gcode.siemens.expr import Node, Variables, evaluate
from gcode.siemens.machine import Machine, Values
from gcode.siemens.state import PLANES
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

#: the 840D standard cycles whose names do not begin with CYCLE (cycles manual: drilling
#: patterns HOLES1, HOLES2; milling patterns LONGHOLE, SLOT1, SLOT2, POCKET1 to POCKET4):
#: called without a program file of that name they are the control's cycles, not missing
#: subprograms
STANDARD_CYCLES = frozenset(
    ("HOLES1", "HOLES2", "LONGHOLE", "SLOT1", "SLOT2", "POCKET1", "POCKET2", "POCKET3", "POCKET4")
)
#: cycle -> its parameters that the expansion uses, in call order
PARAMETERS = {
    "CYCLE81": ("RTP", "RFP", "SDIS", "DP", "DPR"),
    "CYCLE82": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB"),
}


def check_cycle(ex: Machine, name: str, args: tuple[Node | None, ...]) -> None:
    if name not in PARAMETERS:
        raise Diagnostic(
            "SIEM-CYCLE-UNSUPPORTED",
            f"{name} is not expanded by this reader (CYCLE81, CYCLE82 are)",
            ex.loc,
        )
    if len(args) > len(PARAMETERS[name]):
        raise Diagnostic(
            "SIEM-CYCLE-ARGS", f"{name} takes at most {len(PARAMETERS[name])} parameters", ex.loc
        )


def _number(node: Node | None, scope: Variables) -> float:
    return 0.0 if node is None else evaluate(node, scope)


def setting_cycle(ex: Machine, name: str, args: tuple, scope: Variables) -> bool:
    """Run CYCLE832 or a CYCLE800 to the unswivelled plane (True), else False."""
    if name == "CYCLE832":
        tol = _number(args[0] if args else None, scope)
        if tol < 0:
            raise Diagnostic("SIEM-CYCLE-ARGS", "CYCLE832: negative tolerance", ex.loc)
        ex.s.control = 642 if tol > 0 else 60
        mode = canon.MotionMode.CONTINUOUS if tol > 0 else canon.MotionMode.EXACT_STOP
        ex.emit(canon.SetMotionControlMode(mode, tol, source=ex.loc))
        return True
    if name == "CYCLE800" and any(a is not None for a in args) and len(args) < 13:
        return False  # neither "swivel off" nor a swivel stating its offsets and angles
    if name == "CYCLE800":
        swivel = [_number(node, scope) for node in args[4:13]]
        if any(abs(value) > 1e-12 for value in swivel):
            raise Diagnostic(
                "SIEM-CYCLE-UNSUPPORTED",
                "CYCLE800 swivelling the work plane (offsets or angles not 0) is not read: "
                "the IR has no swivelled plane",
                ex.loc,
            )
        return True
    return False


def run_cycle(ex: Machine, name: str, args: tuple, scope: Variables) -> None:
    """Expand one drilling cycle at the current position."""
    if setting_cycle(ex, name, args, scope):
        return
    check_cycle(ex, name, args)
    p = dict.fromkeys(PARAMETERS[name], 0.0)
    for key, node in zip(PARAMETERS[name], args, strict=False):
        if node is not None:
            p[key] = evaluate(node, scope)
    if p["SDIS"] < 0 or p["DPR"] < 0 or p.get("DTB", 0.0) < 0:
        raise Diagnostic(
            "SIEM-CYCLE-ARGS", f"{name}: SDIS, DPR and DTB are given without sign", ex.loc
        )
    depth = p["RFP"] - p["DPR"] if p["DPR"] else p["DP"]
    top = p["RFP"] + p["SDIS"]
    if not depth < top <= p["RTP"]:
        raise Diagnostic(
            "SIEM-CYCLE-ARGS",
            f"{name}: the depth must lie below RFP + SDIS ({top:g}) and RTP not below it",
            ex.loc,
        )
    s = ex.s
    axis = "XYZ"[PLANES[s.plane][1][2]]
    saved = (s.motion, s.absolute)
    s.absolute = True
    try:
        dwell = p.get("DTB", 0.0)  # CYCLE82's (CYCLE81 has none)
        for code, value in ((0, top), (1, depth), (None, dwell), (0, p["RTP"])):
            if code is None:
                if name == "CYCLE82":
                    ex.emit(canon.Dwell(value, source=ex.loc))
                continue
            s.motion = code
            motion.execute(ex, Values(v={axis: value}), False)
    finally:
        s.motion, s.absolute = saved
