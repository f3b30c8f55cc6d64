"""How the CLI reports problems: compiler-style diagnostics and DESIGN.md exit codes.

Exit codes: 0 clean, 1 errors in the program(s), 2 usage or I/O error.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable
from typing import ParamSpec, TypeVar

import click

from cli.excerpt import render_diagnostic
from cli.main import verbosity
from kernel.diagnostics import Diagnostic, Location

EXIT_OK = 0
EXIT_PROGRAM_ERROR = 1
EXIT_USAGE = 2
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE

P = ParamSpec("P")
R = TypeVar("R")


def report(diag: Diagnostic) -> None:
    """Print one diagnostic to stderr: ``file:line:col: error[CODE]: message``, then the
    source line with a caret and, with ``-v``, the code's explanation (:mod:`cli.excerpt`)."""
    click.echo(render_diagnostic(diag, verbosity()), err=True)


def guarded(func: Callable[P, R]) -> Callable[P, R]:
    """Run a command body; turn diagnostics and I/O errors into messages and exit codes."""

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return func(*args, **kwargs)
        except Diagnostic as diag:
            report(diag)
            sys.exit(EXIT_USAGE if diag.code.startswith("IO-") else EXIT_PROGRAM_ERROR)
        except BrokenPipeError:
            # the reader of standard output went away (``| head``): stop quietly with the
            # status of a C tool killed by SIGPIPE, and keep Python from complaining at exit
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            sys.exit(EXIT_BROKEN_PIPE)
        except OSError as exc:
            name = getattr(exc, "filename", None) or ""
            click.echo(f"{name}: error[IO-ERROR]: {exc.strerror or exc}", err=True)
            sys.exit(EXIT_USAGE)
        except MemoryError:
            # the last net (the stages that hold a whole program say where it ran out
            # themselves): a coded error at the program, not a traceback
            given = kwargs.get("program") or kwargs.get("file")
            report(
                Diagnostic(
                    "LIMIT-MEMORY",
                    "out of memory: the program needs more memory than there is",
                    Location(given if isinstance(given, str) else None),
                )
            )
            sys.exit(EXIT_PROGRAM_ERROR)

    return wrapper
