"""`btgen analyze`: what a mission can and cannot do, found before the robot runs it.

The analysis works on the lowered program (ir/lower.py: the node table in
creation order, SubTrees expanded) and on the instances the data side loads
(ir/dataflow.py: one blackboard per SubTree instance). For every node it
computes, bottom up, the statuses one tick of it can return whatever the
user leaves return (Actions SUCCESS/FAILURE/RUNNING, Conditions
SUCCESS/FAILURE), and for each status the most work such a tick does:

- nodes visited (executeTick calls),
- leaf hooks called (onStart/onRunning of user Actions, tick of user Conditions),
- script evaluations (Script, ScriptCondition, Precondition `if`, pre- and
  post-conditions; `_onHalted` runs on halts and is not counted).

The semantics are BehaviorTree.CPP 4.6.2's, as the interpreter has them:
Repeat and RetryUntilSuccessful yield RUNNING after a cycle that started from
IDLE, so they tick their child at most twice per tick; nothing built in loops
without bound within one tick. A user Control or Decorator may tick its
children any number of times: the bound is then "unbounded" and names it.

Each node has two tables, for a tick that finds it IDLE and for one that finds
it RUNNING (a resumed Sequence skips the children before the running one; a
Repeat starts a second cycle in a tick only when it resumed the first). The
bounds are per outcome and composed along the tick's paths (a Sequence child
that only fails stops the count); they are reached when the leaves' results
are independent of each other, except for Parallel, whose count is an upper
bound. `btgen explore --no-merge` measures the most a tick does, and the tests
check on random missions that analyze is never below it, never calls a ticked
node unreachable and never calls a returned status impossible. With
`--btcpp 4.10.0` the switches of lang/versions.py that change what a tick
returns are followed; a node not modelled here (TryCatch) may return anything.

Scripts whose names are all SubTree constants never written by any node (or
no names at all) are evaluated once here: a constant `_skipIf`, `_while`,
`_successIf`, `_failureIf`, ScriptCondition or Precondition makes branches
unreachable, and the finding says which instance.

The modules: ``results`` (statuses, costs, findings), ``constants`` (constant scripts on the
loaded blackboards), ``ticks`` (the per-node tables, reachability), ``checks``
(``analyze_program``: the findings) and ``command`` (``btgen analyze``, the executor's sizes).
"""

from btgen.tools.analyze.checks import analyze_program, unwritten_script_reads
from btgen.tools.analyze.command import analyze_command, memory, stop_quietly_on_broken_pipe
from btgen.tools.analyze.results import ORDER, UNBOUNDED, Analysis, Cost, F, Finding, K, Outcomes, R, S

__all__ = [
    "ORDER",
    "UNBOUNDED",
    "Analysis",
    "Cost",
    "F",
    "Finding",
    "K",
    "Outcomes",
    "R",
    "S",
    "analyze_command",
    "analyze_program",
    "unwritten_script_reads",
    "memory",
    "stop_quietly_on_broken_pipe",
]
