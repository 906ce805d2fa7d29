"""Counterexamples: SPIN's trail -> a btgen scenario and a .btlog, replayed on both engines.

The trail's leaf choices, in call order, are a scenario (each leaf name's answers in order,
as `interp/scenario.py` reads them); a lasso's loop is unrolled `REPEATS` times. The
scenario is then run:

- on the interpreter, watched node by node (every execute_tick and what it returned), which
  gives each tick's atoms; the property is evaluated on that run by `props.holds_on_lasso`,
  an evaluation independent of SPIN, and must be false;
- the interpreter's statuses after each tick must equal the model's (`@S` lines of the trail);
- on the generated C++ (`tools/cppengine.py`), whose trace must equal the interpreter's
  byte for byte, and whose statuses after each tick (read from that trace) equal the model's.

A counterexample that fails any of these is a bug of btgen verify, reported as such, never
shown as a finding.
"""

from __future__ import annotations

import os
import re
import struct
import subprocess
from dataclasses import dataclass, field
from typing import Optional

from btgen.interp.engine import Interpreter, run_ticks
from btgen.interp.scenario import parse_scenario_text
from btgen.interp.tree import RUNNING, TreeNode
from btgen.ir.lower import Program
from btgen.lang.model import Mission
from btgen.tools.verify.blackboard import compare_entry
from btgen.tools.verify.promela import STATUS, STATUS_NAME
from btgen.tools.verify.props import Frame, Property, atoms_of, holds_on_lasso
from btgen.tools.verify.spin import Trail

REPEATS = 2
_HOOK = "execute_tick"  # the method every visit goes through, wrapped while replaying

# a transition line of a status trace btgen's own engines print (`UID NAME ... OLD -> NEW`)
_LINE = re.compile(
    r"([0-9]{1,9}) (\S+) .* (IDLE|RUNNING|SUCCESS|FAILURE|SKIPPED) -> (IDLE|RUNNING|SUCCESS|FAILURE|SKIPPED)\Z"
)


@dataclass
class Counterexample:
    prop: Property
    scenario: str
    ticks: int
    loop: int  # index of the frame the infinite run loops back to
    model_states: list[tuple[int, ...]]  # statuses after each tick, from SPIN's trail
    trace: str = ""
    frames: list[Frame] = field(default_factory=list)
    interp_states: list[tuple[int, ...]] = field(default_factory=list)
    shown_interp: bool = False
    cpp_trace: Optional[str] = None
    shown_cpp: Optional[bool] = None
    problems: list[str] = field(default_factory=list)


def scenario_of(trail: Trail, program: Program, clock_ms: int, comment: str) -> tuple[str, int, int]:
    """(scenario text, ticks, loop frame index) of a trail."""
    reps = REPEATS if trail.lasso and trail.cycle_ticks else 0
    stream = trail.prefix + trail.cycle * reps
    ticks = trail.prefix_ticks + reps * trail.cycle_ticks
    per: dict[str, list[str]] = {}
    for node, status in stream:
        per.setdefault(program.nodes[node].name, []).append(STATUS_NAME[status])
    lines = [f"# {line}" for line in comment.splitlines()]
    lines.append(f"ticks {max(ticks, 1)}")
    if clock_ms:
        lines.append(f"clock_ms {clock_ms}")
    for name, sts in per.items():
        lines.append(f"leaf {name} {' '.join(sts)}")
    # a loop of the run itself, or the position after its end, which stays (ENDED frame)
    loop = ticks - trail.cycle_ticks if reps else ticks
    return "\n".join(lines) + "\n", max(ticks, 1), loop


def model_states(trail_text: str, trail: Trail) -> list[tuple[int, ...]]:
    pre: list[tuple[int, ...]] = []
    cyc: list[tuple[int, ...]] = []
    in_cycle = False
    for line in trail_text.splitlines():
        if "START OF CYCLE" in line:
            in_cycle = True
            continue
        at = line.find("@S")
        if at >= 0:
            (cyc if in_cycle else pre).append(tuple(int(x) for x in line[at + 2 :].split()))
    reps = REPEATS if trail.lasso and trail.cycle_ticks else 0
    return pre + cyc * reps


