"""`btgen upgrade-check MISSION.xml --from 4.6.2 --to 4.10.0 [--scenario FILE]`.

Every place of a mission (its includes and models files) where moving from one
BehaviorTree.CPP release to the other changes loading or behaviour, as one
``path:line:col: warning:`` line each that names the change and the release that
made it (lang/versions.py lists the switches). With ``--scenario`` the mission
also runs on both versions (the interpreter) and the first tick where the traces
part is printed with both lines. Exit 0 when nothing changes, 1 when something does.

The static findings are conservative where the change depends on values known
only when the mission runs (which entries a SetBlackboard meets, whether a
child is skipped while RUNNING): they say where to look; ``--scenario`` shows
what happens.
"""

from __future__ import annotations

import sys
from collections.abc import Iterator

from btgen import pipeline
from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.lang import blackboard as bbmod
from btgen.lang import script as scriptmod
from btgen.lang import values
from btgen.lang.catalogue import ENTRY_PORTS
from btgen.lang.model import Attr, Mission, Node, SubTreeNode
from btgen.lang.versions import SINCE, semantics

EXIT_OK, EXIT_CHANGES, EXIT_USAGE = 0, 1, 2


def _nodes(mission: Mission) -> Iterator[Node]:
    for tree in mission.trees:
        stack = [tree.root]
        while stack:
            n = stack.pop()
            yield n
            stack.extend(reversed(n.children))


def _scripts(node: Node) -> Iterator[Attr]:
    for a in node.pre + node.post:
        yield a
    for a in node.ports:
        if a.script is not None:
            yield a


class _Findings:
    def __init__(self, old: str, new: str) -> None:
        self.old, self.new = semantics(old), semantics(new)
        self.items: list[Diagnostic] = []
        self.seen: set[tuple[Loc, str]] = set()
        # key -> the first node whose `entry` port (InputPort<BT::Any>) names it as `{key}`
        self.bt_any_keys: dict[str, Node] = {}

    def changed(self, switch: str) -> bool:
        return getattr(self.old, switch) != getattr(self.new, switch)

    def add(self, loc: Loc, message: str) -> None:
        if (loc, message) not in self.seen:
            self.seen.add((loc, message))
            self.items.append(Diagnostic(loc, message, "warning"))


def _canonical(script: scriptmod.Script) -> str:
    return "; ".join(scriptmod.format_expr(s) for s in script.statements)


def _literal_kinds(script: scriptmod.Script) -> list[tuple[str, type, object]]:
    """(text, type, value) of the literals; `-5` counts as one (a double in 4.9.0: negation)."""
    out: list[tuple[str, type, object]] = []
    for stmt in script.statements:
        negated: set[int] = set()
        for n in scriptmod.walk(stmt):
            if isinstance(n, scriptmod.Unary) and n.op == "-" and isinstance(n.operand, scriptmod.Literal):
                v = n.operand.value
                out.append(("-" + n.operand.text, float, -v if isinstance(v, (int, float)) else v))
                negated.add(id(n.operand))
            elif isinstance(n, scriptmod.Literal) and id(n) not in negated:
                out.append((n.text, type(n.value), n.value))
    return out


