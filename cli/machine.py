"""``cnc machine``: show the effective profile, validate profiles, write a starter profile.

Examples::

    cnc machine show                  # the built-in default 3-axis mill
    cnc machine show mill.toml        # mill.toml with every default filled in
    cnc machine validate mill.toml lathe.toml
    cnc machine init -o mill.toml     # a commented starter profile

The profile format is kernel.machine's (docs/machine-profile.md); ``validate`` also checks
the ``[check]``, ``[spindle]`` and ``[tools]`` tables ``cnc check`` reads (docs/check-rules.md)
and that the tool table they name can be read.
"""

from __future__ import annotations

import json
import math
import sys
from dataclasses import fields
from typing import Any

import click

from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, EXIT_USAGE, guarded, report
from cli.options import force_option, machine_option, output_option
from cli.outputs import refuse_output, write_output
from cli.programs import load_machine
from kernel.diagnostics import Diagnostic, Location
from kernel.machine import DEFAULT_MACHINE, KINDS, AxisLimits, Controller, Machine
from kernel.machine_presets import PRESETS

_HEAD = """\
# cnc machine profile (TOML). Units: mm, degrees, seconds. Reference: docs/machine-profile.md
# {about}
name = "{name}"
# What the machine is: mill, router, laser, plasma or lathe. `cnc check` judges programs as
# this kind of machine runs them (docs/machine-profile.md, "Presets").
kind = "{kind}"

# One table per axis (x y z a b c): travel limits in machine coordinates, velocity (per s),
# acceleration (per s^2) and jerk (per s^3).
"""

_MIDDLE = """
# Controller: interpolation period (s), look-ahead depth (blocks), acc/dec profile
# ("trapezoid" or "scurve"), blending tolerance for G64 without P (mm).
[controller]
interpolation_period = 0.001
lookahead = 200
accdec = "trapezoid"
blend_tolerance = 0.0
"""

_SPINDLE = {
    "laser": "# Laser power: the range of S (Grbl's $30), judged by `cnc check` (CNC501).\n",
    "plasma": "# The torch has no speed: S is not judged. A spindle range would be\n",
}

_TAIL = """
# Tool table: a LinuxCNC .tbl or NIST tool file relative to this profile, and the unit of
# its lengths ("mm" or "inch").
# [tools]
# file = "tools.tbl"
# units = "mm"

# M codes the machine's PLC takes (MACHINE_FUNCTION events of Fanuc, Haas and Siemens
# programs): a name, the seconds the machine stops there (default 0) and `forbid = true` for
# one it must never be sent. `cnc check` notes M codes not listed here (CNC702).
[m_codes]
# 31 = { name = "chip conveyor on", time = 0.0 }
# 32 = { name = "chip conveyor off", time = 0.0 }
# 10 = { name = "clamp", time = 1.5 }
# 75 = { name = "tool setter", forbid = true }

# `cnc check` settings (docs/check-rules.md): uncomment what applies to your shop.
[check]
# safe_z = 5.0                                        # mm, work coordinates
# stock = { min = [0.0, 0.0, -20.0], max = [100.0, 80.0, 0.0] }
# unsupported = ["G5.2"]                              # codes your controller rejects
# disable = []                                        # rule ids switched off
# enable = ["CNC601"]                                 # opt-in rules switched on
"""


def starter(kind: str = "mill") -> str:
    """The commented starter profile of a kind of machine (kernel.machine_presets)."""
    p = PRESETS[kind]
    out = [_HEAD.format(about=p.about, name=p.name, kind=p.kind)]
    for a in p.axes:
        out.append(
            f"[axes.{a.name}]\nmin = {a.min!r}\nmax = {a.max!r}\nvelocity = {a.velocity!r}\n"
            f"acceleration = {a.acceleration!r}\njerk = {a.jerk!r}\n\n"
        )
    out[-1] = out[-1][:-1]
    out.append(_MIDDLE)
    out.append(
        "\n"
        + _SPINDLE.get(
            kind, "# Spindle speed range (rpm), judged by `cnc check` (CNC501, CNC502).\n"
        )
    )
    if p.spindle is None:
        out.append("# [spindle]\n# max_speed = 1.0\n")
    else:
        out.append(f"[spindle]\nmin_speed = {p.spindle[0]!r}\nmax_speed = {p.spindle[1]!r}\n")
    out.append(_TAIL)
    out.extend(f"{k} = {_value(v)}\n" for k, v in p.check.items())
    return "".join(out)


# --------------------------------------------------------------------------- TOML writing
def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {v!r} as TOML")


def _table(name: str, d: dict[str, Any], out: list[str]) -> None:
    simple = {k: v for k, v in d.items() if not isinstance(v, dict)}
    nested = {k: v for k, v in d.items() if isinstance(v, dict)}
    out.append(f"\n[{name}]")
    out.extend(f"{k} = {_value(v)}" for k, v in simple.items())
    for k, v in nested.items():
        _table(f"{name}.{k}", v, out)