class _Watch:
    """Every execute_tick of the interpreter's nodes: who was ticked, what each returned."""

    def __init__(self, interp: Interpreter) -> None:
        self.index = {id(n): n.uid - 1 for n in interp.nodes}
        self.ticked: set[int] = set()
        self.returned: set[tuple[int, int]] = set()
        self.inside: set[int] = set()
        self.patched: list[tuple[type, object]] = []
        self.active = True
        classes = {k for n in interp.nodes for k in type(n).__mro__ if issubclass(k, TreeNode)}
        for cls in classes:
            if "execute_tick" in cls.__dict__:
                original = cls.__dict__["execute_tick"]
                self.patched.append((cls, original))
                setattr(cls, _HOOK, self._wrap(original))

    def _wrap(self, original):
        watch = self

        def execute_tick(node):
            i = watch.index.get(id(node))
            if i is None or not watch.active:
                return original(node)
            if i in watch.inside:  # a subclass's execute_tick calling its base's
                return original(node)
            watch.ticked.add(i)
            watch.inside.add(i)
            try:
                result = original(node)
            finally:
                watch.inside.discard(i)
            watch.returned.add((i, result))
            return result

        return execute_tick

    def restore(self) -> None:
        for cls, original in self.patched:
            setattr(cls, _HOOK, original)


def run_interpreter(mission: Mission, scenario_text: str, prop: Property) -> tuple[str, list[Frame], list[tuple]]:
    """The trace, each tick's frame of the property's atoms, each tick's statuses."""
    scenario = parse_scenario_text(scenario_text, "<counterexample>")
    interp = _WatchedInterpreter(mission, scenario)
    interp.keys = atoms_of(prop.formula)
    parts: list[str] = []
    interp.watch = _Watch(interp)
    try:
        run_ticks(interp, scenario, parts.append)
    finally:
        interp.watch.restore()
    return "".join(parts), interp.frames, interp.states


class _WatchedInterpreter(Interpreter):
    """The interpreter, recording each tick's frame and statuses."""

    def __init__(self, mission: Mission, scenario) -> None:
        super().__init__(mission, scenario)
        self.frames: list[Frame] = []
        self.states: list[tuple] = []
        self.keys: set = set()
        self.watch: Optional[_Watch] = None
        self.order = sorted(range(len(self.nodes)), key=lambda i: self.nodes[i].uid)

    def tick_once(self):
        w = self.watch
        assert w is not None
        w.ticked.clear()
        w.returned.clear()
        result = super().tick_once()
        status = [self.nodes[i].status for i in self.order]
        root = STATUS[result.name]
        frame: Frame = {}
        for key in self.keys:
            kind = key[0]
            if kind == "ticked":
                frame[key] = key[1] in w.ticked
            elif kind == "returned":
                frame[key] = (key[1], key[2]) in w.returned
            elif kind == "running":
                frame[key] = status[key[1]] == RUNNING
            elif kind == "bb":  # the interpreter's own root blackboard
                values = {k: e.value for k, e in self.root_bb._storage.items()}
                frame[key] = compare_entry(values, key)
            else:
                frame[key] = root == key[1]
        self.frames.append(frame)
        self.states.append(tuple(status))
        return result


def trace_states(trace: str, n: int) -> list[tuple[int, ...]]:
    """Every node's status after each tick, read from a status trace."""
    status = [0] * n
    out: list[tuple[int, ...]] = []
    for line in trace.splitlines():
        if line.startswith("result "):
            out.append(tuple(status))
            continue
        m = _LINE.match(line)
        if m:
            status[int(m.group(1)) - 1] = STATUS[m.group(4)]
    return out


