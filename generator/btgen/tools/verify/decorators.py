"""The Promela of the built-in Decorators (and SubTree), as `interp/decorators.py` runs them.

A mixin of `promela.Emitter`: each `k_KIND` returns the statements of one node's tick, its
result left in `rv` (`leave` jumps to the node's end with it).
"""

from __future__ import annotations

from btgen.ir.lower import IRNode
from btgen.lang.versions import Semantics

NONE = 255  # a timer not armed


class DecoratorTicks:
    sem: Semantics
    params_from_bb: set[int]

    def param_limit(self, n: IRNode) -> list[str]:  # pragma: no cover - bbnodes.BlackboardNodeTicks
        raise NotImplementedError

    def param_reread(self, n: IRNode) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def then_skip(self, n: IRNode) -> tuple[list[str], str]:  # pragma: no cover
        raise NotImplementedError

    # given by promela.Emitter
    def child_tick(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def reset_child(self, c: int) -> list[str]:  # pragma: no cover
        raise NotImplementedError

    def leave(self, i: int, value: str) -> str:  # pragma: no cover
        raise NotImplementedError

    def ticks_of(self, n: IRNode) -> int:  # pragma: no cover
        raise NotImplementedError

    def k_Inverter(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        return [
            f"st[{i}] = RUNNING;",
            *self.child_tick(c),
            f"cs{i} = rv;",
            f"if :: cs{i} == SUCCESS -> st[{c}] = IDLE; rv = FAILURE",
            f"   :: cs{i} == FAILURE -> st[{c}] = IDLE; rv = SUCCESS",
            "   :: else -> skip fi;",
        ]

    def k_force(self, n: IRNode, result: str) -> list[str]:
        i, c = n.index, n.children[0]
        return [
            f"st[{i}] = RUNNING;",
            *self.child_tick(c),
            f"cs{i} = rv;",
            f"if :: cs{i} == SUCCESS || cs{i} == FAILURE ->",
            *("   " + s for s in self.reset_child(c)),
            f"   rv = {result}",
            ":: else -> skip fi;",
        ]

    def k_ForceSuccess(self, n: IRNode) -> list[str]:
        return self.k_force(n, "SUCCESS")

    def k_ForceFailure(self, n: IRNode) -> list[str]:
        return self.k_force(n, "FAILURE")

    def k_KeepRunningUntilFailure(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        rc = self.reset_child(c)
        return [
            f"st[{i}] = RUNNING;",
            *self.child_tick(c),
            f"cs{i} = rv;",
            f"if :: cs{i} == FAILURE ->",
            *("   " + s for s in rc),
            "   rv = FAILURE",
            f":: cs{i} == SUCCESS ->",
            *("   " + s for s in rc),
            "   rv = RUNNING",
            f":: cs{i} == RUNNING -> rv = RUNNING",
            f":: else -> rv = st[{i}] fi;",
        ]

    def k_loop(self, n: IRNode, retry: bool) -> list[str]:
        i, c = n.index, n.children[0]
        limit = n.params[0]
        read = i in self.params_from_bb  # the count read from the blackboard (bbnodes.py): lim{i}
        endless = limit == -1 and not read
        # INT_MIN as a literal: SPIN reads 2147483648 as INT_MIN, and -INT_MIN is positive in pan's C
        bound = "(-2147483647 - 1)" if limit == -(2**31) else str(limit)
        more = "true" if endless else (f"(lim{i} == -1 || cnt{i} < lim{i})" if read else f"cnt{i} < {bound}")
        track = not self.sem.loop_end_never_skipped
        out = self.param_limit(n) if read else []
        if track:
            out.append(f"if :: st[{i}] == IDLE -> als{i} = 1 :: else -> skip fi;")
        out += [f"st[{i}] = RUNNING;", "do", f":: {more} ->", f"   prv{i} = st[{c}];"]
        out.extend("   " + s for s in self.child_tick(c))
        out.append(f"   cs{i} = rv;")
        if track:
            out.append(f"   if :: cs{i} != SKIPPED -> als{i} = 0 :: else -> skip fi;")
        rc = self.reset_child(c)
        inc = "" if endless else f"cnt{i}++;"
        zero = "" if endless else f"cnt{i} = 0;"
        out.append("   if")
        if retry:
            out.append(f"   :: cs{i} == SUCCESS -> {zero}")
            out.extend("      " + s for s in rc)
            out.append(f"      {self.leave(i, 'SUCCESS')}")
            out.append(f"   :: cs{i} == FAILURE -> {inc}")
            if read:
                out.extend("      " + s for s in self.param_reread(n))
            out.extend("      " + s for s in rc)
            out.append(f"      if :: prv{i} == IDLE && ({more}) -> {self.leave(i, 'RUNNING')} :: else -> skip fi")
        else:
            out.append(f"   :: cs{i} == SUCCESS -> {inc}")
            out.extend("      " + s for s in rc)
            out.append(f"      if :: prv{i} == IDLE && ({more}) -> {self.leave(i, 'RUNNING')} :: else -> skip fi")
            out.append(f"   :: cs{i} == FAILURE -> {zero}")
            out.extend("      " + s for s in rc)
            out.append(f"      {self.leave(i, 'FAILURE')}")
        out.append(f"   :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        out.append("   :: else ->")
        out.extend("      " + s for s in rc)
        out.append(f"      {self.leave(i, 'SKIPPED')}")
        out.append("   fi")
        out.append(":: else -> break")
        out.append("od;")
        if zero:
            out.append(zero)
        final = "FAILURE" if retry else "SUCCESS"
        if track:
            out.append(f"if :: als{i} -> rv = SKIPPED :: else -> rv = {final} fi;")
        else:
            out.append(f"rv = {final};")
        return out

    def k_Repeat(self, n: IRNode) -> list[str]:
        return self.k_loop(n, False)

    def k_RetryUntilSuccessful(self, n: IRNode) -> list[str]:
        return self.k_loop(n, True)

    def k_RunOnce(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        read, skip = self.then_skip(n)  # then_skip from the blackboard: bbnodes.py
        then = self.leave(i, "SKIPPED") if skip == "1" else self.leave(i, f"ret{i}")
        if read:
            then = f"if :: {skip} -> {self.leave(i, 'SKIPPED')} :: else -> {self.leave(i, f'ret{i}')} fi"
        return [
            *read,
            f"if :: done{i} -> {then} :: else -> skip fi;",
            f"st[{i}] = RUNNING;",
            *self.child_tick(c),
            f"if :: rv == SUCCESS || rv == FAILURE -> done{i} = 1; ret{i} = rv; st[{c}] = IDLE",
            ":: else -> skip fi;",
        ]

    def k_SubTree(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        return [
            f"if :: st[{i}] == IDLE -> st[{i}] = RUNNING :: else -> skip fi;",
            *self.child_tick(c),
            f"if :: rv == SUCCESS || rv == FAILURE -> st[{c}] = IDLE :: else -> skip fi;",
        ]

    def k_Delay(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        k = self.ticks_of(n)
        out = [f"if :: !started{i} -> started{i} = 1; st[{i}] = RUNNING; el{i} = 0 :: else -> skip fi;"]
        out.append(f"if :: el{i} >= {k} ->")
        out.extend("   " + s for s in self.child_tick(c))
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: cs{i} == SUCCESS || cs{i} == FAILURE -> started{i} = 0; el{i} = {NONE};")
        out.extend("      " + s for s in self.reset_child(c))
        out.append("   :: else -> skip fi;")
        out.append(f"   rv = cs{i}")
        out.append(":: else -> rv = RUNNING fi;")
        return out

    def k_Timeout(self, n: IRNode) -> list[str]:
        i, c = n.index, n.children[0]
        k = self.ticks_of(n)
        arm = "0" if n.params[0] > 0 else str(NONE)
        out = [f"if :: !started{i} -> started{i} = 1; st[{i}] = RUNNING; el{i} = {arm}"]
        out.append(f":: else -> if :: el{i} != {NONE} && el{i} >= {k} -> el{i} = {NONE};")
        out.append(f"      if :: st[{c}] == RUNNING ->")
        out.extend("         " + s for s in self.reset_child(c))
        out.append(f"         started{i} = 0; {self.leave(i, 'FAILURE')}")
        out.append("      :: else -> skip fi")
        out.append("   :: else -> skip fi")
        out.append("fi;")
        out.extend(self.child_tick(c))
        out.append(f"cs{i} = rv;")
        out.append(f"if :: cs{i} == SUCCESS || cs{i} == FAILURE -> started{i} = 0; el{i} = {NONE};")
        out.extend("   " + s for s in self.reset_child(c))
        out.append(":: else -> skip fi;")
        out.append(f"rv = cs{i};")
        return out
