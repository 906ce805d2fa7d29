"""Random valid missions and scenarios for differential testing (reliability).

:func:`random_case` turns a seed into a mission (BTCPP_format="4" XML) and a
few scenarios, deterministically: the same seed and feature set give the
same bytes on every machine and Python version (only ``random.Random`` with
an integer seed and explicit choices are used, never hash order).

Feature sets:

- ``control``: every control node and decorator that needs no blackboard
  (Sequence ... ParallelAll, IfThenElse, WhileDoElse, Inverter ... Delay),
  AlwaysSuccess/AlwaysFailure/Sleep, scripted Actions and Conditions,
  SubTrees, names that need escaping in the trace, time (``clock_ms``);
- ``full``: all of the above plus the data side: an initialising Script,
  Script/ScriptCondition, SetBlackboard/UnsetBlackboard, Precondition,
  Switch2..6, LoopInt/Bool/Double/String (literal and blackboard queues),
  SkipUnlessUpdated/WaitValueUpdate/WasEntryUpdated, SubTrees with
  `{key}` remapping, literal remapping, `_autoremap` and `@key`, pre- and
  post-condition scripts on any node, leaves with declared ports;
- ``dynamic``: all of ``full`` plus two root entries, `v` and `w`, whose type
  changes at run time (4.6.2 allows it for entries no typed port declared):
  scripts assign them integers, doubles, strings and bools, update them with
  `+=`, concatenate and compare them; SetBlackboard writes literals and copies
  into them and out of them; UnsetBlackboard removes `v`; an untyped port
  creates both at load (so a typed `int` port may read them too) and Switch
  reads `v` as text; Loops write their `value` into them (a typed write: the
  entry takes the Loop's type, which later writes convert to or throw on); in half
  of the missions a typed entry `td` (int, unsigned, double or bool, declared at load
  by a node that never runs) that scripts write, that SetBlackboard copies `v` and `w`
  into and that conditions read.

- ``hostile``: all of ``dynamic`` with the leaf models, their ports and the integer
  entries renamed to names of HOSTILE_NAMES (C++ keywords, macros, the runtime's and the
  generated code's own names), Move's typed ports first written with the other kind of
  number (``i0 := 2.0`` for an int port, ``d := 1`` for a double one).

- ``edges``: all of ``full`` with the edges of 4.6.2's parameters (docs/btcpp-4.6.2-edges.md):
  Repeat/Retry counts 0, -0, -2, INT_MIN, INT_MAX, literals read as a prefix (``2.5``,
  ``1abc``, ``0x3``) and an integer entry (``{k}``, which SetBlackboard sets to one of
  them first); Parallel thresholds 0, -2, INT_MIN and below minus the children;
  durations 0, ``-0``, ``0x9``, ``5x``; Loop items spelt oddly (``1.5``, `` 2.5``, empty
  strings); Switch cases left out or empty; ``else``/``if_empty`` IDLE (an error in both
  engines); ``_skipIf="true"`` on any node; empty strings written to entries.

Every mission the generator writes passes ``btgen validate`` by construction
(the differential driver counts and reports any that does not); whether the
C++ back end compiles it is decided by ``btgen compile`` itself, so a feature
set can be run before the back end supports all of it and the missions it
rejects are counted, never silently dropped.

    python -m btgen.tools.fuzzgen SEED [--features control|full]   # print mission and scenarios
"""

from __future__ import annotations

import argparse
import random
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Optional

FEATURE_SETS = ("control", "full", "dynamic", "hostile", "edges")
BTCPP_VERSIONS = ("4.6.2", "4.10.0")  # `--btcpp`: the release the mission is written for

# Hex and special floats: std::stod (4.6.2) reads `0x1p3` as 8, std::from_chars (4.10.0) as 0
# (stopping at `x`) and refuses a blank or `+` first (a literal queue: a load error then).
FLOAT_TEXTS = ("0x1p3", "0X10", "inf", "-inf", "nan", "infinity", "1e1")
FLOAT_TEXTS_462 = (" 2.5", "+1.5")

# `edges`: the values at the edges of 4.6.2's parameters (docs/btcpp-4.6.2-edges.md): counts
# that never start a loop, INT_MIN/INT_MAX, literals read as a prefix, zero durations.
INT_MIN_TEXT, INT_MAX_TEXT = "-2147483648", "2147483647"
EDGE_COUNTS = ("0", "-0", "-2", INT_MIN_TEXT, INT_MAX_TEXT, "2.5", "1abc", "0x3", "-1", "1", "2")
EDGE_DURATIONS = ("0", "-0", "0x9", "5x", "1.9")
DYN_VARS = ("v", "w")  # `dynamic`: root entries whose type changes at run time
DYN_KEY_NAMES = ("v", "w", "fresh2")  # the names `dk` holds (`fresh2`: an entry only it creates)
# `dynamic`: the typed entry `td` that values of changing type are copied into: the node that
# declares it at load (never ticked) and the first values the init script gives it.
TYPED_DSTS = {
    "int": ('<LoopInt queue="1" value="{td}"><AlwaysSuccess/></LoopInt>', ("1", "0", "2.0", "'3'")),
    "unsigned": ('<Timeout msec="{td}"><AlwaysSuccess/></Timeout>', ("2", "0", "'7'")),
    "double": ('<LoopDouble queue="1.5" value="{td}"><AlwaysSuccess/></LoopDouble>', ("0.5", "1", "'2.5'")),
    "bool": ('<LoopBool queue="true" value="{td}"><AlwaysSuccess/></LoopBool>', ("true", "false", "1", "'true'")),
}

