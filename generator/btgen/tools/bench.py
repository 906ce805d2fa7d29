"""`btgen bench`: build a mission with instant leaves and measure its ticks.

    btgen bench MISSION.xml [--ticks N]

compiles the mission, builds it at -O2 together with `bench/bench_main.cpp`
(leaves that finish at once, a clock that never moves) and the allocation
counter (`runtime/src/testing/alloc_counter.cpp`, which replaces the global
operator new/delete and malloc), runs N ticks and prints one `key value` per
line: KEYS below, then `binary`, the executable's path. The executable is
cached like the scenario runner (btgen.tools.cppengine), keyed by its contents.

`BINARY N` performs N ticks and prints nothing, so its instructions can be
counted: `valgrind --tool=callgrind BINARY N`, for two values of N, gives the
instructions of one tick as the difference divided by the difference of N.
`BINARY N --report` prints the numbers. `bench/run_benchmarks.py` does all
of that for the shipped and the synthetic missions and prints a table.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path
from typing import Optional

from btgen import cmdline, resources
from btgen.diagnostics import InternalError
from btgen.pipeline import DEFAULTS, CompileOptions, options_from_args
from btgen.tools.cppengine import build_mission_executable

BENCH_MAIN = resources.BENCH_DIR / "bench_main.cpp"
ALLOC_COUNTER = resources.RUNTIME_SRC / "testing" / "alloc_counter.cpp"
BENCH_FLAGS = ("-std=c++17", "-O2", "-DNDEBUG")

# What the executable reports, in the order `btgen bench` prints it.
KEYS = (
    "nodes",
    "ticks",
    "ns_per_tick",
    "allocs_create",
    "allocs_per_tick",
    "state_bytes",
    "node_state_bytes",
    "blackboard_bytes",
    "visited_per_tick",
    "result",
    "alloc_counter",
)


def build_bench(mission_path: str, warnings: Optional[list] = None, opts: CompileOptions = DEFAULTS) -> Path:
    """The mission's benchmark executable (cached); errors as cppengine.build_cpp."""
    return build_mission_executable(mission_path, (BENCH_MAIN, ALLOC_COUNTER), BENCH_FLAGS, warnings, opts)


def parse_report(text: str) -> dict[str, str]:
    """The `key value` lines of `BINARY N --report`."""
    out: dict[str, str] = {}
    for line in text.splitlines():
        key, _, value = line.partition(" ")
        if key:
            out[key] = value
    return out


def run_report(binary: Path, ticks: int) -> dict[str, str]:
    """Run `binary ticks --report`; its numbers by key."""
    proc = subprocess.run([str(binary), str(ticks), "--report"], capture_output=True, check=False)
    if proc.returncode != 0:
        raise InternalError(
            f"{binary} {ticks} --report exited with {proc.returncode}:\n" + proc.stderr.decode("utf-8", "replace")
        )
    report = parse_report(proc.stdout.decode("utf-8", "replace"))
    missing = [k for k in KEYS if k not in report]
    if missing:
        raise InternalError(f"{binary} did not report {', '.join(missing)}")
    return report


def bench_command(args: argparse.Namespace) -> int:
    """The `bench` subcommand: 0 on success; UserError (a bad --ticks too) propagates to the CLI."""
    if args.ticks < 1:
        raise cmdline.error(args, "--ticks", f"--ticks must be at least 1, not {args.ticks}")
    warnings: list = []
    binary = build_bench(args.mission, warnings, options_from_args(args))
    for w in warnings:
        print(str(w), file=sys.stderr)
    report = run_report(binary, args.ticks)
    for key in KEYS:
        print(f"{key} {report[key]}")
    print(f"binary {binary}")
    return 0
