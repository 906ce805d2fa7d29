#!/usr/bin/env python3
"""Shrink a mission on which btgen's interpreter and the real BehaviorTree.CPP disagree.

    python scripts/oracle_minimize.py MISSION.xml SCENARIO.scenario VERSION [OUT_STEM]

Greedy delta debugging on the XML (remove an element, put a child in its parent's place, drop an
attribute or one statement of a script, drop a tree or a model) and on the scenario (drop a line,
fewer ticks), keeping each step that still shows the same divergence: the library and the
interpreter (under VERSION, on that release's harness, scripts/oracle_random.py) still disagree,
each failing or not as before, and a failing library with the same last message. Writes
OUT_STEM.xml and OUT_STEM.scenario (default: beside MISSION, `.min`).
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

from lxml import etree

sys.path.insert(0, str(Path(__file__).resolve().parent))

import oracle_random as orc

KEEP_ATTRS = {"ID", "BTCPP_format", "main_tree_to_execute"}


def signature(xml: str, scenario: str, version: str, tmp: str) -> tuple | None:
    m, s = os.path.join(tmp, "x.xml"), os.path.join(tmp, "x.scenario")
    Path(m).write_text(xml, encoding="utf-8")
    Path(s).write_text(scenario, encoding="utf-8")
    lib = orc.observe(orc.default_harness(version), xml, m, s, tmp)
    got = orc.interpreter(m, s, version)
    if orc.compare(lib, got, version, xml) != "divergence":
        return None
    return lib[1], got[1], lib[2].splitlines()[-1] if lib[1] else "", got[2][:30] if got[1] else ""


def _candidates(xml: str):
    root = etree.fromstring(xml.encode("utf-8"))
    n = sum(1 for _ in root.iter())
    for i in range(n):
        for op in ("drop", "hoist0", "hoist1", "hoist2", "attrs", "script"):
            r = etree.fromstring(xml.encode("utf-8"))
            el = list(r.iter())[i]
            if not isinstance(el.tag, str) or el is r:
                continue
            parent = el.getparent()
            if op == "drop":
                parent.remove(el)
                yield etree.tostring(r, encoding="unicode")
            elif op.startswith("hoist"):
                kids = [c for c in el if isinstance(c.tag, str)]
                k = int(op[-1])
                if k < len(kids) and el.tag != "BehaviorTree":
                    el.addprevious(kids[k])
                    parent.remove(el)
                    yield etree.tostring(r, encoding="unicode")
            elif op == "attrs":
                for name in list(el.attrib):
                    if name in KEEP_ATTRS:
                        continue
                    r2 = etree.fromstring(xml.encode("utf-8"))
                    e2 = list(r2.iter())[i]
                    del e2.attrib[name]
                    yield etree.tostring(r2, encoding="unicode")
            elif op == "script":
                for name, value in el.attrib.items():
                    parts = value.split(";")
                    if len(parts) < 2:
                        continue
                    for j in range(len(parts)):
                        r2 = etree.fromstring(xml.encode("utf-8"))
                        e2 = list(r2.iter())[i]
                        e2.set(name, ";".join(parts[:j] + parts[j + 1 :]).strip())
                        yield etree.tostring(r2, encoding="unicode")


def _scenario_candidates(scenario: str):
    lines = scenario.splitlines()
    for i, ln in enumerate(lines):
        if ln.startswith("ticks "):
            t = int(ln.split()[1])
            for smaller in (1, t // 2, t - 1):
                if 1 <= smaller < t:
                    yield "\n".join(lines[:i] + [f"ticks {smaller}"] + lines[i + 1 :]) + "\n"
        else:
            yield "\n".join(lines[:i] + lines[i + 1 :]) + "\n"


def minimize(xml: str, scenario: str, version: str) -> tuple[str, str]:
    with tempfile.TemporaryDirectory() as tmp:
        want = signature(xml, scenario, version, tmp)
        if want is None:
            raise SystemExit("oracle_minimize: no divergence to shrink")
        xml = etree.tostring(etree.fromstring(xml.encode("utf-8")), encoding="unicode")
        changed = True
        while changed:
            changed = False
            for cand in _scenario_candidates(scenario):
                if signature(xml, cand, version, tmp) == want:
                    scenario, changed = cand, True
                    break
            for cand in _candidates(xml):
                if len(cand) < len(xml) and signature(cand, scenario, version, tmp) == want:
                    xml, changed = cand, True
                    break
    return xml, scenario


def main(argv: list[str]) -> int:
    if len(argv) not in (3, 4):
        sys.exit(__doc__)
    mission, scen, version = argv[:3]
    out = argv[3] if len(argv) == 4 else os.path.splitext(mission)[0] + ".min"
    xml, scenario = minimize(Path(mission).read_text(encoding="utf-8"), Path(scen).read_text(encoding="utf-8"), version)
    Path(out + ".xml").write_text(xml + "\n", encoding="utf-8")
    Path(out + ".scenario").write_text(scenario, encoding="utf-8")
    print(xml)
    print(scenario)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
