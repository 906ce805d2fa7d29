"""How `btgen verify` scales: states, memory and seconds of SPIN (and Storm) per mission.

    .venv/bin/python bench/verify_scale.py [--sizes 100,1000] [--storm] [--timeout S]

Missions: Nav2's navigate_to_pose_w_replanning_and_recovery (tests/real_files/nav2, with
Nav2's models file), the shipped Lab Tour and Reception, and generated missions of N nodes
(`tools/synth.balanced_mission`: Sequence, Fallback and Inverter levels) whose leaves are
made free: every other leaf a user Condition (`Ready`), the others a user Action (`Work`).
For each: the Promela model's size, the seconds to build pan (spin -a and tcc or gcc), and two
searches: the whole reachable state space (the property `[] true`) and the liveness property
`<> (root(SUCCESS) || root(FAILURE))` with `--running-bound 1` (every Action finishes after
at most one RUNNING answer), on runs of at most --ticks ticks (default 3; 0: unbounded).
A whole-state-space search that does not finish within --timeout seconds (or does not fit
pan's memory bound) is reported as such; then a bitstate search (pan -DBITSTATE, 2^30 bits: a
partial search, NOT a proof) is run and labelled so. Seconds are CPU seconds (the machine is
shared) unless they say wall. Prints numbers; it passes or fails nothing.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "generator"))

from btgen import pipeline
from btgen.diagnostics import Loc
from btgen.tools.synth import balanced_mission
from btgen.tools.verify import (
    build_model,
    spin,
)
from btgen.tools.verify import props as P
from btgen.tools.verify.promela import ModelOptions

ROOT = os.path.dirname(HERE)
NAV2_TREES = ("navigate_to_pose_w_replanning_and_recovery",)
NAV2_CONTRACT = tuple(
    (name, (2,))
    for name in (
        "ProgressCheckerSelector",
        "GoalCheckerSelector",
        "PathHandlerSelector",
        "ControllerSelector",
        "PlannerSelector",
    )
)


def free_leaves(xml: str) -> str:
    """Every AlwaysFailure of a balanced mission becomes a free Condition or Action, in turn."""
    count = [0]

    def swap(_m: re.Match) -> str:
        count[0] += 1
        return "<Ready/>" if count[0] % 2 else "<Work/>"

    return re.sub(r"<AlwaysFailure/>", swap, xml)


def cpu() -> float:
    """CPU seconds of the children so far (spin, the C compiler, pan): the machine is shared."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_pan_timed(
    work: str, args: list[str], timeout: float, bitstate: bool = False
) -> tuple[spin.SpinResult, bool, float]:
    c0 = cpu()
    try:
        res, done = spin.run_pan(work, args, wall=timeout, bitstate=bitstate), True
    except Exception as e:  # subprocess.TimeoutExpired
        if type(e).__name__ != "TimeoutExpired":
            raise
        res, done = spin.SpinResult(holds=None, incomplete=f"not finished within {timeout:.0f} s"), False
    return res, done, cpu() - c0


def verdict(res: spin.SpinResult) -> str:
    if res.partial:
        return "PARTIAL (bitstate: no proof)"
    return {True: "holds", False: "VIOLATED", None: f"INCOMPLETE ({res.incomplete or 'see pan'})"}[res.holds]


