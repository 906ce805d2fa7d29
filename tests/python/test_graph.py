"""`btgen graph`: Graphviz pictures of a mission, coloured by a trace or a .btlog."""

from __future__ import annotations

import os
import re
import shutil
import struct
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
    assert dot.count("subgraph cluster_") == 2
    assert 'label="Sub (sub1)";' in dot and 'label="Sub (Sub::14)";' in dot
    assert nodes[1]["label"].startswith("root\\n[Sequence]  #1") and nodes[1]["shape"] == "box"
    assert nodes[4]["shape"] == "ellipse" and nodes[5]["style"] == "rounded,filled"  # Condition, Action
    assert nodes[6]["shape"] == "hexagon" and "num_attempts = 2" in nodes[6]["label"]
    assert nodes[7]["shape"] == "box3d" and "x = {count}" in nodes[7]["label"]
    assert "n7 -> n8;" in dot and "n1 -> n13;" in dot  # a SubTree node leads into its cluster
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
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.png"))[0] == 2
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--tick", "2")[0] == 2
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--trace", "a", "--btlog", "b")[0] == 2
    assert cli(capsys, "graph", str(MISSION), "-o", str(tmp_path / "x.dot"), "--trace", "t", "--tick", "0")[0] == 2
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