def static_findings(path: str, opts: pipeline.CompileOptions, old: str, new: str) -> list[Diagnostic]:
    """What changes between `old` and `new` for the mission at `path` (loaded as `old`)."""
    f = _Findings(old, new)
    mission = pipeline.load(path, pipeline.CompileOptions(**{**opts.__dict__, "btcpp": old}))
    upgrading = semantics(new).version != "4.6.2"

    # Loading: what the new release refuses (its own loader says where and why).
    from btgen.interp.engine import Interpreter

    known: set[tuple[Loc, str]] = set()
    try:
        Interpreter(mission)  # what already fails to create on the old version is no change
    except UserError as e:
        known = {(d.loc, d.message) for d in e.diagnostics}
    try:
        later = pipeline.load(path, pipeline.CompileOptions(**{**opts.__dict__, "btcpp": new}))
        # creating the tree (the library's createTree) checks port types across entries
        Interpreter(later)
    except UserError as e:
        for d in e.diagnostics:
            if (d.loc, d.message) in known:
                continue
            if d.severity == "error":
                msg = d.message
                if "(refused from BehaviorTree.CPP" not in msg:
                    msg = f"BehaviorTree.CPP {new} refuses to load this: {msg}"
                else:
                    head, _, since = msg.rpartition(" (refused from BehaviorTree.CPP ")
                    msg = f"refused from BehaviorTree.CPP {since.rstrip(')')}: {head}"
                f.add(d.loc, msg)

    for node in _nodes(mission):
        entry_attr = node.port("entry")
        key = bbmod.strip_blackboard_pointer(entry_attr.value) if entry_attr is not None else None
        if (node.id, "entry") in ENTRY_PORTS and key is not None:
            f.bt_any_keys.setdefault(key, node)
    new_grammar = semantics(new).script_grammar_49
    old_grammar = semantics(old).script_grammar_49
    for node in _nodes(mission):
        # Scripts: the same text read by the other parser
        if f.changed("script_grammar_49"):
            for attr in _scripts(node):
                try:
                    a = scriptmod.parse_script(attr.value, old_grammar)
                    b = scriptmod.parse_script(attr.value, new_grammar)
                except scriptmod.ScriptSyntaxError:
                    continue  # refused by one of them: reported with the loading changes
                since = SINCE["script_grammar_49"]
                if _canonical(a) != _canonical(b):
                    if upgrading:
                        text = f"{since} parses `{attr.value}` in `{attr.name}` of `{node.id}` as `{_canonical(b)}`"
                        text += f" (before: `{_canonical(a)}`)"
                    else:
                        text = f"{new} parses `{attr.value}` in `{attr.name}` of `{node.id}` as `{_canonical(b)}`"
                        text += f" ({since} and later: `{_canonical(a)}`)"
                    f.add(attr.value_loc, text)
                for (text, ta, va), (_, tb, vb) in zip(_literal_kinds(a), _literal_kinds(b)):
                    if ta is not tb and isinstance(va, (int, float)) and isinstance(vb, (int, float)):
                        double = values.format_double(float(vb if upgrading else va))
                        f.add(
                            attr.value_loc,
                            f"from {since} `{text}` in `{attr.name}` of `{node.id}` is the double {double}, not an "
                            f"integer (`..` writes it as `{double}`)",
                        )
                        break
        _node_findings(f, mission, node)
    return sorted(f.items, key=lambda d: (d.loc.path, d.loc.line, d.loc.col, d.message))


def _node_findings(f: _Findings, mission: Mission, node: Node) -> None:
    nid = node.id
    if f.changed("skipped_by_count") and nid in (
        "Sequence",
        "SequenceWithMemory",
        "Fallback",
        "AsyncSequence",
        "AsyncFallback",
    ):
        for child in node.children:
            if child.pre_condition("_while") is not None:
                f.add(
                    child.loc,
                    f"{SINCE['skipped_by_count']} decides SKIPPED by counting the children skipped in this run: "
                    f"when `_while` skips this child after it was RUNNING, the parent `{nid}` returns "
                    f"SKIPPED where 4.6.2 returns {'SUCCESS' if 'Sequence' in nid else 'FAILURE'}",
                )
    if nid in ("Repeat", "RetryUntilSuccessful"):
        port = "num_cycles" if nid == "Repeat" else "num_attempts"
        a = node.port(port)
        if f.changed("loop_end_never_skipped") and a is not None and not bbmod.is_blackboard_pointer(a.value):
            try:
                count = int(a.value)
            except ValueError:
                count = None
            if count is not None and (count == 0 or count < -1):
                f.add(
                    a.value_loc,
                    f'`{nid}` with {port}="{a.value}" never runs its child: 4.6.2 returns SKIPPED, '
                    f"{SINCE['loop_end_never_skipped']} returns {'SUCCESS' if nid == 'Repeat' else 'FAILURE'}",
                )
        if (
            nid == "RetryUntilSuccessful"
            and f.changed("retry_rereads_attempts")
            and a is not None
            and bbmod.is_blackboard_pointer(a.value)
        ):
            f.add(
                a.value_loc,
                f"{SINCE['retry_rereads_attempts']} reads num_attempts `{a.value}` again after every failure "
                f"of the child (4.6.2: once per tick)",
            )
    if nid == "Precondition" and f.changed("precondition_if_until_started") and node.port("if") is not None:
        f.add(
            node.loc,
            f"{SINCE['precondition_if_until_started']} evaluates `if` of Precondition only until its child "
            f"has started, then ticks the child to completion (4.6.2: every tick, returning `else` "
            f"without halting a RUNNING child)",
        )
    if nid == "SetBlackboard" and f.changed("setblackboard_converts_to_entry_type"):
        a = node.port("value")
        out = node.port("output_key")
        watcher = f.bt_any_keys.get(out.value) if out is not None else None
        if a is not None and out is not None and watcher is not None:
            f.add(
                a.value_loc,
                f"{SINCE['setblackboard_converts_to_entry_type']} SetBlackboard converts a string with the "
                f"destination's converter: `{out.value}` is also the `entry` of `{watcher.id}` "
                f'"{watcher.display_name}" ({watcher.loc}), which creates it typed BT::Any when it loads first, '
                f"and convertFromString<BT::Any> throws (4.6.2: the entry becomes a string, or a copy is stored)",
            )
        if a is not None:
            if bbmod.is_blackboard_pointer(a.value):
                what = "copying an entry that has no value yet returns FAILURE"
            else:
                what = (
                    "a literal written into an entry created without a type (by a Script or an untyped "
                    "port) leaves it empty (typed BT::Any), and the next string written there throws"
                )
            f.add(a.value_loc, f"{SINCE['setblackboard_converts_to_entry_type']} SetBlackboard: {what}")
    if nid.startswith("Loop") and f.changed("loop_queue_untyped"):
        a = node.port("queue")
        if a is not None and bbmod.is_blackboard_pointer(a.value):
            f.add(
                a.value_loc,
                f"{SINCE['loop_queue_untyped']} `queue` of `{nid}` is an untyped port: the entry is created "
                f"untyped, a string in it is converted into a new queue each time the loop starts (not "
                f"consumed for good)",
            )
    if nid.startswith("Switch") and f.changed("switch_whole_parse"):
        from btgen.interp.controls import _to_int_prefix, _to_real_prefix

        for a in node.ports:
            if bbmod.is_blackboard_pointer(a.value):
                continue
            prefix = _to_int_prefix(a.value) is not None or _to_real_prefix(a.value) is not None
            whole = _to_int_prefix(a.value, True) is not None or _to_real_prefix(a.value, True) is not None
            if prefix and not whole:
                f.add(
                    a.value_loc,
                    f'{SINCE["switch_whole_parse"]} matches `{a.name}="{a.value}"` as a number only when the '
                    f"whole text is one (4.6.2 reads the number at its start)",
                )
    if isinstance(node, SubTreeNode) and f.changed("subtree_literals_typed"):
        for a in node.ports:
            if bbmod.is_blackboard_pointer(a.value) or a.value == "{=}":
                continue
            typed = bbmod.typed_literal(a.value)
            if typed is not None:
                kind = "an int" if isinstance(typed, int) else "a double"
                f.add(
                    a.value_loc,
                    f'{SINCE["subtree_literals_typed"]} stores the SubTree literal {a.name}="{a.value}" as '
                    f"{kind}, not a string: scripts may do arithmetic on it, and a string or double port "
                    f"connected to `{{{a.name}}}` inside `{node.target}` is a load error",
                )


