"""Configuration of ``cnc check``: which rules run, at what severity, with which limits.

The settings come from the machine profile's ``[check]`` table or from a ``[tool.cnc.check]``
table of a pyproject-style TOML file (documented in ``docs/check-rules.md``)::

    [check]
    disable = ["CNC108"]            # rule ids switched off
    enable = ["CNC202"]             # opt-in rules switched on at their default severity
    safe_z = 5.0                    # mm, work coordinates: rapids across XY stay above it
    stock = { min = [0, 0, -20], max = [100, 80, 0] }   # mm, work coordinates
    max_dwell = 60.0                # s
    max_blend = 1.0                 # mm: largest G64 P path deviation accepted
    max_feed = 5000.0               # mm/min: cap on programmed feeds (besides the axes')
    arc_tolerance = "linuxcnc"      # or "grbl", "mach3"
    unsupported = ["G5.2", "M7"]    # codes the target controller rejects
    tool_length = "program"         # or "machine": who applies the tool length offset

    [check.rules]
    CNC108 = "warning"              # severity override: error, warning, note or off

Values are validated; a mistake is a ``CHECK-CONFIG`` diagnostic, never a silent default.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.profile_where import ProfileWhere

ARC_TOLERANCES: dict[str, tuple[float, float, float]] = {
    # name: (absolute mm, relative, hard absolute mm) - research/anchors.md §1.1
    # LinuxCNC interp_arc.cc: 2·0.01 mm·√2 absolute and 0.1 %, hard limit 100·absolute.
    "linuxcnc": (2 * 0.01 * math.sqrt(2.0), 0.001, 100 * 2 * 0.01 * math.sqrt(2.0)),
    # Grbl: 0.005 mm and 0.1 %, hard 0.5 mm.
    "grbl": (0.005, 0.001, 0.5),
    # Mach3: 0.002 mm, no relative allowance.
    "mach3": (0.002, 0.0, 0.002),
}

_CODE_RE = re.compile(r"^([GM])(\d+)(?:\.(\d))?$")
_KEYS = {
    "disable",
    "enable",
    "rules",
    "safe_z",
    "stock",
    "max_dwell",
    "arc_tolerance",
    "unsupported",
    "tool_length",
    "max_feed",
    "max_blend",
}


@dataclass(frozen=True, slots=True)
class CheckConfig:
    """Validated check settings. ``overrides`` maps rule id -> severity, None meaning off."""

    overrides: dict[str, Severity | None] = field(default_factory=dict)
    enabled: frozenset[str] = frozenset()
    safe_z: float | None = None
    stock: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
    max_dwell: float = 60.0
    arc_tolerance: str = "linuxcnc"
    unsupported: frozenset[str] = frozenset()
    tool_length_by_program: bool = True
    max_feed: float | None = None  # mm/min
    max_blend: float = 1.0  # mm

    def severity(self, rule: str, default: Severity, enabled: bool) -> Severity | None:
        """The severity ``rule`` runs at, or None when it is off."""
        if rule in self.overrides:
            return self.overrides[rule]
        return default if enabled or rule in self.enabled else None


def normalise_code(code: str) -> str:
    """``g05.2`` -> ``G5.2``, ``M07`` -> ``M7``; raises ValueError for anything else."""
    m = _CODE_RE.match(code.strip().upper())
    if not m:
        raise ValueError(code)
    letter, num, dec = m.groups()
    return f"{letter}{int(num)}" + (f".{dec}" if dec and dec != "0" else "")


def _fail(msg: str, loc: Location) -> Diagnostic:
    return Diagnostic("CHECK-CONFIG", msg, loc)


def _num(v: object, what: str, loc: Location, positive: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float) or math.isnan(float(v)):
        raise _fail(f"{what} must be a number, not {v!r}", loc)
    if positive and not v > 0:
        raise _fail(f"{what} must be positive, got {v!r}", loc)
    return float(v)


def _rule_ids(v: object, what: str, known: set[str], loc: Location) -> list[str]:
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise _fail(f"{what} must be a list of rule ids", loc)
    for x in v:
        if x not in known:
            raise _fail(f"{what}: unknown rule {x!r}", loc)
    return list(v)


def config_from_dict(
    data: dict[str, Any], known_rules: set[str], file: str | None = None
) -> CheckConfig:
    """Validate a ``[check]`` table (already parsed TOML) into a :class:`CheckConfig`."""
    loc = Location(file)
    if not isinstance(data, dict):
        raise _fail("[check] must be a table", loc)
    unknown = set(data) - _KEYS
    if unknown:
        raise _fail(f"[check]: unknown key(s) {', '.join(sorted(unknown))}", loc)
    overrides: dict[str, Severity | None] = {}
    for rid in _rule_ids(data.get("disable", []), "check.disable", known_rules, loc):
        overrides[rid] = None
    enabled = _rule_ids(data.get("enable", []), "check.enable", known_rules, loc)
    rules = data.get("rules", {})
    if not isinstance(rules, dict):
        raise _fail("[check.rules] must be a table", loc)
    for rid, value in rules.items():
        if rid not in known_rules:
            raise _fail(f"check.rules: unknown rule {rid!r}", loc)
        if value is False or value == "off":
            overrides[rid] = None
        elif value is True:
            enabled.append(rid)
        elif isinstance(value, str) and value in {s.value for s in Severity}:
            overrides[rid] = Severity(value)
        else:
            raise _fail(f"check.rules.{rid} must be error, warning, note, off or a boolean", loc)
    kw: dict[str, Any] = {}
    if "safe_z" in data:
        kw["safe_z"] = _num(data["safe_z"], "check.safe_z", loc)
    if "stock" in data:
        kw["stock"] = _stock(data["stock"], loc)
    if "max_dwell" in data:
        kw["max_dwell"] = _num(data["max_dwell"], "check.max_dwell", loc, positive=True)
    if "max_feed" in data:
        kw["max_feed"] = _num(data["max_feed"], "check.max_feed", loc, positive=True)
    if "max_blend" in data:
        kw["max_blend"] = _num(data["max_blend"], "check.max_blend", loc, positive=True)
    if "arc_tolerance" in data:
        if data["arc_tolerance"] not in ARC_TOLERANCES:
            raise _fail(f"check.arc_tolerance must be one of {', '.join(ARC_TOLERANCES)}", loc)
        kw["arc_tolerance"] = data["arc_tolerance"]
    if "unsupported" in data:
        codes = data["unsupported"]
        if not isinstance(codes, list) or not all(isinstance(c, str) for c in codes):
            raise _fail("check.unsupported must be a list of G/M codes", loc)
        try:
            kw["unsupported"] = frozenset(normalise_code(c) for c in codes)
        except ValueError as exc:
            raise _fail(f"check.unsupported: {exc.args[0]!r} is not a G or M code", loc) from None
    if "tool_length" in data:
        if data["tool_length"] not in ("program", "machine"):
            raise _fail("check.tool_length must be 'program' or 'machine'", loc)
        kw["tool_length_by_program"] = data["tool_length"] == "program"
    return CheckConfig(overrides=overrides, enabled=frozenset(enabled), **kw)


def _stock(v: object, loc: Location) -> tuple[tuple[float, float, float], ...]:
    if not isinstance(v, dict) or set(v) != {"min", "max"}:
        raise _fail("check.stock must be a table with keys min and max", loc)
    out: list[tuple[float, float, float]] = []
    for key in ("min", "max"):
        xs = v[key]
        if not isinstance(xs, list) or len(xs) != 3:
            raise _fail(f"check.stock.{key} must be a list [x, y, z]", loc)
        what = f"check.stock.{key}"
        out.append((_num(xs[0], what, loc), _num(xs[1], what, loc), _num(xs[2], what, loc)))
    if not all(a < b for a, b in zip(out[0], out[1], strict=True)):
        raise _fail("check.stock: min must be below max on every axis", loc)
    return tuple(out)


def spindle_range(extra: dict[str, Any], where: ProfileWhere | None = None) -> tuple[float, float]:
    """(min, max) rpm from the profile's ``[spindle]`` table (``min_speed``, ``max_speed``);
    errors are located by ``where`` (the profile's key positions)."""
    at = (where or ProfileWhere()).at
    table = extra.get("spindle", {})
    if not isinstance(table, dict):
        raise _fail("[spindle] must be a table", at("spindle"))
    lo = _num(table.get("min_speed", 0.0), "spindle.min_speed", at("spindle", "min_speed"))
    hi = _num(table.get("max_speed", math.inf), "spindle.max_speed", at("spindle", "max_speed"))
    if lo < 0 or not lo < hi:
        raise _fail("spindle: need 0 <= min_speed < max_speed", at("spindle", "min_speed"))
    return lo, hi


def tool_table_spec(
    extra: dict[str, Any], where: ProfileWhere | None = None
) -> tuple[str | None, float]:
    """The profile's ``[tools]`` table: ``file`` (a ``.tbl`` or NIST tool file, relative to
    the profile) and ``units`` of its lengths (``mm`` or ``inch``); returns (file, mm/unit)."""
    at = (where or ProfileWhere()).at
    table = extra.get("tools", {})
    if not isinstance(table, dict):
        raise _fail("[tools] must be a table", at("tools"))
    path = table.get("file")
    if path is not None and not isinstance(path, str):
        raise _fail("tools.file must be a string", at("tools", "file"))
    units = table.get("units", "mm")
    if units not in ("mm", "inch"):
        raise _fail("tools.units must be 'mm' or 'inch'", at("tools", "units"))
    return path, 25.4 if units == "inch" else 1.0


def merge_tables(base: dict[str, Any], top: dict[str, Any]) -> dict[str, Any]:
    """``top`` over ``base``; the ``rules`` sub-tables and enable/disable lists combine."""
    out = dict(base)
    for k, v in top.items():
        if k == "rules" and isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = {**out[k], **v}
        elif k in ("enable", "disable") and isinstance(v, list) and isinstance(out.get(k), list):
            out[k] = [*out[k], *v]
        else:
            out[k] = v
    return out
