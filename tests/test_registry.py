"""The dialect registry is the one table every dialect lookup and CLI choice comes from."""

from __future__ import annotations

import importlib

import click
import pytest
from click.testing import CliRunner

from cli.main import cli
from gcode import registry
from gcode.registry import REGISTRY
from kernel.diagnostics import Diagnostic


@pytest.mark.parametrize("entry", REGISTRY, ids=[e.name for e in REGISTRY])
def test_every_row_names_modules_that_hold_what_it_says(entry: registry.DialectEntry) -> None:
    if entry.dialect is not None:
        assert importlib.import_module(entry.dialect).DIALECT.name == entry.name
        assert registry.get_dialect(entry.name).name == entry.name
    if entry.reader is not None:
        module = importlib.import_module(entry.reader)
        assert callable(module.interpret) and callable(module.interpret_text)
    for alias in entry.aliases:
        assert registry.canonical_name(alias.upper()) == entry.name


def test_names_aliases_and_suffixes_are_unique() -> None:
    names = [e.name for e in REGISTRY]
    aliases = [a for e in REGISTRY for a in e.aliases]
    suffixes = [s for e in REGISTRY for s in e.suffixes]
    assert len(set(names + aliases)) == len(names) + len(aliases)
    assert len(set(suffixes)) == len(suffixes)


def test_an_unknown_name_is_a_located_diagnostic_listing_the_known_ones() -> None:
    with pytest.raises(Diagnostic) as info:
        registry.get_dialect("heidenhain")
    assert info.value.code == "CONV-DIALECT"
    assert all(name in info.value.message for name in registry.NAMES)


def test_a_suffix_names_its_dialect_else_rs274ngc() -> None:
    assert registry.dialect_for_suffix(".MPF") == "siemens840d"
    assert registry.dialect_for_suffix(".spf") == "siemens840d"
    assert registry.dialect_for_suffix(".nc") == "rs274ngc"


def _choices(command: str, option: str) -> list[str]:
    group = cli
    ctx = click.Context(group)
    cmd = group.get_command(ctx, command)
    assert cmd is not None
    param = next(p for p in cmd.params if option in getattr(p, "opts", ()))
    assert isinstance(param.type, click.Choice)
    return list(param.type.choices)


def test_the_cli_choices_are_generated_from_the_registry() -> None:
    every_name = [*registry.NAMES, *registry.ALIASES]
    assert _choices("convert", "--to") == every_name
    assert set(_choices("convert", "--from")) >= {*registry.INPUTS, *registry.ALIASES}
    assert set(_choices("check", "--dialect")) >= {*registry.INPUTS, *registry.ALIASES}
    help_text = CliRunner().invoke(cli, ["convert", "--help"]).output
    assert all(name in help_text for name in registry.NAMES)
