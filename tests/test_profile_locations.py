"""A machine profile's errors name the line and column of the key at fault, as a program's
errors do (kernel.profile_where): the oracle is the position where each test wrote the key."""

from __future__ import annotations

import tomllib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kernel.axes.accdec import config_from_machine
from kernel.check.config import spindle_range
from kernel.diagnostics import Diagnostic
from kernel.machine import parse_machine
from kernel.profile_where import profile_where


def _error(text: str) -> Diagnostic:
    with pytest.raises(Diagnostic) as exc:
        parse_machine(text, "m.toml")
    return exc.value


@pytest.mark.parametrize(
    ("text", "code", "line", "column"),
    [
        ('name = "m"\n[axes.x]\nmax_velocity = -5\n', "MACH-KEY", 3, 1),
        ("[axes.x]\nvelocity = 10\n  acceleration = -5\n", "MACH-RANGE", 3, 3),
        ("[axes.x]\nmin = 10\nmax = 0\n", "MACH-RANGE", 3, 1),
        ('[axes.x]\nvelocity = 5\n\n[controller]\nmodel = "linuxcn"\n', "MACH-RANGE", 5, 1),
        ('[axes]\nx = {velocity = 5, acceleration = "fast"}\n', "MACH-TYPE", 2, 20),
        ('[axes.x]\nvelocity = 5\n[m_codes]\n31 = {name = "c", time = -2}\n', "MACH-RANGE", 4, 19),
        ('[axes.x]\nvelocity = 5\n[m_codes]\n31 = {name = "c", colour = 2}\n', "MACH-KEY", 4, 19),
        ('name = "m"\nkind = "boat"\n[axes.x]\nvelocity = 5\n', "MACH-KIND", 2, 1),
        ("[axes.x]\nvelocity = 5\n[controller]\nlookahead = 0\n", "MACH-RANGE", 4, 1),
        ('axes.x.velocity = 5\naxes."y".velocity = -1\n', "MACH-RANGE", 2, 10),
        ("[axes.q]\nvelocity = 5\n", "MACH-AXIS", 1, 1),
        ('# a comment with key = 1\n[axes.x] # x\nvelocity = """\nx"""\n', "MACH-TYPE", 3, 1),
    ],
)
def test_a_profile_error_is_located_at_the_key_that_causes_it(
    text: str, code: str, line: int, column: int
) -> None:
    err = _error(text)
    assert (err.code, err.location.file, err.location.line, err.location.column) == (
        code,
        "m.toml",
        line,
        column,
    )


def test_a_profile_error_of_a_key_not_written_is_located_at_its_table() -> None:
    err = _error("[axes.x]\nvelocity = 5\n\n[axes.y]\nmin = 3\nmax = 3\n")
    assert (err.location.line, err.location.column) == (6, 1)
    machine = parse_machine("[axes.x]\nvelocity = 5\n[spindle]\nmax_speed = 0\n", "m.toml")
    with pytest.raises(Diagnostic) as exc:
        spindle_range(machine.extra, machine.where)
    assert (exc.value.location.line, exc.value.location.column) == (3, 1)


def test_an_extra_table_error_is_located_in_the_profile_not_at_its_name() -> None:
    machine = parse_machine(
        '[axes.x]\nvelocity = 5\n[accdec]\ntype = "linear"\ntau = -1\n', "m.toml"
    )
    with pytest.raises(Diagnostic) as exc:
        config_from_machine(machine)
    loc = exc.value.location
    assert (loc.file, loc.line, loc.column) == ("m.toml", 5, 1)


_NAMES = st.from_regex(r"[a-z][a-z0-9_]{0,6}", fullmatch=True)


@settings(max_examples=150, deadline=None)
@given(
    tables=st.dictionaries(
        _NAMES,
        st.dictionaries(_NAMES, st.integers(-5, 5) | st.text("ab #=[]{}\"'", max_size=5)),
        max_size=4,
    ),
    indent=st.sampled_from(["", "  ", "\t"]),
    quoted=st.booleans(),
)
def test_every_key_position_points_at_that_key_in_the_text(
    tables: dict[str, dict[str, object]], indent: str, quoted: bool
) -> None:
    """Property: for any profile of tables and keys, the scanner's position of each key is
    where the key's name is written (the text is checked to be TOML first)."""
    lines: list[str] = []
    for table, keys in tables.items():
        lines.append(f"[{table}]")
        for key, value in keys.items():
            name = f'"{key}"' if quoted else key
            shown = value if isinstance(value, int) else repr(value).replace("\\", "")
            if isinstance(value, str):
                shown = '"' + value.replace('"', "").replace("\\", "") + '"'
            lines.append(f"{indent}{name} = {shown} # {key} = 1")
    text = "\n".join(lines) + "\n"
    data = tomllib.loads(text)
    where = profile_where(text)
    rows = text.splitlines()
    for table, keys in data.items():
        line, col = where.positions[(table,)]
        assert rows[line - 1][col - 1 :].startswith(f"[{table}]")
        for key in keys:
            line, col = where.positions[(table, key)]
            start = col - 1 + (1 if quoted else 0)
            assert rows[line - 1][start:].startswith(key)
