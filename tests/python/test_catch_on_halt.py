"""TryCatch catch_on_halt (BehaviorTree.CPP 4.9.0) in the generated C++: a halt that ticks.

A TryCatch halted while its try block runs ticks its catch child inside the halt
(engine.hpp, halt_node). test_conformance_cpp_410.py runs the recorded
`v410_x6_catch_on_halt_*` cases as every mission is built (straight-line code);
here the same cases run with the nodes on the table interpreter (straight-line
budget 0), across the boundary between both (budget 3), and under ASan and UBSan,
where a tick inside a halt would show as a stack clobbered or overrun. Random missions
(btgen.tools.fuzzgen, their Sequences and Fallbacks made catch_on_halt TryCatch nodes)
run on both engines and must agree.
"""

import difflib
import glob
import os
import subprocess
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "scripts"))
import difftest

CASES_410 = os.path.join(ROOT, "tests", "conformance", "btcpp-4.10.0")
STEMS = sorted(os.path.basename(p)[:-6] for p in glob.glob(os.path.join(CASES_410, "v410_x6_catch_on_halt_*.trace")))


def test_the_cases_are_there():
    assert len(STEMS) >= 9, STEMS


@pytest.mark.parametrize(
    "budget, sanitize", [("0", "1"), ("3", "")], ids=["interpreted-sanitized", "straight-line-boundary"]
)
def test_catch_on_halt_cases_on_every_form(budget, sanitize, monkeypatch):
    monkeypatch.chdir(CASES_410)
    monkeypatch.setenv("BTGEN_STRAIGHT_LINE_BUDGET", budget)
    monkeypatch.setenv("BTGEN_SANITIZE", sanitize)
    monkeypatch.setattr(difftest, "BTCPP", ["4.10.0"])
    binary = difftest.build_batch([s + ".xml" for s in STEMS])
    for index, stem in enumerate(STEMS):
        proc = subprocess.run([str(binary), str(index), stem + ".scenario"], capture_output=True, check=False)
        out, err = proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8")
        with open(stem + ".trace", encoding="utf-8") as f:
            expected = f.read()
        assert proc.returncode == 0 and err == "", f"{stem}: {err}"
        assert out == expected, "".join(
            difflib.unified_diff(expected.splitlines(True), out.splitlines(True), "4.10.0", f"C++ {stem}")
        )


def _with_trycatch(case):
    """A random mission whose Sequences and Fallbacks (plain and async, with memory) became
    TryCatch nodes with catch_on_halt="true", each given one more child, its catch child (a
    scenario leaf, or a Sequence of two)."""
    import dataclasses
    import xml.etree.ElementTree as ET

    text = case.mission.split("?>", 1)[1] if case.mission.startswith("<?xml") else case.mission
    root = ET.fromstring(text)
    k = 0
    for el in root.iter():
        if el.tag in ("Sequence", "Fallback", "SequenceWithMemory", "AsyncSequence", "AsyncFallback"):
            el.tag = "TryCatch"
            el.set("catch_on_halt", "true")
            k += 1
            if k % 3 == 0:
                seq = ET.SubElement(el, "Sequence")
                ET.SubElement(seq, "Act", {"name": "a"})
                ET.SubElement(seq, "Act", {"name": "e"})
            else:
                ET.SubElement(el, "Act", {"name": "c" if k % 3 == 1 else "e"})
    return dataclasses.replace(case, mission=ET.tostring(root, encoding="unicode"))


def test_random_missions_with_catch_on_halt_agree_with_the_interpreter(monkeypatch, tmp_path):
    from btgen.interp import controls

    catching = []
    halt = controls.TryCatchNode.halt

    def counting_halt(self):
        if self.get_input("catch_on_halt", "bool") is True and not self.in_catch and self.status == controls.RUNNING:
            catching.append(self)
        halt(self)

    monkeypatch.setattr(controls.TryCatchNode, "halt", counting_halt)
    random_case = difftest.random_case
    monkeypatch.setattr(difftest, "random_case", lambda *a: _with_trycatch(random_case(*a)))
    report = difftest.difftest(range(0, 60), "control", 2, jobs=2, keep=tmp_path / "keep", btcpp="4.10.0")
    assert len(report.compiled) == 60, (report.invalid, report.rejected, report.unsupported)
    assert report.divergences == [], report.divergences
    assert len(catching) >= 5  # the runs do halt TryCatch nodes in their try block