def first_difference(path: str, scenario_path: str, opts: pipeline.CompileOptions, old: str, new: str):
    """(tick, line of old, line of new) where the traces part, or None; each run on the
    interpreter, stopping at a load or run-time error (its message is the last line).
    UserError when neither version runs at all (a missing or bad scenario, a mission neither
    loads): two failures are not a comparison."""
    from btgen.interp.engine import run_trace
    from btgen.interp.scenario import check_scenario, parse_scenario

    scenario = parse_scenario(scenario_path)  # the same file for both: its errors are the file's
    failed: dict[str, UserError] = {}

    def trace(version: str) -> list[str]:
        parts: list[str] = []
        try:
            mission = pipeline.load(path, pipeline.CompileOptions(**{**opts.__dict__, "btcpp": version}))
            check_scenario(scenario, mission)
            run_trace(mission, scenario, parts.append)
        except UserError as e:
            if not parts:
                failed[version] = e
            parts.append(f"error: {e.diagnostics[0].message}\n" if e.diagnostics else "error\n")
        return "".join(parts).splitlines()

    a, b = trace(old), trace(new)
    if old in failed and new in failed:
        diags = list(failed[old].diagnostics)
        diags += [d for d in failed[new].diagnostics if d not in diags]
        raise UserError(diags)
    tick = 0
    for i in range(max(len(a), len(b))):
        la = a[i] if i < len(a) else "(end of trace)"
        lb = b[i] if i < len(b) else "(end of trace)"
        if la.startswith("tick "):
            tick = int(la.split()[1])
        if la != lb:
            return tick, la, lb
    return None


def upgrade_command(args) -> int:
    old, new = args.from_version, args.to_version
    opts = pipeline.options_from_args(args)
    try:
        findings = static_findings(args.mission, opts, old, new)
    except UserError as e:
        print_diagnostics(e.diagnostics)
        return EXIT_CHANGES
    print_diagnostics(findings)
    changed = bool(findings)
    if args.scenario:
        diff = first_difference(args.mission, args.scenario, opts, old, new)
        if diff is None:
            print(f"{args.scenario}: the traces of {old} and {new} are the same")
        else:
            tick, la, lb = diff
            changed = True
            print(f"{args.scenario}: the traces part at tick {tick}:")
            print(f"  {old}: {la}")
            print(f"  {new}: {lb}")
    if not changed:
        print(f"{args.mission}: nothing changes from BehaviorTree.CPP {old} to {new}")
    sys.stdout.flush()
    return EXIT_CHANGES if changed else EXIT_OK


__all__ = ["upgrade_command", "static_findings", "first_difference"]
