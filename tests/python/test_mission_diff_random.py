"""`btgen diff` cross-checked on random missions (tools/fuzzgen.py): every "equivalent" is
sampled with random scenarios that must run alike, every counterexample must replay as a
difference. Pairs: a mission under 4.6.2 and 4.10.0, and a mission and the same with two
children of one control node swapped.

BTGEN_DIFF_SEEDS=N runs N seeds (default 12, a few seconds)."""

from __future__ import annotations

import os
import random
import xml.etree.ElementTree as ET

from btgen import pipeline
from btgen.diagnostics import UserError
from btgen.interp.scenario import parse_scenario_text
from btgen.tools.diff.product import Differ, first_difference, observe
from btgen.tools.explore import NAMES
from btgen.tools.fuzzgen import random_mission, random_scenario

SEEDS = int(os.environ.get("BTGEN_DIFF_SEEDS", "12"))
TICKS = 5
CLOCK = 10
SAMPLES = 25
CONTROLS = {"Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory", "Parallel"}


def _swap(xml: str, rng: random.Random) -> str:
    root = ET.fromstring(xml)
    parents = [e for e in root.iter() if e.tag in CONTROLS and len(e) >= 2]
    if not parents:
        return xml
    p = rng.choice(parents)
    i = rng.randrange(len(p) - 1)
    a, b = p[i], p[i + 1]
    p.remove(a)
    p.insert(i + 1, a)
    del b
    return ET.tostring(root, encoding="unicode")


def _scenario(rng: random.Random) -> str:
    lines = [ln for ln in random_scenario(rng).splitlines() if not ln.startswith(("ticks", "clock_ms"))]
    return "\n".join([f"ticks {TICKS}", f"clock_ms {CLOCK}", *lines]) + "\n"


def _load(tmp_path, name: str, text: str, version: str):
    path = tmp_path / f"{name}.xml"
    path.write_text(text)
    return pipeline.load(str(path), pipeline.CompileOptions(btcpp=version))


def _check_pair(old, new, rng: random.Random, tally: dict) -> None:
    try:
        outcome = Differ(old, new, max_ticks=TICKS, clock_ms=CLOCK, max_states=3000).decide()
    except UserError:  # a mission the interpreter cannot build (a load-time run error): no claim
        tally["skipped"] += 1
        return
    if not outcome.equivalent:
        tally["different"] += 1
        picks = "\n".join(f"leaf {n} " + " ".join(NAMES[s] for s in sts) for n, sts in outcome.plan.items())
        sc = parse_scenario_text(f"ticks {outcome.ticks}\nclock_ms {CLOCK}\n{picks}\n")
        assert first_difference(observe(old, sc), observe(new, sc)) is not None
        return
    if outcome.why_bounded == "states":
        tally["partial"] += 1
        return
    tally["equivalent"] += 1
    for _ in range(SAMPLES):
        sc = parse_scenario_text(_scenario(rng))
        try:
            a = observe(old, sc)
        except UserError:
            continue
        b = observe(new, sc)
        assert first_difference(a, b) is None, "an `equivalent` pair runs differently"


def test_claims_hold_on_random_missions(tmp_path):
    tally = {"equivalent": 0, "different": 0, "partial": 0, "skipped": 0}
    for seed in range(SEEDS):
        rng = random.Random(seed)
        xml = random_mission(seed, "control" if seed % 2 else "full")
        try:
            m462 = _load(tmp_path, f"m{seed}", xml, "4.6.2")
        except UserError:
            tally["skipped"] += 1
            continue
        try:
            m410 = _load(tmp_path, f"m{seed}", xml, "4.10.0")
            _check_pair(m462, m410, rng, tally)
        except UserError:
            tally["skipped"] += 1
        swapped = _swap(xml, rng)
        try:
            ms = _load(tmp_path, f"s{seed}", swapped, "4.6.2")
        except UserError:
            tally["skipped"] += 1
            continue
        _check_pair(m462, ms, rng, tally)
    print(f"{SEEDS} seeds: {tally}")
    # both verdicts were exercised
    assert tally["equivalent"] > 0 and tally["different"] > 0
