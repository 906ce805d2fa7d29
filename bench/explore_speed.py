"""How fast `btgen explore` searches: states per second on the shipped missions.

    .venv/bin/python bench/explore_speed.py                       # this checkout's btgen
    .venv/bin/python bench/explore_speed.py --max-states 5000      # a bound for every mission
    PYTHONPATH=/path/to/other/checkout/generator .venv/bin/python bench/explore_speed.py

It runs `btgen explore MISSION --json` in this process for each mission (`missions/*.xml`, or
those named) and prints one Markdown row each: states and runs explored, whether the search
was exhaustive or bounded, the goals covered, the wall clock and the CPU time of the search, and
states per second of each, for the whole command (loading the mission and `btgen analyze`'s
pass included, about a second). CPU time is the number to compare on a shared machine (the wall
clock grows with the load). The btgen measured is the one Python
imports: this checkout's `generator/`, unless PYTHONPATH names another (an older commit's
worktree), which gives the "before" of a change. It prints numbers; it asserts nothing.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import io
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
if not os.environ.get("PYTHONPATH"):  # this checkout's btgen, not one installed in the environment
    sys.path.insert(0, os.path.join(ROOT, "generator"))


def measure(mission: str, max_states: int | None, ticks: int | None) -> dict:
    import btgen
    from btgen.cli import main

    argv = ["explore", mission, "--json"]
    if max_states is not None:
        argv += ["--max-states", str(max_states)]
    if ticks is not None:
        argv += ["--ticks", str(ticks)]
    out = io.StringIO()
    cpu0, wall0 = time.process_time(), time.perf_counter()
    with contextlib.redirect_stdout(out):
        main(argv)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    report = json.loads(out.getvalue())
    return {
        "mission": os.path.relpath(mission, ROOT),
        "btgen": os.path.dirname(os.path.dirname(btgen.__file__)),
        "states": report["states"],
        "runs": report["runs"],
        "search": report.get("search", "?"),
        "covered": f"{report['covered']}/{report['goals']}",
        "wall": wall,
        "cpu": cpu,
    }


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("missions", nargs="*", metavar="MISSION.xml", help="default: missions/*.xml")
    p.add_argument("--max-states", type=int, metavar="N", help="the bound of every search (default: explore's)")
    p.add_argument("--ticks", type=int, metavar="N", help="most root ticks of a run (default: explore's)")
    args = p.parse_args()
    missions = args.missions or sorted(glob.glob(os.path.join(ROOT, "missions", "*.xml")))
    print("| mission | states | runs | search | goals covered | wall s | states/s (wall) | CPU s | states/s (CPU) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for mission in missions:
        r = measure(mission, args.max_states, args.ticks)
        print(
            f"| {r['mission']} | {r['states']} | {r['runs']} | {r['search']} | {r['covered']} | {r['wall']:.2f} | "
            f"{r['states'] / r['wall'] if r['wall'] else 0:.0f} | {r['cpu']:.2f} | "
            f"{r['states'] / r['cpu'] if r['cpu'] else 0:.0f} |"
        )
    print(f"\nbtgen: {r['btgen'] if missions else '?'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
