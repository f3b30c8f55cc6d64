"""The simulation's findings as ``cnc check`` rules (CNC9xx), run when stock is given.

Each ``SIM-*`` finding code has a check rule id; a finding keeps its ``SIM-*`` code as the
check finding's ``code`` and its severity comes from the check configuration
(``[check.rules]``), so CI sees the simulation like the other rules. These rules are not
in :data:`kernel.check.RULES` (judged on the canonical stream alone): they need the stock,
so ``cnc check`` runs them only with ``--stock`` or a profile's ``[stock]`` (and the
design rules only with ``--design``).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from kernel.check import CheckContext, Finding
from kernel.check.rules import Rule
from kernel.diagnostics import Diagnostic, Severity
from kernel.ir import canon
from kernel.stock.design import compare_design
from kernel.stock.heightfield import HeightField, StockBox
from kernel.stock.simulate import RULES as SIM_SEVERITY
from kernel.stock.simulate import SimResult, simulate_removal
from kernel.stock.solids import Fixture
from kernel.stock.tools import ToolShape
from kernel.stock.turning import Bar, TurnedProfile, simulate_turning

#: SIM finding code -> (check rule id, name, summary)
_IDS: dict[str, tuple[str, str, str]] = {
    "SIM-RAPID-IN-STOCK": (
        "CNC901",
        "sim-rapid-in-stock",
        "Simulated: a rapid move's swept tool enters material still there at that time.",
    ),
    "SIM-HOLDER": (
        "CNC902",
        "sim-holder-contact",
        "Simulated: the shank above the flutes or the holder touches material.",
    ),
    "SIM-FLUTE-DEPTH": (
        "CNC903",
        "sim-flute-depth",
        "Simulated: a feed move cuts deeper than the tool's flute length.",
    ),
    "SIM-PLUNGE-NON-CENTRE": (
        "CNC904",
        "sim-plunge-non-centre",
        "Simulated: a plunge that cuts, with a tool that does not cut at its centre.",
    ),
    "SIM-AIR-CUTTING": (
        "CNC905",
        "sim-air-cutting",
        "Simulated: more than half of a tool's feed path removes no material.",
    ),
    "SIM-GOUGE": (
        "CNC906",
        "sim-gouge",
        "Simulated with --design: the final stock is below the design's surface.",
    ),
    "SIM-LEFTOVER": (
        "CNC907",
        "sim-leftover",
        "Simulated with --design: material is left above the design's surface.",
    ),
    "SIM-FIXTURE": (
        "CNC908",
        "sim-fixture",
        "Simulated: the tool, its shank or its holder enters a fixture.",
    ),
}

#: the simulation's check rules by id
SIM_RULES: dict[str, Rule] = {
    rid: Rule(rid, name, SIM_SEVERITY[code], summary) for code, (rid, name, summary) in _IDS.items()
}
#: check rule id of each SIM finding code
RULE_OF: dict[str, str] = {code: ids[0] for code, ids in _IDS.items()}


@dataclass(frozen=True, slots=True)
class SimSetup:
    """What ``cnc check`` needs to simulate a program (picklable): the stock box, and the
    stock's initial top (a mesh stock, on the box's grid at ``resolution``), the design's
    top surface on that grid (``--design``) and the fixtures, where given. A :class:`Bar`
    is a lathe's stock: the turning profile (kernel.stock.turning)."""

    box: StockBox | Bar
    tools: dict[int, ToolShape] = field(default_factory=dict)
    resolution: float = 0.5
    chord_tol: float = 0.005
    stock_top: np.ndarray | None = None
    design_top: np.ndarray | None = None
    design_tol: float = 0.1
    fixtures: tuple[Fixture, ...] = ()


def sim_findings(
    commands: Iterable[canon.Command],
    setup: SimSetup,
    ctx: CheckContext,
    program: str | None = None,
) -> list[Finding]:
    """Simulate the program on the stock and give its findings as check findings at the
    configured severities (a rule switched off gives none). A program the simulation
    refuses (a rotary axis, a NURBS move) is a CNC001 finding with its ``SIM-*`` code.
    ``program`` locates a design finding at a cell no move cut."""
    try:
        if isinstance(setup.box, Bar):
            prof = TurnedProfile(setup.box, setup.resolution)
            return as_check(simulate_turning(commands, prof, setup.tools, setup.chord_tol), ctx)
        hf = HeightField(setup.box, setup.resolution)
        if setup.stock_top is not None:
            hf.h[...] = setup.stock_top
        result = simulate_removal(
            commands,
            hf,
            setup.tools,
            setup.chord_tol,
            track_moves=setup.design_top is not None,
            fixtures=setup.fixtures,
        )
    except Diagnostic as exc:
        return [Finding("CNC001", Severity.ERROR, exc.message, exc.location, exc.code)]
    if setup.design_top is not None:
        compare_design(hf, setup.design_top, result, setup.design_tol, program)
    return as_check(result, ctx)


def as_check(result: SimResult, ctx: CheckContext) -> list[Finding]:
    """The simulation's findings at their configured severities (a rule switched off
    gives none)."""
    out = []
    for f in result.findings:
        rule = SIM_RULES[RULE_OF[f.code]]
        sev = ctx.config.severity(rule.id, rule.severity, rule.default_enabled)
        if sev is not None:
            out.append(Finding(rule.id, sev, f.message, f.location, f.code))
    return out
