"""`docs/rules/`: one page per code of `codes.RULES`, and an index, written from the table.

`python -m btgen.tools.check.rules_doc [DIR]` (re)writes them (default: docs/rules of the
repository); `tests/python/test_check_rules.py` fails when the pages on disk are not what the
table gives, and runs every example through `btgen check`.
"""

from __future__ import annotations

import os
import sys
from typing import Optional

from btgen.tools.check.codes import RULES, Rule

_SOURCES = {
    "loader": "the front end and the IR (what `btgen validate` and `btgen compile` report)",
    "analysis": "the analysis of `btgen analyze`",
    "upgrade": "`btgen upgrade-check` (reported when `upgrade-to` is set in the configuration)",
    "check": "`btgen check` itself, from what it knows of the whole project",
    "config": "the configuration file",
}


def _files(files: dict[str, str]) -> list[str]:
    out = []
    for name, text in files.items():
        out += [
            f"`{name}`:",
            "",
            "<!-- docs-test: not run: tests/python/test_check_rules.py runs it through btgen check -->",
            "```xml",
            text.rstrip("\n"),
            "```",
            "",
        ]
    return out


def page(rule: Rule) -> str:
    lines = [
        f"# {rule.code} `{rule.name}`",
        "",
        f"**{rule.severity}** by default{'' if rule.default else ', reported only when selected'}: {rule.summary}.",
        "",
        f"Reported by {_SOURCES[rule.source]}.",
        "",
    ]
    if rule.why:
        lines += [rule.why, ""]
    if rule.bad:
        lines += ["## Reported", ""] + _files(rule.bad)
        lines += ["## Not reported", ""] + _files(rule.good)
    elif rule.code in ("E999", "W999"):
        lines += ["No example: a message that lands here is a gap in the table; please report it.", ""]
    else:
        lines += [
            "No example file: what it reports needs more than a folder of XML (a file system condition, "
            "a configuration, a second release, a capacity); the tests of `btgen validate` and "
            "`btgen analyze` hold its cases.",
            "",
        ]
    lines += [
        "Select or ignore it with `--select`/`--ignore` (or `select`/`ignore` in [tool.btgen]); "
        f"suppress one line with `<!-- btgen: ignore[{rule.code}] -->` on it.",
        "",
        "_Generated from `generator/btgen/tools/check/codes.py` by `python -m btgen.tools.check.rules_doc`._",
        "",
    ]
    return "\n".join(lines)


def index() -> str:
    lines = [
        "# btgen check: diagnostic codes",
        "",
        "Every finding of `btgen check` carries one of these codes (docs/check.md tells how to select, "
        "ignore and suppress them). Each page shows a folder where `check` reports the code and the "
        "same folder fixed; a test runs every example.",
        "",
        "| code | name | level | what |",
        "|---|---|---|---|",
    ]
    for r in RULES:
        level = r.severity + ("" if r.default else " (when selected)")
        lines.append(f"| [{r.code}]({r.code}.md) | `{r.name}` | {level} | {r.summary} |")
    lines += ["", "_Generated from `generator/btgen/tools/check/codes.py`._", ""]
    return "\n".join(lines)


def pages() -> dict[str, str]:
    out = {"README.md": index()}
    for r in RULES:
        out[f"{r.code}.md"] = page(r)
    return out


def main(argv: Optional[list[str]] = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    here = os.path.dirname(os.path.abspath(__file__))
    folder = argv[0] if argv else os.path.normpath(os.path.join(here, "..", "..", "..", "..", "docs", "rules"))
    os.makedirs(folder, exist_ok=True)
    for name, text in pages().items():
        with open(os.path.join(folder, name), "w", encoding="utf-8") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
