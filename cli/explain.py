"""Generate :mod:`cli.explanations` from ``docs/errors.md``, the one source of truth.

``docs/errors.md`` lists every diagnostic code in tables of ``| `CODE` | meaning |``; the
CLI's ``-v`` prints that meaning under a diagnostic. The docs folder is not shipped in the
package, so the table is compiled into a small module, committed, and a test
(``tests/test_diagnostics_render.py``) fails when the two drift apart. Regenerate with::

    python -m cli.explain
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "errors.md"
MODULE = ROOT / "cli" / "explanations.py"

_ROW = re.compile(r"^\| (.+?) \| (.*) \|\s*$")
_CODE = re.compile(r"`([A-Z][A-Z0-9]*(?:-[A-Z0-9.]+)+)`")


def parse(text: str) -> dict[str, str]:
    """Code -> meaning for every table row of ``docs/errors.md`` (a row may name several
    codes, as the G76 row does); a code listed in several sections gets its
    meanings joined in order (backquotes and table escapes removed)."""
    out: dict[str, str] = {}
    for line in text.splitlines():
        m = _ROW.match(line)
        if m is None:
            continue
        codes = _CODE.findall(m.group(1))
        meaning = m.group(2).replace("\\|", "|").replace("`", "").strip()
        for code in codes:
            if code in out and meaning not in out[code]:
                out[code] = f"{out[code]}; also: {meaning}"
            else:
                out.setdefault(code, meaning)
    return out


def _quote(text: str) -> str:
    """A string literal as ``ruff format`` writes it: double quotes, unless the text holds
    more double quotes than single ones (the fewer escapes win)."""
    body = text.replace("\\", "\\\\")
    if text.count('"') > text.count("'"):
        return "'" + body.replace("'", "\\'") + "'"
    return '"' + body.replace('"', '\\"') + '"'


def module_text(table: dict[str, str]) -> str:
    """The source of :mod:`cli.explanations` for ``table``."""
    lines = [
        '"""Every diagnostic code\'s meaning, generated from docs/errors.md by',
        '``python -m cli.explain`` (do not edit: edit docs/errors.md and regenerate)."""',
        "",
        "# ruff: noqa: E501",
        "",
        "EXPLANATIONS: dict[str, str] = {",
    ]
    for code in sorted(table):
        lines.append(f"    {_quote(code)}: {_quote(table[code])},")
    lines.append("}")
    return "\n".join(lines) + "\n"


def main() -> None:
    """Rewrite :mod:`cli.explanations` from ``docs/errors.md``."""
    MODULE.write_text(module_text(parse(DOC.read_text(encoding="utf-8"))), encoding="utf-8")
    print(f"wrote {MODULE}", file=sys.stderr)


if __name__ == "__main__":
    main()
