"""The Promela of Nav2's Controls and Decorators, as `interp/nav2.py` runs them.

A mixin of `promela.Emitter` (like `decorators.DecoratorTicks`): PipelineSequence,
RecoveryNode, RoundRobin and RateController. RateController's period is counted in ticks of
the virtual clock: the first tick count at which the elapsed time, in Nav2's single-precision
seconds (`interp.nav2.elapsed_seconds_f32`), reaches the period 1/hz.
"""

from __future__ import annotations

from typing import Optional

from btgen.interp.nav2 import elapsed_seconds_f32
from btgen.ir.lower import IRNode

NAV2_KINDS = frozenset({"PipelineSequence", "RecoveryNode", "RoundRobin", "RateController"})


def rate_ticks(hz: float, clock_ms: int, most: int) -> Optional[int]:
    """Ticks after a RateController's start at which its period has passed (None: not within
    `most` ticks, or never)."""
    period = 1.0 / hz if hz != 0.0 else float("inf")
    if period <= 0.0:
        return 0
    if clock_ms <= 0 or period == float("inf"):
        return None
    for k in range(1, most + 1):
        if elapsed_seconds_f32(k * clock_ms) >= period:
            return k
    return None


class Nav2Ticks:
    # given by promela.Emitter
    def child_tick(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def reset_child(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def reset_children(self, n: IRNode) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def halt_node(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def retries(self, n: IRNode) -> tuple[list[str], str]:  # pragma: no cover - bbnodes.BlackboardNodeTicks
        raise NotImplementedError

    def leave(self, i: int, value: str) -> str:  # pragma: no cover
        raise NotImplementedError

    def dispatch(self, var: str, n: IRNode, body, positions=None) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def ticks_of(self, n: IRNode) -> int:  # pragma: no cover
        raise NotImplementedError

    def k_PipelineSequence(self, n: IRNode) -> list[str]:
        """Every child in order; a RUNNING child at or past the furthest one reached ends the tick
        (its status is not set to RUNNING first: Nav2's tick() does not)."""
        i, nn = n.index, len(n.children)
        out = [f"sk{i} = 0; k{i} = 0;", "do", f":: k{i} < {nn} ->"]
        out.extend("   " + s for s in self.dispatch(f"k{i}", n, lambda pos, c: self.child_tick(c)))
        out.append(f"   cs{i} = rv;")
        out.append("   if")
        out.append(f"   :: cs{i} == FAILURE ->")
        out.extend("      " + s for s in self.reset_children(n))
        out.append(f"      last{i} = 0; {self.leave(i, 'FAILURE')}")
        out.append(f"   :: cs{i} == SKIPPED -> sk{i}++")
        out.append(f"   :: cs{i} == RUNNING -> if :: k{i} >= last{i} -> last{i} = k{i}; {self.leave(i, 'RUNNING')}")
        out.append("      :: else -> skip fi")
        out.append("   :: else -> skip")
        out.append("   fi;")
        out.append(f"   k{i}++")
        out.append(":: else -> break")
        out.append("od;")
        out.extend(self.reset_children(n))
        out.append(f"last{i} = 0;")
        out.append(f"if :: sk{i} == {nn} -> rv = SKIPPED :: else -> rv = SUCCESS fi;")
        return out

    def k_RecoveryNode(self, n: IRNode) -> list[str]:
        i, (c0, c1) = n.index, n.children
        read, r = self.retries(n)  # number_of_retries from the blackboard: bbnodes.py
        halt = self.halt_node(i)
        out = [*read, f"st[{i}] = RUNNING;", "do", f":: rcur{i} < 2 && rcnt{i} <= {r} ->"]
        out.extend("   " + s for s in self.dispatch(f"rcur{i}", n, lambda pos, c: self.child_tick(c)))
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: rcur{i} == 0 ->")
        out.append(f"      if :: cs{i} == SKIPPED ->")
        out.extend("         " + s for s in halt)
        out.append(f"         {self.leave(i, 'SKIPPED')}")
        out.append(f"      :: cs{i} == SUCCESS ->")
        out.extend("         " + s for s in self.reset_child(c1))
        out.extend("         " + s for s in halt)
        out.append(f"         {self.leave(i, 'SUCCESS')}")
        out.append(f"      :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        out.append(f"      :: else -> if :: rcnt{i} < {r} ->")
        out.extend("            " + s for s in self.reset_child(c0))
        out.append(f"            rcur{i} = 1")
        out.append("         :: else ->")
        out.extend("            " + s for s in halt)
        out.append(f"            {self.leave(i, 'FAILURE')}")
        out.append("         fi")
        out.append("      fi")
        out.append("   :: else ->")
        out.append(f"      if :: cs{i} == SKIPPED -> rcur{i} = 0;")
        out.extend("         " + s for s in self.reset_child(c1))
        out.append(f"         {self.leave(i, 'FAILURE')}")
        out.append(f"      :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        out.append(f"      :: cs{i} == SUCCESS ->")
        out.extend("         " + s for s in self.reset_child(c1))
        out.append(f"         rcnt{i}++; rcur{i} = 0")
        out.append("      :: else ->")
        out.extend("         " + s for s in halt)
        out.append(f"         {self.leave(i, 'FAILURE')}")
        out.append("      fi")
        out.append("   fi")
        out.append(":: else -> break")
        out.append("od;")
        out.extend(halt)
        out.append("rv = FAILURE;")
        return out

    def k_RoundRobin(self, n: IRNode) -> list[str]:
        i, nn = n.index, len(n.children)
        wrap = bool(n.params[0])
        out = [f"st[{i}] = RUNNING; sk{i} = 0;", "do", f":: fl{i} + sk{i} < {nn} ->"]
        out.extend("   " + s for s in self.dispatch(f"ix{i}", n, lambda pos, c: self.child_tick(c)))
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: cs{i} != RUNNING -> ix{i}++;")
        if wrap:
            out.append(f"      if :: ix{i} == {nn} -> ix{i} = 0 :: else -> skip fi")
        else:  # the round ends at the last child, whatever it answered
            out.append(f"      if :: ix{i} == {nn} ->")
            out.append(f"         if :: cs{i} == SKIPPED -> sk{i}++ :: cs{i} == FAILURE -> fl{i}++ :: else -> skip fi;")
            out.append("         break")
            out.append("      :: else -> skip fi")
        out.append("   :: else -> skip fi;")
        out.append(f"   if :: cs{i} == SUCCESS -> fl{i} = 0;")
        out.extend("      " + s for s in self.reset_children(n))
        out.append(f"      {self.leave(i, 'SUCCESS')}")
        out.append(f"   :: cs{i} == FAILURE -> fl{i}++")
        out.append(f"   :: cs{i} == SKIPPED -> sk{i}++")
        out.append(f"   :: else -> {self.leave(i, 'RUNNING')}")
        out.append("   fi")
        out.append(":: else -> break")
        out.append("od;")
        out.append(f"if :: sk{i} == {nn} -> tmp{i} = 1 :: else -> tmp{i} = 0 fi;")
        out.extend(self.halt_node(i))
        out.append(f"if :: tmp{i} -> rv = SKIPPED :: else -> rv = FAILURE fi;")
        return out

    def k_RateController(self, n: IRNode) -> list[str]:
        """From IDLE: the period starts and the child is ticked; afterwards the child is ticked
        while RUNNING or once the period has passed (a SUCCESS starts the next period)."""
        i, c = n.index, n.children[0]
        k = self.ticks_of(n)
        return [
            f"if :: st[{i}] == IDLE -> el{i} = 0; first{i} = 1 :: else -> skip fi;",
            f"st[{i}] = RUNNING;",
            f"if :: first{i} || st[{c}] == RUNNING || el{i} >= {k} -> first{i} = 0;",
            *("   " + s for s in self.child_tick(c)),
            f"   if :: rv == SUCCESS -> el{i} = 0 :: else -> skip fi",
            f":: else -> rv = st[{i}] fi;",
        ]
