"""`btgen analyze` against `btgen explore --no-merge` on random missions (tools/fuzzgen.py):
every node explore ticks is reachable for analyze, every status a node returns is one analyze
finds possible, and no tick does more work than analyze's bound. Deterministic seeds."""

from __future__ import annotations

import pytest

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.ir.data.records import DataOptions
from btgen.ir.lower import lower
from btgen.tools.analyze import analyze_program
from btgen.tools.explore import BY_NAME, Explorer
from btgen.tools.fuzzgen import random_mission

# Of the 25 missions of each set, those on which explore reaches analyze's bound of nodes per
# tick exactly (measured 2026-11-28; each set generated for the release it runs under). A change
# that makes analyze's bound looser, or explore reach less, fails here; one that makes them meet
# more often raises the floor.
EXACT_FLOOR = {("control", "4.6.2"): 21, ("full", "4.6.2"): 14, ("full", "4.10.0"): 12, ("edges", "4.6.2"): 14}


@pytest.mark.parametrize(("features", "btcpp"), sorted(EXACT_FLOOR))
def test_analyze_is_sound_and_mostly_exact(tmp_path, features, btcpp):
    exact = total = refused = 0
    for seed in range(25):
        path = tmp_path / f"{features}_{seed}.xml"
        path.write_text(random_mission(seed, features, btcpp))
        mission = load_mission(str(path), btcpp=btcpp)
        try:
            program = lower(mission)
        except UserError:
            refused += 1  # analyze reads the lowered tables: a mission the back end refuses
            continue
        result = analyze_program(mission, program, DataOptions())
        possible = {
            i: ({BY_NAME[s] for s in result.outcomes[i]} if result.reachable[i] else set())
            for i in range(len(program.nodes))
        }
        ex = Explorer(mission, ticks=3, depth=30, clock_ms=100, max_states=3000, possible=possible, merge=False)
        run = ex.explore()
        index = {n.uid: i for i, n in enumerate(ex.nodes)}
        for goal in ex.reached:
            i = index[goal[1]]
            assert result.reachable[i], (seed, goal)
            if goal[0] == "outcome":
                assert goal[2] in possible[i], (seed, goal, result.outcomes[i])
        worst = result.worst()
        assert run.max_visits <= worst[0] and run.max_hooks <= worst[1], (seed, run.max_visits, worst)
        total += 1
        exact += run.max_visits == worst[0]
    assert (total, refused) == (25, 0)
    assert exact >= EXACT_FLOOR[(features, btcpp)], (exact, total)


@pytest.mark.parametrize("features", ["control", "full"])
def test_merging_states_loses_no_goal(tmp_path, features):
    """The state hash of explore cuts runs that reach a state already explored: the goals reached
    must be those of the exhaustive search without it."""
    for seed in range(15):
        path = tmp_path / f"{features}_{seed}.xml"
        path.write_text(random_mission(seed, features))
        mission = load_mission(str(path))
        full = Explorer(mission, ticks=3, depth=30, clock_ms=100, max_states=5000, merge=False)
        merged = Explorer(mission, ticks=3, depth=30, clock_ms=100, max_states=5000, merge=True)
        a, b = full.explore(), merged.explore()
        assert not a.truncated and not b.truncated
        assert merged.reached == full.reached, seed
        assert b.states <= a.states
