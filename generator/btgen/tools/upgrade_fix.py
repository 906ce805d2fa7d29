"""`btgen upgrade-check MISSION.xml --fix -o OUT`: the mission rewritten for the new release,
and the proof (`btgen diff`'s product search) that OUT under the new release behaves as
MISSION under the old one.

The rewrite edits the mission file's text in place (the rest of the file, its comments,
quotes and layout, is kept byte for byte):

- a script the new release parses differently (4.9.0: `&&` above `||`, double-quoted
  strings refused, chained ternaries) is written as the OLD release parsed it, every operator
  group in parentheses (`a || b && c` -> `(a || b) && c`), double quotes made single; the
  rewrite is kept only when both releases parse it to that same expression;
- an ID that 4.8.4's name rules refuse (a tree ID, a SubTree's ID, `main_tree_to_execute`, a
  user node's element name or `ID`, its TreeNodesModel entry) is renamed as upgrade-check
  proposes (`version_rules.allowed_name`, made unique); a leaf renamed so is a `--rename` of
  the proof (its scenario name changes with it);
- a direct child of ReactiveSequence written `<Action ID="X" .../>` (refused from 4.7.0) is
  written `<X .../>`;
- a port left to its default where the two releases' defaults differ gets the old default
  written out (the built-in catalogues of 4.6.2 and 4.10.0 hold no such port today: the step
  compares them and writes nothing).

Only the mission file itself is rewritten: a finding in an included file is listed as not
fixed. Then OUT is loaded under the new release and compared with MISSION under the old one
by `tools/diff/product.Differ`: "proved equivalent (exhaustively)", "equivalent up to K
ticks" (bounded: said so), "partial" (the state budget ran out: no proof), or "different"
with the shortest scenario. OUT is written whole (fileio.write_output) before the proof, and
never over the input.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass, field
from typing import Optional
from xml.sax.saxutils import escape

from btgen import pipeline
from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.fileio import check_output, write_output
from btgen.frontend import version_rules
from btgen.lang import script as scriptmod
from btgen.lang.catalogue import KINDS
from btgen.lang.model import Mission, Node
from btgen.lang.script.nodes import Binary, Compare, Literal, Name, Ternary, Unary
from btgen.lang.versions import semantics
from btgen.tools.upgrade import static_findings

# ====================================================================== the file's tags
_NAME = r"[^\s=/>]+"
_NAME_RE = re.compile(_NAME)
_ATTR = re.compile(r"\s*(" + _NAME + r")\s*=\s*(\"[^\"]*\"|'[^']*')")


@dataclass
class _Tag:
    name: str
    name_at: int  # offset of the element name (after `<`)
    attrs: dict[str, tuple[int, int]]  # name -> (start, end) of the value between its quotes
    attr_spans: dict[str, tuple[int, int]]  # name -> (start, end) of ` name="value"` (leading blank)
    closing: Optional[int] = None  # offset of the end tag's name, when not self-closing
    children: list[_Tag] = field(default_factory=list)
    parent: Optional[_Tag] = None
    line: int = 0


def _scan(text: str) -> list[_Tag]:
    """Every element of the file in document order (comments, CDATA, PIs skipped)."""
    out: list[_Tag] = []
    stack: list[_Tag] = []
    i = 0
    n = len(text)
    while True:
        i = text.find("<", i)
        if i < 0 or i + 1 >= n:
            return out
        if text.startswith("<!--", i):
            i = text.find("-->", i) + 3 if text.find("-->", i) >= 0 else n
            continue
        if text.startswith("<![CDATA[", i):
            j = text.find("]]>", i)
            i = j + 3 if j >= 0 else n
            continue
        if text[i + 1] in "?!":
            j = text.find(">", i)
            i = j + 1 if j >= 0 else n
            continue
        if text[i + 1] == "/":
            m = _NAME_RE.match(text, i + 2)
            if m and stack:
                stack.pop().closing = m.start()
            i = text.find(">", i) + 1 or n
            continue
        m = _NAME_RE.match(text, i + 1)
        if not m:
            i += 1
            continue
        tag = _Tag(m.group(0), m.start(), {}, {}, line=text.count("\n", 0, i) + 1)
        j = m.end()
        while True:
            a = _ATTR.match(text, j)
            if not a:
                break
            tag.attrs[a.group(1)] = (a.start(2) + 1, a.end(2) - 1)
            tag.attr_spans[a.group(1)] = (a.start(), a.end())
            j = a.end()
        k = text.find(">", j)
        self_closing = k > 0 and text[k - 1] == "/"
        if stack:
            tag.parent = stack[-1]
            stack[-1].children.append(tag)
        out.append(tag)
        if not self_closing:
            stack.append(tag)
        i = k + 1 if k >= 0 else n


def _value(text: str, tag: _Tag, name: str) -> Optional[str]:
    from html import unescape

    span = tag.attrs.get(name)
    return unescape(text[span[0] : span[1]]) if span else None


# ====================================================================== scripts
def _fmt(node, top: bool = False) -> str:
    """format_expr with the outermost parentheses of a statement left out and double-quoted
    strings written with single quotes (4.9.0 takes single quotes only)."""
    if isinstance(node, Literal):
        if isinstance(node.value, str) and node.text.startswith('"') and "'" not in node.value:
            return "'" + node.value + "'"
        return node.text
    if isinstance(node, Name):
        return node.name
    if isinstance(node, Unary):
        return f"{node.op}{_fmt(node.operand)}"
    if isinstance(node, Binary):
        s = f"{_fmt(node.left)} {node.op} {_fmt(node.right)}"
    elif isinstance(node, Compare):
        parts = [_fmt(node.operands[0])]
        for op, o in zip(node.ops, node.operands[1:]):
            parts += [op, _fmt(o)]
        s = " ".join(parts)
    elif isinstance(node, Ternary):
        s = f"{_fmt(node.cond)} ? {_fmt(node.then)} : {_fmt(node.orelse)}"
    else:  # an assignment
        return f"{node.target} {node.op} {_fmt(node.value, True)}"
    return s if top else f"({s})"


def _canonical(script: scriptmod.Script) -> str:
    """Every operator group in parentheses, strings in single quotes: two scripts with the
    same canonical text are the same expressions."""
    return "; ".join(_fmt(s) for s in script.statements)


def fixed_script(text: str, old: str, new: str) -> Optional[str]:
    """The script rewritten so that `new` parses it as `old` parses `text`; None when nothing
    needs to change, or when no rewrite is found (ValueError with the reason)."""
    g_old, g_new = semantics(old).script_grammar_49, semantics(new).script_grammar_49
    before = scriptmod.parse_script(text, g_old)  # loads under old: the caller checked
    try:
        if _canonical(scriptmod.parse_script(text, g_new)) == _canonical(before):
            return None
    except scriptmod.ScriptSyntaxError:
        pass
    written = "; ".join(_fmt(s, True) for s in before.statements)
    try:
        same = all(_canonical(scriptmod.parse_script(written, g)) == _canonical(before) for g in (g_old, g_new))
    except scriptmod.ScriptSyntaxError as e:
        raise ValueError(f"`{written}` does not parse under both releases: {e}") from None
    if not same:
        raise ValueError(f"no writing of `{text}` parses the same under both releases")
    return written


# ====================================================================== the rewrite
@dataclass
class Rewrite:
    text: str  # the rewritten file
    changes: list[Diagnostic]  # what was changed, where (notes at the input's places)
    left: list[Diagnostic]  # findings not fixed, and why
    rename: dict[str, str]  # leaf scenario names: old -> new (for the proof)


def _nodes(root: Node):
    stack = [root]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(n.children))


def _unique(name: str, taken: set[str]) -> str:
    fixed = version_rules.allowed_name(name)
    k = 2
    out = fixed
    while out in taken:
        out = f"{fixed}_{k}"
        k += 1
    taken.add(out)
    return out


def rewrite(path: str, mission: Mission, old: str, new: str) -> Rewrite:
    with open(path, encoding="utf-8", newline="") as f:
        text = f.read()
    tags = _scan(text)
    edits: list[tuple[int, int, str]] = []
    changes: list[Diagnostic] = []
    left: list[Diagnostic] = []
    rename: dict[str, str] = {}
    line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
    here = mission.files[0] if mission.files else path
    sem_new = semantics(new)
    node_map: dict[str, str] = {}  # user node IDs renamed

    def offset(loc: Loc) -> int:
        return line_starts[loc.line - 1] + loc.col - 1

    def note(line: int, message: str) -> None:
        changes.append(Diagnostic(Loc(path, line, 1), message, "note"))

    def set_value(tag: _Tag, attr: str, value: str) -> None:
        a, b = tag.attrs[attr]
        quote = text[a - 1]  # the attribute's own quotes: the one to escape inside
        edits.append((a, b, escape(value, {'"': "&quot;"} if quote == '"' else {"'": "&apos;"})))

    # ---- scripts (by the loaded mission's attribute places)
    if semantics(old).script_grammar_49 != sem_new.script_grammar_49:
        by_start = {span[0]: (tag, name) for tag in tags for name, span in tag.attrs.items()}
        for tree in mission.trees:
            for node in _nodes(tree.root):
                for attr in node.pre + node.post + node.ports:
                    if attr.script is None and attr not in node.pre + node.post:
                        continue
                    try:
                        written = fixed_script(attr.value, old, new)
                    except ValueError as e:
                        left.append(Diagnostic(attr.value_loc, f"not rewritten: {e}", "warning"))
                        continue
                    except scriptmod.ScriptSyntaxError:
                        continue
                    if written is None:
                        continue
                    where = by_start.get(offset(attr.value_loc)) if attr.value_loc.path == here else None
                    if where is None:
                        left.append(
                            Diagnostic(attr.value_loc, f"not rewritten (not in {path}): `{attr.value}`", "warning")
                        )
                        continue
                    set_value(where[0], where[1], written)
                    note(attr.value_loc.line, f"`{attr.value}` in `{attr.name}` of `{node.id}` written `{written}`")

    # ---- IDs 4.8.4 refuses
    if sem_new.name_validation_484 and not semantics(old).name_validation_484:
        builtins = mission.builtins
        tree_ids = {t.id for t in mission.trees}
        node_ids = {n.id for t in mission.trees for n in _nodes(t.root)} | {s.id for s in mission.models}
        taken = set(tree_ids) | node_ids | set(builtins)
        tree_map: dict[str, str] = {}
        for tid in sorted(tree_ids):
            if version_rules.forbidden_char(tid) or tid in ("Root", "root"):
                tree_map[tid] = _unique(tid, taken)
        for nid in sorted(node_ids):
            if nid in builtins or nid in KINDS or nid in tree_ids:
                continue
            if version_rules.forbidden_char(nid) or nid in ("Root", "root"):
                node_map[nid] = _unique(nid, taken)
        renamed_nodes: set[str] = set()
        for tag in tags:
            anc = tag.parent
            in_tree = in_models = False
            while anc is not None:
                in_tree = in_tree or anc.name == "BehaviorTree"
                in_models = in_models or anc.name == "TreeNodesModel"
                anc = anc.parent
            tid = _value(text, tag, "ID") or ""
            if tag.name == "root":
                main = _value(text, tag, "main_tree_to_execute")
                if main in tree_map:
                    set_value(tag, "main_tree_to_execute", tree_map[main])
                    note(tag.line, f"main_tree_to_execute `{main}` renamed `{tree_map[main]}`")
            elif tag.name == "BehaviorTree" and tid in tree_map:
                set_value(tag, "ID", tree_map[tid])
                note(tag.line, f"BehaviorTree ID `{tid}` renamed `{tree_map[tid]}`")
            elif tag.name == "SubTree" and in_tree and tid in tree_map:
                set_value(tag, "ID", tree_map[tid])
                note(tag.line, f"SubTree ID `{tid}` renamed `{tree_map[tid]}`")
            elif in_models and tid in node_map:
                set_value(tag, "ID", node_map[tid])
                note(tag.line, f"TreeNodesModel ID `{tid}` renamed `{node_map[tid]}`")
            elif in_tree and tag.name in KINDS and tid in node_map:
                set_value(tag, "ID", node_map[tid])
                renamed_nodes.add(tid)
                note(tag.line, f"node ID `{tid}` renamed `{node_map[tid]}`")
            elif in_tree and tag.name in node_map:
                new_name = node_map[tag.name]
                edits.append((tag.name_at, tag.name_at + len(tag.name), new_name))
                if tag.closing is not None:
                    edits.append((tag.closing, tag.closing + len(tag.name), new_name))
                renamed_nodes.add(tag.name)
                note(tag.line, f"node `{tag.name}` renamed `{new_name}`")
        for t in mission.trees:
            for n in _nodes(t.root):
                if n.id in renamed_nodes and n.name is None and n.kind in ("Action", "Condition"):
                    rename[n.id] = node_map[n.id]
        for tid in tree_map:
            t = mission.tree(tid)
            if t.loc.path != here:
                left.append(Diagnostic(t.loc, f"not renamed (not in {path}): BehaviorTree `{tid}`", "warning"))

    # ---- ReactiveSequence children in the explicit form (refused from 4.7.0)
    if sem_new.reactive_sequence_child_checks and not semantics(old).reactive_sequence_child_checks:
        for tag in tags:
            if (
                tag.parent is not None
                and tag.parent.name == "ReactiveSequence"
                and tag.name in KINDS
                and tag.name != "SubTree"
                and "ID" in tag.attrs
            ):
                nid = _value(text, tag, "ID") or ""
                nid = node_map.get(nid, nid)
                edits.append((tag.name_at, tag.name_at + len(tag.name), nid))
                if tag.closing is not None:
                    edits.append((tag.closing, tag.closing + len(tag.name), nid))
                a, b = tag.attr_spans["ID"]
                edits.append((a, b, ""))
                note(tag.line, f'<{tag.name} ID="{nid}"> under ReactiveSequence written <{nid}>')

    # ---- two SubTrees of one tree with the same name (their paths clash from 4.8.4)
    if sem_new.unique_subtree_paths and not semantics(old).unique_subtree_paths:
        for tree_tag in (t for t in tags if t.name == "BehaviorTree"):
            subs: list[_Tag] = []
            stack = list(tree_tag.children)
            while stack:
                tg = stack.pop(0)
                if tg.name == "SubTree":
                    subs.append(tg)
                stack[:0] = tg.children
            names = {v for v in (_value(text, tg, "name") for tg in subs) if v is not None}
            seen: set[str] = set()
            for tg in subs:
                name = _value(text, tg, "name")
                if name is None:
                    continue
                if name in seen:
                    k = 2
                    while f"{name}_{k}" in names:
                        k += 1
                    names.add(f"{name}_{k}")
                    set_value(tg, "name", f"{name}_{k}")
                    note(tg.line, f"the second SubTree named `{name}` renamed `{name}_{k}` (unique SubTree paths)")
                seen.add(name)

    # ---- defaults that changed
    old_b = pipeline_builtins(old, mission)
    new_b = pipeline_builtins(new, mission)
    by_line: dict[int, list[_Tag]] = {}
    for tag in tags:
        by_line.setdefault(tag.line, []).append(tag)
    for t in mission.trees:
        for n in _nodes(t.root):
            a_spec, b_spec = old_b.get(n.id), new_b.get(n.id)
            if a_spec is None or b_spec is None:
                continue
            b_ports = {p.name: p for p in b_spec.ports}
            for p in a_spec.ports:
                q = b_ports.get(p.name)
                if q is None or q.default == p.default or p.default is None or n.port(p.name) is not None:
                    continue
                cands = [tg for tg in by_line.get(n.loc.line, []) if tg.name in (n.tag, n.id)]
                if n.loc.path != here or len(cands) != 1:
                    left.append(Diagnostic(n.loc, f"not rewritten: `{p.name}` of `{n.id}` left to its default"))
                    continue
                tg = cands[0]
                at = tg.name_at + len(tg.name)
                edits.append((at, at, f' {p.name}="{escape(p.default, {chr(34): "&quot;"})}"'))
                was = f'the default of {old}; {new}: "{q.default}"'
                note(tg.line, f'`{p.name}` of `{n.id}` written out: "{p.default}" ({was})')

    out = text
    for a, b, s in sorted(edits, key=lambda e: (e[0], e[1]), reverse=True):
        out = out[:a] + s + out[b:]
    changes.sort(key=lambda d: d.loc.line)
    return Rewrite(out, changes, left, rename)


def pipeline_builtins(version: str, mission: Mission):
    from btgen.lang.model import builtins_for

    return builtins_for(version, mission.nav2)


# ====================================================================== the command
def fix_command(args) -> int:
    from btgen import cmdline
    from btgen.interp.engine import Interpreter
    from btgen.tools.diff.product import Differ

    if not args.fix:
        raise cmdline.error(args, "-o", "-o is the output of --fix: add --fix")
    if not args.output:
        raise cmdline.error(args, "--fix", "--fix writes a new file: name it with -o OUT.xml")
    if args.scenario:
        raise cmdline.error(args, "--scenario", "--fix proves the rewrite for every scenario: drop --scenario")
    old, new = args.from_version, args.to_version
    opts = pipeline.options_from_args(args)
    out_path = args.output
    mission_old = pipeline.load(args.mission, pipeline.CompileOptions(**{**opts.__dict__, "btcpp": old}))
    inputs = (*mission_old.files, *(opts.models or ()))
    check_output(out_path, inputs)
    findings = static_findings(args.mission, opts, old, new)
    print_diagnostics(findings)
    rw = rewrite(args.mission, mission_old, old, new)
    write_output(out_path, rw.text.encode("utf-8"), inputs)
    for d in rw.changes:
        print(f"{d.loc}: fixed: {d.message}")
    if not rw.changes:
        print(f"{args.mission}: nothing to rewrite; {out_path} is a copy")
    print_diagnostics(rw.left)
    try:
        mission_new = pipeline.load(out_path, pipeline.CompileOptions(**{**opts.__dict__, "btcpp": new}))
        Interpreter(mission_new)  # creating the tree checks port types across entries (createTree)
    except UserError as e:
        print_diagnostics(e.diagnostics)
        print(f"{out_path}: not proved: BehaviorTree.CPP {new} does not load it (see above)")
        return 1
    rename = {a: b for a, b in rw.rename.items()}
    differ = Differ(mission_old, mission_new, rename, args.max_ticks, 100, args.max_states)
    outcome = differ.decide()
    what = f"{out_path} under BehaviorTree.CPP {new} vs {args.mission} under {old}"
    stats = f"{outcome.runs} runs, {outcome.states} product states, {outcome.seconds:.2f} s"
    if outcome.equivalent and outcome.exhaustive:
        print(f"{what}: proved equivalent (exhaustively; {stats})")
        return 0
    if outcome.equivalent and outcome.why_bounded == "ticks":
        print(f"{what}: equivalent up to {outcome.bound} ticks (bounded, not a proof for longer runs; {stats})")
        return 0
    if outcome.equivalent:
        print(
            f"{what}: not proved: the search stopped at --max-states {args.max_states} with no difference found "
            f"(a partial search; {stats})"
        )
        return 1
    from btgen.tools.explore import NAMES

    picks = "; ".join(f"leaf {k} {' '.join(NAMES[s] for s in v)}" for k, v in outcome.plan.items())
    ticks = f"{outcome.ticks} tick{'s' if outcome.ticks != 1 else ''}"
    print(
        f"{what}: different: the rewrite does not behave as the original (first difference within {ticks}; "
        f"scenario: {picks or 'no leaf calls'}); compare them with "
        f"`btgen diff {args.mission} {out_path} --btcpp-old {old} --btcpp-new {new}`"
    )
    sys.stdout.flush()
    return 1
