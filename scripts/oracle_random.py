#!/usr/bin/env python3
"""Differential testing against the real BehaviorTree.CPP: fuzzgen's random missions on both releases.

    python scripts/oracle_random.py --seeds 0:100 [--features full,dynamic,edges,...]
                                    [--btcpp 4.6.2,4.10.0] [--scenarios 2] [--keep DIR]
                                    [--harness-462 PATH] [--harness-410 PATH]

For every feature set, every release the missions are written for (fuzzgen's `--btcpp`) and every
seed, the mission is run with each of its scenarios on the real library of BOTH releases (a mission
written for one release is a valid test of the other too: where the other refuses it, btgen must
refuse it there as well) and by btgen's interpreter following that release. The trace (cut short
where the library threw) and whether the run failed must agree; the library's message is not
compared (the interpreter prints its own, located one). A divergence is written to --keep (default
build/oracle-divergences) as mission, scenario, the library's trace and error, the interpreter's.

Missions with a Delay, Timeout or Sleep are left out and counted: the library times them with a
thread on the wall clock, so their traces race with the ticks (the scenario's `clock_ms` is
btgen's injected clock only). The harnesses are the project's oracle builds
(../shared/oracle/README.md: ORACLE_462_PREFIX and ORACLE_410_PREFIX, the environment variables
BTGEN_ORACLE_462 and BTGEN_ORACLE_410, default ../oracle/462 and ../oracle/410 beside the
checkout's parent; the harness source: BTGEN_ORACLE_HARNESS_SRC, default
../shared/oracle/harness.cpp beside the checkout's parent). The compiled C++ is
compared with the interpreter on the same seeds by scripts/difftest.py. Exit 1 on any divergence.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "generator"))

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.engine import run_trace
from btgen.interp.scenario import load_scenario
from btgen.tools.fuzzgen import BTCPP_VERSIONS, FEATURE_SETS, random_case

_BESIDE = ROOT.parent.parent if ROOT.parent.name == "wt" else ROOT.parent  # a worktree's checkouts sit in wt/
PREFIX = {
    "4.6.2": os.environ.get("BTGEN_ORACLE_462", str(_BESIDE / "oracle" / "462")),
    "4.10.0": os.environ.get("BTGEN_ORACLE_410", str(_BESIDE / "oracle" / "410")),
}
HARNESS = {v: str(Path(p) / "bin" / "harness") for v, p in PREFIX.items()}
# The harness built by `--build-harness` (build/oracle-harness/): the same source with the tree never
# destroyed. The library's Tree destructor halts the tree after the last tick; an `_onHalted` script
# that throws there ends the process in std::terminate and loses the whole trace (exit 134).
OWN = ROOT / "build" / "oracle-harness"
SHARED_HARNESS = os.environ.get("BTGEN_ORACLE_HARNESS_SRC", str(_BESIDE / "shared" / "oracle" / "harness.cpp"))
TIMED = ("<Delay", "<Timeout", "<Sleep")
# Where btgen follows a later release on purpose (tests/conformance/FORMAT.md, "Where btgen follows
# a later BehaviorTree.CPP on purpose"): a run the library ends with one of these messages is
# counted as that documented difference, not as a divergence.
DOCUMENTED = {
    "4.6.2": (
        # (and a Loop node's literal queue emptied for good: compare)
        (
            "operator cannot be mixed with previous operators",
            "4.6.2 refuses an arithmetic or bitwise operand of a comparison or of `&&`/`||`",
        ),
    ),
    "4.10.0": (),
}


def build_harness(prefix: dict[str, str]) -> dict[str, str]:
    """Build OWN/harness<ver> from the shared oracle's harness.cpp, its tree never destroyed."""
    src = Path(SHARED_HARNESS).read_text(encoding="utf-8")
    line = "  BT::Tree tree = createTree(factory, mission);\n"
    if src.count(line) != 2:
        sys.exit("oracle_random: the shared harness.cpp changed; patch it by hand")
    head, _, tail = src.partition(line)  # the first one is the trace mode's
    OWN.mkdir(parents=True, exist_ok=True)
    (OWN / "harness.cpp").write_text(
        head + "  BT::Tree& tree = *new BT::Tree(createTree(factory, mission));  // never destroyed\n" + tail,
        encoding="utf-8",
    )
    out = {}
    for version, pre in prefix.items():
        binary = OWN / f"harness{version.replace('.', '')}"
        cmd = ["g++", "-std=c++17", "-O1", "-o", str(binary), str(OWN / "harness.cpp"), f"-I{pre}/include"]
        cmd += [f"-L{pre}/lib", f"-Wl,-rpath,{pre}/lib", "-lbehaviortree_cpp"]
        subprocess.run(cmd, check=True)
        out[version] = str(binary)
    return out


