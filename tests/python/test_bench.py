"""`btgen bench` and the benchmark scripts: behaviour, not timing.

The benchmark builds a mission with instant leaves at -O2 (cached), ticks it
and reports its numbers; these tests check the report is complete and sane
and that nothing allocates. How fast it is belongs to bench/run_benchmarks.py.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from btgen.cli import main
from btgen.tools import synth

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH_DIR = os.path.join(ROOT, "bench")
KEYS = (
    "nodes",
    "ticks",
    "ns_per_tick",
    "allocs_create",
    "allocs_per_tick",
    "state_bytes",
    "node_state_bytes",
    "blackboard_bytes",
    "binary",
)

needs_cxx = pytest.mark.skipif(shutil.which(os.environ.get("CXX") or "c++") is None, reason="no C++ compiler")


def _parse(out: str) -> dict[str, str]:
    report = {}
    for line in out.splitlines():
        key, _, value = line.partition(" ")
        report[key] = value
    return report


def _bench(capsys, *args: str) -> tuple[int, dict[str, str], str]:
    rc = main(["bench", *args])
    captured = capsys.readouterr()
    return rc, _parse(captured.out), captured.err


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """A private build cache, so test runs do not fill the user's."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("BTGEN_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        yield


@pytest.fixture
def balanced_20(tmp_path):
    path = tmp_path / "balanced_20.xml"
    path.write_text(synth.balanced_mission(20), encoding="utf-8")
    return str(path)


@pytest.fixture(scope="module")
def bench_20(cache, tmp_path_factory):
    """`btgen bench` on a 20-node balanced mission, 50 ticks: (exit status, report, stderr)."""
    path = tmp_path_factory.mktemp("mission") / "balanced_20.xml"
    path.write_text(synth.balanced_mission(20), encoding="utf-8")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "bench", str(path), "--ticks", "50"],
        capture_output=True,
        check=False,
        env=dict(os.environ, PYTHONPATH=os.path.join(ROOT, "generator")),
    )
    return proc.returncode, _parse(proc.stdout.decode()), proc.stderr.decode()


@needs_cxx
def test_report_has_every_key_with_sane_values_and_no_allocation(bench_20):
    rc, report, err = bench_20
    assert rc == 0, err
    for key in KEYS:
        assert key in report, f"`{key}` missing from {report}"
    assert int(report["nodes"]) == 20
    assert int(report["ticks"]) == 50
    assert 0 < float(report["ns_per_tick"]) < 1e9
    assert report["allocs_create"] == "0"
    assert float(report["allocs_per_tick"]) == 0.0
    # a status byte per node at least, and all of the state in the object
    assert 20 <= int(report["state_bytes"]) <= 20 * 64
    # the nodes' part of it: a status byte per node at least, at most the 8 bytes per node of
    # the performance targets; this mission has no blackboard entries (an empty struct)
    nodes_part, bb_part = int(report["node_state_bytes"]), int(report["blackboard_bytes"])
    assert 20 <= nodes_part <= 20 * 8
    assert bb_part == 1
    assert nodes_part + bb_part <= int(report["state_bytes"])
    # a balanced synthetic mission: every tick visits every node and succeeds
    assert float(report["visited_per_tick"]) == 20.0
    assert report["result"] == "SUCCESS"
    assert report["alloc_counter"] == "new+malloc"
    assert os.access(report["binary"], os.X_OK)


@needs_cxx
def test_binary_with_a_tick_count_only_prints_nothing(bench_20):
    rc, report, err = bench_20
    assert rc == 0, err
    proc = subprocess.run([report["binary"], "5"], capture_output=True, check=False)
    assert (proc.returncode, proc.stdout, proc.stderr) == (0, b"", b"")
    bad = subprocess.run([report["binary"], "five"], capture_output=True, check=False)
    assert bad.returncode == 2 and b"usage:" in bad.stderr


@needs_cxx
def test_shipped_mission_allocates_nothing(capsys, cache):
    rc, report, err = _bench(capsys, os.path.join(ROOT, "missions", "PickPlaceBall.xml"), "--ticks", "100")
    assert rc == 0, err
    assert (report["nodes"], report["allocs_create"], report["allocs_per_tick"]) == ("7", "0", "0")


def test_ticks_must_be_positive(capsys, balanced_20):
    rc, report, err = _bench(capsys, balanced_20, "--ticks", "0")
    assert rc == 1 and report == {}
    assert "--ticks must be at least 1" in err


def test_invalid_mission_is_a_diagnostic_not_a_traceback(capsys, tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><NoSuchNode/></BehaviorTree></root>\n', encoding="utf-8"
    )
    rc, _, err = _bench(capsys, str(bad), "--ticks", "10")
    assert rc == 1
    assert err.startswith(f"{bad}:") and "error:" in err and "Traceback" not in err


def test_committed_synthetic_missions_are_what_make_missions_writes():
    proc = subprocess.run(
        [sys.executable, os.path.join(BENCH_DIR, "make_missions.py"), "--check"], capture_output=True, check=False
    )
    assert proc.returncode == 0, proc.stderr.decode()


@pytest.mark.parametrize("kind", synth.KINDS)
def test_synthetic_missions_have_exact_size_and_every_tick_visits_every_node(kind, tmp_path):
    from btgen.frontend.loader import load_mission
    from btgen.interp.engine import Interpreter
    from btgen.interp.scenario import parse_scenario_text
    from btgen.ir.lower import creation_order

    n = 60
    path = tmp_path / f"{kind}.xml"
    path.write_text(synth.mission(kind, n), encoding="utf-8")
    mission = load_mission(str(path))
    assert len(creation_order(mission)) == n
    interp = Interpreter(mission, parse_scenario_text("ticks 2\n"))
    for _ in range(2):
        assert interp.tick_once().name == "SUCCESS"
    changed = [line.split()[0] for line in interp.take_lines() if "->" in line and not line.endswith("-> IDLE")]
    # every node moves to RUNNING, SUCCESS or FAILURE in each of the 2 ticks
    assert sorted(set(changed)) == sorted(str(uid) for uid in range(1, n + 1))


def _run_benchmarks_module():
    sys.path.insert(0, BENCH_DIR)
    try:
        import run_benchmarks
    finally:
        sys.path.remove(BENCH_DIR)
    return run_benchmarks


def test_measured_section_is_appended_when_absent_and_replaced_alone_when_present():
    rb = _run_benchmarks_module()
    assert rb.SECTION == "## Measured" and rb.PAGE.name == "performance.md" and rb.PAGE.exists()
    new = "## Measured\n\nnew numbers\n"
    assert rb.replace_section("# btgen\n\ntext\n", new) == "# btgen\n\ntext\n\n" + new
    before = "# btgen\n\n## Measured\n\nold\n| a |\n\n## Layout\n\nkept\n"
    assert rb.replace_section(before, new) == "# btgen\n\n" + new + "\n## Layout\n\nkept\n"
    assert rb.replace_section("# btgen\n\n## Measured\n\nold\n", new) == "# btgen\n\n" + new
