"""`btgen graph`: Graphviz pictures of a mission, coloured by a trace or a .btlog."""

from __future__ import annotations

import os
import re
import shutil
import struct
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.frontend.loader import load_mission
from btgen.ir.lower import creation_order
from btgen.ir.treexml import groot2_tree
from btgen.tools.graph import FILL, WAS_FILL, walk

ROOT = Path(__file__).resolve().parents[2]
MISSION = ROOT / "tests" / "groot2" / "monitored.xml"
SCENARIO = ROOT / "tests" / "groot2" / "monitored.scenario"


def trace_of(tmp_path: Path, capsys) -> Path:
    out = tmp_path / "m.trace"
    capsys.readouterr()
    assert main(["run", str(MISSION), "--scenario", str(SCENARIO)]) == 0
    out.write_text(capsys.readouterr().out)
    return out


def cli(capsys, *args: str) -> tuple[int, str]:
    """Runs `btgen ARGS` in this process: (exit status, stderr)."""
    capsys.readouterr()
    try:
        rc = main(list(args))
    except SystemExit as e:  # argparse misuse
        rc = int(e.code)
    return rc, capsys.readouterr().err


def nodes_of(dot: str) -> dict[int, dict[str, str]]:
    found = {}
    for m in re.finditer(
        r'^\s*n(\d+) \[label="((?:[^"\\]|\\.)*)", shape=(\w+), style="([^"]*)", fillcolor="([^"]*)"\];$', dot, re.M
    ):
        found[int(m.group(1))] = dict(label=m.group(2), shape=m.group(3), style=m.group(4), fill=m.group(5))
    return found


def test_whole_mission_with_clusters_shapes_names_and_ports(tmp_path):
    out = tmp_path / "m.dot"
    assert main(["graph", str(MISSION), "-o", str(out)]) == 0
    dot = out.read_text()
    nodes = nodes_of(dot)
    mission = load_mission(str(MISSION))
    assert sorted(nodes) == [uid for uid, _, _ in creation_order(mission)]  # every node once, by its UID
    assert dot.count("subgraph cluster_") == 3  # the main tree and two SubTree instances
    assert 'label="Sub (sub1)";' in dot and 'label="Sub (Sub::14)";' in dot
    assert nodes[1]["label"].startswith("root\\n[Sequence]  #1") and nodes[1]["shape"] == "box"
    assert nodes[4]["shape"] == "ellipse" and nodes[5]["style"] == "rounded,filled"  # Condition, Action
    assert nodes[6]["shape"] == "hexagon" and "num_attempts = 2" in nodes[6]["label"]
    assert nodes[7]["shape"] == "box3d" and "x = {count}" in nodes[7]["label"]
    assert "n1 -> n13;" in dot
    assert "n7 -> n8 [style=dashed, constraint=false];" in dot  # a SubTree node leads into its cluster
    assert {n["fill"] for n in nodes.values()} == {"#ffffff"}


def test_trace_colours_show_the_statuses_at_a_tick(tmp_path, capsys):
    trace = trace_of(tmp_path, capsys)
    out = tmp_path / "m.dot"
    assert main(["graph", str(MISSION), "-o", str(out), "--trace", str(trace), "--tick", "1"]) == 0
    nodes = nodes_of(out.read_text())
    # After tick 1: Script done, `ready` failed, the Fallback waits on a RUNNING `move`.
    assert nodes[1]["fill"] == FILL["RUNNING"] and nodes[5]["fill"] == FILL["RUNNING"]
    assert nodes[2]["fill"] == FILL["SUCCESS"] and nodes[4]["fill"] == FILL["FAILURE"]
    assert nodes[13]["fill"] == FILL["IDLE"]
    assert main(["graph", str(MISSION), "-o", str(out), "--trace", str(trace)]) == 0  # the last tick
    nodes = nodes_of(out.read_text())
    # SUCCESS at tick 5, then reset as the root is: shown as "was SUCCESS", paler
    assert nodes[1]["fill"] == WAS_FILL["SUCCESS"] and nodes[1]["label"].endswith("\\n(was SUCCESS)")
    never = [uid for uid, n in nodes.items() if n["fill"] == FILL["IDLE"]]
    assert all("was" not in nodes[uid]["label"] for uid in never)
    assert all(f"\n{uid} " not in "\n" + trace.read_text() for uid in never)  # white: never ran


