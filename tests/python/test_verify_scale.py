"""`btgen verify` at scale: halts as d_steps (a smaller verifier, the same runs), bitstate search
labelled partial (never "holds"), and `--search auto` when the exhaustive search does not fit."""

from __future__ import annotations

import math
import re
import subprocess

import pytest

from btgen import pipeline
from btgen.cli import main
from btgen.tools.verify import spin
from btgen.tools.verify.agree import explore_tick_states, spin_tick_states
from btgen.tools.verify.promela import D_STEP_LINES, ModelOptions, emit_model
from verify_missions import GRASP, write_mission

SAFE = "[] !(running(Grasp) && running(Place))"  # holds: a Sequence runs one child at a time


def test_bitstate_search_is_partial_never_holds(tmp_path, capsys):
    path = write_mission(tmp_path, GRASP)
    rc = main(["verify", path, "--search", "bitstate", "--property", SAFE])
    out, err = capsys.readouterr()
    assert rc == 2, err
    assert "holds" not in out
    line = next(x for x in out.splitlines() if SAFE in x)
    assert line.startswith("  partial ") and "(bitstate, hash factor" in line and "): not a proof" in line
    assert "bitstate search: no proofs" in out
    # the same property, exhaustively: proved
    assert main(["verify", path, "--property", SAFE]) == 0
    assert "holds     " + SAFE in capsys.readouterr().out


def test_a_bitstate_violation_is_a_counterexample_that_replays(tmp_path, capsys):
    path = write_mission(tmp_path, GRASP)
    rc = main(["verify", path, "--search", "bitstate", "--property", "[] !running(Grasp)", "--property", SAFE])
    out, _ = capsys.readouterr()
    assert rc == 1  # a violation outranks a partial answer
    assert "VIOLATED  [] !running(Grasp)" in out
    assert "replayed on the interpreter: the violation shows" in out
    assert "  partial   " + SAFE in out


def test_auto_falls_back_to_bitstate_when_the_exhaustive_search_does_not_fit(tmp_path, capsys, monkeypatch):
    path = write_mission(tmp_path, GRASP)
    # 40 MB: pan's hash table alone does not fit (its exhaustive search stops at once); the
    # bitstate search takes a quarter of it
    monkeypatch.setenv("BTGEN_PAN_MEMLIM_MB", "40")
    assert spin.bitstate_bits() == 26  # 8 MB: the largest power of two within 10 MB
    rc = main(["verify", path, "--property", SAFE])
    out, err = capsys.readouterr()
    assert rc == 1 and "no proof, the search is incomplete: the search ran out of memory (40 MB)" in err
    assert "holds" not in out
    rc = main(["verify", path, "--search", "auto", "--property", SAFE])
    out, err = capsys.readouterr()
    assert rc == 2, err
    line = next(x for x in out.splitlines() if SAFE in x)
    assert line.startswith("  partial ") and "not a proof" in line
    assert "the exhaustive search did not fit: the search ran out of memory (40 MB)" in line


def test_search_needs_a_property(tmp_path, capsys):
    path = write_mission(tmp_path, GRASP)
    assert main(["verify", path, "--search", "bitstate"]) == 1
    assert "--search bitstate|auto checks properties" in capsys.readouterr().err


def test_the_coverage_estimate_by_hand():
    # hash factor 100, 3 bits a state: a state is missed with (1 - e^-0.03)^3 = 2.6e-5
    text = spin.bitstate_summary(1000, 100.0)
    miss = (1 - math.exp(-0.03)) ** 3
    assert abs(miss - 2.6e-5) < 1e-6
    assert (
        text == "no violation found in 1000 states (bitstate, hash factor 100, coverage estimate 99.9974%): not a proof"
    )
    assert "coverage estimate 0%" in spin.bitstate_summary(10, 0.0)
    assert "coverage estimate >99.9999%" in spin.bitstate_summary(10, 1e6)


# A Sequence of many Inverters over a Fallback each: its halt is longer than one d_step may be.
def _wide(n: int) -> str:
    kids = "".join(
        f'<Inverter><Fallback><Ready name="r{i}"/><Work name="w{i}"/></Fallback></Inverter>' for i in range(n)
    )
    return f"""<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><Sequence><Sequence>{kids}</Sequence><Work name="last"/></Sequence></BehaviorTree>
  <TreeNodesModel><Condition ID="Ready"/><Action ID="Work"/></TreeNodesModel>
</root>
"""