CONTROLS = (
    "Sequence",
    "SequenceWithMemory",
    "AsyncSequence",
    "ReactiveSequence",
    "Fallback",
    "AsyncFallback",
    "ReactiveFallback",
    "Parallel",
    "ParallelAll",
)
DECORATORS = (
    "Inverter",
    "ForceSuccess",
    "ForceFailure",
    "KeepRunningUntilFailure",
    "Repeat",
    "RetryUntilSuccessful",
    "RunOnce",
    "Timeout",
    "Delay",
)
DATA_DECORATORS = (
    "Precondition",
    "LoopInt",
    "LoopBool",
    "LoopDouble",
    "LoopString",
    "SkipUnlessUpdated",
    "WaitValueUpdate",
)

# Scripted leaves: IDs declared in TreeNodesModel, and the names the scenario scripts.
ACTION_IDS = ("Act", "Move")
CONDITION_IDS = ("Check",)
ACTION_NAMES = ("a", "b", "c", "d", "e")
CONDITION_NAMES = ("p", "q", "r")
# Names that exercise the trace's quoting (FORMAT.md): given to non-leaf nodes only.
ODD_NAMES = (
    'say "hi"',
    "back\\slash",
    "tab\there",
    "line\nbreak",
    "caf\u00e9 \u2615",
    "",
    " spaced ",
    "cr\rhere",
    "del\x7f",
    "<&>",
)

# Names that must survive the trip to C++ identifiers: what the generated code and
# the runtime declare or use unqualified, what the C library declares at global scope and a
# few macros; C++ keywords come from naming.CPP_KEYWORDS. Drawn for model IDs, ports, keys.
HOSTILE_NAMES = (
    "std",
    "btgen",
    "detail",
    "leaf",
    "kId",
    "kKind",
    "kModel",
    "node",
    "blackboard",
    "bb_",
    "err_",
    "node_",
    "bb",
    "n",
    "err",
    "e",
    "value",
    "seq",
    "exists",
    "has_value",
    "T",
    "scratch0_",
    "scratch1_",
    "loop_0",
    "loop_1",
    "Engine",
    "Leaves",
    "Clock",
    "Observer",
    "Spec",
    "Blackboard",
    "Semantics",
    # the leaf dispatch (Spec::Model, ModelOf, visit_action: btgen/leaf_dispatch.hpp)
    "Model",
    "ModelOf",
    "ModelBase",
    "Hook",
    "Args",
    "args",
    "call",
    "visit_action",
    "LeafHooks",
    "model",
    "leaves",
    "main",
    "engine",
    "observer",
    "clock",
    "errno",
    "time",
    "exit",
    "random",
    "remove",
    "system",
    "abs",
    "printf",
    "NULL",
    "EOF",
    "EDOM",
    "INT_MAX",
    "SIZE_MAX",
    "stdin",
    "stdout",
    "stderr",
    "assert",
    "linux",
    "unix",
    # macros of a build and of btgen's runtime (NDEBUG: every Release build)
    "NDEBUG",
    "BTGEN_STRAIGHT_LINE_BUDGET",
    "BTGEN_MISSION_HEADER",
    "BTGEN_MISSION_TEMPLATE",
    "ZMQ_PUB",
    "EFSM",
    "set_x",
    "x",
    "int",
    "class",
    "and",
    "not",
    "bool",
    "true",
    "delete",
    "operator",
    "this",
    "return",
)

INT_VARS = ("i0", "i1")
PARAM_VARS = ("p0", "p1")  # the ports of a remapped SubTree, bound to the caller's ints


@dataclass(frozen=True)
class Case:
    """One generated mission and the scenarios to run it on."""

    seed: int
    features: str
    mission: str
    scenarios: tuple[str, ...]


def _xml_attr(value: str) -> str:
    """`value` as a double-quoted XML attribute value that decodes back to exactly `value`."""
    out = []
    for ch in value:
        if ch == "&":
            out.append("&amp;")
        elif ch == "<":
            out.append("&lt;")
        elif ch == ">":
            out.append("&gt;")
        elif ch == '"':
            out.append("&quot;")
        elif ch in "\t\n\r" or ord(ch) < 0x20:
            out.append(f"&#{ord(ch)};")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


class _Scope:
    """The blackboard names a tree may use: ints, and the other root variables
    (`s`, `flag`, `d`, `u`, `q`) spelt as this tree reaches them (`@s` from a tree
    with its own blackboard)."""

    def __init__(self, ints: Sequence[str], prefix: Optional[str]) -> None:
        self.ints = tuple(ints)
        self.has_root_vars = prefix is not None
        self.prefix = prefix or ""
        self.main_like = prefix == "" and self.ints == INT_VARS  # the main tree or an _autoremap one

    def var(self, name: str) -> str:
        return self.prefix + name


