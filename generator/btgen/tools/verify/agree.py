"""Agreement of the Promela model with `btgen explore` (tools/explore/search.py).

Both enumerate the runs of a mission whose leaves answer freely, up to a number of ticks:
explore replays plans on the interpreter, SPIN searches the model. What they must agree on
is the set of *tick-end states* each reaches, projected on what both hold the same way:
the status of every node after each tick (the interpreter's `TreeNode.status`, the model's
`st[]`). A state one reaches and the other does not is a bug in one of the two.

`explore_tick_states` runs explore's search (its state merging, its plans) and records the
projection after every completed tick of every run; `spin_tick_states` runs the model with
`print_states` (every tick end prints `@S` and the statuses) through SPIN's exhaustive search.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from btgen.diagnostics import UserError
from btgen.ir.lower import Program
from btgen.lang.model import Mission
from btgen.tools import explore as ex
from btgen.tools.verify import spin
from btgen.tools.verify.promela import ModelOptions, emit_model


class _Recorder(ex.Explorer):
    """explore's search, recording every node's status after every completed tick."""

    def __init__(self, *a, **k) -> None:
        super().__init__(*a, **k)
        self.tick_states: set[tuple[int, ...]] = set()
        self.order = sorted(range(len(self.nodes)), key=lambda i: self.nodes[i].uid)

    def run(self, plan):  # explore.Explorer.run with a record after each tick
        # Every plan from the initial state (explore's own run resumes from the tick where the
        # plan departs from the last one; this one records every tick, so it replays them all).
        self.marks.clear()
        self.last_plan = ()
        self._restore(self._initial)
        run = ex._Run(self, plan)
        self.current = run
        interp = run.interp
        try:
            for n in range(1, self.ticks + 1):
                run.tick_no = n
                if n > 1 and self.clock_ms:
                    interp.advance_clock(self.clock_ms)
                status = interp.tick_once()
                interp.take_text()
                self.tick_states.add(tuple(interp.nodes[i].status for i in self.order))
                if status.name in ("SUCCESS", "FAILURE"):
                    return "done", run, None
            return "ticks", run, None
        except ex._Branch as b:
            return "branch", run, b.options
        except ex._Stop as s:
            return s.reason, run, None
        except UserError as e:
            run.error = e.diagnostics[0] if e.diagnostics else None
            return "error", run, None
        finally:
            self.current = None


@dataclass
class Agreement:
    explore_states: set[tuple[int, ...]]
    spin_states: set[tuple[int, ...]]
    explore_runs: int
    explore_truncated: bool
    spin: spin.SpinResult

    @property
    def agree(self) -> bool:
        return self.explore_states == self.spin_states and not self.explore_truncated


def explore_tick_states(
    mission: Mission, ticks: int, clock_ms: int, max_states: int = 200000
) -> tuple[set[tuple[int, ...]], int, bool]:
    rec = _Recorder(mission, ticks, 10**9, clock_ms, max_states)
    result = rec.explore()
    return rec.tick_states, result.runs, result.truncated


def spin_tick_states(
    mission: Mission, program: Program, ticks: int, clock_ms: int, workdir: str, atomic_paths: int = 64
) -> tuple[set[tuple[int, ...]], spin.SpinResult]:
    options = ModelOptions(ticks=ticks, clock_ms=clock_ms, print_states=True, atomic_paths=atomic_paths)
    text = emit_model(mission, program, options)
    res = spin.reachable(text, workdir, print_states=True)
    states = {tuple(int(x) for x in line.split()[1:]) for line in res.lines if line.startswith("@S")}
    return states, res


def agreement(
    mission: Mission, program: Program, ticks: int, clock_ms: int, workdir: str, max_states: int = 200000
) -> Agreement:
    es, runs, truncated = explore_tick_states(mission, ticks, clock_ms, max_states)
    ss, res = spin_tick_states(mission, program, ticks, clock_ms, workdir)
    return Agreement(es, ss, runs, truncated, res)


def describe(state: tuple[int, ...], program: Program, other: Optional[set] = None) -> str:
    from btgen.tools.verify.promela import STATUS_NAME

    return " ".join(f"{n.uid}:{STATUS_NAME[s][0]}" for n, s in zip(program.nodes, state))
