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
block that moves, until ``MCALL`` alone. Other cycles are refused (SIEM-CYCLE-UNSUPPORTED).
"""

from __future__ import annotations

from gcode.siemens import motion
from gcode.siemens.expr import Node, Variables, evaluate
from gcode.siemens.machine import Machine, Values
from gcode.siemens.state import PLANES
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

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


def run_cycle(ex: Machine, name: str, args: tuple, scope: Variables) -> None:
    """Expand one drilling cycle at the current position."""
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