class _Gen:
    def __init__(self, seed: int, features: str, btcpp: str = "4.6.2") -> None:
        if features not in FEATURE_SETS:
            raise ValueError(f"unknown feature set `{features}` (use {', '.join(FEATURE_SETS)})")
        if btcpp not in BTCPP_VERSIONS:
            raise ValueError(f"unknown BehaviorTree.CPP version `{btcpp}` (use {', '.join(BTCPP_VERSIONS)})")
        self.rng = random.Random(
            seed * 7919 + {"control": 0, "full": 1, "dynamic": 2, "hostile": 3, "edges": 4}[features]
        )
        # The draws of the features added later (TryCatch, skippable conditions, hex and special
        # floats) come from their own generator, so a seed's mission changes only where one of
        # them is picked.
        self.xrng = random.Random(seed * 6007 + BTCPP_VERSIONS.index(btcpp) * 13 + len(features))
        self.btcpp = btcpp
        self.later = btcpp != "4.6.2"  # 4.10.0: TryCatch; doubles read with std::from_chars
        self.data = features in ("full", "dynamic", "hostile", "edges")
        self.edges = features == "edges"
        self.dyn = features in ("dynamic", "hostile")
        self.hostile = features == "hostile"
        self.counter = 0
        self.n_trees = self.rng.choice((1, 2, 3, 3))
        self.budget = self.rng.randint(6, 45)
        # SubTree k may call SubTrees > k only (no cycles). Its calling convention:
        # "plain" (no data), "remap" (p0/p1 bound to the caller's ints), "auto" (_autoremap).
        self.modes = ["main"] + [self._subtree_mode() for _ in range(1, self.n_trees)]
        self.uses_queue_key = False
        self.uses_count_key = False
        self.leaf_ports = self.data and self.rng.random() < 0.5
        # `ld`, declared double at load by a LoopDouble that never runs and set by the init
        # script: SetBlackboard writes hex and special float texts into it, conditions read it.
        self.typed_ld = self.data and not self.hostile and self.xrng.random() < 0.5
        # `dynamic`: `dk`, the key a SetBlackboard output_key="{dk}" reads when it runs, given
        # literal names of the root's entries by scripts (issue 44).
        # (their own generator too, so the missions of earlier seeds change only where they are picked)
        self.krng = random.Random(seed * 104729 + BTCPP_VERSIONS.index(btcpp) * 17 + len(features))
        self.dyn_keys = self.dyn and not self.hostile and self.krng.random() < 0.6
        # `dynamic`: Loops writing their `value` into `v` and `w` (their own generator too)
        self.wrng = random.Random(seed * 15485863 + BTCPP_VERSIONS.index(btcpp) * 19 + len(features))
        self.dyn_writes = self.dyn and not self.hostile and self.wrng.random() < 0.6
        # `dynamic`: `td`, a typed entry values of changing type are copied into (its own generator)
        self.trng = random.Random(seed * 1299709 + BTCPP_VERSIONS.index(btcpp) * 19 + len(features))
        self.typed_dst = self.trng.choice(tuple(TYPED_DSTS)) if self.dyn and not self.hostile else None
        if self.typed_dst is not None and self.trng.random() < 0.5:
            self.typed_dst = None

    def _subtree_mode(self) -> str:
        if not self.data:
            return "plain"
        return self.rng.choice(("plain", "remap", "remap", "auto"))

    # ------------------------------------------------------------ helpers
    def name(self) -> str:
        self.counter += 1
        if self.rng.random() < 0.06:
            odd = self.rng.choice(ODD_NAMES)
            if self.later and any((ord(c) < 32 and c not in "\t\n\r") or ord(c) == 127 for c in odd):
                return "del"  # 4.8.4 refuses these control characters in a created node's name
            return odd
        return f"n{self.counter}"

    def name_attr(self) -> str:
        r = self.rng.random()
        if r < 0.15:
            return ""  # the ID is the name
        return f" name={_xml_attr(self.name())}"

    def int_var(self, scope: _Scope) -> str:
        return self.rng.choice(scope.ints)

    def int_expr(self, scope: _Scope) -> str:
        v = self.int_var(scope)
        return self.rng.choice(
            (
                f"{v} + 1",
                f"{v} - 1",
                f"{v} * 2",
                "3",
                f"{v}",
                f"{v} > 2 ? {v} - 2 : {v} + 1",
                f"({v} + {self.int_var(scope)}) - 1",
            )
        )

    def cond_expr(self, scope: _Scope) -> str:
        v = self.int_var(scope)
        k = self.rng.randint(0, 4)
        simple = [f"{v} < {k}", f"{v} == {k}", f"{v} >= {k}", f"{v} != {self.int_var(scope)}", "true", "false"]
        if scope.has_root_vars:
            s, f = scope.var("s"), scope.var("flag")
            simple += [f"{s} == 'a'", f"{s} != 'b'", f"!{f}", f"{f}"]
            if scope.main_like:
                simple.append("u == 'x'")  # a run-time error once UnsetBlackboard removed `u`
                if self.typed_ld:
                    simple += ["ld == 8.0", "ld > 1.0", "ld == 0.0"]
            if self.dyn:
                dv, dw = scope.var("v"), scope.var("w")
                simple += [
                    f"{dv} == 7",
                    f"{dv} == 'abc'",
                    f"{dv} != {dw}",
                    f"{dv} .. '' == '7'",
                    f"{dv} > 2",
                    f"{dw} < {dv}",
                    f"{dw} == '7.000000'",
                    f"{dv} == {v}",
                    f"{dv}",
                    f"!{dw}",
                    f"{dv} .. {dw} != 'x'",
                    f"({dv} + 1) >= 3",
                    f"{v} > 1 ? {dv} == 7 : {dw} != 2",
                ]
        e = self.rng.choice(simple)
        r = self.rng.random()
        if r < 0.15:
            rhs = self.rng.choice(simple)
            if "?" in e and "?" in rhs:  # `a ? b : c && d ? e : f` chains `?:`, which 4.6.2's grammar rejects
                rhs = f"({rhs})"
            e = f"{e} && {rhs}"
        elif r < 0.25:
            e = f"({e}) || ({self.rng.choice(simple)})"
        return e

    def statement(self, scope: _Scope) -> str:
        v = self.int_var(scope)
        opts = [f"{v} := {self.int_expr(scope)}", f"{v} += 1", f"{v} -= 1", f"{v} = {self.rng.randint(0, 3)}"]
        if scope.has_root_vars:
            s, f = scope.var("s"), scope.var("flag")
            opts += [f"{s} := '{self.rng.choice('abc')}'", f"{f} := !{f}", f"{f} := {v} > 1"]
            if self.dyn:
                opts += self.dyn_statements(scope, v)
        st = self.rng.choice(opts)
        if self.rng.random() < 0.2:
            st += "; " + self.rng.choice(opts)
        return st

    def dyn_value(self) -> str:
        return self.rng.choice(("3", "7", "-1", "2.5", "7.0", "'abc'", "'7'", "'2.5'", "''", "true", "false", "0x10"))

    def dyn_statements(self, scope: _Scope, v: str) -> list[str]:
        dv, dw, s = scope.var("v"), scope.var("w"), scope.var("s")
        x = self.dyn_value()
        return [
            f"{dv} := {x}",
            f"{dw} := {self.dyn_value()}",
            f"{dv} = {x}",
            f"{dv} += 1",
            f"{dv} += 'z'",
            f"{dw} -= 2",
            f"{dw} := {dv}",
            f"{dv} := {dv} .. 'x'",
            f"{dw} := {dv} + 1",
            f"{dv} := {dw} .. {v}",
            f"{dv} := {v} > 1 ? 'big' : {v}",
            f"{dw} := {dv} == 7",
            f"{s} := {dv} .. ''",
            f"{v} += {dv}",
            f"{dv} := -{dw}",
            f"{dw} := {dv} * 2",
        ]

    # ------------------------------------------------------------- nodes
    def node(self, depth: int, tree: int, scope: _Scope) -> str:
        self.budget -= 1
        if depth >= 6 or self.budget <= 0 or self.rng.random() < 0.3:
            return self.leaf(tree, scope)
        r = self.rng.random()
        if r < 0.40:
            return self.control(depth, tree, scope)
        if r < 0.50:
            return self.if_then_else(depth, tree, scope)
        if r < 0.56 and self.data:
            return self.switch(depth, tree, scope)
        if r < 0.62 and tree + 1 < self.n_trees:
            return self.subtree(tree, scope)
        return self.decorator(depth, tree, scope)

    def with_conditions(self, scope: _Scope) -> str:
        """Random pre/post-condition attributes (data side only); `edges`: skipped anywhere."""
        if self.edges and self.rng.random() < 0.06:
            return ' _skipIf="true"'
        if not self.data or self.rng.random() > 0.15:
            return ""
        out = []
        for attr in ("_skipIf", "_successIf", "_failureIf", "_while"):
            if self.rng.random() < 0.3:
                out.append(f" {attr}={_xml_attr(self.cond_expr(scope))}")
        for attr in ("_onSuccess", "_onFailure", "_onHalted", "_post"):
            if self.rng.random() < 0.3:
                out.append(f" {attr}={_xml_attr(self.statement(scope))}")
        return "".join(out)

    def children(self, depth: int, tree: int, scope: _Scope, lo: int = 1, hi: int = 4) -> list[str]:
        return [self.node(depth + 1, tree, scope) for _ in range(self.rng.randint(lo, hi))]

    def control(self, depth: int, tree: int, scope: _Scope) -> str:
        kind = self.rng.choice(CONTROLS)
        if self.later and self.xrng.random() < 0.12:
            return self.try_catch(depth, tree, scope)
        kids = self.children(depth, tree, scope)
        n = len(kids)
        attrs = ""
        # thresholds never above the children: that is a deliberate compile-time refusal
        # (edges table P3), where 4.6.2 throws only when the node is ticked
        edge: tuple = ()
        if self.edges:
            edge = (0, -2, -n - 1, -n - 5, INT_MIN_TEXT, f"{min(n, 1)}.5", "-0")
        if kind == "Parallel":
            if self.rng.random() < 0.7:
                attrs += f' success_count="{self.rng.choice((-1, 1, n, -n, max(1, n - 1)) + edge)}"'
            if self.rng.random() < 0.7:
                attrs += f' failure_count="{self.rng.choice((1, -1, n, -n, max(1, n - 1)) + edge)}"'
        elif kind == "ParallelAll" and self.rng.random() < 0.7:
            attrs = f' max_failures="{self.rng.choice((1, -1, n, 0, max(1, n - 1)) + edge)}"'
        return f"<{kind}{self.name_attr()}{attrs}{self.with_conditions(scope)}>" + "".join(kids) + f"</{kind}>"

    def try_catch(self, depth: int, tree: int, scope: _Scope) -> str:
        """4.10.0's TryCatch: try children, then the catch child; `catch_on_halt` a literal or absent."""
        kids = self.children(depth, tree, scope, 2, 4)
        attrs = self.xrng.choice(("", ' catch_on_halt="true"', ' catch_on_halt="false"', ' catch_on_halt="1"'))
        return f"<TryCatch{self.name_attr()}{attrs}{self.with_conditions(scope)}>" + "".join(kids) + "</TryCatch>"

    def skippable_condition(self, scope: _Scope) -> str:
        """A condition that may answer SKIPPED (the library throws on the run where it does) or,
        in 4.6.2, keep a stale SUCCESS: `_skipIf`/`_while` on it or in a Sequence, RunOnce."""
        x = self.xrng
        cond = x.choice(("_skipIf", "_while"))
        guard = f" {cond}={_xml_attr(self.cond_expr(scope))}"
        r = x.random()
        if r < 0.3:
            return f"<ScriptCondition{self.name_attr()} code={_xml_attr(self.cond_expr(scope))}{guard}/>"
        if r < 0.5:
            return f'<RunOnce{self.name_attr()} then_skip="true">{self.safe_condition(scope)}</RunOnce>'
        # An Action under `_while` may be RUNNING, then halted and skipped: 4.6.2's Sequence
        # keeps the SUCCESS of its flag, 4.10.0's counts the skip.
        inner = (
            self.scripted_leaf("Action", scope, conditions=False)[:-2] + guard + "/>"
            if x.random() < 0.5
            else self.safe_condition(scope)[:-2] + guard + "/>"
        )
        more = self.safe_condition(scope) if x.random() < 0.4 else ""
        return f"<Sequence{self.name_attr()}>{inner}{more}</Sequence>"

    def safe_condition(self, scope: _Scope) -> str:
        """A child that never returns SKIPPED or RUNNING (IfThenElse/WhileDoElse condition)."""
        if self.data and self.rng.random() < 0.35:
            return f"<ScriptCondition{self.name_attr()} code={_xml_attr(self.cond_expr(scope))}/>"
        return self.scripted_leaf("Condition", scope, conditions=False)

    def if_then_else(self, depth: int, tree: int, scope: _Scope) -> str:
        kind = self.rng.choice(("IfThenElse", "WhileDoElse"))
        skippable = self.data and self.xrng.random() < 0.3
        cond = self.skippable_condition(scope) if skippable else self.safe_condition(scope)
        kids = [cond] + self.children(depth, tree, scope, 1, 2)
        return f"<{kind}{self.name_attr()}{self.with_conditions(scope)}>" + "".join(kids) + f"</{kind}>"

    def switch(self, depth: int, tree: int, scope: _Scope) -> str:
        n = self.rng.randint(2, 6)
        # `variable` is a string port: an entry it reads holds a string (btgen types every entry).
        var = "{" + scope.var("v" if self.dyn and self.rng.random() < 0.4 else "s") + "}"
        cases = [self.rng.choice(("a", "b", "c", "x") + (("", None, None) if self.edges else ())) for _ in range(n)]
        attrs = "".join(f" case_{i + 1}={_xml_attr(c)}" for i, c in enumerate(cases) if c is not None)
        kids = [self.node(depth + 1, tree, scope) for _ in range(n + 1)]
        return (
            f"<Switch{n}{self.name_attr()} variable={_xml_attr(var)}{attrs}{self.with_conditions(scope)}>"
            + "".join(kids)
            + f"</Switch{n}>"
        )

    def decorator(self, depth: int, tree: int, scope: _Scope) -> str:
        pool = DECORATORS + (DATA_DECORATORS if self.data else ())
        kind = self.rng.choice(pool)
        rng = self.rng
        if self.edges and rng.random() < 0.3:
            kind = rng.choice(("Repeat", "RetryUntilSuccessful"))
        counts: tuple = EDGE_COUNTS if self.edges else (-1, 0, 1, 2, 3)
        durations: tuple = EDGE_DURATIONS if self.edges else ()
        count = rng.choice(counts)
        if self.edges and scope.has_root_vars and rng.random() < 0.25:
            # blackboard-fed, read on every tick: `k`, an integer only the init script writes
            count = "{" + scope.var("k") + "}"
            self.uses_count_key = True
        attrs = {
            "Repeat": f' num_cycles="{count}"',
            "RetryUntilSuccessful": f' num_attempts="{count}"',
            "RunOnce": rng.choice(("", ' then_skip="true"', ' then_skip="false"')),
            "Timeout": f' msec="{rng.choice((0, 5, 15, 40) + durations)}"',
            "Delay": f' delay_msec="{rng.choice((0, 10, 30) + durations)}"',
        }.get(kind, "")
        if kind == "Precondition":
            attrs = f" if={_xml_attr(self.cond_expr(scope))}"
            if rng.random() < 0.7:
                status = rng.choice(("FAILURE", "SUCCESS", "SKIPPED", "RUNNING"))
                attrs += f' else="{"IDLE" if self.edges and rng.random() < 0.1 else status}"'
        elif kind.startswith("Loop"):
            attrs = self.loop_ports(kind, scope, tree)
        elif kind in ("SkipUnlessUpdated", "WaitValueUpdate"):
            attrs = f' entry="{{{rng.choice(scope.ints + (scope.var("u"),))}}}"'
        child = self.node(depth + 1, tree, scope)
        return f"<{kind}{self.name_attr()}{attrs}{self.with_conditions(scope)}>{child}</{kind}>"

    def loop_ports(self, kind: str, scope: _Scope, tree: int = 0) -> str:
        rng = self.rng
        elem = {
            "LoopInt": ("1", "2", "3", "-4") + (("1.5", "2x", "-0", INT_MIN_TEXT) if self.edges else ()),
            "LoopBool": ("true", "false", "1", "0"),
            # (` 2.5`: std::stod only; 4.10.0 refuses it on load)
            "LoopDouble": ("0.5", "1.25", "2", "-3.5")
            + (((" 2.5",) if not self.later else ()) + ("1e1x", "-0") if self.edges else ()),
            "LoopString": ("a", "b", "kitchen") + (("", " ") if self.edges else ()),
        }[kind]
        # Each loop writes an entry of its own element type (LoopInt's `int` is not a script's integer).
        target = scope.var({"LoopInt": "li", "LoopBool": "lb", "LoopDouble": "ld", "LoopString": "ls"}[kind])
        if self.dyn_writes and scope.has_root_vars and (scope.prefix == "@" or tree == 0) and self.wrng.random() < 0.35:
            # `dynamic`: a typed write (Blackboard::set<T>) into `v` or `w`, whose type changes at
            # run time, on the root blackboard that holds them (issue 44)
            target = scope.var(self.wrng.choice(DYN_VARS))
        queue = ";".join(rng.choice(elem) for _ in range(rng.randint(0, 4)))
        if kind == "LoopDouble" and queue and self.xrng.random() < 0.7:
            texts = FLOAT_TEXTS + (() if self.later else FLOAT_TEXTS_462)
            queue = ";".join(self.xrng.choice(texts) if self.xrng.random() < 0.5 else q for q in queue.split(";"))
        if kind == "LoopInt" and scope.main_like and rng.random() < 0.3:
            self.uses_queue_key = True
            queue = "{q}"
        out = f" queue={_xml_attr(queue)} value={_xml_attr('{' + target + '}')}"
        if rng.random() < 0.5:
            status = rng.choice(("SUCCESS", "FAILURE", "SKIPPED"))
            out += f' if_empty="{"IDLE" if self.edges and rng.random() < 0.1 else status}"'
        return out

    def subtree(self, tree: int, scope: _Scope) -> str:
        callee = self.rng.randint(tree + 1, self.n_trees - 1)
        mode = self.modes[callee]
        if mode == "auto" and not scope.main_like:
            # An _autoremap tree's names do not exist in this tree's blackboard.
            return self.leaf(tree, scope)
        attrs = self.name_attr()
        if self.later and attrs == ' name=""':
            # 4.8.4: the path of a SubTree named "" in the main tree is the main tree's own
            attrs = f' name="s{self.counter}"'
        if mode == "remap":
            for p in PARAM_VARS:
                attrs += f' {p}="{{{self.int_var(scope)}}}"'
        elif mode == "auto":
            attrs += ' _autoremap="true"'
        return f'<SubTree ID="T{callee}"{attrs}{self.with_conditions(scope)}/>'

    def scripted_leaf(self, kind: str, scope: _Scope, conditions: bool = True) -> str:
        if kind == "Condition":
            lid, name = self.rng.choice(CONDITION_IDS), self.rng.choice(CONDITION_NAMES)
        else:
            lid, name = self.rng.choice(ACTION_IDS), self.rng.choice(ACTION_NAMES)
        attrs = ""
        if self.rng.random() < 0.85:
            attrs += f' name="{name}"'
        if self.leaf_ports and self.rng.random() < 0.5:
            if lid == "Move":
                if self.hostile and scope.main_like and self.rng.random() < 0.5:
                    attrs += ' speed="{d}"'  # `d` is a typed double entry, its first write maybe an integer
                if self.dyn and scope.has_root_vars and self.rng.random() < 0.3:
                    attrs += f' goal="{{{scope.var(self.rng.choice(DYN_VARS))}}}"'
                else:
                    attrs += f' goal="{{{self.int_var(scope)}}}"' if self.rng.random() < 0.5 else ' goal="4"'
            elif lid == "Check":
                attrs += f' level="{self.rng.randint(0, 9)}"'
        pre = self.with_conditions(scope) if conditions else ""
        return f"<{lid}{attrs}{pre}/>"

    def leaf(self, tree: int, scope: _Scope) -> str:
        if self.typed_dst is not None and scope.main_like and self.trng.random() < 0.2:
            return self.typed_dst_leaf()
        r = self.rng.random()
        rng = self.rng
        if r < 0.07:
            return f"<AlwaysSuccess{self.name_attr()}{self.with_conditions(scope)}/>"
        if r < 0.12:
            return f"<AlwaysFailure{self.name_attr()}{self.with_conditions(scope)}/>"
        if r < 0.17:
            msec = rng.choice((0, 10, 25) + (EDGE_DURATIONS if self.edges else ()))
            return f'<Sleep{self.name_attr()} msec="{msec}"{self.with_conditions(scope)}/>'
        if self.data and r < 0.40:
            d = rng.random()
            if d < 0.3:
                return f"<Script{self.name_attr()} code={_xml_attr(self.statement(scope))}/>"
            if d < 0.55:
                return f"<ScriptCondition{self.name_attr()} code={_xml_attr(self.cond_expr(scope))}/>"
            if self.dyn and d < 0.75 and rng.random() < 0.5:
                dv, dw = scope.var("v"), scope.var("w")
                opts = [
                    f'value="{rng.choice(("7", "abc", "2.5", "", "true"))}" output_key="{rng.choice((dv, dw))}"',
                    f'value="{{{dv}}}" output_key="{dw}"',
                    f'value="{{{dw}}}" output_key="{dv}"',
                    f'value="{{{self.int_var(scope)}}}" output_key="{dv}"',
                    f'value="{{{scope.var("s")}}}" output_key="{dw}"',
                ]
                if scope.main_like:
                    opts.append('value="{v}" output_key="fresh"')
                return f"<SetBlackboard{self.name_attr()} {rng.choice(opts)}/>"
            if d < 0.75 and self.typed_ld and scope.main_like and self.xrng.random() < 0.6:
                # text through the double entry's converter: std::stod or std::from_chars
                text = self.xrng.choice(
                    self.xrng.choice((FLOAT_TEXTS[:2], FLOAT_TEXTS[2:], FLOAT_TEXTS_462 + ("2.5", "abc")))
                )
                return f'<SetBlackboard{self.name_attr()} value={_xml_attr(text)} output_key="ld"/>'
            if self.dyn_keys and scope.main_like and d < 0.75 and self.krng.random() < 0.7:
                return self.dynamic_key_leaf()
            if d < 0.75:
                # A literal is a string (4.6.2 stores the text): only into string entries.
                if rng.random() < 0.5:  # a copy between two integer entries
                    return (
                        f'<SetBlackboard{self.name_attr()} value="{{{self.int_var(scope)}}}" '
                        f'output_key="{self.int_var(scope)}"/>'
                    )
                text = rng.choice(("a", "b", "c", "x") + (("",) if self.edges else ()))  # `edges`: an empty string
                return f'<SetBlackboard{self.name_attr()} value="{text}" output_key="{scope.var("s")}"/>'
            if scope.main_like:
                if d < 0.85:
                    key = "v" if self.dyn and rng.random() < 0.3 else "u"
                    return f'<UnsetBlackboard{self.name_attr()} key="{key}"/>'
                if d < 0.92:
                    return f'<SetBlackboard{self.name_attr()} value="{rng.choice("xyz")}" output_key="u"/>'
            return f'<WasEntryUpdated{self.name_attr()} entry="{{{self.int_var(scope)}}}"/>'
        return self.scripted_leaf("Condition" if rng.random() < 0.35 else "Action", scope)

    # ---------------------------------------------------------- mission
    def mission(self) -> str:
        trees = []
        for t in range(self.n_trees):
            mode = self.modes[t]
            if not self.data:
                scope = _Scope((), None)
            elif mode == "remap":
                scope = _Scope(PARAM_VARS, "@")
            elif mode == "plain":
                scope = _Scope(tuple("@" + v for v in INT_VARS), "@")
            else:
                scope = _Scope(INT_VARS, "")
            body = self.node(0, t, scope)
            if t == 0 and self.data:
                body = self.with_init(body)
            trees.append(f'  <BehaviorTree ID="T{t}">\n    {body}\n  </BehaviorTree>\n')
        speed = '      <input_port name="speed" type="double"/>\n' if self.hostile else ""
        models = [
            '    <Action ID="Act"/>\n',
            f'    <Action ID="Move">\n      <input_port name="goal" type="int"/>\n{speed}    </Action>\n',
            '    <Condition ID="Check">\n      <input_port name="level" type="int" default="1"/>\n    </Condition>\n',
        ]
        if self.dyn:
            models.append(
                '    <Action ID="Show">\n      <input_port name="what"/>\n      <input_port name="other"/>\n'
                "    </Action>\n"
            )
        for t in range(1, self.n_trees):
            if self.modes[t] == "remap":
                models.append(
                    f'    <SubTree ID="T{t}">\n'
                    + "".join(f'      <inout_port name="{p}"/>\n' for p in PARAM_VARS)
                    + "    </SubTree>\n"
                )
        return (
            '<?xml version="1.0" encoding="UTF-8"?>\n'
            '<root BTCPP_format="4" main_tree_to_execute="T0">\n'
            + "".join(trees)
            + "  <TreeNodesModel>\n"
            + "".join(models)
            + "  </TreeNodesModel>\n</root>\n"
        )

    def dynamic_key_leaf(self) -> str:
        """A Script pointing `dk` at another root entry, or a SetBlackboard writing the entry
        `dk` names (a literal, a copy of a dynamic, string or integer entry; under 4.6.2 also of
        the double entry `ld` a port typed). Unnamed: it draws nothing from the main generator."""
        x = self.krng
        if x.random() < 0.35:
            return f'<Script code="dk := {x.choice(DYN_KEY_NAMES)!r}"/>'
        values = ['"7"', '"abc"', '"2.5"', '"{v}"', '"{w}"', '"{s}"', '"{i0}"']
        if self.typed_ld and not self.later:
            values.append('"{ld}"')
        return f'<SetBlackboard value={x.choice(values)} output_key="{{dk}}"/>'

    def typed_dst_leaf(self) -> str:
        """A leaf on the typed entry `td`: a SetBlackboard copy of `v` or `w` into it (4.6.2 copies
        the value as it is; 4.10.0 converts a string and throws on another type), a script
        writing it, or a condition reading it. Unnamed: it draws nothing from the main generator."""
        x = self.trng
        r = x.random()
        if r < 0.5:
            return f'<SetBlackboard value="{{{x.choice(DYN_VARS)}}}" output_key="td"/>'
        if r < 0.65:
            return f"<Script code={_xml_attr('td := ' + x.choice(('1', '0', '2.5', chr(39) + '4' + chr(39), 'v')))}/>"
        return f"<ScriptCondition code={_xml_attr(x.choice(('td == 1', 'td != 0', 'td == v', '(td + 1) > 1')))}/>"

    def with_init(self, body: str) -> str:
        """Define the root blackboard's variables first (btgen rejects a read it can see comes first)."""
        rng = self.rng
        i0, i1, d = rng.randint(0, 3), rng.randint(0, 3), "0.5"
        i0_text = str(i0)
        if self.hostile:
            # The other kind of number as the first write of a typed entry (`goal` is an int port,
            # `speed` a double one): 4.6.2 keeps the value's kind in the empty entry.
            i0_text = rng.choice((str(i0), f"{i0}.0", f"-{i0}", f"{2 * i0} / 2"))
            d = rng.choice(("0.5", "1", "-2", "3 / 2", "2.0"))
        init = (
            f"i0 := {i0_text}; i1 := {i1}; s := '{rng.choice('abc')}'; "
            f"flag := {rng.choice(('true', 'false'))}; d := {d}; u := 'x'"
        )
        extra = ""
        if self.uses_count_key:
            if rng.random() < 0.6:
                # text into the `int` entry the count port declared (a script's `-2` is a double)
                text = rng.choice(("0", "-2", "-1", "1", "2", INT_MIN_TEXT))
                extra = f'<SetBlackboard value="{text}" output_key="k"/>'
            else:
                # a script's number, bool or text into it: getInput<int> casts or parses what it holds
                # (a fraction, 2^32: the node throws)
                k = rng.choice(("2.0", "-1.0", "0.0", "1.5", "'2'", "true", "false", "4294967296"))
                extra = f'<Script code="k := {k}"/>'
        if self.typed_ld:
            init += "; ld := 0.5"
            extra = (
                '<Fallback><AlwaysSuccess/><LoopDouble queue="1.0" value="{ld}"><AlwaysSuccess/></LoopDouble>'
                "</Fallback>" + extra
            )
        if self.uses_queue_key:
            q = ";".join(str(rng.randint(0, 9)) for _ in range(rng.randint(0, 4)))
            extra += f'<SetBlackboard value="{q}" output_key="q"/>'
        if self.dyn:
            init += f"; v := {self.dyn_value()}; w := {self.dyn_value()}"
            if self.dyn_keys:
                init += f"; dk := {self.krng.choice(DYN_KEY_NAMES)!r}"
                if self.krng.random() < 0.5:
                    extra += self.dynamic_key_leaf()
            # Never ticked: its untyped ports create `v` and `w` at load (type AnyTypeAllowed), before any
            # typed port could declare them.
            extra = '<Fallback><AlwaysSuccess/><Show what="{v}" other="{w}"/></Fallback>' + extra
            if self.typed_dst is not None:
                node, firsts = TYPED_DSTS[self.typed_dst]
                init += f"; td := {self.trng.choice(firsts)}"
                extra = f"<Fallback><AlwaysSuccess/>{node}</Fallback>" + extra
        return f'<Sequence name="init"><Script code={_xml_attr(init)}/>{extra}{body}</Sequence>'


