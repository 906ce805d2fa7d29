"""The blackboard nodes in the Promela model, as the reference interpreter runs them.

SetBlackboard, UnsetBlackboard, WasEntryUpdated, Switch2..6, Precondition, LoopInt/Bool/
Double/String, SkipUnlessUpdated, WaitValueUpdate, the loop counts a Repeat or a
RetryUntilSuccessful reads from the blackboard (`num_attempts="{n}"`), RunOnce's
`then_skip="{flag}"`, `_onHalted`, and TryCatch's catch_on_halt. What such a node does
with the blackboard is, as for scripts (`blackboard.py`), not re-written in Promela: the
interpreter's own node code runs on every reachable blackboard and the model gets its effect
as tables (`bb == S -> bb = S'; result`, made by `bbjobs.py`), per node and *role*:

    SetBlackboard, UnsetBlackboard,     "tick"   tick(): the write, SUCCESS or FAILURE
      WasEntryUpdated
    Switch                              "case"   select(): the child to tick
    Precondition                        "if"     `else` then the `if` script: 16 x else + truth
                                        "else"   `else` alone (4.7.0+: the child has started)
    Loop                                "idle"   pop_phase() from IDLE: POPPED, or 16 x if_empty
                                        "cont"   pop_phase() when the child is not running
    SkipUnlessUpdated, WaitValueUpdate  "upd"    consume_update(): 1 when the entry was updated
    Repeat, RetryUntilSuccessful        "param"  the count read from the blackboard (an index
                                        "reread" into `Tables.params`); 4.7.0+ Retry reads it
                                                 again after a failure (KEEP: no value)
    RunOnce                             "param"  then_skip read from the blackboard (no value: true)
    RecoveryNode (Nav2)                 "param"  number_of_retries, every tick (no value: KEEP)

The members of these nodes that the blackboard decides are part of the *blackboard state*
(`bbjobs.Members`): a Loop's queue (what is left of it), and each entry-update node's last seen
update counter, kept as how it stands to the entry's counter now (equal, behind, or ahead by
how much after the entry was unset and made again: all the node's comparison depends on),
so the states stay finite. What the node keeps beside (the running child of a Switch, a
Loop's `child_running`, an entry-update node's `still_executing`, a Precondition's
`children_running`) is a Promela variable.

A run-time error of the node (a port that cannot be read or converted, `else="IDLE"`) ends
the run there (`goto Error`), as the tree's exception ends it.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from btgen.ir.lower import IRNode
from btgen.tools.verify.bbjobs import KEEP, PARAM_FROM_BB, POPPED
from btgen.tools.verify.blackboard import lookup, result_is

if TYPE_CHECKING:  # pragma: no cover
    from btgen.lang.versions import Semantics
    from btgen.tools.verify.blackboard import Tables


_LABEL = re.compile(r"\b((?:E|TC)\d+)\b(?!@)")  # a node's labels (promela.py: E<i>, TC<i>)
_OPEN, _CLOSE = "/*@H{*/", "/*@H}*/"  # a halt's copy of a tick: its labels are `@H`, made unique by the emitter


def unique_labels(lines: list[str]) -> list[str]:
    """Each copy of a tick a halt emits (the same lines may be emitted in several places) gets
    labels of its own: `E5@H` becomes `E5_h<k>`, k counting the copies, innermost first."""
    out: list[str] = []
    stack: list[str] = []
    count = 0
    for line in lines:
        if line.strip() == _OPEN:
            count += 1
            stack.append(f"_h{count}")
            continue
        if line.strip() == _CLOSE:
            stack.pop()
            continue
        out.append(line.replace("@H", stack[-1]) if stack and "@H" in line else line)
    return out


# ---------------------------------------------------------------- the Promela (a mixin of promela.Emitter)
class BlackboardNodeTicks:
    bbt: Tables
    sem: Semantics

    # given by promela.Emitter
    def child_tick(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def reset_child(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def reset_children(self, n: IRNode) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def leave(self, i: int, value: str) -> str:  # pragma: no cover
        raise NotImplementedError

    def var(self, decl: str, temp: bool = False) -> None:  # pragma: no cover
        raise NotImplementedError

    def table(self, i: int, role: str, into: str) -> list[str]:
        return lookup(self.bbt.node[(i, role)], result_is(into))

    def declare_bb(self, n: IRNode) -> None:
        i, k = n.index, n.kind
        if k == "Switch":
            self.var(f"byte rc{i}")  # the running child + 1 (0: none)
            self.var(f"byte sw{i}", True)
            self.var(f"byte cs{i}", True)
        elif k == "Precondition":
            self.var(f"byte pc{i}", True)
            if self.sem.precondition_if_until_started:
                self.var(f"bit cr{i}")  # children_running (4.7.0+)
        elif k == "Loop":
            self.var(f"bit cr{i}")  # child_running
            self.var(f"byte lp{i}", True)
        elif k in ("SkipUnlessUpdated", "WaitValueUpdate"):
            self.var(f"bit se{i}")  # still_executing
            self.var(f"bit eu{i}", True)
        elif k == "TryCatch" and (n.params[0] or i in self.bbt.params):
            self.var(f"byte ch{i}", True)  # the result the halt's tick of the catch child must not clobber
            if i in self.bbt.params:
                self.var(f"bit coh{i}", True)  # catch_on_halt read from the blackboard
        elif k == "RecoveryNode" and i in self.bbt.params:
            self.var(f"int rlim{i} = 1")  # number_of_retries: the last value read stays (a member)
        elif k == "RunOnce" and i in self.bbt.params:
            self.var(f"bit ts{i}", True)
        elif k in PARAM_FROM_BB and i in self.bbt.params:
            self.var(f"int lim{i}", True)

    def halt_bb(self, n: IRNode) -> list[str]:
        """What halt() clears beside the children and the status."""
        i, k = n.index, n.kind
        if k == "Switch":
            return [f"rc{i} = 0;"]
        if k == "Loop":  # child_running is cleared at the next start from IDLE: the same states merge now
            return [f"cr{i} = 0;"]
        if k in ("SkipUnlessUpdated", "WaitValueUpdate"):
            return [f"se{i} = 0;"]
        return []  # a Precondition keeps children_running (the library's halt() does not clear it)

    def catch_on_halt(self, n: IRNode) -> list[str]:
        """4.9.0+ TryCatch catch_on_halt="true": halted while in the try block, it halts the try
        children and ticks the catch child once (halting it when RUNNING). The catch child's tick
        is emitted again here, its labels made unique."""
        i = n.index
        read = i in self.bbt.params  # catch_on_halt="{key}": read as the halt begins
        if not (n.params[0] or read) or len(n.children) < 2:
            return []
        *tries, last = n.children
        tick = [_LABEL.sub(r"\1@H", s) for s in self.child_tick(last)]
        out = [_OPEN]
        if read:
            values = self.bbt.params[i]
            out += lookup(self.bbt.node[(i, "param")], lambda r: f"coh{i} = {1 if values[r] else 0}")
        out.append(f"if :: {f'coh{i} && ' if read else ''}!inc{i} && st[{i}] == RUNNING ->")
        for c in tries:
            out += ["   " + s for s in self.reset_child(c)]
        out.append(f"   ch{i} = rv;")
        out += ["   " + s for s in tick]
        out.append("   if :: rv == RUNNING ->")
        out += ["      " + s for s in self.reset_child(last)]
        out.append("   :: else -> skip fi;")
        out.append(f"   rv = ch{i}")
        out.append(":: else -> skip fi;")
        out.append(_CLOSE)
        return out

    def on_halted(self, c: int) -> list[str]:
        """haltNode's _onHalted script, after halt()."""
        if (c, "halted") not in self.bbt.node:
            return []
        return lookup(self.bbt.node[(c, "halted")], lambda r: "skip")

    # the leaves
    def k_SetBlackboard(self, n: IRNode) -> list[str]:
        return self.table(n.index, "tick", "rv")

    def k_UnsetBlackboard(self, n: IRNode) -> list[str]:
        return self.table(n.index, "tick", "rv")

    def k_WasEntryUpdated(self, n: IRNode) -> list[str]:
        return self.table(n.index, "tick", "rv")

    # Switch2..6: the case from the table; a change of case halts the child that was running
    def k_Switch(self, n: IRNode) -> list[str]:
        i = n.index
        out = self.table(i, "case", f"sw{i}")
        out.append("if")
        for pos, c in enumerate(n.children):
            out.append(f":: rc{i} == {pos + 1} && sw{i} != {pos} ->")
            out.extend("   " + s for s in self.reset_child(c))
        out += [":: else -> skip", "fi;", "if"]
        for pos, c in enumerate(n.children):
            out.append(f":: sw{i} == {pos} ->")
            out.extend("   " + s for s in self.child_tick(c))
        out += [":: else -> assert(false)", "fi;", f"cs{i} = rv;"]
        out.append(f"if :: cs{i} == SKIPPED -> rc{i} = 0 :: cs{i} == RUNNING -> rc{i} = sw{i} + 1")
        out.append(":: else ->")
        out.extend("   " + s for s in self.reset_children(n))
        out.append(f"   rc{i} = 0")
        out.append(f"fi; rv = cs{i};")
        return out

    def k_Precondition(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        tick = [*self.child_tick(c), "if :: rv == SUCCESS || rv == FAILURE ->"]
        tick += ["   " + s for s in self.reset_child(c)]
        if (i, "else") in self.bbt.node:  # 4.7.0+: `if` only until the child has started
            tick.append(f"   cr{i} = 0")
            tick.append(":: else -> skip fi;")
            out = [f"if :: !cr{i} ->"]
            out += ["   " + s for s in self.table(i, "if", f"pc{i}")]
            out.append(f"   cr{i} = pc{i} & 1")
            out.append(":: else ->")
            out += ["   " + s for s in self.table(i, "else", f"pc{i}")]
            out.append("fi;")
            out.append(f"if :: !cr{i} -> if :: pc{i} / 16 == IDLE -> goto Error :: else -> rv = pc{i} / 16 fi")
            out.append(":: else ->")
            out += ["   " + s for s in tick]
            out.append("fi;")
            return out
        tick.append(":: else -> skip fi;")
        out = self.table(i, "if", f"pc{i}")
        out.append(f"if :: pc{i} & 1 ->")
        out += ["   " + s for s in tick]
        out.append(f":: pc{i} / 16 == IDLE -> goto Error  /* setStatus(IDLE) throws */")
        out.append(f":: else -> rv = pc{i} / 16")
        out.append("fi;")
        return out

    def k_Loop(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        out = [f"if :: !cr{i} || st[{i}] == IDLE ->"]
        out += [f"   if :: st[{i}] == IDLE ->"]
        out += ["      " + s for s in self.table(i, "idle", f"lp{i}")]
        out += ["   :: else ->"]
        out += ["      " + s for s in self.table(i, "cont", f"lp{i}")]
        out += ["   fi;"]
        out.append(f"   if :: lp{i} == 0 -> goto Error  /* if_empty IDLE: setStatus(IDLE) throws */")
        out.append(f"   :: lp{i} != {POPPED} -> {self.leave(i, f'lp{i} / 16')}")
        out.append("   :: else -> skip fi")
        out.append(":: else -> skip fi;")
        out.append(f"if :: st[{i}] == IDLE -> st[{i}] = RUNNING :: else -> skip fi;")
        out += self.child_tick(c)
        out.append(f"if :: rv == RUNNING -> cr{i} = 1 :: else -> cr{i} = 0 fi;")
        out.append("if :: rv == SUCCESS || rv == FAILURE ->")
        out += ["   " + s for s in self.reset_child(c)]
        out.append(":: else -> skip fi;")
        out.append("if :: rv == FAILURE -> skip :: else -> rv = RUNNING fi;")
        return out

    def k_entry_updated(self, n: IRNode, if_not_updated: str) -> list[str]:
        i, c = n.index, n.children[0]
        out = [f"if :: se{i} -> eu{i} = 1", ":: else ->"]
        out += ["   " + s for s in self.table(i, "upd", f"eu{i}")]
        out.append("fi;")
        out.append(f"if :: eu{i} ->")
        out += ["   " + s for s in self.child_tick(c)]
        out.append(f"   if :: rv == RUNNING -> se{i} = 1 :: else -> se{i} = 0 fi")
        out.append(f":: else -> rv = {if_not_updated} fi;")
        return out

    def k_SkipUnlessUpdated(self, n: IRNode) -> list[str]:
        return self.k_entry_updated(n, "SKIPPED")

    def k_WaitValueUpdate(self, n: IRNode) -> list[str]:
        return self.k_entry_updated(n, "RUNNING")

    # a Repeat's or a Retry's count read from the blackboard
    def param_limit(self, n: IRNode) -> list[str]:
        """`lim{i}` read as the tick begins (require_input: no value is a run-time error)."""
        i = n.index
        values = self.bbt.params[i]
        return lookup(self.bbt.node[(i, "param")], lambda r: f"lim{i} = {_count(values[r])}")

    def then_skip(self, n: IRNode) -> tuple[list[str], str]:
        """RunOnce's then_skip read from the blackboard (every tick, before anything): the lines
        and the test; a literal: no lines."""
        i = n.index
        if i not in self.bbt.params:
            return [], "1" if n.params[0] else "0"
        values = self.bbt.params[i]
        return lookup(self.bbt.node[(i, "param")], lambda r: f"ts{i} = {1 if values[r] else 0}"), f"ts{i}"

    def retries(self, n: IRNode) -> tuple[list[str], str]:
        """Nav2's RecoveryNode: number_of_retries read from the blackboard every tick (no value:
        the last one read stays, 1 at first); a literal: no lines."""
        i = n.index
        if i not in self.bbt.params:
            return [], str(n.params[0])
        values = self.bbt.params[i]
        keep = lambda r: "skip" if r == KEEP else f"rlim{i} = {_count(values[r])}"  # noqa: E731
        return lookup(self.bbt.node[(i, "param")], keep), f"rlim{i}"

    def param_reread(self, n: IRNode) -> list[str]:
        """4.7.0+ Retry: num_attempts read again after a failure (no value: the count stays)."""
        i = n.index
        if (i, "reread") not in self.bbt.node:
            return []
        values = self.bbt.params[i]
        return lookup(self.bbt.node[(i, "reread")], lambda r: "skip" if r == KEEP else f"lim{i} = {_count(values[r])}")


def _count(v: int) -> int:
    """A count below -1 loops as little as 0 does (`cnt < lim` is false at once): one Promela
    literal for them all (INT_MIN would not parse as one)."""
    return -2 if v < -1 else v
