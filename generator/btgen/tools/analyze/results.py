"""What analyze computes: per node and status, the most work one tick does (Cost), and the
findings; the status names and the arithmetic of costs."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from btgen.diagnostics import Loc
from btgen.ir.lower import Program

S, F, R, K = "SUCCESS", "FAILURE", "RUNNING", "SKIPPED"
ORDER = (S, F, R, K)
UNBOUNDED = -1

Cost = tuple[int, int, int]  # visits, hooks, scripts (UNBOUNDED in any: no bound)
Outcomes = dict[str, Cost]


def _add(a: Cost, b: Cost) -> Cost:
    return tuple(UNBOUNDED if x == UNBOUNDED or y == UNBOUNDED else x + y for x, y in zip(a, b))  # type: ignore[return-value]


def _max(a: Optional[Cost], b: Cost) -> Cost:
    if a is None:
        return b
    return tuple(UNBOUNDED if x == UNBOUNDED or y == UNBOUNDED else max(x, y) for x, y in zip(a, b))  # type: ignore[return-value]


def _put(out: Outcomes, status: str, cost: Cost) -> None:
    out[status] = _max(out.get(status), cost)


ZERO: Cost = (0, 0, 0)
ONE: Cost = (1, 0, 0)


@dataclass
class Finding:
    loc: Loc
    category: str  # unreachable | budget | blackboard | reactive
    message: str

    def as_json(self) -> dict:
        return {
            "file": self.loc.path,
            "line": self.loc.line,
            "column": self.loc.col,
            "category": self.category,
            "message": self.message,
        }


@dataclass
class Analysis:
    program: Program
    outcomes: list[Outcomes]  # per node index: what one tick of it can return, and its most work
    reachable: list[bool]
    unbounded_by: Optional[int] = None  # index of the node that makes the tick unbounded
    findings: list[Finding] = field(default_factory=list)
    constants: dict = field(default_factory=dict)  # (node index, attr name) -> bool

    def worst(self) -> Cost:
        c: Cost = ZERO
        for v in self.outcomes[0].values():
            c = _max(c, v)
        return c