def random_mission(seed: int, features: str = "control", btcpp: str = "4.6.2") -> str:
    """The mission of `seed`: a valid BTCPP_format="4" document for release `btcpp`."""
    return _Gen(seed, features, btcpp).mission()


# Names of the hostile pool that can be model IDs, ports and script variables (XML names and
# script identifiers: not the script's `true`/`false`, not 4.6.2's reserved port names).
# Nor the generator's own leaf names, keys and models (a Condition ID `e` would be scripted by
# the lines of the Action named `e`).
_GENERATOR_NAMES = frozenset(
    ACTION_NAMES
    + CONDITION_NAMES
    + DYN_VARS
    + DYN_KEY_NAMES
    + ("dk", "td")
    + INT_VARS
    + PARAM_VARS
    + (
        "s",
        "d",
        "u",
        "q",
        "k",
        "flag",
        "lb",
        "li",
        "ld",
        "ls",
        "Show",
        "what",
        "other",
        "Act",
        "Move",
        "Check",
        "goal",
        "speed",
        "level",
    )
)
_HOSTILE_IDS = tuple(
    n
    for n in HOSTILE_NAMES
    if n not in ("true", "false", "name", "ID") and n not in _GENERATOR_NAMES and not n.startswith("T")
)


def hostile_names(seed: int) -> dict[str, str]:
    """The `hostile` feature set's renaming of seed `seed`: model IDs (Act, Move, Check), their
    ports (goal, speed, level) and the integer entries (i0, i1) become names of the hostile pool
    (C++ keywords, macros, the runtime's and the generated code's names), all different."""
    rng = random.Random(seed * 31337 + 5)
    picks = rng.sample(_HOSTILE_IDS, 8)
    return dict(zip(("Act", "Move", "Check", "goal", "speed", "level", "i0", "i1"), picks))


