"""Front-end fuzzing (scripts/fuzz_frontend.py): a bounded run in CI, and the inputs it found.

Every input, however broken, ends in success or in `path:line:col:` diagnostics
with exit status 1: never a traceback, an internal error (exit 3), a hang or
unbounded memory. The bounded run goes through a subprocess with its own
memory limit and time budget; scripts/fuzz_frontend.py runs any number.
"""

import os
import subprocess
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "scripts"))

import fuzz_frontend

ITERATIONS = int(os.environ.get("BTGEN_FUZZ_ITERATIONS", "1500"))


def _btgen(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "btgen", *args], cwd=cwd, capture_output=True, check=False, timeout=120
    )


def test_bounded_fuzz_run(tmp_path):
    proc = subprocess.run(
        [
            sys.executable,
            os.path.join(ROOT, "scripts", "fuzz_frontend.py"),
            "--iterations",
            str(ITERATIONS),
            "--seed",
            "20261122",
            "--cli",
            "100",
            "--keep",
            str(tmp_path),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        check=False,
        timeout=1200,
    )
    out = proc.stdout.decode("utf-8", "replace")
    print(out[-3000:])
    assert proc.returncode == 0, out[-6000:]
    assert ", 0 findings," in out


def test_the_oracle_catches_a_crash(tmp_path, monkeypatch):
    """A fuzzer whose oracle cannot fail proves nothing: make validation crash and look."""
    import btgen.frontend.loader

    def boom(path):
        raise KeyError("a bug")

    monkeypatch.setattr(btgen.frontend.loader, "load_mission", boom)
    stats = fuzz_frontend.fuzz(5, 1, "mission", keep=tmp_path)
    assert len(stats["findings"]) == 5
    assert "KeyError" in (tmp_path / os.path.basename(stats["findings"][0][0] + ".txt")).read_text()


def test_the_oracle_catches_a_hang(tmp_path, monkeypatch):
    import btgen.kb.lint

    def forever(*args, **kwargs):
        while True:
            pass

    monkeypatch.setattr(btgen.kb.lint, "lint_kb", forever)
    stats = fuzz_frontend.fuzz(1, 1, "kb", keep=tmp_path, time_limit=0.5)
    assert [p for _, p in stats["findings"]] == ["no answer within 0.5 s of CPU"]


def test_the_oracle_catches_an_input_that_blocks(tmp_path, monkeypatch):
    # No CPU is spent, so only the wall-clock backstop can end it.
    import time

    import btgen.kb.lint

    monkeypatch.setattr(btgen.kb.lint, "lint_kb", lambda *args, **kwargs: time.sleep(60))
    monkeypatch.setattr(fuzz_frontend, "WALL_FACTOR", 2)
    stats = fuzz_frontend.fuzz(1, 1, "kb", keep=tmp_path, time_limit=0.5)
    assert [p for _, p in stats["findings"]] == ["no answer within 1.0 s of wall-clock time"]


def test_mutations_are_deterministic():
    import random

    corpus = fuzz_frontend.mission_corpus()
    a = [
        fuzz_frontend.mutate(
            corpus[0], random.Random(s), corpus, fuzz_frontend.TOKENS, fuzz_frontend.mutate_mission_structure
        )
        for s in range(20)
    ]
    b = [
        fuzz_frontend.mutate(
            corpus[0], random.Random(s), corpus, fuzz_frontend.TOKENS, fuzz_frontend.mutate_mission_structure
        )
        for s in range(20)
    ]
    assert a == b and len(set(a)) > 10


# ------------------------------------------------------------ what fuzzing found
@pytest.mark.parametrize(
    "xml,expected",
    [
        # A line break quoted from the input made a diagnostic span two lines.
        (
            '<root BTCPP_format="&#10;"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>\n',
            'm.xml:1:21: error: BTCPP_format="\\n" is not supported; btgen reads BehaviorTree.CPP v4 files '
            '(BTCPP_format="4")\n',
        ),
        # (`--` inside a comment that ends loads, as tinyxml2 reads it: tests/regressions/tinyxml2_*;
        # one that never ends at `-->` is still an error, whose message quotes the comment)
        (
            '<root BTCPP_format="4">\n<!--\n a - b --\n>\n'
            '<BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>\n',
            "m.xml:3:8: error: malformed XML: Double hyphen within comment: <!--\\n a - b \n",
        ),
    ],
)
def test_a_diagnostic_is_one_line(tmp_path, xml, expected):
    (tmp_path / "m.xml").write_text(xml, encoding="utf-8")
    proc = _btgen("validate", "m.xml", cwd=tmp_path)
    assert (proc.returncode, proc.stderr.decode("utf-8")) == (1, expected)


def test_node_id_with_a_space_in_the_mission_xsd(tmp_path):
    """A bug the front-end fuzzing found: a TreeNodesModel ID such as `IV.Act/1` crashed the mission XSD."""
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><Action ID="IV.Act/1"/>'
        '<Action ID="IV.Act/1" name="again"/></Sequence></BehaviorTree>'
        '<TreeNodesModel><Action ID="IV.Act/1"/></TreeNodesModel></root>\n',
        encoding="utf-8",
    )
    proc = _btgen("validate", "m.xml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    proc = _btgen("xsd", "m.xml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    from lxml import etree

    etree.XMLSchema(etree.fromstring(proc.stdout))  # a well-formed, loadable schema
