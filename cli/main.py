"""The ``cnc`` command: a click group whose subcommands live one per module in ``cli/``.

Subcommands are loaded lazily so ``cnc canon`` never imports the kernel's numpy/scipy stack
or STEP-NC's cadquery. A module ``cli/<name>.py`` exposing ``command`` is registered under
the name given in ``SUBCOMMANDS``.
"""

from __future__ import annotations

import importlib
import importlib.util

import click

from cli.global_options import add_verbosity

#: command name -> module defining ``command`` (a click command or group)
SUBCOMMANDS: dict[str, str] = {
    "canon": "cli.canon",
    "plan": "cli.plan",
    "trace": "cli.trace",
    "stepnc": "cli.stepnc",
    "check": "cli.check",
    "run": "cli.run",
    "machine": "cli.machine",
    "convert": "cli.convert",
    "sim": "cli.sim",
}


class LazyGroup(click.Group):
    """A group that imports a subcommand's module only when it is used."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(n for n, m in SUBCOMMANDS.items() if importlib.util.find_spec(m))

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        module = SUBCOMMANDS.get(cmd_name)
        if module is None or importlib.util.find_spec(module) is None:
            return None
        command: click.Command = importlib.import_module(module).command
        return add_verbosity(command)


EPILOG = """\b
Examples:
  cnc canon part.ngc                     canonical machining commands
  cnc check *.ngc --format sarif -o r.sarif
  cnc plan part.ngc -m mill.toml         cycle time and limit hits
  post.py | cnc check -d fanuc -         a program on standard input
  cnc stepnc info ex1.stp                workplan, features, tools

\b
Shell completion (bash): eval "$(_CNC_COMPLETE=bash_source cnc)"
Colour is used only on a terminal; NO_COLOR=1 turns it off.
Shared options (-m, -t, -d, -o, --force, -q/-v anywhere): docs/cli.md.
Exit codes: 0 clean, 1 errors in the program(s), 2 usage or I/O error.
"""


@click.group(
    cls=LazyGroup,
    context_settings={"help_option_names": ["-h", "--help"]},
    epilog=EPILOG,
)
@click.version_option(package_name="cnc-toolchain", prog_name="cnc")
@click.option("-q", "--quiet", count=True, help="Print less (repeat for errors only).")
@click.option("-v", "--verbose", count=True, help="Print more (repeat for debugging detail).")
@click.option(
    "--limit",
    "limit_values",
    multiple=True,
    metavar="NAME=N",
    help="Change a resource limit (repeatable): digits, nesting, expression_depth, "
    "cycle_passes, loop_passes, loop_total, samples_per_move, arc_chords, nurbs_points, "
    "toolpath_passes, line_chars, seconds "
    "(docs/reliability.md).",
)
@click.pass_context
def cli(ctx: click.Context, quiet: int, verbose: int, limit_values: tuple[str, ...]) -> None:
    """cnc: G-code and STEP-NC to canonical machining commands, planning and simulation."""
    ctx.ensure_object(dict)
    ctx.obj["verbosity"] = verbose - quiet
    if limit_values:
        set_limits(limit_values)


def set_limits(values: tuple[str, ...]) -> None:
    """``NAME=N`` pairs into :func:`kernel.limits.configure` (a usage error when malformed).
    The kernel is imported here, not at the top: ``cnc --version`` loads no kernel module."""
    import kernel.limits as limits
    from kernel.diagnostics import Diagnostic

    pairs: dict[str, float] = {}
    for item in values:
        name, _, number = item.partition("=")
        try:
            pairs[name.strip()] = float(number)
        except ValueError:
            raise click.BadParameter(f"{item!r}: give NAME=N", param_hint="--limit") from None
    try:
        limits.configure(**pairs)
    except Diagnostic as exc:
        raise click.BadParameter(exc.message, param_hint="--limit") from None


def verbosity(ctx: click.Context | None = None) -> int:
    """The ``-v``/``-q`` balance of the current invocation (0 by default)."""
    ctx = ctx or click.get_current_context(silent=True)
    while ctx is not None:
        if isinstance(ctx.obj, dict) and "verbosity" in ctx.obj:
            return int(ctx.obj["verbosity"])
        ctx = ctx.parent
    return 0


def main() -> None:
    cli()


if __name__ == "__main__":
    main()
