"""``cnc check`` as users and CI run it: exit codes, batches, output formats and schemas."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
import pytest
import xmlschema
from click.testing import CliRunner

from cli.main import cli
from tests.data_paths import CORPUS_STEPNC

HERE = Path(__file__).parent
PROGS = HERE / "check"
SHOP = str(PROGS / "shop.toml")
SCHEMAS = HERE / "schemas"
REPORT_SCHEMA = HERE.parent / "docs" / "schemas" / "check-report-1.schema.json"


def cnc(*args: str, env: dict[str, str] | None = None):
    return CliRunner().invoke(cli, ["check", *args], env=env, catch_exceptions=False)


def test_clean_program_exits_0() -> None:
    res = cnc("-m", SHOP, str(PROGS / "clean.canon"))
    assert res.exit_code == 0, res.output
    assert "0 errors, 0 warnings" in res.output


def test_warnings_alone_exit_0_and_errors_exit_1() -> None:
    assert cnc("-m", SHOP, str(PROGS / "CNC503.canon")).exit_code == 0
    res = cnc("-m", SHOP, str(PROGS / "CNC504.canon"))
    assert res.exit_code == 1
    assert "CNC504.canon:" in res.output and "error[CNC504]" in res.output


def test_missing_file_exits_2_and_the_rest_is_still_checked() -> None:
    res = cnc("-m", SHOP, "-f", "json", str(PROGS / "nope.ngc"), str(PROGS / "CNC504.canon"))
    assert res.exit_code == 2
    doc = json.loads(res.output)
    assert [f["status"] for f in doc["files"]] == ["io-error", "findings"]


def test_corrupt_file_is_a_finding_and_the_batch_completes(tmp_path: Path) -> None:
    bad = tmp_path / "bad.ngc"
    bad.write_bytes(b"G1 X1\x00\x01\x02garbage")
    good = tmp_path / "good.canon"
    shutil.copy(PROGS / "clean.canon", good)
    res = cnc("-m", SHOP, "-f", "json", "-j", "2", str(bad), str(good))
    assert res.exit_code == 1
    doc = json.loads(res.output)
    first, second = doc["files"]
    assert first["findings"][0]["rule"] == "CNC001"
    assert first["findings"][0]["code"] == "CHECK-BINARY"
    assert second["status"] == "clean"


def test_bad_profile_setting_is_a_diagnostic(tmp_path: Path) -> None:
    prof = tmp_path / "m.toml"
    prof.write_text("[axes.x]\nmin = 0.0\nmax = 10.0\n[check]\nsafe_height = 3\n")
    res = cnc("-m", str(prof), str(PROGS / "clean.canon"))
    assert res.exit_code == 1
    assert "error[CHECK-CONFIG]" in res.output and "safe_height" in res.output


def test_pyproject_table_reconfigures_rules(tmp_path: Path) -> None:
    cfg = tmp_path / "pyproject.toml"
    cfg.write_text('[tool.cnc.check]\nrules = { CNC504 = "warning" }\n')
    res = cnc("-m", SHOP, "--config", str(cfg), str(PROGS / "CNC504.canon"))
    assert res.exit_code == 0
    assert "warning[CNC504]" in res.output
    cfg.write_text('[tool.cnc.check]\ndisable = ["CNC504"]\n')
    res = cnc("-m", SHOP, "--config", str(cfg), str(PROGS / "CNC504.canon"))
    assert res.exit_code == 0 and "CNC504]" not in res.output


def test_parallel_batch_gives_the_same_report_as_serial() -> None:
    files = sorted(str(p) for p in PROGS.glob("*.canon"))
    one = json.loads(cnc("-m", SHOP, "-f", "json", "-j", "1", *files).output)
    two = json.loads(cnc("-m", SHOP, "-f", "json", "-j", "3", *files).output)
    strip = [
        [{k: v for k, v in f.items() if k != "seconds"} for f in d["files"]] for d in (one, two)
    ]
    assert strip[0] == strip[1]
    assert one["summary"]["files"] == len(files)


def test_directory_arguments_expand_to_programs() -> None:
    doc = json.loads(cnc("-m", SHOP, "-f", "json", str(PROGS)).stdout)
    names = {Path(f["file"]).name for f in doc["files"]}
    assert "clean.ngc" in names and "clean.canon" in names and "shop.toml" not in names


def test_text_output_has_no_colour_off_a_terminal() -> None:
    res = cnc("-m", SHOP, str(PROGS / "CNC504.canon"), env={"NO_COLOR": "1"})
    assert "\x1b[" not in res.output


def test_list_rules_shows_every_rule_and_its_state() -> None:
    res = cnc("-m", SHOP, "--list-rules")
    assert res.exit_code == 0
    lines = res.output.splitlines()
    assert len(lines) >= 25
    assert any(line.startswith("CNC601") and " warning " in line for line in lines)


def test_json_report_follows_its_published_schema() -> None:
    files = [str(p) for p in sorted(PROGS.glob("*.canon"))] + [str(PROGS / "missing.ngc")]
    doc = json.loads(cnc("-m", SHOP, "-f", "json", *files).output)
    schema = json.loads(REPORT_SCHEMA.read_text())
    jsonschema.Draft202012Validator(schema).validate(doc)
    assert doc["schema"] == "cnc-check-report" and doc["version"] == 1
    assert doc["summary"]["io_errors"] == 1


def _junit_valid(xml_path: Path) -> tuple[bool, str]:
    """Validate with the published Jenkins JUnit XSD (xmlschema, a full XSD 1.0 validator)."""
    schema = xmlschema.XMLSchema(str(SCHEMAS / "junit-10.xsd"))
    errors = [str(e) for e in schema.iter_errors(str(xml_path))]
    return not errors, "\n".join(errors[:3])


def test_junit_report_validates_against_the_jenkins_schema(tmp_path: Path) -> None:
    out = tmp_path / "check.xml"
    files = [str(p) for p in sorted(PROGS.glob("*.canon"))] + [str(PROGS / "missing.ngc")]
    res = cnc("-m", SHOP, "-f", "junit", "-o", str(out), *files)
    assert res.exit_code == 2
    ok, msg = _junit_valid(out)
    assert ok, msg
    root = ET.parse(out).getroot()
    errors = sum(1 for _ in root.iter("failure"))
    assert errors == int(root.get("failures", "-1")) > 0
    # the validator does reject a report missing a required attribute
    broken = tmp_path / "broken.xml"
    broken.write_text('<testsuites><testsuite name="x"/></testsuites>')
    assert not _junit_valid(broken)[0]


def test_sarif_report_validates_against_the_sarif_2_1_0_schema(tmp_path: Path) -> None:
    schema_file = SCHEMAS / "sarif-schema-2.1.0.json"
    out = tmp_path / "check.sarif"
    files = [str(p) for p in sorted(PROGS.glob("*.canon"))] + [str(PROGS / "missing.ngc")]
    cnc("-m", SHOP, "-f", "sarif", "-o", str(out), *files)
    doc = json.loads(out.read_text())
    schema = json.loads(schema_file.read_text())
    jsonschema.Draft4Validator(schema).validate(doc)
    run = doc["runs"][0]
    rule_ids = [r["id"] for r in run["tool"]["driver"]["rules"]]
    for res in run["results"]:
        assert rule_ids[res["ruleIndex"]] == res["ruleId"]
        assert res["locations"][0]["physicalLocation"]["region"]["startLine"] >= 1
    assert run["invocations"][0]["executionSuccessful"] is False
    doc["runs"][0]["results"][0]["level"] = "fatal"
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.Draft4Validator(schema).validate(doc)


def test_program_kind_is_detected_by_content_not_extension(tmp_path: Path) -> None:
    from cli.programs import detect_kind, read_head
    from kernel.ir import canon

    canon_as_nc = tmp_path / "prog.nc"
    shutil.copy(PROGS / "CNC504.canon", canon_as_nc)
    gcode_as_txt = tmp_path / "prog.txt"
    shutil.copy(PROGS / "CNC504.ngc", gcode_as_txt)
    with open(PROGS / "CNC504.canon") as fh:
        lines = list(canon.to_jsonl(canon.read_commands(fh, keep_linuxcnc=True)))
    jsonl = tmp_path / "prog.data"
    jsonl.write_text("\n".join(lines) + "\n")
    stp = CORPUS_STEPNC / "ex1.stp"
    assert detect_kind(read_head(str(canon_as_nc))) == "canon"
    assert detect_kind(read_head(str(gcode_as_txt))) == "gcode"
    assert detect_kind(read_head(str(jsonl))) == "jsonl"
    assert detect_kind(read_head(str(stp))) == "part21"  # opens with a /* comment */
    for p in (canon_as_nc, jsonl):
        doc = json.loads(cnc("-m", SHOP, "-f", "json", str(p)).output)
        assert [f["rule"] for f in doc["files"][0]["findings"]] == ["CNC504"]
    doc = json.loads(cnc("-f", "json", str(stp)).output)
    assert "CNC001" not in {f["rule"] for f in doc["files"][0]["findings"]}


def test_quiet_levels() -> None:
    files = [str(PROGS / "CNC503.canon"), str(PROGS / "CNC504.canon")]
    loud = CliRunner().invoke(cli, ["check", "-m", SHOP, *files]).output
    quiet = CliRunner().invoke(cli, ["-q", "check", "-m", SHOP, *files]).output
    errors_only = CliRunner().invoke(cli, ["-qq", "check", "-m", SHOP, *files]).output
    assert "files with findings" in loud and "files with findings" not in quiet
    assert "warning[CNC503]" in quiet and "2 files checked" in quiet
    assert errors_only.strip().splitlines() == [
        line for line in loud.splitlines() if "error[CNC504]" in line
    ]


def test_a_bug_in_a_rule_is_reported_and_the_batch_goes_on(monkeypatch) -> None:
    from dataclasses import replace

    from kernel.check import RULES

    def boom(cmd, st, ctx):  # noqa: ANN001, ANN202
        raise ZeroDivisionError("rule bug")

    monkeypatch.setitem(RULES, "CNC040", replace(RULES["CNC040"], check=boom, kinds=()))
    files = [str(PROGS / "clean.canon"), str(PROGS / "CNC504.canon")]
    doc = json.loads(cnc("-m", SHOP, "-f", "json", *files).output)
    for f in doc["files"]:
        assert f["findings"][0]["code"] == "CHECK-INTERNAL"
        assert "ZeroDivisionError" in f["findings"][0]["message"]
