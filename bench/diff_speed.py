"""How fast `btgen diff` decides: a mission against itself, generated missions of 100 and 1,000
nodes and the Robot Lab Tour.

    .venv/bin/python bench/diff_speed.py                                 # this checkout's btgen
    .venv/bin/python bench/diff_speed.py --sizes 100,1000 --max-states 2000
    PYTHONPATH=/path/to/other/checkout/generator .venv/bin/python bench/diff_speed.py   # "before"

Each mission is compared with itself under 4.6.2 (`btgen diff M M --format json`, in this
process): the answer (exhaustive, bounded, or partial when --max-states stops it), runs,
product states, the wall clock and CPU time of the search as the command reports it, and
product states per CPU second. The generated missions come from
`btgen.tools.synth.balanced_mission` (Sequence, Fallback and Inverter over leaves, the same
generator as tests/python/make_big_mission.py), one per size. It prints numbers; it asserts
nothing.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
if not os.environ.get("PYTHONPATH"):
    sys.path.insert(0, os.path.join(ROOT, "generator"))


def measure(path: str, max_ticks: int, max_states: int) -> dict:
    from btgen.cli import main

    argv = ["diff", path, path, "--format", "json", "--max-ticks", str(max_ticks), "--max-states", str(max_states)]
    out = io.StringIO()
    c0, t0 = time.process_time(), time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        rc = main(argv)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    r = json.loads(out.getvalue())
    answer = "partial" if r.get("equivalent") is None else ("exhaustive" if r["exhaustive"] else "bounded")
    return {
        "rc": rc,
        "answer": answer,
        "runs": r["runs"],
        "states": r["states"],
        "search_s": r["seconds"],
        "wall": wall,
        "cpu": cpu,
    }


def main_() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="100,1000", help="generated mission sizes, comma-separated")
    p.add_argument("--max-ticks", type=int, default=3)
    p.add_argument("--max-states", type=int, default=20000)
    p.add_argument("--no-lab-tour", action="store_true")
    a = p.parse_args()
    import btgen
    from btgen.tools.synth import balanced_mission

    print(f"btgen from {os.path.dirname(btgen.__file__)}; --max-ticks {a.max_ticks}, --max-states {a.max_states}")
    print("| mission | nodes | answer | runs | product states | search s | whole command CPU s | states / CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for n in (int(x) for x in a.sizes.split(",") if x):
            path = os.path.join(tmp, f"balanced_{n}.xml")
            with open(path, "w", encoding="utf-8") as f:
                f.write(balanced_mission(n))
            cases.append((f"balanced {n}", path, n))
        if not a.no_lab_tour:
            tour = os.path.join(ROOT, "tests", "conformance", "btcpp-4.10.0", "robot_lab_tour.xml")
            cases.append(("Robot Lab Tour", tour, 60))
        for name, path, n in cases:
            r = measure(path, a.max_ticks if name != "Robot Lab Tour" else 10, a.max_states)
            rate = r["states"] / r["cpu"] if r["cpu"] else 0.0
            print(
                f"| {name} | {n} | {r['answer']} | {r['runs']} | {r['states']} | {r['search_s']:.1f} | "
                f"{r['cpu']:.1f} | {rate:.0f} |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main_())
