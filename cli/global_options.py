"""``-q``/``-v`` after the subcommand as well as before it: ``cnc check -q x.ngc`` is
``cnc -q check x.ngc``. ``cli.main`` applies :func:`add_verbosity` to each command as it
loads it; this module imports nothing of the readers or the kernel (``cnc --version`` stays
light)."""

from __future__ import annotations

from collections.abc import Callable

import click


def _adjust(sign: int) -> Callable[[click.Context, click.Parameter, int], None]:
    """A callback adding ``sign * count`` to the invocation's ``-v``/``-q`` balance."""

    def callback(ctx: click.Context, param: click.Parameter, value: int) -> None:
        if not value:
            return
        root = ctx.find_root()
        root.ensure_object(dict)
        root.obj["verbosity"] = int(root.obj.get("verbosity", 0)) + sign * value
        if ctx.obj is not root.obj:
            ctx.ensure_object(dict)
            ctx.obj["verbosity"] = root.obj["verbosity"]

    return callback


def _verbosity_params() -> list[click.Parameter]:
    return [
        click.Option(
            ["-q", "--quiet"],
            count=True,
            expose_value=False,
            callback=_adjust(-1),
            help="Print less (as cnc -q; repeat for errors only).",
        ),
        click.Option(
            ["-v", "--verbose"],
            count=True,
            expose_value=False,
            callback=_adjust(+1),
            help="Print more (as cnc -v; repeat for debugging detail).",
        ),
    ]


def add_verbosity(command: click.Command) -> click.Command:
    """``command`` (and each subcommand of a group) accepting ``-q``/``-v`` after its name,
    the same as before it; a command that declares either spelling itself keeps its own."""
    taken = {o for p in command.params for o in p.opts}
    if not taken & {"-q", "--quiet", "-v", "--verbose"}:
        command.params.extend(_verbosity_params())
    if isinstance(command, click.Group):
        for sub in command.commands.values():
            add_verbosity(sub)
    return command