@pytest.mark.skipif(shutil.which("dot") is None and not os.environ.get("CI"), reason="Graphviz is not installed")
def test_svg_through_graphviz(tmp_path):
    out = tmp_path / "m.svg"
    assert main(["graph", str(MISSION), "-o", str(out)]) == 0
    svg = out.read_text()
    assert svg.lstrip().startswith("<?xml") and "<svg" in svg and "RetryUntilSuccessful" in svg


def _svg_positions(svg: str) -> dict[int, tuple[float, float]]:
    """The (x, y) of the first text line of every node `n<UID>` of an SVG Graphviz wrote (x is
    the node's centre: its lines are centred)."""
    ns = {"s": "http://www.w3.org/2000/svg"}
    found = {}
    for g in ET.fromstring(svg).iter("{http://www.w3.org/2000/svg}g"):
        title = g.find("s:title", ns)
        if g.get("class") == "node" and title is not None and re.fullmatch(r"n\d+", title.text or ""):
            text = g.find("s:text", ns)
            found[int(title.text[1:])] = (float(text.get("x")), float(text.get("y")))
    return found


def _order_problems(mission, svg: str) -> list[str]:
    """Where the picture does not read left to right in execution order: a parent's children
    not left to right in the order it ticks them, or a row of a tree (the nodes of one tree
    instance at one depth) not left to right in creation (depth-first) order."""
    nodes, _ = walk(mission)
    at = _svg_positions(svg)
    assert sorted(at) == [n.uid for n in nodes]
    by_uid = {n.uid: n for n in nodes}
    children: dict[int, list[int]] = {}
    rows: dict[tuple[int, int], list[int]] = {}
    depth: dict[int, int] = {}
    for n in nodes:
        children.setdefault(n.parent, []).append(n.uid)
        inside = n.parent and by_uid[n.parent].cluster == n.cluster
        depth[n.uid] = depth[n.parent] + 1 if inside else 0
        rows.setdefault((n.cluster, depth[n.uid]), []).append(n.uid)
    problems = []
    for parent, uids in children.items():
        xs = [at[u][0] for u in uids]
        if parent and any(a >= b for a, b in zip(xs, xs[1:])):
            problems.append(f"children of #{parent}: {list(zip(uids, xs))}")
    for key, uids in rows.items():
        xs = [at[u][0] for u in uids]
        if any(a >= b for a, b in zip(xs, xs[1:])):
            problems.append(f"row {key}: {list(zip(uids, xs))}")
    return problems


NEEDS_DOT = pytest.mark.skipif(
    shutil.which("dot") is None and not os.environ.get("CI"), reason="Graphviz is not installed"
)


@NEEDS_DOT
@pytest.mark.parametrize(
    "mission",
    [
        ROOT / "missions" / "LabTour.xml",
        ROOT / "missions" / "Reception.xml",
        MISSION,
        ROOT / "tests" / "conformance" / "btcpp-4.6.2" / "parallel_subtree.xml",
    ],
    ids=lambda p: p.stem,
)
def test_svg_reads_left_to_right_in_execution_order(mission, tmp_path):
    """The Lab Tour's `DeclineOrTour` Fallback drew `Tour` left of `Declined`, and SubTree
    clusters reordered whole branches."""
    out = tmp_path / "m.svg"
    assert main(["graph", str(mission), "-o", str(out)]) == 0
    svg = out.read_text()
    assert _order_problems(load_mission(str(mission)), svg) == []


@NEEDS_DOT
@pytest.mark.parametrize("seed", range(4))
def test_svg_of_random_missions_reads_left_to_right(seed, tmp_path):
    from btgen.tools.fuzzgen import random_mission

    path = tmp_path / "r.xml"
    path.write_text(random_mission(seed, "full"), encoding="utf-8")
    out = tmp_path / "r.svg"
    assert main(["graph", str(path), "-o", str(out)]) == 0
    assert _order_problems(load_mission(str(path)), out.read_text()) == []


