"""`btgen graph`: a picture of a mission (Graphviz), optionally coloured by a run.

    btgen graph MISSION.xml -o FILE.svg|FILE.dot [--models FILE.xml] [--main-tree ID]
                [--trace FILE [--tick N] | --btlog FILE [--record N]]

The whole main tree with its SubTrees expanded. Left to right is the order in
which a parent ticks its children. Each tree instance is a frame of its own
(labelled with its tree ID and the path BehaviorTree.CPP gives it), the main
tree on top and every SubTree instance below the one before, in creation order,
with a dashed arrow from its SubTree node: the picture is as wide as its widest
tree, not as all of them side by side. Node kinds have their own shapes
(Control: box, Decorator: hexagon, Action: rounded box, Condition: ellipse,
SubTree: 3-D box), every node shows its name, its ID when the name differs, its
UID and its ports as written.

With a status trace (`btgen run` output, tests/conformance/FORMAT.md) the
nodes are filled with their statuses at the end of tick N (default: the last
tick in the file). A .btlog (Groot2's FileLogger2 format, written by
btgen::btlog::FileLogger or BehaviorTree.CPP) has no tick boundaries, so it
is read up to record N (default: all); its tree must be the mission's.
"""

from __future__ import annotations

import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded
from btgen.fileio import check_output, write_output
from btgen.ir.numbering import number_nodes
from btgen.lang.model import Mission, SubTreeNode

STATUS_NAMES = ("IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED")
FILL = {"RUNNING": "#f5a623", "SUCCESS": "#7ed321", "FAILURE": "#e74c3c", "SKIPPED": "#9ecae1", "IDLE": "#ffffff"}
# A node reset to IDLE after it ran shows the status it had, paler (as Groot2 and btview show it:
# "was SUCCESS"), so the picture of a tick that ended with the tree reset still tells what ran.
WAS_FILL = {"RUNNING": "#fbd9a0", "SUCCESS": "#cdf0a8", "FAILURE": "#f4b3ab", "SKIPPED": "#d6e8f3"}


def _was(status: dict[int, str], uid: int, to: str) -> None:
    """Record a transition to `to` in `status`; IDLE after a status keeps it as `was:<status>`."""
    before = status.get(uid, "IDLE")
    if to == "IDLE" and before != "IDLE":
        status[uid] = "was:" + before.removeprefix("was:")
    else:
        status[uid] = to


SHAPES = {
    "Control": ("box", ""),
    "Decorator": ("hexagon", ""),
    "Action": ("box", "rounded"),
    "Condition": ("ellipse", ""),
    "SubTree": ("box3d", ""),
}


def _error(path: str, line: int, col: int, message: str) -> UserError:
    return UserError(Diagnostic(Loc(path, line, col), message))


@dataclass(frozen=True)
class GNode:
    uid: int
    kind: str
    id: str
    name: str
    ports: tuple[tuple[str, str], ...]
    parent: int  # UID, 0 for the root
    cluster: int  # index of the tree instance holding it


def walk(mission: Mission) -> tuple[list[GNode], list[tuple[str, str]]]:
    """Nodes in creation order (UID order) and the tree instances (tree ID, path)."""
    numbering = number_nodes(mission)
    paths = numbering.instance_paths()
    cluster_of = {inst: i for i, inst in enumerate(numbering.instances())}
    clusters = [
        (mission.main_tree if inst < 0 else numbering[inst].node.target, paths[inst])  # type: ignore[attr-defined]
        for inst in numbering.instances()
    ]
    nodes: list[GNode] = []
    for n in numbering:
        node = n.node
        if isinstance(node, SubTreeNode):
            kind = "SubTree"
        else:
            try:
                kind = mission.spec(node.id).kind
            except KeyError:
                kind = "Action"
        ports = tuple((p.name, p.value) for p in node.ports) + tuple((a.name, a.value) for a in node.pre + node.post)
        parent = n.parent + 1  # UID, 0 for the root
        nodes.append(GNode(n.uid, kind, n.reg_id, node.display_name, ports, parent, cluster_of[n.instance]))
    return nodes, clusters