def default_harness(version: str) -> str:
    own = OWN / f"harness{version.replace('.', '')}"
    return str(own) if own.is_file() else HARNESS[version]


def library(harness: str, mission: str, scenario: str) -> tuple[str, bool, str]:
    """The library's trace, whether it refused or threw, and its messages (stderr, warnings left out)."""
    # unbuffered: a run that ends in std::terminate keeps the lines it printed
    unbuffered = ["stdbuf", "-o0"] if shutil.which("stdbuf") else []
    proc = subprocess.run(
        [*unbuffered, harness, "trace", mission, scenario], capture_output=True, timeout=120, check=False
    )
    err = [
        ln for ln in proc.stderr.decode("utf-8", "replace").splitlines() if ln.strip() and not ln.startswith("warning:")
    ]
    return proc.stdout.decode("utf-8", "replace"), proc.returncode != 0, "\n".join(err)


def unmasked(harness: str, text: str, scenario: str, tmp: str, lib: tuple[str, bool, str]) -> tuple[str, bool, str]:
    """4.6.2 may end a refusal in std::terminate: while it unwinds the half-created tree, a halt
    runs an `_onHalted` script that throws, and the refusal's own message is lost. Run the mission
    without its `_onHalted` scripts: when the library then refuses it with no trace, that refusal
    (and its message) is the one the abort hid; otherwise the abort stands."""
    trace = lib[0]
    ticks = re.search(r"^ticks (\d+)", Path(scenario).read_text(encoding="utf-8"), re.M)
    last = trace.rstrip("\n").rsplit("\n", 1)[-1]
    done = last in ("result SUCCESS", "result FAILURE") or (
        last.startswith("result ") and ticks is not None and trace.count("\ntick ") + 1 == int(ticks.group(1))
    )
    if trace.startswith("tick 1\n") and done:
        # every tick ran and printed: the abort came after the run (the harness ends with the tree
        # still RUNNING), which is no part of the trace
        return trace, False, lib[2] + "\n(after the last tick)"
    variant = os.path.join(tmp, "unmasked.xml")
    Path(variant).write_text(re.sub(r'\s_onHalted="[^"]*"', "", text), encoding="utf-8")
    again = library(harness, variant, scenario)
    if again[1] and not again[0] and "terminate called" not in again[2]:
        return again[0], True, lib[2] + "\n(without its _onHalted scripts:)\n" + again[2]
    if not lib[0] and (not again[1] or (again[0] and "terminate called" not in again[2])):
        # the abort came before the first tick and the mission runs (or starts to run) without
        # its _onHalted scripts: a halt while the library was creating the tree, no part of any
        # trace; that run is the one to compare
        return again[0], again[1], ABORT_MARK + lib[2] + ("\n" + again[2] if again[1] else "")
    return lib


def observe(harness: str, text: str, mission: str, scenario: str, tmp: str) -> tuple[str, bool, str]:
    """The library's run of `mission` (whose text is `text`), an abort unmasked (`unmasked`)."""
    lib = library(harness, mission, scenario)
    if lib[1] and "terminate called" in lib[2]:
        lib = unmasked(harness, text, scenario, tmp, lib)
    return lib


def interpreter(mission: str, scenario: str, version: str) -> tuple[str, bool, str]:
    """btgen's interpreter under `version`: the trace, whether it failed, its first message."""
    out: list[str] = []
    try:
        m = load_mission(mission, btcpp=version)
        sc, _ = load_scenario(scenario, m)
        run_trace(m, sc, out.append)
    except UserError as e:
        return "".join(out), True, e.diagnostics[0].message
    return "".join(out), False, ""


ABORT_MARK = "(the library aborted before the first tick; this is its run without the _onHalted scripts) "


def compare(lib: tuple[str, bool, str], got: tuple[str, bool, str], version: str, mission: str = "") -> str:
    """The verdict: `agree`, `documented` (a difference FORMAT.md documents) or `divergence`."""
    if lib[:2] == got[:2]:
        return "library abort" if lib[2].startswith(ABORT_MARK) else "agree"
    if lib[1] and any(m in lib[2] for m, _ in DOCUMENTED[version]):
        return "documented"
    if version == "4.6.2" and (
        _reentered_literal_loop(lib[0], got[0], mission) or _entry_update_462(lib[0], got[0], mission)
    ):
        return "documented"
    return "divergence"