@NEEDS_DOT
def test_lab_tour_is_as_wide_as_its_widest_tree(tmp_path):
    """Every SubTree instance side by side made the Lab Tour 9,764 pt wide (13,062 px as PNG);
    stacked, each instance below the one before, it is as wide as its widest tree."""
    out = tmp_path / "tour.svg"
    assert main(["graph", str(ROOT / "missions" / "LabTour.xml"), "-o", str(out)]) == 0
    width = float(re.search(r'<svg width="([0-9.]+)pt"', out.read_text()).group(1))
    assert width < 2500, width
    declined, tour = 52, 59  # DeclineOrTour's children, in the order it ticks them
    at = _svg_positions(out.read_text())
    assert at[declined][0] < at[tour][0]


def test_models_and_main_tree_are_accepted(tmp_path, capsys):
    """The layout docs/getting-started.md recommends for one's own project: models in a file of their own."""
    project = ROOT / "examples" / "user_project" / "mission"
    out = tmp_path / "p.dot"
    rc, err = cli(capsys, "graph", str(project / "patrol.xml"), "-o", str(out))
    assert rc == 1 and "--models" in err
    assert main(["graph", str(project / "patrol.xml"), "--models", str(project / "nodes.xml"), "-o", str(out)]) == 0
    assert len(nodes_of(out.read_text())) == len(
        walk(load_mission(str(project / "patrol.xml"), (str(project / "nodes.xml"),)))[0]
    )
    two = tmp_path / "two.xml"
    two.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="A"><AlwaysSuccess name="in_a"/></BehaviorTree>'
        '<BehaviorTree ID="B"><Sequence name="in_b"><AlwaysFailure/></Sequence></BehaviorTree></root>'
    )
    rc, err = cli(capsys, "graph", str(two), "-o", str(out))
    assert rc == 1 and "main_tree_to_execute" in err
    assert main(["graph", str(two), "--main-tree", "B", "-o", str(out)]) == 0
    dot = out.read_text()
    assert "in_b" in dot and "in_a" not in dot and "(main tree B)" in dot


def test_btlog_colours_and_a_log_of_another_mission(tmp_path, capsys):
    mission = load_mission(str(MISSION))
    xml = groot2_tree(mission).xml.encode()
    records = [(1, 1), (2, 1), (2, 2), (3, 1), (4, 3), (5, 1)]
    body = b"".join(struct.pack("<Q", 10 * i)[:6] + struct.pack("<HB", uid, st) for i, (uid, st) in enumerate(records))
    log = tmp_path / "run.btlog"
    log.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + body)
    out = tmp_path / "m.dot"
    assert main(["graph", str(MISSION), "-o", str(out), "--btlog", str(log), "--record", "3"]) == 0
    nodes = nodes_of(out.read_text())
    assert nodes[2]["fill"] == FILL["SUCCESS"] and nodes[3]["fill"] == FILL["IDLE"]
    assert main(["graph", str(MISSION), "-o", str(out), "--btlog", str(log)]) == 0
    nodes = nodes_of(out.read_text())
    assert nodes[4]["fill"] == FILL["FAILURE"] and nodes[5]["fill"] == FILL["RUNNING"]

    other = load_mission(str(ROOT / "missions" / "PickPlaceBall.xml"))
    xml2 = groot2_tree(other).xml.encode()
    bad = tmp_path / "other.btlog"
    bad.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml2)) + xml2 + struct.pack("<q", 0))
    rc, err = cli(capsys, "graph", str(MISSION), "-o", str(out), "--btlog", str(bad))
    assert rc == 1
    assert re.fullmatch(
        rf"{re.escape(str(bad))}:1:24: error: the log's tree is not this mission's \(\d+ nodes, "
        rf"the mission has 20; first difference at UID \d+\)\n",
        err,
    )


