"""Instructions per tick of BehaviorTree.CPP itself on the benchmark missions, recorded once.

    .venv/bin/python bench/btcpp_instructions.py HARNESS [MISSION.xml ...] > bench/btcpp-4.6.2.tsv

HARNESS is the oracle's harness (an oracle build of the real library, see the oracle's
README: `harness bench MISSION.xml N` ticks N times with instant leaves). Like
run_benchmarks.py for btgen, callgrind counts the instructions of two runs (2 and 7
ticks) and the difference is divided by 5, so loading the XML and building the tree
cancel. The output is a tab-separated table (mission path, instructions per tick) that
run_benchmarks.py reads for its `BT.CPP instr/tick` and `vs BT.CPP` columns. The
10,000-node missions take a few minutes each under callgrind.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
TICKS = (2, 7)


def default_missions() -> list[Path]:
    return sorted((ROOT / "missions").glob("*.xml")) + sorted((HERE / "missions").glob("*.xml"))


def instructions(harness: str, mission: Path, ticks: int) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        proc = subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                f"--callgrind-out-file={tmp}/cg.out",
                harness,
                "bench",
                str(mission),
                str(ticks),
            ],
            capture_output=True,
            text=True,
            check=False,
        )
    m = re.search(r"Collected : (\d+)", proc.stderr)
    if proc.returncode != 0 or m is None:
        raise SystemExit(f"{mission}: the harness failed (exit {proc.returncode}): {proc.stderr[-500:]}")
    return int(m.group(1))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("harness")
    p.add_argument("missions", nargs="*", type=Path)
    args = p.parse_args(argv)
    print("# mission\tBehaviorTree.CPP instructions per tick (callgrind, ticks 7 minus 2, divided by 5)")
    for mission in args.missions or default_missions():
        lo, hi = (instructions(args.harness, mission, n) for n in TICKS)
        rel = mission.resolve().relative_to(ROOT)
        print(f"{rel}\t{(hi - lo) // (TICKS[1] - TICKS[0])}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