def replay(
    mission: Mission,
    program: Program,
    prop: Property,
    trail: Trail,
    trail_text: str,
    clock_ms: int,
) -> Counterexample:
    comment = f"btgen verify: a counterexample of {prop.text}"
    text, ticks, loop = scenario_of(trail, program, clock_ms, comment)
    cx = Counterexample(prop, text, ticks, loop, model_states(trail_text, trail))
    cx.trace, cx.frames, cx.interp_states = run_interpreter(mission, text, prop)
    if len(cx.frames) != ticks:
        cx.problems.append(f"the interpreter ran {len(cx.frames)} ticks, the counterexample has {ticks}")
    elif cx.interp_states != cx.model_states:
        k = next(i for i, (a, b) in enumerate(zip(cx.interp_states, cx.model_states)) if a != b)
        cx.problems.append(f"after tick {k + 1} the interpreter's statuses differ from the model's")
    else:
        frames = list(cx.frames)
        if cx.loop >= len(frames):  # the run ended (or was cut): nothing is ticked any more
            last = cx.interp_states[-1] if cx.interp_states else ()
            frames.append(
                {k: k[0] == "running" and bool(last) and last[k[1]] == RUNNING for k in atoms_of(prop.formula)}
            )
        cx.shown_interp = not holds_on_lasso(prop.formula, frames, cx.loop)
        if not cx.shown_interp:
            cx.problems.append("on the interpreter's run the property holds")
    return cx


def replay_cpp(cx: Counterexample, mission_path: str, opts, scenario_path: str, nodes: int) -> None:
    """The counterexample on the generated C++: the same trace as the interpreter, the model's statuses."""
    from btgen.tools.cppengine import build_cpp

    binary = build_cpp(mission_path, None, opts)
    p = subprocess.run([str(binary), scenario_path], capture_output=True, text=True, check=False)
    cx.cpp_trace = p.stdout
    if p.returncode != 0:
        cx.problems.append(f"the C++ engine exited with {p.returncode}: {p.stderr.strip()[:400]}")
        cx.shown_cpp = False
    elif cx.cpp_trace != cx.trace:
        cx.problems.append("the C++ engine's trace differs from the interpreter's")
        cx.shown_cpp = False
    else:
        cx.shown_cpp = trace_states(cx.cpp_trace, nodes) == cx.model_states and cx.shown_interp
        if trace_states(cx.cpp_trace, nodes) != cx.model_states:
            cx.problems.append("the C++ engine's statuses after some tick differ from the model's")


def btlog_bytes(program: Program, trace: str, clock_ms: int) -> bytes:
    """A Groot2 log (FileLogger2) of the run: each status change, stamped by its tick."""
    assert program.groot2 is not None
    xml = program.groot2.xml.encode("utf-8")
    body = bytearray()
    tick = 0
    seq = 0
    step = max(clock_ms, 1) * 1000
    for line in trace.splitlines():
        if line.startswith("tick "):
            tick = int(line.split()[1])
            seq = 0
            continue
        m = _LINE.match(line)
        if m:
            usec = (tick - 1) * step + seq
            seq += 1
            body += usec.to_bytes(6, "little") + struct.pack("<HB", int(m.group(1)), STATUS[m.group(4)])
    return b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + bytes(body)


def write_files(cx: Counterexample, program: Program, directory: str, stem: str, clock_ms: int) -> list[str]:
    """stem.scenario, stem.btlog and stem.trace in directory, each whole or not at all."""
    from btgen.tools.graph import _write

    os.makedirs(directory, exist_ok=True)
    out = []
    for ext, data in (
        (".scenario", cx.scenario.encode("utf-8")),
        (".btlog", btlog_bytes(program, cx.trace, clock_ms)),
        (".trace", cx.trace.encode("utf-8")),
    ):
        path = os.path.join(directory, stem + ext)
        _write(path, data)
        out.append(path)
    return out
