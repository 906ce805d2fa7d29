"""The code table of `btgen check`, its pages in docs/rules/ and its examples: the pages are what the
table gives, and every example folder is reported with its code, and its fixed twin is not."""

import os
from pathlib import Path

import pytest

from btgen.tools.check import rules_doc, runner
from btgen.tools.check.codes import BY_CODE, RULES
from btgen.tools.check.config import load_settings

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs" / "rules"

EXAMPLES = [r.code for r in RULES if r.bad]


def test_pages_are_generated_from_the_table():
    expected = rules_doc.pages()
    on_disk = {p.name: p.read_text() for p in DOCS.glob("*.md")}
    stale = sorted(n for n in set(expected) | set(on_disk) if expected.get(n) != on_disk.get(n))
    assert stale == [], "run `python -m btgen.tools.check.rules_doc` to regenerate docs/rules/"


def test_most_codes_have_examples():
    # the codes without one need a file system condition, a second release or a configuration
    assert len(EXAMPLES) >= 33


def _codes(folder: Path, code: str) -> set:
    old = os.getcwd()
    os.chdir(folder)
    try:
        found = os.path.join(".", "btgen.toml") if (folder / "btgen.toml").exists() else None  # as check finds it
        settings = runner.with_cli(load_settings(found), [], [], [code])
        report = runner.check(["."], settings)
    finally:
        os.chdir(old)
    return {f.code for f in report.findings}


@pytest.mark.parametrize("code", EXAMPLES)
def test_example(code, tmp_path):
    rule = BY_CODE[code]
    bad, good = tmp_path / "bad", tmp_path / "good"
    for folder, files in ((bad, rule.bad), (good, rule.good)):
        folder.mkdir()
        for name, text in files.items():
            (folder / name).write_text(text)
    assert code in _codes(bad, code)
    assert code not in _codes(good, code)
