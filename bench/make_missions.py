"""Write the synthetic benchmark missions into bench/missions/ (btgen.synth).

    .venv/bin/python bench/make_missions.py           # write the missions that changed
    .venv/bin/python bench/make_missions.py --check   # exit 1 if a committed one differs

Every mission has exactly the number of nodes in its name (SubTrees
expanded), and with leaves that finish at once (Actions and Conditions
SUCCESS) one tick of the root visits every node and succeeds:

- balanced_N: Sequence / Fallback / Inverter over leaves, 4 children per
  control node (btgen.synth.balanced_mission);
- reactive_N: the same with ReactiveSequence / ReactiveFallback;
- subtrees_N: spread over SubTrees two levels deep (Main calls Part 4 times,
  Part calls Leg 4 times);
- scripts_N: Script / ScriptCondition leaves and Actions with a `_failureIf`
  pre-condition over one blackboard entry.

Output is deterministic, so the committed files are what this script writes.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "generator"))

from btgen import synth  # noqa: E402
from btgen.compiler import write_if_changed  # noqa: E402

MISSION_DIR = HERE / "missions"

# kind -> sizes. The balanced trees show how costs grow with size; the other
# kinds what reactive nodes, SubTrees and scripts cost on top.
SIZES: dict[str, tuple[int, ...]] = {
    "balanced": (100, 1000, 10000),
    "reactive": (1000, 10000),
    "subtrees": (1000, 10000),
    "scripts": (1000, 10000),
}


def missions() -> dict[str, str]:
    """File name -> text of every synthetic mission, in table order."""
    out: dict[str, str] = {}
    for kind, sizes in SIZES.items():
        for n in sizes:
            out[f"{kind}_{n}.xml"] = synth.mission(kind, n)
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="write nothing; exit 1 if a file is missing or differs")
    args = p.parse_args(argv)
    expected = missions()
    if args.check:
        stale = [name for name, text in expected.items()
                 if not (MISSION_DIR / name).is_file() or (MISSION_DIR / name).read_text(encoding="utf-8") != text]
        for name in stale:
            print(f"bench/missions/{name} is out of date: run bench/make_missions.py", file=sys.stderr)
        return 1 if stale else 0
    for name, text in expected.items():
        if write_if_changed(MISSION_DIR / name, text):
            print(os.path.relpath(MISSION_DIR / name))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