# ------------------------------------------------------------------ statuses
# Traces and logs are read whole: this bounds what `--trace /dev/zero` may cost.
MAX_LOG_BYTES = 64 << 20
# A UID or tick number: ASCII digits (str.isdigit() also takes `²` and `١`, which int() then
# refuses) and few enough that int() never meets its 4,300-digit limit.
_NUMBER = re.compile(r"[0-9]{1,18}\Z", re.ASCII)


@dataclass(frozen=True)
class TraceRead:
    """A status trace as read and checked against the mission: its transitions (each with
    the count of `tick` lines before it), the tick numbers in order, and its line count."""

    moves: tuple[tuple[int, int, str, str], ...]  # (ticks seen before, uid, from, to)
    ticks: tuple[int, ...]
    lines: int


def is_transition(words: list[str]) -> bool:
    """Whether the words of a trace line are `UID ID "name" FROM -> TO`."""
    return (
        len(words) >= 5
        and _NUMBER.match(words[0]) is not None
        and words[-2] == "->"
        and words[-1] in STATUS_NAMES
        and words[-3] in STATUS_NAMES
    )


def read_trace(path: str, nodes: list[GNode]) -> TraceRead:
    """The one reader of a status trace (`btgen run` output), for `graph --trace` and `cover`
    alike: every line is a tick, a result or a transition of a node of the mission (words
    separated by any blanks), or the trace is refused at that line."""
    data = read_bounded(path, MAX_LOG_BYTES, "trace", cannot="cannot read the trace")
    try:
        lines = data.decode("utf-8").splitlines()
    except UnicodeDecodeError as e:
        good = data[: e.start].decode("utf-8")
        raise _error(
            path,
            good.count("\n") + 1,
            len(good) - (good.rfind("\n") + 1) + 1,
            f"invalid UTF-8 (byte 0x{data[e.start]:02x}); traces are UTF-8",
        ) from None
    by_uid = {n.uid: n for n in nodes}
    moves: list[tuple[int, int, str, str]] = []
    ticks: list[int] = []
    for i, line in enumerate(lines, 1):
        if not line.strip():
            continue
        words = line.split()
        if words[0] == "tick" and len(words) == 2 and _NUMBER.match(words[1]):
            ticks.append(int(words[1]))
            continue
        if words[0] == "result" and len(words) == 2 and words[1] in STATUS_NAMES:
            continue
        if is_transition(words):
            uid = int(words[0])
            if uid not in by_uid:
                raise _error(path, i, 1, f"UID {uid} is not a node of the mission (it has {len(nodes)})")
            # (an ID may hold a space, `<Action ID="Grasp Cup"/>`: it ends where the quoted name starts)
            rest, node_id = line.split(None, 1)[1], by_uid[uid].id
            after = rest[len(node_id) :]
            if not (rest.startswith(node_id) and after[:1].isspace() and after.lstrip().startswith('"')):
                raise _error(
                    path,
                    i,
                    len(words[0]) + 2,
                    f"UID {uid} is `{by_uid[uid].id}` in the mission, `{words[1]}` in the trace",
                )
            moves.append((len(ticks), uid, words[-3], words[-1]))
            continue
        raise _error(path, i, 1, f"not a line of a status trace: `{line[:60]}`")
    return TraceRead(tuple(moves), tuple(ticks), len(lines))


def trace_statuses(path: str, tick: Optional[int], nodes: list[GNode]) -> tuple[dict[int, str], int]:
    """Statuses at the end of `tick` (default: the last) from a status trace."""
    trace = read_trace(path, nodes)
    current = 0
    seen = len(trace.ticks)  # the tick lines whose transitions count
    for k, n in enumerate(trace.ticks):
        if tick is not None and n > tick:
            seen = k
            break
        current = n
    else:
        if tick is not None and tick > current:
            raise _error(path, max(trace.lines, 1), 1, f"the trace ends at tick {current}; there is no tick {tick}")
    status: dict[int, str] = {}
    for before_ticks, uid, _, to in trace.moves:
        if before_ticks > seen:
            break
        _was(status, uid, to)
    return status, current