def _first_difference(lib: str, got: str) -> tuple[str, str]:
    a, b = lib.splitlines(), got.splitlines()
    i = next((k for k, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
    return (a[i] if i < len(a) else ""), (b[i] if i < len(b) else "")


def _entry_update_462(lib: str, got: str, mission: str) -> bool:
    """Two 4.6.2 behaviours of the entry-update nodes btgen leaves on purpose (FORMAT.md): a
    SetBlackboard copy (`value="{key}"`) is no update for them, and halting SkipUnlessUpdated or
    WaitValueUpdate leaves their RUNNING child running (btgen halts it). Approximate: the mission
    has such a node, and a copy or, where the traces part, btgen halts a node."""
    if not re.search(r"<(SkipUnlessUpdated|WaitValueUpdate|WasEntryUpdated)\b", mission):
        return False
    _, theirs = _first_difference(lib, got)
    copies = re.search(r'<SetBlackboard\b[^>]*\svalue="\{', mission) is not None
    halts = theirs.endswith("RUNNING -> IDLE")
    return halts or copies


def _reentered_literal_loop(lib: str, got: str, mission: str) -> bool:
    """4.6.2 empties a Loop node's literal queue for good (FORMAT.md): where the traces part, btgen
    starts a Loop node again that has a literal queue in the mission."""
    _, theirs = _first_difference(lib, got)
    m = re.fullmatch(r'\d+ (Loop(?:Int|Bool|Double|String)) ".*" IDLE -> RUNNING', theirs)
    return m is not None and re.search(rf'<{m.group(1)}\b[^>]*\squeue="(?!\{{)', mission) is not None


def keep_case(keep: Path, stem: str, mission: str, scenario: str, lib: tuple, got: tuple) -> Path:
    out = keep / stem
    keep.mkdir(parents=True, exist_ok=True)
    Path(f"{out}.xml").write_text(mission, encoding="utf-8")
    Path(f"{out}.scenario").write_text(scenario, encoding="utf-8")
    Path(f"{out}.lib").write_text(f"{lib[0]}--- failed={lib[1]} {lib[2]}\n", encoding="utf-8")
    Path(f"{out}.interp").write_text(f"{got[0]}--- failed={got[1]} {got[2]}\n", encoding="utf-8")
    return out


def timing_is_safe(mission: str, scenario: str, margin_ms: int = 4) -> bool:
    """`--timed`: a mission whose Delay, Timeout and Sleep durations are all literal whole numbers of
    milliseconds, with a scenario clock that moves at least 10 ms a tick, every duration at least
    `margin_ms` away from a multiple of the clock and none of them 0 (a 0 ms timer races with the
    next tick on both releases). The harness sleeps `clock_ms` between ticks, so such a timer fires
    well inside a gap between two ticks, as btgen's virtual clock has it."""
    clock = re.search(r"^clock_ms (\d+)", scenario, re.M)
    if clock is None or int(clock.group(1)) < 10:
        return False
    c = int(clock.group(1))
    values = re.findall(r'<(?:Delay|Timeout|Sleep)\b[^>]*?\s(?:delay_msec|msec)="([^"]*)"', mission)
    if len(values) != sum(mission.count(t) for t in TIMED):
        return False
    for v in values:
        if not v.isdigit() or int(v) == 0:
            return False
        r = int(v) % c
        if r < margin_ms or c - r < margin_ms:
            return False
    return True


def run(
    features: list[str],
    written_for: list[str],
    seeds: range,
    n_scenarios: int,
    keep: Path,
    harness: dict[str, str],
    log=print,
    timed: bool = False,
) -> tuple[Counter, list[str]]:
    """Counts keyed (features, written for, run on, what) and the divergences kept."""
    counts: Counter = Counter()
    found: list[str] = []
    with tempfile.TemporaryDirectory() as tmp:
        mission, scenario = os.path.join(tmp, "m.xml"), os.path.join(tmp, "m.scenario")
        for feat, wf, seed in ((f, w, s) for f in features for w in written_for for s in seeds):
            case = random_case(seed, feat, n_scenarios, wf)
            scenarios = list(enumerate(case.scenarios))
            if any(t in case.mission for t in TIMED):
                scenarios = [(j, t) for j, t in scenarios if timed and timing_is_safe(case.mission, t)]
                if not scenarios:
                    counts[(feat, wf, "*", "timed, left out")] += 1
                    continue
                counts[(feat, wf, "*", "timed, run")] += 1
            Path(mission).write_text(case.mission, encoding="utf-8")
            counts[(feat, wf, "*", "missions")] += 1
            for j, text in scenarios:
                Path(scenario).write_text(text, encoding="utf-8")
                for version in BTCPP_VERSIONS:
                    lib = observe(harness[version], case.mission, mission, scenario, tmp)
                    got = interpreter(mission, scenario, version)
                    key = (feat, wf, version)
                    counts[(*key, "runs")] += 1
                    if lib[1]:
                        counts[(*key, "library failed" if lib[0] else "library refused")] += 1
                    verdict = compare(lib, got, version, case.mission)
                    if verdict == "agree":
                        continue
                    counts[(*key, verdict)] += 1
                    if verdict in ("documented", "library abort"):
                        continue
                    stem = keep_case(
                        keep, f"{feat}_{wf}_{seed}_s{j}_on{version.replace('.', '')}", case.mission, text, lib, got
                    )
                    found.append(str(stem))
                    log(
                        f"DIVERGENCE {stem}.xml: library failed={lib[1]} ({lib[2][-150:]!r}), "
                        f"interpreter failed={got[1]} ({got[2][:150]!r})"
                    )
    return counts, found


def table(counts: Counter) -> str:
    rows = sorted({k[:2] for k in counts})
    lines = [
        "| features | written for | missions | of them timed | timed, left out | runs on 4.6.2 | on 4.10.0 "
        "| library threw or refused | documented differences | library aborted | divergences |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for feat, wf in rows:
        threw = sum(counts[(feat, wf, v, w)] for v in BTCPP_VERSIONS for w in ("library failed", "library refused"))
        div = sum(counts[(feat, wf, v, "divergence")] for v in BTCPP_VERSIONS)
        doc = sum(counts[(feat, wf, v, "documented")] for v in BTCPP_VERSIONS)
        abort = sum(counts[(feat, wf, v, "library abort")] for v in BTCPP_VERSIONS)
        missions, timed = counts[(feat, wf, "*", "missions")], counts[(feat, wf, "*", "timed, left out")]
        timed_run = counts[(feat, wf, "*", "timed, run")]
        runs = [counts[(feat, wf, v, "runs")] for v in BTCPP_VERSIONS]
        lines.append(
            f"| {feat} | {wf} | {missions} | {timed_run} | {timed} | {runs[0]} | {runs[1]} "
            f"| {threw} | {doc} | {abort} | {div} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", required=True, metavar="A:B", help="seeds A to B-1")
    p.add_argument("--features", default="control,full,dynamic,hostile,edges")
    p.add_argument("--btcpp", default=",".join(BTCPP_VERSIONS), help="the releases the missions are written for")
    p.add_argument("--scenarios", type=int, default=2)
    p.add_argument("--keep", type=Path, default=ROOT / "build" / "oracle-divergences")
    p.add_argument("--harness-462", default=default_harness("4.6.2"))
    p.add_argument("--harness-410", default=default_harness("4.10.0"))
    p.add_argument(
        "--timed", action="store_true", help="also run timed missions whose timers cannot race (timing_is_safe)"
    )
    p.add_argument("--build-harness", action="store_true", help=f"build the harness copies into {OWN} first")
    args = p.parse_args(argv)
    a, _, b = args.seeds.partition(":")
    features = args.features.split(",")
    written = args.btcpp.split(",")
    for f in features:
        if f not in FEATURE_SETS:
            p.error(f"unknown feature set `{f}`")
    for v in written:
        if v not in BTCPP_VERSIONS:
            p.error(f"unknown release `{v}`")
    harness = {"4.6.2": args.harness_462, "4.10.0": args.harness_410}
    if args.build_harness:
        harness = build_harness(PREFIX)
    start = time.monotonic()
    counts, found = run(
        features,
        written,
        range(int(a), int(b)),
        args.scenarios,
        args.keep,
        harness,
        log=lambda s: print(s, file=sys.stderr, flush=True),
        timed=args.timed,
    )
    print(table(counts))
    print(f"{len(found)} divergences, {time.monotonic() - start:.0f} s")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