@pytest.mark.parametrize(
    "content, where, message",
    [
        ("tick 1\nbogus line\n", "2:1", "not a line of a status trace: `bogus line`"),
        ('tick 1\n99 Sequence "x" IDLE -> RUNNING\n', "2:1", "UID 99 is not a node of the mission (it has 20)"),
        (
            'tick 1\n1 Fallback "root" IDLE -> RUNNING\n',
            "2:3",
            "UID 1 is `Sequence` in the mission, `Fallback` in the trace",
        ),
        ("tick 1\nresult RUNNING\n", "2:1", "the trace ends at tick 1; there is no tick 4"),
        # Unicode digits and numbers past int()'s 4,300 digits once ended in a traceback
        ("tick \u00b2\n", "1:1", "not a line of a status trace: `tick \u00b2`"),
        ('\u0661 Sequence "x" IDLE -> RUNNING\n', "1:1", "not a line of a status trace: `\u0661 Sequence"),
        ("tick " + "9" * 5000 + "\n", "1:1", "not a line of a status trace: `tick " + "9" * 55 + "`"),
        ("9" * 5000 + ' Sequence "x" IDLE -> RUNNING\n', "1:1", "not a line of a status trace: `" + "9" * 60 + "`"),
        (b"tick 1\n\xff\n", "2:1", "invalid UTF-8 (byte 0xff); traces are UTF-8"),
    ],
)
def test_bad_traces_are_path_line_col_errors(tmp_path, capsys, content, where, message):
    trace = tmp_path / "t.trace"
    if isinstance(content, bytes):
        trace.write_bytes(content)
    else:
        trace.write_text(content, encoding="utf-8")
    args = ["graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--trace", str(trace)]
    if "tick 4" in message:
        args += ["--tick", "4"]
    rc, err = cli(capsys, *args)
    assert rc == 1
    assert err.startswith(f"{trace}:{where}: error: {message}") and err.count("\n") == 1
    assert not (tmp_path / "x.dot").exists()


def test_bad_btlog_and_bad_options(tmp_path, capsys):
    log = tmp_path / "bad.btlog"
    log.write_bytes(b"not a log at all")
    rc, err = cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--btlog", str(log))
    assert rc == 1 and err == f"{log}:1:1: error: not a Groot2 log: no `BTCPP4-FileLogger2` header\n"
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.png"))[0] == 1
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--tick", "2")[0] == 1
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--trace", "a", "--btlog", "b")[0] == 1
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--trace", "t", "--tick", "0")[0] == 1
    bad_mission = tmp_path / "bad.xml"
    bad_mission.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><Nope/></BehaviorTree></root>')
    rc, err = cli(capsys, "graph", str(bad_mission), "-o", str(tmp_path / "x.dot"))
    assert rc == 1 and err.startswith(f"{bad_mission}:1:") and "Traceback" not in err
    assert not (tmp_path / "x.dot").exists()


@pytest.mark.parametrize("uid", ["\u00b2", "9" * 5000])
def test_btlog_uids_that_are_not_ascii_numbers(tmp_path, capsys, uid):
    # (`str.isdigit()` took `²`, and int() refuses more than 4,300 digits: both were tracebacks)
    xml = groot2_tree(load_mission(str(MISSION))).xml.replace('_uid="3"', f'_uid="{uid}"', 1).encode()
    log = tmp_path / "odd.btlog"
    log.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0))
    rc, err = cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--btlog", str(log))
    assert (rc, err) == (
        1,
        f"{log}:1:24: error: the log's tree is not this mission's (19 nodes, the mission has 20; "
        "first difference at UID 3)\n",
    )


@pytest.mark.parametrize(
    "option, message",
    [
        ("--trace", "file is larger than 67108864 bytes; trace files are limited to 67108864 bytes"),
        ("--btlog", "file is larger than 67108864 bytes; log files are limited to 67108864 bytes"),
        ("--enums", "file is larger than 1048576 bytes; enums files are limited to 1048576 bytes"),
        ("--models", "file is larger than 16777216 bytes; missions are limited to 16777216 bytes"),
    ],
)
def test_endless_inputs_are_read_to_a_bound(tmp_path, capsys, option, message):
    # (each read /dev/zero until the kernel killed btgen at 24 GB)
    if option in ("--trace", "--btlog"):
        rc, err = cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), option, "/dev/zero")
    else:
        rc, err = cli(capsys, "validate", str(MISSION), option, "/dev/zero")
    assert (rc, err) == (1, f"/dev/zero:1:1: error: {message}\n")
    assert not (tmp_path / "x.dot").exists()


def test_walk_agrees_with_the_uids_and_instances_groot2_sees():
    mission = load_mission(str(ROOT / "missions" / "LabTour.xml"))
    nodes, clusters = walk(mission)
    tree = groot2_tree(mission)
    assert [(n.uid, n.id, n.name) for n in nodes] == creation_order(mission)
    assert [(t, p) for t, p in clusters] == [(i.tree_id, i.path) for i in tree.instances]