def btlog_statuses(path: str, record: Optional[int], nodes: list[GNode]) -> tuple[dict[int, str], int]:
    """Statuses after the first `record` transitions (default: all) of a .btlog."""
    data = read_bounded(path, MAX_LOG_BYTES, "log", cannot="cannot read the log")
    if data[:18] != b"BTCPP4-FileLogger2" or len(data) < 23:
        raise _error(path, 1, 1, "not a Groot2 log: no `BTCPP4-FileLogger2` header")
    size = struct.unpack_from("<i", data, 19)[0]
    if size < 0 or 23 + size + 8 > len(data):
        raise _error(path, 1, 20, f"the tree XML length {size} runs past the end of the file")
    try:
        root = ET.fromstring(data[23 : 23 + size].decode("utf-8"))
    except (ET.ParseError, UnicodeDecodeError) as e:
        raise _error(path, 1, 24, f"the log's tree XML does not parse: {e}") from None
    logged = {}
    for el in root.iter():
        uid = el.get("_uid")
        if uid is not None and _NUMBER.match(uid):
            logged[int(uid)] = el.tag
    mine = {n.uid: n.id for n in nodes}
    if logged != mine:
        differ = sorted(set(logged.items()) ^ set(mine.items()))
        raise _error(
            path,
            1,
            24,
            f"the log's tree is not this mission's ({len(logged)} nodes, the mission has "
            f"{len(mine)}; first difference at UID {differ[0][0]})",
        )
    body = data[23 + size + 8 :]
    count = len(body) // 9
    if record is not None and record > count:
        raise _error(path, 1, 1, f"the log has {count} records; there is no record {record}")
    status: dict[int, str] = {}
    for k in range(count if record is None else record):
        rec_uid = int.from_bytes(body[9 * k + 6 : 9 * k + 8], "little")
        code = body[9 * k + 8]
        if rec_uid not in mine or code >= len(STATUS_NAMES):
            raise _error(path, 1, 1, f"record {k + 1}: UID {rec_uid} status {code} is not valid for this mission")
        _was(status, rec_uid, STATUS_NAMES[code])
    return status, count if record is None else record