def machine_dict(m: Machine) -> dict[str, Any]:
    """The effective profile as plain data (every default filled in)."""
    axes = {}
    for a in m.axes:
        d = {f.name: getattr(a, f.name) for f in fields(AxisLimits) if f.name != "name"}
        if not d["servo"]:
            del d["servo"]
        axes[a.name] = d
    ctrl = {f.name: getattr(m.controller, f.name) for f in fields(Controller)}
    out: dict[str, Any] = {"name": m.name, "kind": m.kind, "axes": axes, "controller": ctrl}
    if m.m_codes:
        out["m_codes"] = {
            str(code): {"name": spec.name, "time": spec.time, "forbid": spec.forbid}
            for code, spec in sorted(m.m_codes.items())
        }
    return {**out, **m.extra}


def machine_toml(m: Machine) -> str:
    d = machine_dict(m)
    out = [f"name = {_value(d['name'])}", f"kind = {_value(d['kind'])}"]
    for name, axis in d["axes"].items():
        _table(f"axes.{name}", axis, out)
    _table("controller", d["controller"], out)
    if "m_codes" in d:  # one inline table per code: `31 = { name = ..., time = ... }`
        out.append("\n[m_codes]")
        out.extend(f"{code} = {_value(spec)}" for code, spec in d["m_codes"].items())
    for k, v in d.items():
        if k in ("name", "kind", "axes", "controller", "m_codes"):
            continue
        if isinstance(v, dict):
            _table(k, v, out)
        else:
            out.insert(1, f"{k} = {_value(v)}")
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------- commands
@click.group("machine")
def command() -> None:
    """Show, validate or create machine profiles.

    \b
    Examples:
      cnc machine init -o mill.toml
      cnc machine validate mill.toml
      cnc machine show mill.toml -f json
    """


@command.command("show")
@click.argument("profile", required=False, type=click.Path(exists=True, dir_okay=False))
@machine_option(help="The profile to show, as in the other commands (same as PROFILE).")
@click.option(
    "--format", "-f", "fmt", type=click.Choice(["toml", "json"]), default="toml", show_default=True
)
@guarded
def show(profile: str | None, machine_path: str | None, fmt: str) -> None:
    """Print the effective profile: PROFILE (default: the built-in mill) with defaults filled.

    \b
    Examples:
      cnc machine show
      cnc machine show mill.toml -f json
      cnc machine show -m mill.toml
    """
    if profile and machine_path:
        raise click.UsageError("give the profile once: PROFILE or -m PROFILE")
    profile = profile or machine_path
    m = load_machine(profile) if profile else DEFAULT_MACHINE
    if fmt == "json":
        click.echo(json.dumps(machine_dict(m), indent=2, default=str))
    else:
        click.echo(machine_toml(m), nl=False)


def validate_profile(path: str) -> Machine:
    """Parse ``path`` and check the tables ``cnc check`` reads; raises Diagnostic."""
    from cli.check import load_context

    m = load_machine(path)
    try:
        load_context(path, path, None)
    except OSError as exc:  # a tool table named by the profile that cannot be read
        raise Diagnostic(
            "MACH-TOOLS",
            f"cannot read the tool table: {exc.strerror or exc}",
            Location(getattr(exc, "filename", None) or path),
        ) from None
    return m


@command.command("validate")
@click.argument("profiles", nargs=-1, required=True, type=click.Path(dir_okay=False))
def validate(profiles: tuple[str, ...]) -> None:
    """Check that each profile is valid; report every broken one.

    \b
    Example:
      cnc machine validate mill.toml lathe.toml
    """
    code = EXIT_OK
    for p in profiles:
        try:
            m = validate_profile(p)
        except Diagnostic as diag:
            report(diag)
            code = max(code, EXIT_PROGRAM_ERROR)
            continue
        except OSError as exc:
            click.echo(f"{p}: error[IO-ERROR]: {exc.strerror or exc}", err=True)
            code = EXIT_USAGE
            continue
        axes = "".join(m.axis_names).upper()
        click.echo(f"{p}: ok ({m.name}, axes {axes})")
    sys.exit(code)


@command.command("init")
@output_option(help="File to write (default: standard output).")
@force_option(help="Overwrite an existing file.")
@click.option(
    "--kind",
    "-k",
    type=click.Choice(list(KINDS)),
    default="mill",
    show_default=True,
    help="Kind of machine: its typical limits, and `cnc check` judges programs as it runs them.",
)
@guarded
def init(output: str | None, force: bool, kind: str) -> None:
    """Write a commented starter profile for a kind of machine.

    \b
    Examples:
      cnc machine init -o mill.toml && cnc machine validate mill.toml
      cnc machine init --kind laser -o laser.toml
    """
    text = starter(kind)
    if output is None:
        click.echo(text, nl=False)
        return
    refuse_output(output, force, what="file")
    write_output(output, text)
    click.echo(f"wrote {output}", err=True)
