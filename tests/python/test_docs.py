"""The README is a first page, the docs are a site that builds with --strict, and every shell
and XML example in them runs (or says why not).

The marker convention (docs/index.md, "Writing a page"): an HTML comment on the line before a
fence, `<!-- docs-test: not run: REASON -->`, `exit N`, `same as FILE [lines A-B]`,
`fragment: REASON` or `output of examples/first_mission`.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import pytest
from lxml import etree

import cppbuild
from conftest import ROOT

REPO = Path(ROOT)
README = REPO / "README.md"
DOC_FILES = [README, *sorted((REPO / "docs").rglob("*.md"))]
RUN_LANGS = {"sh", "bash", "shell", "console", "xml"}
MARKER = re.compile(r"^\s*<!-- docs-test: (?P<body>.+?) -->\s*$")
FENCE = re.compile(r"^(?P<indent>\s*)```(?P<lang>[^`\s]*)\s*$")
FIRST_MISSION = REPO / "examples" / "first_mission"
KNOWN_MARKERS = r"not run: (.{12,})|exit \d+|same as \S+( lines \d+-\d+)?|fragment: .{12,}|output of \S+"


@dataclass(frozen=True)
class Block:
    path: Path
    line: int  # of the opening fence, 1-based
    lang: str
    text: str
    marker: Optional[str]

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(REPO)}:{self.line}"


def blocks(path: Path) -> list[Block]:
    lines = path.read_text(encoding="utf-8").split("\n")
    found, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, start = m.group("indent"), i
        body = []
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            body.append(lines[i][len(indent) :] if lines[i].startswith(indent) else lines[i].lstrip())
            i += 1
        assert i < len(lines), f"{path}:{start + 1}: a fence that is never closed"
        marker = MARKER.match(lines[start - 1]) if start else None
        found.append(Block(path, start + 1, m.group("lang"), "\n".join(body) + "\n", marker and marker.group("body")))
        i += 1
    return found


ALL_BLOCKS = [b for path in DOC_FILES for b in blocks(path)]
CHECKED = [b for b in ALL_BLOCKS if b.lang in RUN_LANGS or b.marker]


def test_every_fence_says_its_language_and_every_marker_is_known():
    assert len(ALL_BLOCKS) > 20
    bad = [b.where for b in ALL_BLOCKS if not b.lang]
    assert not bad, f"fences without a language (```sh, ```text, ```cpp ...): {bad}"
    for b in ALL_BLOCKS:
        if b.marker is None:
            continue
        assert re.fullmatch(KNOWN_MARKERS, b.marker), f"{b.where}: unknown marker `{b.marker}` (see docs/index.md)"


def test_no_indented_code_blocks():
    """Indented code blocks have no language and no marker: every example is fenced."""
    for path in DOC_FILES:
        lines, fenced = path.read_text(encoding="utf-8").split("\n"), False
        for n, line in enumerate(lines):
            if FENCE.match(line) or line.strip() == "```":
                fenced = not fenced
            prev = lines[n - 1] if n else ""
            starts_code = line.startswith("    ") and not line.lstrip().startswith(("-", "|", "<!--"))
            assert fenced or not (starts_code and prev == "" and not _in_list(lines, n)), f"{path}:{n + 1}"


def _in_list(lines: list[str], n: int) -> bool:
    """Whether line n continues a list item (then 4 spaces are the item's text, not code)."""
    for k in range(n - 1, -1, -1):
        if lines[k].strip() == "":
            continue
        return bool(re.match(r"\s*([-*]|\d+\.)\s", lines[k])) or lines[k].startswith("  ")
    return False


@pytest.fixture(scope="module")
def shim_env(tmp_path_factory):
    """An environment whose `btgen` runs this checkout's generator."""
    shim = tmp_path_factory.mktemp("bin")
    (shim / "btgen").write_text(f'#!/bin/sh\nexec "{sys.executable}" -m btgen "$@"\n')
    (shim / "btgen").chmod(0o755)
    return dict(os.environ, PATH=f"{shim}{os.pathsep}{os.environ['PATH']}", PYTHONPATH=str(REPO / "generator"))


def _workdir(tmp_path: Path) -> Path:
    """A folder that sees the repository's top-level folders: examples write into it, never
    into the checkout."""
    work = tmp_path / "work"
    work.mkdir()
    for entry in REPO.iterdir():
        if entry.name not in {".git", "build", ".venv"}:
            (work / entry.name).symlink_to(entry)
    return work


def _expected_exit(b: Block) -> int:
    m = re.fullmatch(r"exit (\d+)", b.marker or "")
    return int(m.group(1)) if m else 0


@pytest.mark.parametrize("block", [b for b in CHECKED if b.lang in RUN_LANGS], ids=lambda b: b.where)
def test_example(block, shim_env, tmp_path):
    marker = block.marker or ""
    if marker.startswith("not run: "):
        return  # the reason is the marker (checked above)
    if marker.startswith(("same as ", "output of ")):
        return  # test_blocks_that_are_files
    env, work = shim_env, _workdir(tmp_path)
    if block.lang == "xml":
        if marker.startswith("fragment: "):
            etree.fromstring(f"<fragment>{block.text}</fragment>".encode())
            return
        mission = work / "example.xml"
        mission.write_text(block.text, encoding="utf-8")
        proc = subprocess.run(
            ["btgen", "validate", str(mission)], cwd=work, env=env, capture_output=True, text=True, check=False
        )
        assert proc.returncode == _expected_exit(block), f"{block.where}\n{proc.stderr}"
        return
    if block.lang == "console":
        _console(block, work, env)
        return
    proc = subprocess.run(
        ["bash", "-e", "-o", "pipefail", "-c", block.text],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert proc.returncode == _expected_exit(block), (
        f"{block.where}: exit {proc.returncode}\n{block.text}\n{proc.stdout[-3000:]}{proc.stderr[-3000:]}"
    )


def _console(block: Block, work: Path, env: dict) -> None:
    """`$ command` lines, each followed by what it prints (stdout and stderr, in order)."""
    steps: list[tuple[str, list[str]]] = []
    for line in block.text.rstrip("\n").split("\n"):
        if line.startswith("$ "):
            steps.append((line[2:], []))
        else:
            assert steps, f"{block.where}: output before the first `$ ` line"
            steps[-1][1].append(line)
    for cmd, expected in steps:
        proc = subprocess.run(
            ["bash", "-c", cmd],
            cwd=work,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            timeout=300,
            check=False,
        )
        assert proc.returncode == _expected_exit(block), f"{block.where}: `{cmd}` exit {proc.returncode}"
        assert proc.stdout.rstrip("\n").split("\n") == expected, f"{block.where}: `{cmd}` printed\n{proc.stdout}"


def test_blocks_that_are_files():
    """`same as FILE [lines A-B]`: the block is that file, or those lines of it."""
    same = [b for b in ALL_BLOCKS if (b.marker or "").startswith("same as ")]
    assert same, "the first page's example is marked `same as` its files"
    for b in same:
        m = re.fullmatch(r"same as (\S+)(?: lines (\d+)-(\d+))?", b.marker or "")
        assert m, b.where
        lines = (REPO / m.group(1)).read_text(encoding="utf-8").split("\n")
        if m.group(2):
            lines = lines[int(m.group(2)) - 1 : int(m.group(3))]
        assert b.text.rstrip("\n") == "\n".join(lines).rstrip("\n"), f"{b.where} differs from {m.group(0)[8:]}"


def test_the_first_mission_builds_and_prints_what_the_readme_shows(tmp_path):
    """examples/first_mission: compiled by btgen, built -Werror, run: it prints the README's lines."""
    from btgen.cli import main

    assert main(["validate", "-q", str(FIRST_MISSION / "deliver.xml")]) == 0
    assert main(["compile", str(FIRST_MISSION / "deliver.xml"), "-o", str(tmp_path)]) == 0
    exe = cppbuild.build(
        [FIRST_MISSION / "main.cpp", tmp_path / "deliver.cpp"], tmp_path / "deliver", includes=[tmp_path]
    )
    run = subprocess.run([exe], capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 0, run.stderr
    shown = [b for b in ALL_BLOCKS if b.marker == "output of examples/first_mission"]
    assert len(shown) == 1
    assert run.stdout == shown[0].text


# ------------------------------------------------------------------ the first page
def _section(text: str, title: str) -> str:
    return text.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]


def test_the_readme_is_a_first_page():
    text = README.read_text(encoding="utf-8")
    assert text.startswith("# btgen\n")  # the wheel's long description (test_package.py)
    assert text.count("\n") <= 250, "the README is a first page: move the rest to docs/"
    two = [b for b in blocks(README) if b.lang == "sh"]
    setup = _section(text, "Two commands on a fresh Debian machine (as root)")
    assert [b.text for b in two if b.text.strip() in setup] == ["bash scripts/demo.sh\n", "bash scripts/test.sh\n"]
    assert "bash scripts/test.sh" in (REPO / ".ci" / "run").read_text()
    mission_xml = [b for b in blocks(README) if b.lang == "xml"]
    assert len(mission_xml) == 1 and mission_xml[0].text.count("\n") <= 25


def test_the_readme_cmake_call_has_every_keyword():
    cmake = (REPO / "cmake" / "btgen.cmake").read_text()
    keywords = {"MISSION", "OUTPUT_DIR", "RELATIVE_TO", "SCENARIO_RUNNER"}
    for prop in ("BTGEN_ONE_VALUE_OPTIONS", "BTGEN_MULTI_VALUE_OPTIONS"):
        m = re.search(rf'set_property\(GLOBAL PROPERTY {prop} "([^"]+)"\)', cmake)
        assert m, prop
        keywords |= set(m.group(1).split(";"))
    snippet = [b.text for b in blocks(README) if b.lang == "cmake"]
    assert len(snippet) == 1
    assert {k for k in keywords if not re.search(rf"\b{k}\b", snippet[0])} == set()


def test_the_readme_table_has_every_command():
    from btgen.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    table = _section(README.read_text(encoding="utf-8"), "Commands")
    assert {c for c in sub.choices if f"`btgen {c}" not in table} == set()


def _slug(title: str) -> str:
    value = re.sub(r"[^\w\s-]", "", title).strip().lower()
    return re.sub(r"[-\s]+", "-", value)


def test_the_readme_links_resolve():
    text = README.read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if target.startswith(("http://", "https://")):
            continue
        path, _, anchor = target.partition("#")
        file = REPO / path
        assert file.exists(), target
        if anchor:
            titles = re.findall(r"^#+ (.+)$", file.read_text(encoding="utf-8"), re.M)
            assert anchor in {_slug(t) for t in titles}, target


# ------------------------------------------------------------------ the site
def _mkdocs(config: Path, site: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(config), "-d", str(site)],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
        check=False,
    )


def test_the_site_builds_with_warnings_as_errors(tmp_path):
    proc = _mkdocs(REPO / "mkdocs.yml", tmp_path / "site")
    assert proc.returncode == 0, proc.stderr
    assert "WARNING" not in proc.stderr
    assert (tmp_path / "site" / "index.html").exists()
    for page in ("getting-started", "limits", "performance"):
        assert (tmp_path / "site" / page / "index.html").exists(), page


def test_a_broken_link_fails_the_site_and_an_unlisted_page_is_kept(tmp_path):
    """What --strict is for, on a site of three pages: a link to a repository file that does not
    exist or to a missing anchor fails; a page the nav leaves out is built under "More pages"."""
    docs = tmp_path / "docs"
    docs.mkdir()
    (tmp_path / "exists.txt").write_text("x\n")
    (docs / "index.md").write_text("# Home\n\n[a file](../exists.txt) [a page](other.md#there)\n")
    (docs / "other.md").write_text("# Other\n\n## There\n")
    (docs / "new.md").write_text("# New page\n")
    config = (REPO / "mkdocs.yml").read_text()
    config = config.split("\nnav:\n", 1)[0] + "\nnav:\n  - index.md\n  - other.md\n"
    config = config.replace("scripts/mkdocs_hooks.py", str(REPO / "scripts" / "mkdocs_hooks.py"))
    (tmp_path / "mkdocs.yml").write_text(config)
    good = _mkdocs(tmp_path / "mkdocs.yml", tmp_path / "site")
    assert good.returncode == 0, good.stderr
    assert "More pages" in (tmp_path / "site" / "index.html").read_text()
    assert (tmp_path / "site" / "new" / "index.html").exists()
    assert "<code>exists.txt</code>" in (tmp_path / "site" / "index.html").read_text()
    (docs / "index.md").write_text("# Home\n\n[a file](../missing.txt) [a page](other.md#nowhere)\n")
    bad = _mkdocs(tmp_path / "mkdocs.yml", tmp_path / "site2")
    assert bad.returncode != 0
    assert "links to '../missing.txt', which is not a file of the repository" in bad.stderr
    assert "does not contain an anchor '#nowhere'" in bad.stderr