# ------------------------------------------------------------------- drawing
def _q(text: str) -> str:
    """A Graphviz quoted string whose text shows as is."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _label(n: GNode) -> str:
    head = n.name if n.name == n.id else f"{n.name}\n[{n.id}]"
    lines = [f"{head}  #{n.uid}"]
    for k, v in n.ports:
        shown = v if len(v) <= 48 else v[:45] + "..."
        lines.append(f"{k} = {shown}")
    return "\n".join(lines)


def dot_text(
    mission: Mission,
    nodes: list[GNode],
    clusters: list[tuple[str, str]],
    status: Optional[dict[int, str]] = None,
    caption: str = "",
) -> str:
    """The Graphviz text: children left to right in the order their parent ticks them.

    Graphviz keeps each node's out-edge order (`ordering=out`) when the edges of a parent are
    written in the order of its children and nothing else pulls nodes sideways; clusters
    nested in the tree did (a cluster cannot overlap another, so instances were pushed
    aside and their neighbours with them), so each instance is a block of its own."""
    out = [
        "digraph mission {",
        "  rankdir=TB;",
        "  ordering=out;",
        "  nodesep=0.12;",
        "  ranksep=0.35;",
        '  node [fontname="Helvetica", fontsize=10, margin="0.06,0.03"];',
        "  edge [arrowsize=0.6];",
        f"  label={_q(caption or mission.path)};",
        "  labelloc=t;",
    ]

    def node_line(n: GNode) -> str:
        shape, style = SHAPES.get(n.kind, ("box", ""))
        styles = [s for s in (style, "filled") if s]
        st = status.get(n.uid, "IDLE") if status is not None else "IDLE"
        if st.startswith("was:"):
            fill, label = WAS_FILL[st[4:]], _label(n) + f"\n(was {st[4:]})"
        else:
            fill, label = FILL[st], _label(n)
        return f"n{n.uid} [label={_q(label)}, shape={shape}, style={_q(','.join(styles))}, fillcolor={_q(fill)}];"

    # Each tree instance is a block of its own: the main tree first, then every SubTree
    # instance in creation order, each below the one before, framed, with a dashed arrow from
    # its SubTree node. Expanded in place, the instances added their widths side by side (the
    # Lab Tour was 9,764 pt wide); stacked, the picture is as wide as its widest tree.
    members: dict[int, list[GNode]] = {}
    for n in nodes:
        members.setdefault(n.cluster, []).append(n)
    by_uid = {n.uid: n for n in nodes}
    depth: dict[int, int] = {}
    deepest: list[int] = []  # per block: a node on its lowest rank
    for c, (tree_id, path) in enumerate(clusters):
        block = members.get(c, [])
        for n in block:
            depth[n.uid] = depth[n.parent] + 1 if n.parent and by_uid[n.parent].cluster == c else 0
        deepest.append(max(block, key=lambda n: (depth[n.uid], -n.uid)).uid if block else 0)
        title = f"{tree_id} (main tree)" if c == 0 else f"{tree_id} ({path})"
        out.append(f"  subgraph cluster_{c} {{")
        out.append(f"    label={_q(title)};")
        out.append(f'    style="rounded,{"solid" if c == 0 else "dashed"}";')
        for n in block:
            out.append("    " + node_line(n))
        out.append("  }")
    for n in nodes:  # UID order: each parent's edges in the order of its children
        if n.parent and by_uid[n.parent].cluster == n.cluster:
            out.append(f"  n{n.parent} -> n{n.uid};")
        elif n.parent:
            out.append(f"  n{n.parent} -> n{n.uid} [style=dashed, constraint=false];")
    for c in range(1, len(clusters)):
        if deepest[c - 1] and members.get(c):
            out.append(f"  n{deepest[c - 1]} -> n{members[c][0].uid} [style=invis, weight=0];")
    if status is not None:
        cells = "".join(
            f'<td bgcolor="{FILL[s]}">{s}</td>' for s in ("RUNNING", "SUCCESS", "FAILURE", "SKIPPED", "IDLE")
        )
        cells += "".join(f'<td bgcolor="{WAS_FILL[s]}">was {s}</td>' for s in ("SUCCESS", "FAILURE", "SKIPPED"))
        out.append(
            '  legend [shape=plaintext, label=<<table border="0" cellborder="1" cellspacing="0">'
            f"<tr>{cells}</tr></table>>];"
        )
    out.append("}")
    return "\n".join(out) + "\n"


def graph_command(args) -> int:
    from btgen import pipeline
    from btgen.pipeline import options_from_args

    output: str = args.output
    ext = os.path.splitext(output)[1].lower()
    if ext not in (".svg", ".dot"):
        raise cmdline.error(args, output, f"-o {output}: the output is a .svg or a .dot file")
    if args.tick is not None and args.trace is None:
        raise cmdline.error(
            args, "--tick", "--tick needs --trace (a .btlog has no tick boundaries: use --btlog FILE --record N)"
        )
    if args.record is not None and args.btlog is None:
        raise cmdline.error(args, "--record", "--record needs --btlog")
    mission = pipeline.load(args.mission, options_from_args(args))
    nodes, clusters = walk(mission)
    status = None
    caption = f"{mission.path} (main tree {mission.main_tree})"
    if args.trace is not None:
        status, tick = trace_statuses(args.trace, args.tick, nodes)
        caption += f"\nstatuses at the end of tick {tick} of {args.trace}"
    elif args.btlog is not None:
        status, record = btlog_statuses(args.btlog, args.record, nodes)
        caption += f"\nstatuses after record {record} of {args.btlog}"
    text = dot_text(mission, nodes, clusters, status, caption)
    inputs = (*mission.files, *(f for f in (args.trace, args.btlog) if f is not None))
    check_output(output, inputs)
    if ext == ".dot":
        _write(output, text.encode("utf-8"), inputs)
        return 0
    dot = shutil.which("dot")
    if dot is None:
        print(
            "btgen: error: Graphviz `dot` is not installed (Debian: apt-get install graphviz); "
            "write a .dot file instead",
            file=sys.stderr,
        )
        return 1
    proc = subprocess.run([dot, "-Tsvg"], input=text.encode("utf-8"), capture_output=True, timeout=600, check=False)
    if proc.returncode != 0:
        print(f"btgen: error: dot failed: {proc.stderr.decode('utf-8', 'replace').strip()}", file=sys.stderr)
        return 1
    _write(output, proc.stdout, inputs)
    return 0


def _write(path: str, data: bytes, inputs: Sequence[str] = ()) -> None:
    """Writes `path` whole or not at all, never over an input (fileio.write_output)."""
    write_output(path, data, inputs)