def test_halts_are_d_steps_split_where_spin_would_refuse_them(tmp_path):
    path = write_mission(tmp_path, _wide(40))
    mission, program = pipeline.build(path)
    text = emit_model(mission, program, ModelOptions(ticks=2, running_bound=1))
    assert "atomic { d_step {" in text
    # no d_step longer than the bound (SPIN refuses a few hundred statements), none nested
    depth, longest, start = 0, 0, 0
    for k, line in enumerate(text.splitlines()):
        if "d_step {" in line and "atomic {" in line:  # a halt's (the tick end's is one too)
            assert depth == 0, "a nested d_step"
            depth, start = 1, k
        elif depth and line.strip() == "} };":
            depth, longest = 0, max(longest, k - start - 1)
    assert 0 < longest <= D_STEP_LINES
    (tmp_path / "w").mkdir()
    (tmp_path / "w" / "model.pml").write_text(text, encoding="utf-8")
    p = subprocess.run(["spin", "-a", "model.pml"], cwd=tmp_path / "w", capture_output=True, text=True, check=False)
    assert p.returncode == 0 and "too long" not in p.stdout + p.stderr, p.stdout + p.stderr


@pytest.mark.parametrize("n", [3, 6])
def test_split_halts_reach_explores_tick_end_states(tmp_path, n):
    """The halt code split into several d_steps (a small D_STEP_LINES) keeps the runs: the
    tick-end states SPIN reaches are explore's."""
    from btgen.tools.verify import promela

    path = write_mission(tmp_path, _wide(n))
    mission, program = pipeline.build(path)
    old = promela.D_STEP_LINES
    try:
        promela.D_STEP_LINES = 4
        text = emit_model(mission, program, ModelOptions(ticks=2))
        assert len(re.findall(r"d_step \{", text)) > n
        ex, _runs, truncated = explore_tick_states(mission, 2, 100)
        sp, _res = spin_tick_states(mission, program, 2, 100, str(tmp_path / "w"), atomic_paths=0)
    finally:
        promela.D_STEP_LINES = old
    assert ex == sp and not truncated and len(sp) > 2


def test_pan_built_by_tcc_searches_as_gccs(tmp_path, monkeypatch):
    """tcc builds pan when installed: the same states, transitions and tick-end states as gcc's."""
    import shutil

    if shutil.which("tcc") is None:
        pytest.skip("no tcc")  # scripts/setup.sh installs it
    path = write_mission(tmp_path, GRASP)
    mission, program = pipeline.build(path)
    text = emit_model(mission, program, ModelOptions(ticks=4, running_bound=1, print_states=True))
    seen = {}
    for cc in ("gcc", "tcc"):
        monkeypatch.setenv("BTGEN_PAN_CC", cc)
        assert spin.tools()[1].endswith(cc)
        res = spin.reachable(text, str(tmp_path / cc), print_states=True)
        seen[cc] = (res.states, res.transitions, sorted(x for x in res.lines if x.startswith("@S")))
    assert seen["gcc"] == seen["tcc"] and seen["gcc"][0] > 100


@pytest.mark.parametrize("seed", [3, 7])
def test_packed_state_vector_reaches_the_same_states(tmp_path, seed):
    """Status temporaries and counters as bit fields: a smaller state vector, the same tick-end
    states as the model of bytes (with a RUNNING bound too: its counter packed), and explore's."""
    from btgen.tools.fuzzgen import random_case

    path = write_mission(tmp_path, random_case(seed, "control", 1).mission)
    mission, program = pipeline.build(path)
    seen = {}
    for bound in (None, 1):
        for pack in (False, True):
            options = ModelOptions(ticks=3, running_bound=bound, print_states=True, pack=pack)
            text = emit_model(mission, program, options)
            assert ("unsigned cs0 : 3;" in text) is pack
            res = spin.reachable(text, str(tmp_path / f"{pack}{bound}"), print_states=True)
            ends = {tuple(int(x) for x in line.split()[1:]) for line in res.lines if line.startswith("@S")}
            seen[pack, bound] = (ends, res.vector_bytes)
        assert seen[True, bound][0] == seen[False, bound][0]
        assert seen[True, bound][1] < seen[False, bound][1]
    explored, _runs, truncated = explore_tick_states(mission, 3, 100)
    assert explored == seen[True, None][0] and not truncated
    assert seen[True, 1][0] <= explored  # the bound only cuts runs
