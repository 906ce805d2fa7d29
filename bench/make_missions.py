"""Write the synthetic benchmark missions into bench/missions/ (btgen.tools.synth).

    .venv/bin/python bench/make_missions.py           # write the missions that changed
    .venv/bin/python bench/make_missions.py --check   # exit 1 if a committed one differs

Every mission has exactly the number of nodes in its name (SubTrees
expanded), and with leaves that finish at once (Actions and Conditions
SUCCESS) one tick of the root visits every node and succeeds:

- balanced_N: Sequence / Fallback / Inverter over leaves, 4 children per
  control node (btgen.tools.synth.balanced_mission);
- reactive_N: the same with ReactiveSequence / ReactiveFallback;
- subtrees_N: spread over SubTrees two levels deep (Main calls Part 4 times,
  Part calls Leg 4 times);
- scripts_N: Script / ScriptCondition leaves and Actions with a `_failureIf`
  pre-condition over one blackboard entry;
- balanced5_1043: the balanced tree with 5 children per control node (four
  levels of Sequence / Fallback under the root), 1,043 nodes: the size BehaviorTree.CPP 4.6.2 was
  measured on for the performance targets (997,604 instructions per tick);
- museum_93: a 93-node mission of the museum's shape (SubTrees, a
  RetryUntilSuccessful, two Parallels, a ReactiveSequence; BehaviorTree.CPP
  4.6.2: 128,888 instructions per tick, as measured for the performance targets).

Output is deterministic, so the committed files are what this script writes.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "generator"))

from btgen.compiler import write_if_changed
from btgen.tools import synth

MISSION_DIR = HERE / "missions"

# kind -> sizes. The balanced trees show how costs grow with size; the other
# kinds what reactive nodes, SubTrees and scripts cost on top.
SIZES: dict[str, tuple[int, ...]] = {
    "balanced": (100, 1000, 10000),
    "reactive": (1000, 10000),
    "subtrees": (1000, 10000),
    "scripts": (1000, 10000),
}


def museum_mission() -> str:
    """93 nodes (SubTrees expanded) shaped like the museum mission: a start-up
    SubTree, a ReactiveSequence guarding a tour of exhibit SubTrees, two
    Parallels and a docking SubTree under a RetryUntilSuccessful. With leaves
    that succeed at once one tick visits every node and succeeds."""
    exhibit = [
        '    <Sequence name="Exhibit">',
        "      <Ready/>",
        '      <Fallback name="Approach">',
        "        <Inverter>",
        "          <Ready/>",
        "        </Inverter>",
        "        <Work/>",
        "      </Fallback>",
        "      <Work/>",
        "      <Work/>",
        "    </Sequence>",
    ]
    startup = [
        '    <Sequence name="Startup">',
        "      <Ready/>",
        "      <Work/>",
        "      <ForceSuccess>",
        "        <Work/>",
        "      </ForceSuccess>",
        "      <Work/>",
        "    </Sequence>",
    ]
    dock = ['    <Sequence name="Dock">', "      <Ready/>", "      <Work/>", "      <Work/>", "    </Sequence>"]
    main = [
        '    <Sequence name="Museum">',
        '      <SubTree ID="Startup"/>',
        '      <ReactiveSequence name="Guarded">',
        "        <Ready/>",
        "        <Ready/>",
        '        <Sequence name="Tour">',
    ]
    main += [f'          <SubTree ID="Exhibit" name="Exhibit{i}"/>' for i in range(5)]
    main += [
        "        </Sequence>",
        "      </ReactiveSequence>",
        '      <Parallel name="Present" success_count="2" failure_count="1">',
        '        <SubTree ID="Exhibit" name="Highlight"/>',
        "        <Sequence>",
        "          <Ready/>",
        "          <Work/>",
        "        </Sequence>",
        "        <Work/>",
        "      </Parallel>",
        '      <RetryUntilSuccessful num_attempts="3">',
        '        <SubTree ID="Dock"/>',
        "      </RetryUntilSuccessful>",
        '      <Parallel name="Farewell" success_count="-1" failure_count="1">',
        "        <Work/>",
        "        <Work/>",
        "        <Ready/>",
        "        <Sequence>",
        "          <Ready/>",
        "          <Work/>",
        "        </Sequence>",
        "      </Parallel>",
        '      <SubTree ID="Exhibit" name="Goodbye"/>',
        "    </Sequence>",
    ]
    return synth._document("Main", [("Main", main), ("Startup", startup), ("Exhibit", exhibit), ("Dock", dock)])


def missions() -> dict[str, str]:
    """File name -> text of every synthetic mission, in table order."""
    out: dict[str, str] = {}
    for kind, sizes in SIZES.items():
        for n in sizes:
            out[f"{kind}_{n}.xml"] = synth.mission(kind, n)
    out["balanced5_1043.xml"] = synth.balanced_mission(1043, branching=5)
    out["museum_93.xml"] = museum_mission()
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="write nothing; exit 1 if a file is missing or differs")
    args = p.parse_args(argv)
    expected = missions()
    if args.check:
        stale = [
            name
            for name, text in expected.items()
            if not (MISSION_DIR / name).is_file() or (MISSION_DIR / name).read_text(encoding="utf-8") != text
        ]
        for name in stale:
            print(f"bench/missions/{name} is out of date: run bench/make_missions.py", file=sys.stderr)
        return 1 if stale else 0
    for name, text in expected.items():
        if write_if_changed(MISSION_DIR / name, text):
            print(os.path.relpath(MISSION_DIR / name))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