def measure(
    label: str,
    path: str,
    timeout: float,
    storm: bool,
    ticks: int | None = None,
    opts=pipeline.DEFAULTS,
    contract: tuple = (),
) -> None:
    mission, program = pipeline.build(path, opts)
    names = P.Names(program)
    whole = P.parse_property("[] true", Loc("<bench>", 1, 1), names, 0)  # holds: the whole state space
    ends = P.parse_property("<> (root(SUCCESS) || root(FAILURE))", Loc("<bench>", 1, 1), names, 1)
    options = ModelOptions(running_bound=1, ticks=ticks, print_states=False, contract=contract)
    text = build_model(mission, program, options, [whole, ends])
    with tempfile.TemporaryDirectory(prefix="btgen-bench-") as work:
        t0 = time.perf_counter()
        times: dict[str, float] = {}
        build = spin.compile_model(text, work, times=times)
        print(
            f"{label:<22} {len(program.nodes):>5} nodes  model {len(text.splitlines()):>6} lines  "
            f"pan sources {times['pan_bytes'] / 1e6:5.1f} MB  built in {build:6.1f} s wall, "
            f"{times['spin_cpu']:.2f} + {times['cc_cpu']:.2f} CPU s (spin -a + {os.path.basename(spin.tools()[1])})"
            + (f"  (runs of at most {ticks} ticks)" if ticks else "")
        )
        reach, done, c_reach = run_pan_timed(work, ["-n", "-a", "-N", "p0"], timeout)
        if done and reach.holds:
            print(
                f"{'':22}   whole state space: {reach.states} states, vector {reach.vector_bytes} B, "
                f"{reach.memory_mb:.0f} MB, {c_reach:.2f} CPU s search"
            )
        else:
            print(f"{'':22}   exhaustive search: {reach.incomplete} ({reach.states} states, {c_reach:.1f} CPU s)")
            bwork = os.path.join(work, "bitstate")
            bt: dict[str, float] = {}
            spin.compile_model(text, bwork, spin.BITSTATE, times=bt)
            bit, ok, c_bit = run_pan_timed(
                bwork, ["-n", "-a", "-N", "p0", f"-w{spin.bitstate_bits()}"], timeout, bitstate=True
            )
            print(
                f"{'':22}   bitstate search: {bit.partial or verdict(bit)}; {bit.memory_mb:.0f} MB, "
                f"{c_bit:.1f} CPU s search (+{bt['cc_cpu']:.2f} CPU s to build it)" + ("" if ok else " (stopped)")
            )
        live, live_done, c_live = run_pan_timed(work, ["-n", "-a", "-N", "p1"], timeout)
        print(
            f"{'':22}   <> root done (--running-bound 1): {verdict(live) if live_done else 'stopped'}; "
            f"{live.states} states, {live.memory_mb:.0f} MB, {c_live:.2f} CPU s search"
        )
        print(f"{'':22}   total {time.perf_counter() - t0:.1f} s wall")
    if storm:
        from btgen.tools.verify.markov import build_chain, storm_queries

        probs = {
            n.name: ([(2, 0.9), (3, 0.1)] if n.kind == "Condition" else [(2, 0.7), (3, 0.1), (1, 0.2)])
            for n in program.nodes
            if n.kind in ("Action", "Condition")
        }
        t1 = time.perf_counter()
        try:
            chain = build_chain(mission, program, probs)
            (p_s,) = storm_queries(chain, ['P=? [F "success"]'])
            print(
                f"{'':22}   Storm: {len(chain.transitions)} states, P(root SUCCESS) = {p_s:.6g}, "
                f"{time.perf_counter() - t1:.1f} s"
            )
        except Exception as e:  # a chain too big is a number to report, not a crash
            print(f"{'':22}   Storm: {type(e).__name__}: {e}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,1000")
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--ticks", type=int, default=3, help="bound the runs (0: unbounded); default 3")
    ap.add_argument("--storm", action="store_true", help="also build the Markov chain and ask Storm")
    ap.add_argument("--shipped", default="LabTour.xml,Reception.xml")
    ap.add_argument(
        "--nav2",
        default=",".join(NAV2_TREES),
        help="Nav2 default trees of tests/real_files/nav2 (comma-separated stems; empty: none)",
    )
    args = ap.parse_args()
    nav2 = os.path.join(ROOT, "tests", "real_files", "nav2")
    for stem in filter(None, args.nav2.split(",")):
        opts = pipeline.CompileOptions(models=(os.path.join(nav2, "nav2_tree_nodes.xml"),))
        path = os.path.join(nav2, stem + ".xml")
        measure(stem[:22], path, args.timeout, args.storm, args.ticks or None, opts)
        # Nav2's selectors are SyncActionNodes that always answer SUCCESS (they publish a choice)
        measure("  selectors SUCCESS", path, args.timeout, args.storm, args.ticks or None, opts, NAV2_CONTRACT)
    for name in filter(None, args.shipped.split(",")):
        measure(name, os.path.join(ROOT, "missions", name), args.timeout, args.storm, args.ticks or None)
    with tempfile.TemporaryDirectory(prefix="btgen-bench-m-") as d:
        for n in (int(x) for x in args.sizes.split(",") if x):
            path = os.path.join(d, f"balanced{n}.xml")
            with open(path, "w", encoding="utf-8") as f:
                f.write(free_leaves(balanced_mission(n)))
            measure(f"balanced {n}", path, args.timeout, args.storm, args.ticks or None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
