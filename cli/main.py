"""The ``cnc`` command: a click group whose subcommands live one per module in ``cli/``.

Subcommands are loaded lazily so ``cnc canon`` never imports the kernel's numpy/scipy stack
or STEP-NC's cadquery. A module ``cli/<name>.py`` exposing ``command`` is registered under
the name given in ``SUBCOMMANDS``.
"""

from __future__ import annotations

import importlib
import importlib.util

import click

#: command name -> module defining ``command`` (a click command or group)
SUBCOMMANDS: dict[str, str] = {
    "canon": "cli.canon",
    "plan": "cli.plan",
    "trace": "cli.trace",
    "stepnc": "cli.stepnc",
}


class LazyGroup(click.Group):
    """A group that imports a subcommand's module only when it is used."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(n for n, m in SUBCOMMANDS.items() if importlib.util.find_spec(m))

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        module = SUBCOMMANDS.get(cmd_name)
        if module is None or importlib.util.find_spec(module) is None:
            return None
        return importlib.import_module(module).command


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="cnc-toolchain", prog_name="cnc")
def cli() -> None:
    """cnc: G-code and STEP-NC to canonical machining commands, planning and simulation."""


def main() -> None:
    cli()


if __name__ == "__main__":
    main()
