#!/usr/bin/env python3
"""Record random edge missions (fuzzgen's `edges` set) on the real BehaviorTree.CPP 4.6.2.

    python scripts/record_random_edges.py HARNESS A:B [OUT]

For seeds A to B-1, the mission and its first scenario go to OUT (default
tests/conformance/edges-4.6.2/random/) with the library's trace, and the interpreter's
trace is compared with it. Missions with a Delay, Timeout or Sleep are left out (4.6.2 times them with a
thread, so their traces race with the ticks), and so are missions the library refuses or throws on (the
written edge cases cover refusals). Prints every disagreement and the counts; exit 1 when
the interpreter disagrees with a trace the library printed.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "generator"))

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import load_scenario
from btgen.tools.fuzzgen import random_case


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        sys.exit(__doc__)
    harness = argv[0]
    a, b = (int(x) for x in argv[1].split(":"))
    out = argv[2] if len(argv) > 2 else os.path.join(ROOT, "tests", "conformance", "edges-4.6.2", "random")
    os.makedirs(out, exist_ok=True)
    kept = refused = differ = timed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(a, b):
            case = random_case(seed, "edges", 1)
            if any(t in case.mission for t in ("<Delay", "<Timeout", "<Sleep")):
                # 4.6.2 times these with a timer thread: even a 0 ms Delay races with the tick
                # (edges table T2), so their traces are not facts to keep
                timed += 1
                continue
            mission, scenario = os.path.join(tmp, "m.xml"), os.path.join(tmp, "m.scenario")
            with open(mission, "w", encoding="utf-8") as f:
                f.write(case.mission)
            with open(scenario, "w", encoding="utf-8") as f:
                f.write(case.scenarios[0])
            proc = subprocess.run([harness, "trace", mission, scenario], capture_output=True, timeout=120, check=False)
            if proc.returncode != 0:
                refused += 1
                why = proc.stderr.decode("utf-8", "replace").strip().splitlines()
                print(f"seed {seed}: refused by 4.6.2: {why[-1] if why else proc.returncode}")
                continue
            expected = proc.stdout.decode("utf-8", "replace")
            try:
                m = load_mission(mission)
                got = trace_text(m, load_scenario(scenario, m)[0])
            except UserError as e:
                got = f"error: {e}"
            if got != expected:
                differ += 1
                print(f"seed {seed}: the interpreter disagrees with 4.6.2")
                continue
            stem = os.path.join(out, f"edges_{seed}")
            for ext, text in ((".xml", case.mission), (".scenario", case.scenarios[0]), (".trace", expected)):
                with open(stem + ext, "w", encoding="utf-8") as f:
                    f.write(text)
            kept += 1
    print(
        f"seeds {a}:{b}: {kept} agree and kept, {differ} disagree, {refused} refused by 4.6.2, "
        f"{timed} left out (timed nodes)"
    )
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
