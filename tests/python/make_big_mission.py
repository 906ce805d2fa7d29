"""Write a balanced N-node mission and, optionally, time the reference interpreter on it.

    .venv/bin/python tests/python/make_big_mission.py 10000 -o big.xml
    .venv/bin/python tests/python/make_big_mission.py 10000 --measure 1000

The mission comes from ``btgen.tools.synth.balanced_mission`` (Sequence, Fallback
and Inverter over leaves; one tick visits every node and the root succeeds).
``--measure T`` builds the interpreter and sends T root ticks
(tickExactlyOnce; the run does not stop at SUCCESS), with the trace written
to /dev/null unless ``--no-trace``, and prints the time taken.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "generator"))

from btgen.frontend.loader import load_mission
from btgen.interp.engine import Interpreter
from btgen.interp.scenario import parse_scenario_text
from btgen.tools.synth import balanced_mission


def measure(path: str, ticks: int, trace: bool) -> dict:
    t0 = time.perf_counter()
    mission = load_mission(path)
    t1 = time.perf_counter()
    interp = Interpreter(mission, parse_scenario_text(f"ticks {ticks}\n"))
    if not trace:

        def discard(_pieces) -> None:
            pass

        for node in interp.nodes:
            node.emit = discard
    t2 = time.perf_counter()
    cpu0 = time.process_time()
    lines = 0
    with open(os.devnull, "w") as sink:
        for n in range(1, ticks + 1):  # what interp.run_trace does, without stopping at SUCCESS
            interp.rt.write_line(f"tick {n}")
            status = interp.tick_once()
            interp.rt.write_line(f"result {status.name}")
            text = interp.take_text()
            lines += text.count("\n")
            sink.write(text)
    t3 = time.perf_counter()
    return {
        "nodes": len(interp.nodes),
        "load_s": t1 - t0,
        "build_s": t2 - t1,
        "ticks": ticks,
        "tick_s": t3 - t2,
        "tick_cpu_s": time.process_time() - cpu0,
        "trace_lines": lines,
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("nodes", type=int)
    p.add_argument(
        "-o", "--output", help="where to write the mission (default: stdout, or a temporary file with --measure)"
    )
    p.add_argument("--branching", type=int, default=4)
    p.add_argument("--measure", type=int, metavar="TICKS", help="time this many ticks of the interpreter")
    p.add_argument("--no-trace", action="store_true", help="measure without producing trace lines")
    args = p.parse_args(argv)
    text = balanced_mission(args.nodes, args.branching)
    if args.measure is None:
        if args.output:
            with open(args.output, "w", encoding="utf-8") as f:
                f.write(text)
        else:
            sys.stdout.write(text)
        return 0
    path = args.output
    tmp = None
    if path is None:
        tmp = tempfile.NamedTemporaryFile(  # noqa: SIM115  (closed below, kept on disk)
            "w", suffix=".xml", delete=False, encoding="utf-8"
        )
        path = tmp.name
        tmp.close()
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    try:
        r = measure(path, args.measure, not args.no_trace)
    finally:
        if tmp is not None:
            os.unlink(path)
    print(
        f"{r['nodes']} nodes: load {r['load_s']:.2f} s, build {r['build_s']:.2f} s; "
        f"{r['ticks']} ticks in {r['tick_s']:.2f} s ({r['tick_cpu_s']:.2f} s CPU), "
        f"{r['trace_lines']} trace lines" + ("" if not args.no_trace else " (trace off)")
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
