"""`btgen verify --probabilities`: Storm's answers equal hand-computed values and lie within the
confidence interval of Monte Carlo runs of the interpreter."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from btgen import pipeline
from btgen.cli import main
from btgen.diagnostics import UserError
from btgen.tools.verify.markov import build_chain, load_probabilities, monte_carlo, storm_queries
from verify_missions import GRASP, write_mission

pytest.importorskip("stormpy")

PROBS = """{"Ready": {"SUCCESS": 0.9, "FAILURE": 0.1},
 "Grasp": {"SUCCESS": 0.5, "FAILURE": 0.3, "RUNNING": 0.2},
 "Place": {"SUCCESS": 0.8, "FAILURE": 0.2}}
"""


def _files(tmp_path: Path, mission: str = GRASP, probs: str = PROBS) -> tuple[str, str]:
    p = tmp_path / "p.json"
    p.write_text(probs, encoding="utf-8")
    return write_mission(tmp_path, mission), str(p)


def test_hand_computed_probabilities(tmp_path, capsys):
    m, p = _files(tmp_path)
    assert main(["verify", m, "--probabilities", p, "--within", "1", "--ever", "Place"]) == 0
    out = capsys.readouterr().out
    values = {line[:42].strip(): float(line[42:]) for line in out.splitlines()[1:]}
    # a run of Grasp ends SUCCESS with 0.5 / 0.8, FAILURE with 0.3 / 0.8 (RUNNING only delays it);
    # the retry fails when two runs fail; Place then succeeds with 0.8
    grasp_fails = (0.3 / 0.8) ** 2
    assert values["P(root SUCCESS)"] == pytest.approx(0.9 * (1 - grasp_fails) * 0.8, abs=1e-9)
    assert values["P(root FAILURE)"] == pytest.approx(1 - 0.9 * (1 - grasp_fails) * 0.8, abs=1e-9)
    assert values["P(Place ever ticked)"] == pytest.approx(0.9 * (1 - grasp_fails), abs=1e-9)
    # within one tick: Ready, Grasp at once and Place at once (a failed attempt takes a tick more)
    assert values["P(root SUCCESS within 1 ticks)"] == pytest.approx(0.9 * 0.5 * 0.8, abs=1e-9)


def test_storm_within_the_confidence_interval_of_monte_carlo(tmp_path):
    m, p = _files(tmp_path)
    mission, program = pipeline.build(m)
    probs = load_probabilities(p, program)
    p_success, expected = storm_queries(build_chain(mission, program, probs), ['P=? [F "success"]', 'R=? [F "done"]'])
    runs = 4000
    succ, fail, mean_ticks = monte_carlo(mission, probs, runs, seed=7)
    assert succ + fail == runs
    sigma = math.sqrt(p_success * (1 - p_success) / runs)
    assert abs(succ / runs - p_success) < 4 * sigma
    assert abs(mean_ticks - expected) < 0.1 * expected


def test_reactive_mission_against_monte_carlo(tmp_path):
    mission_text = GRASP.replace("<Sequence>", "<ReactiveSequence>").replace("</Sequence>", "</ReactiveSequence>")
    m, p = _files(tmp_path, mission_text)
    mission, program = pipeline.build(m)
    probs = load_probabilities(p, program)
    (p_success,) = storm_queries(build_chain(mission, program, probs), ['P=? [F "success"]'])
    runs = 4000
    succ, _, _ = monte_carlo(mission, probs, runs, seed=11)
    assert abs(succ / runs - p_success) < 4 * math.sqrt(p_success * (1 - p_success) / runs)


@pytest.mark.parametrize(
    "text, message",
    [
        ('{"Ready": {"SUCCESS": 0.5}}', "the probabilities add up to 0.5, not 1"),
        ('{"Ready": {"RUNNING": 1}}', "`Ready` (Condition) cannot return `RUNNING`"),
        ('{"Nope": {"SUCCESS": 1}}', "`Nope` is no leaf of the mission"),
        ('{"Ready": {"SUCCESS": 1}}', "no probabilities for the leaves Grasp, Place"),
    ],
)
def test_bad_probability_files(tmp_path, text, message):
    m, p = _files(tmp_path, probs=text)
    _, program = pipeline.build(m)
    with pytest.raises(UserError) as e:
        load_probabilities(p, program)
    assert message in str(e.value.diagnostics[0])


def test_rate_controller_reads_the_clock(tmp_path, capsys):
    """Nav2's RateController re-ticks its child only once its period has passed: a chain without
    a clock would answer for a clock that never moves (P(SUCCESS) 0.5 here), so it is refused
    like Sleep, Delay and Timeout."""
    nav2 = Path(__file__).resolve().parents[2] / "tests" / "real_files" / "nav2"
    probs = tmp_path / "p.json"
    probs.write_text(
        '{"ComputePathToPose": {"SUCCESS": 0.5, "FAILURE": 0.5}, "ControllerSelector": {"SUCCESS": 1.0}, '
        '"PlannerSelector": {"SUCCESS": 1.0}, "FollowPath": {"SUCCESS": 0.5, "RUNNING": 0.5}}'
    )
    tree = nav2 / "navigate_w_replanning_time.xml"
    models = nav2 / "nav2_tree_nodes.xml"
    assert main(["verify", str(tree), "--models", str(models), "--probabilities", str(probs)]) == 1
    err = capsys.readouterr().err
    assert f"{tree}:10:7: error: `RateController` reads the clock: --probabilities does not translate it" in err


def test_an_endless_retry_is_a_finite_chain(tmp_path, capsys):
    """RetryUntilSuccessful num_attempts="-1": its count of attempts is never read, so the chain
    forgets it (before: one state per attempt, the search never ended on this 3-node mission).
    Ready fails with 1/2 and the Retry answers RUNNING then: the ticks to the end are
    geometric, 2 on average; the root ends with SUCCESS for sure."""
    path = tmp_path / "m.xml"
    path.write_text(
        """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <RetryUntilSuccessful num_attempts="-1" name="Again"><Check name="Ready"/></RetryUntilSuccessful>
      <Work name="Go"/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Condition ID="Check"/><Action ID="Work"/></TreeNodesModel>
</root>
""",
        encoding="utf-8",
    )
    probs = tmp_path / "p.json"
    probs.write_text('{"Ready": {"SUCCESS": 0.5, "FAILURE": 0.5}, "Go": {"SUCCESS": 1}}', encoding="utf-8")
    assert main(["verify", str(path), "--probabilities", str(probs)]) == 0
    out = capsys.readouterr().out
    values = dict(line.rsplit(None, 1) for line in out.splitlines()[1:])
    assert float(values["  P(root SUCCESS)"]) == pytest.approx(1.0)
    assert float(values["  expected ticks to the end"]) == pytest.approx(2.0)
    assert "Markov chain of 3 states" in out


def test_a_tick_of_too_many_paths_is_refused_located(tmp_path, monkeypatch):
    """The chain runs one tick per path of leaf answers: past MAX_TICK_PATHS a located error."""
    from btgen.tools.verify import markov

    monkeypatch.setattr(markov, "MAX_TICK_PATHS", 3)
    mission, program = pipeline.build(write_mission(tmp_path, GRASP))
    probs = {"Ready": [(2, 0.9), (3, 0.1)], "Grasp": [(2, 0.5), (3, 0.5)], "Place": [(2, 0.8), (3, 0.2)]}
    with pytest.raises(UserError) as e:
        build_chain(mission, program, probs)
    assert "more than 3 paths of leaf answers through one tick" in str(e.value.diagnostics[0])
