"""``cnc machine show|validate|init``."""

from __future__ import annotations

import tomllib
from pathlib import Path

from click.testing import CliRunner

from cli.main import cli
from kernel.machine import DEFAULT_MACHINE, parse_machine

PROGS = Path(__file__).parent / "check"


def cnc(*args: str):
    return CliRunner().invoke(cli, ["machine", *args], catch_exceptions=False)


def test_init_writes_a_profile_that_validates_and_round_trips(tmp_path: Path) -> None:
    prof = tmp_path / "mill.toml"
    assert cnc("init", "-o", str(prof)).exit_code == 0
    assert "#" in prof.read_text()  # commented
    res = cnc("validate", str(prof))
    assert res.exit_code == 0 and "ok" in res.output
    shown = cnc("show", str(prof)).output
    again = parse_machine(shown)
    assert again == parse_machine(prof.read_text())
    assert cnc("init", "-o", str(prof)).exit_code == 2  # never overwrites silently


def test_show_without_profile_is_the_default_machine() -> None:
    shown = cnc("show").output
    assert parse_machine(shown) == DEFAULT_MACHINE
    assert "interpolation_period" in tomllib.loads(shown)["controller"]


def test_validate_reports_every_broken_profile(tmp_path: Path) -> None:
    bad_axis = tmp_path / "a.toml"
    bad_axis.write_text("[axes.q]\nmin = 0.0\n")
    bad_check = tmp_path / "b.toml"
    bad_check.write_text("[axes.x]\nmin = 0.0\nmax = 1.0\n[check]\nmax_dwell = -1\n")
    bad_tools = tmp_path / "c.toml"
    bad_tools.write_text('[axes.x]\nmin = 0.0\nmax = 1.0\n[tools]\nfile = "none.tbl"\n')
    res = CliRunner().invoke(
        cli,
        [
            "machine",
            "validate",
            str(bad_axis),
            str(bad_check),
            str(bad_tools),
            str(PROGS / "shop.toml"),
        ],
    )
    assert res.exit_code == 1
    assert "MACH-AXIS" in res.stderr and "CHECK-CONFIG" in res.stderr
    assert "MACH-TOOLS" in res.stderr
    assert "shop.toml: ok" in res.stdout