def _rename(text: str, names: dict[str, str], mission: bool) -> str:
    import re

    if not mission:  # scenario lines `leaf <ID> ...`
        return re.sub(r"^leaf (Act|Move|Check) ", lambda m: f"leaf {names[m.group(1)]} ", text, flags=re.M)
    text = re.sub(r'(<|ID=")(Act|Move|Check)\b', lambda m: m.group(1) + names[m.group(2)], text)
    text = re.sub(r'\b(goal|speed|level)(=")', lambda m: names[m.group(1)] + m.group(2), text)
    text = re.sub(r'(name=")(goal|speed|level)"', lambda m: m.group(1) + names[m.group(2)] + '"', text)
    return re.sub(r"(?<![A-Za-z0-9_])(i0|i1)(?![A-Za-z0-9_])", lambda m: names[m.group(1)], text)


def random_scenario(rng: random.Random, clock: bool = True) -> str:
    """A scenario for the leaf names of every generated mission."""
    lines = [f"ticks {rng.randint(3, 40)}"]
    if clock and rng.random() < 0.8:
        lines.append(f"clock_ms {rng.choice((0, 5, 10, 20))}")
    all_conditions_scripted = rng.random() < 0.3
    default = rng.choice(("SUCCESS", "FAILURE", "RUNNING" if all_conditions_scripted else "SUCCESS"))
    if rng.random() < 0.8:
        lines.append(f"default {default}")
    for name in ACTION_NAMES + ACTION_IDS:
        if rng.random() < 0.75:
            lines.append(
                f"leaf {name} "
                + " ".join(rng.choice(("SUCCESS", "FAILURE", "RUNNING", "RUNNING")) for _ in range(rng.randint(1, 12)))
            )
    for name in CONDITION_NAMES + CONDITION_IDS:
        if all_conditions_scripted or rng.random() < 0.75:
            lines.append(
                f"leaf {name} " + " ".join(rng.choice(("SUCCESS", "FAILURE")) for _ in range(rng.randint(1, 12)))
            )
    rng.shuffle(lines)
    return "\n".join(lines) + "\n"


def random_case(seed: int, features: str = "control", n_scenarios: int = 3, btcpp: str = "4.6.2") -> Case:
    """Mission and scenarios of `seed` for release `btcpp` (deterministic)."""
    mission = random_mission(seed, features, btcpp)
    rng = random.Random(seed * 104729 + 17)
    scenarios = tuple(random_scenario(rng) for _ in range(n_scenarios))
    if features == "hostile":
        names = hostile_names(seed)
        mission = _rename(mission, names, True)
        scenarios = tuple(_rename(sc, names, False) for sc in scenarios)
    return Case(seed, features, mission, scenarios)


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m btgen.tools.fuzzgen", description="print a random mission and scenarios"
    )
    p.add_argument("seed", type=int)
    p.add_argument("--features", choices=FEATURE_SETS, default="control")
    p.add_argument("--scenarios", type=int, default=1)
    p.add_argument("--btcpp", choices=BTCPP_VERSIONS, default="4.6.2", help="the release the mission is for")
    args = p.parse_args(argv)
    case = random_case(args.seed, args.features, args.scenarios, args.btcpp)
    sys.stdout.write(case.mission)
    for i, s in enumerate(case.scenarios):
        sys.stdout.write(f"<!-- scenario {i}\n{s}-->\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
