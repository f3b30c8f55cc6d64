"""The options every command shares, declared once so that they are spelled and behave the
same everywhere (issue 18, docs/cli.md):

- ``-m/--machine PROFILE``, ``-t/--tool-table FILE`` with ``--tool-units mm|inch``,
  ``-d/--dialect NAME`` of the commands that read programs;
- ``-q/-v``, accepted after the subcommand as well as before it (cli.global_options, which
  ``cli.main`` applies to each command as it loads it: ``cnc --version`` loads no reader);
- ``--fail-on error|warning|note`` of the batch commands, ``-o/--output`` and ``--force``;
- ``--design`` and ``--design-tol`` of the commands that compare the simulated stock with a
  design model (``cnc sim``, ``cnc check``, ``cnc run``);
- a program argument that takes ``-`` for standard input (:func:`program_argument`).

Old spellings stay accepted as hidden aliases (``--tool-file`` of ``cnc stepnc``), so
scripts written for them keep working while ``--help`` shows one vocabulary.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, TypeVar

import click

from gcode.registry import ALIASES, DEFAULT_INPUT, INPUTS, suffix_summary
from kernel.diagnostics import Severity

F = TypeVar("F", bound=Callable[..., Any])

#: the program argument's spelling of standard input, and the name it is shown under
STDIN_ARG = "-"
STDIN_NAME = "<stdin>"
#: where the invocation keeps standard input's text once read (click's ``Context.meta``)
STDIN_META = "cnc.stdin"


class AliasedOption(click.Option):
    """An option with extra spellings that work but are not shown in ``--help``."""

    def __init__(
        self, param_decls: Sequence[str], hidden_aliases: Sequence[str] = (), **attrs: Any
    ) -> None:
        super().__init__([*param_decls, *hidden_aliases], **attrs)
        self.hidden_aliases = tuple(hidden_aliases)

    def get_help_record(self, ctx: click.Context) -> tuple[str, str] | None:
        """The help line without the hidden spellings."""
        shown = [o for o in self.opts if o not in self.hidden_aliases]
        saved = self.opts
        self.opts = shown
        try:
            return super().get_help_record(ctx)
        finally:
            self.opts = saved


def machine_option(
    dest: str = "machine_path",
    help: str = "Machine profile (TOML); default: the built-in 3-axis mill.",  # noqa: A002
) -> Callable[[F], F]:
    """``-m/--machine PROFILE``: the machine profile (a TOML file that must exist)."""
    return click.option(
        "-m",
        "--machine",
        dest,
        type=click.Path(exists=True, dir_okay=False),
        default=None,
        help=help,
    )


def tool_table_option(
    dest: str = "tool_table",
    help: str = "Tool table: LinuxCNC .tbl or NIST tool file.",  # noqa: A002
    hidden_aliases: Sequence[str] = (),
    must_exist: bool = True,
) -> Callable[[F], F]:
    """``-t/--tool-table FILE`` (``hidden_aliases``: old spellings still accepted;
    ``must_exist``: a missing file is a usage error when parsing, else the command's own
    ``IO-*`` diagnostic)."""
    return click.option(
        "-t",
        "--tool-table",
        dest,
        cls=AliasedOption,
        hidden_aliases=hidden_aliases,
        type=click.Path(exists=must_exist, dir_okay=False),
        default=None,
        help=help,
    )


TOOL_UNITS_HELP = (
    "Length unit of a LinuxCNC .tbl given with -t (it has none of its own: its lengths are "
    "in the machine's units). Default: the table's header comment '; units: mm|inch', else "
    "the profile's [tools] units, else {default}."
)


def tool_units_option(default: str = "mm") -> Callable[[F], F]:
    """``--tool-units mm|inch``: the unit of the ``-t`` table's lengths (``default`` is
    named in the help: the unit the command assumes when nothing else says)."""
    return click.option(
        "--tool-units",
        "tool_units",
        type=click.Choice(["mm", "inch"]),
        default=None,
        help=TOOL_UNITS_HELP.format(default=default),
    )


def tool_library_option(help: str) -> Callable[[F], F]:
    """``--tools FILE``: the tool library (TOML, docs/simulation.md) with the tools' shapes
    for a stock simulation (cnc sim, check, trace); ``help`` says what the command uses
    it for."""
    return click.option(
        "--tools",
        "library",
        type=click.Path(exists=True, dir_okay=False),
        default=None,
        help=help,
    )


def dialect_option(func: F) -> F:
    """``-d/--dialect NAME`` of the commands that read programs."""
    return click.option(
        "-d",
        "--dialect",
        default="auto",
        show_default=True,
        type=click.Choice(["auto", *INPUTS, *ALIASES], case_sensitive=False),
        help=f"Language of G-code input: {', '.join(INPUTS)}; auto: by content and suffix "
        f"({suffix_summary()}), else {DEFAULT_INPUT}; the guess is said on stderr. Canonical "
        "text, JSON lines and Part 21 are recognised by content whatever this says.",
    )(func)


FAIL_ON = ("error", "warning", "note")


def fail_on_option(func: F) -> F:
    """``--fail-on error|warning|note``: the least severe finding that makes the exit
    status 1 (default error)."""
    return click.option(
        "--fail-on",
        "fail_on",
        type=click.Choice(FAIL_ON),
        default="error",
        show_default=True,
        help="Exit 1 when a finding of this severity or a worse one exists.",
    )(func)


def failing(severity: Severity | str, fail_on: str) -> bool:
    """Whether a finding of ``severity`` fails a run under ``--fail-on fail_on``."""
    rank = FAIL_ON.index(Severity(severity).value)
    return rank <= FAIL_ON.index(fail_on)


def output_option(
    dest: str = "output",
    help: str = "Write to this file instead of standard output.",  # noqa: A002
    file_okay: bool = True,
    dir_okay: bool = False,
    **attrs: Any,
) -> Callable[[F], F]:
    """``-o/--output PATH``."""
    return click.option(
        "-o",
        "--output",
        dest,
        type=click.Path(file_okay=file_okay, dir_okay=dir_okay),
        help=help,
        **attrs,
    )


def force_option(
    help: str = "Replace output files that already exist.",  # noqa: A002
) -> Callable[[F], F]:
    """``--force``: replace existing outputs (cli.outputs.refuse_output)."""
    return click.option("--force", is_flag=True, help=help)


def design_option(
    help: str = "Design model (STL, or STEP with cadquery): report gouges and material left.",  # noqa: A002
) -> Callable[[F], F]:
    """``--design part.stl|part.step``: the design model the simulated stock is compared
    with (docs/simulation.md)."""
    return click.option(
        "--design", type=click.Path(exists=True, dir_okay=False), default=None, help=help
    )


def design_tol_option(
    help: str = "Deviation from the design's top surface accepted (mm).",  # noqa: A002
) -> Callable[[F], F]:
    """``--design-tol MM``: the deviation from the design accepted (default 0.1 mm)."""
    return click.option(
        "--design-tol",
        type=click.FloatRange(min=0.0),
        default=0.1,
        show_default=True,
        help=help,
    )


def read_stdin() -> str:
    """Standard input as text, as a program file is read (cli.programs.read_head): UTF-8, a
    byte that is not UTF-8 replaced rather than a decoding traceback; NUL bytes stay, for
    the readers to report as ``CHECK-BINARY``."""
    return click.get_binary_stream("stdin").read().decode("utf-8", errors="replace")


def _stdin_name(ctx: click.Context, param: click.Parameter, value: Any) -> Any:
    """``-`` as the program becomes :data:`STDIN_NAME`; standard input is read here, once
    per invocation, into ``ctx.meta`` (cli.programs.stdin_text hands it to the readers)."""
    given = value if isinstance(value, tuple) else (value,)
    if STDIN_ARG not in given:
        return value
    if given.count(STDIN_ARG) > 1:
        raise click.BadParameter("standard input (-) can be given once")
    ctx.meta[STDIN_META] = read_stdin()
    if isinstance(value, tuple):
        return tuple(STDIN_NAME if v == STDIN_ARG else v for v in value)
    return STDIN_NAME


def program_argument(name: str = "program", **attrs: Any) -> Callable[[F], F]:
    """A program argument (``nargs=-1`` for several) where ``-`` is standard input, then
    named ``<stdin>`` in every diagnostic and report."""
    kind = click.Path(
        exists=attrs.pop("exists", False), dir_okay=attrs.pop("dir_okay", False), allow_dash=True
    )
    return click.argument(name, type=kind, callback=_stdin_name, **attrs)
