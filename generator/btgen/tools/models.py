"""`btgen models PATH...`: a <TreeNodesModel> inferred from how the nodes are used.

Given one mission, the nodes it (its includes, `--trees`, `--models`) uses; given folders (or
several files), the nodes every BehaviorTree.CPP file found under them uses, merged into one file
that the project commits beside its trees, where `btgen check` finds it (a kind told apart in two
places is reported at the second with the first's position).

A program registers its leaves, controls and decorators in C++; its XML often declares none
of them. This reads the mission, its includes, the tree libraries (`--trees`) and the models
already declared (`--models`, TreeNodesModel of those files) the way the front end does
(secure XML, positions), but without refusing unknown nodes, and writes one model per node
ID that is neither built in nor declared:

- its kind from the element and its children: `<Action ID=..>`, `<Condition ID=..>`,
  `<Control ID=..>`, `<Decorator ID=..>` say it; a node written by its ID is an Action
  without children, a Decorator with one, a Control with more (a Condition cannot be told
  from an Action by its use: the file says so in a comment, for the team to review);
- its ports from its attributes (those 4.6.2 reads as ports: starting with a letter, not
  `name`), untyped; a port given a literal somewhere is an `input_port`, one only ever
  given `{key}` an `inout_port` (it may be read or written).

The output is deterministic (models and ports sorted by name). For exact port types the
program itself can write the file: `BT::writeTreeNodesModelXML(factory)` (docs/real-files.md).
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass, field
from typing import Optional
from xml.sax.saxutils import quoteattr

from lxml import etree

from btgen import pipeline
from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.fileio import write_output
from btgen.frontend.loader import _PORT_NAME_RE, MAX_INCLUDE_DEPTH
from btgen.frontend.version_rules import is_port_name
from btgen.frontend.xmlsource import Source, read_source
from btgen.lang.catalogue import KINDS, RESERVED_PORT_NAMES, builtins_for
from btgen.lang.versions import semantics

_ELEMENT_KINDS = ("Action", "Condition", "Control", "Decorator")


@dataclass
class _Use:
    kinds: set[str] = field(default_factory=set)  # kinds the elements say (explicit form)
    children: set[int] = field(default_factory=set)  # child counts of the implicit form
    literal: set[str] = field(default_factory=set)  # ports given a literal somewhere
    keys: dict[str, set[str]] = field(default_factory=dict)  # the entries each port is given as {key}
    ports: set[str] = field(default_factory=set)
    first: Loc = field(default_factory=lambda: Loc("", 1, 1))
    kind_at: dict[str, Loc] = field(default_factory=dict)  # the first use of each kind the elements say
    children_at: dict[int, Loc] = field(default_factory=dict)  # the first use of each child count


class _Reader:
    def __init__(self, btcpp: str = "4.6.2") -> None:
        self.builtins = builtins_for(btcpp)  # TryCatch is built in from 4.9.0 (--btcpp 4.10.0)
        self.sem = semantics(btcpp)
        self.warnings: list[Diagnostic] = []
        self.files: list[str] = []  # real paths read
        self.real: set[str] = set()
        self.shown: list[str] = []
        self.declared: set[str] = set()
        self.trees: set[str] = set()
        self.uses: dict[str, _Use] = {}
        self.queue_keys: dict[str, set[str]] = {}  # entry -> the queue types built-in Loops read it as
        self.sources: list[tuple[Source, list[etree._Element]]] = []

    def read(self, path: str, shown: str, depth: int = 1) -> None:
        """Read a file and its includes (`depth`: the files on the include chain so far,
        refused past the front end's MAX_INCLUDE_DEPTH with its words)."""
        real = os.path.realpath(path)
        if real in self.real:
            return
        self.real.add(real)
        self.files.append(real)
        self.shown.append(shown)
        src = read_source(path, shown)
        if src.root.tag != "root":
            raise UserError.at(
                src.loc(src.root), f'the root element is <{src.root.tag}>; expected <root BTCPP_format="4">'
            )
        trees: list[etree._Element] = []
        for child in src.root:
            if not isinstance(child.tag, str):
                continue
            if child.tag == "BehaviorTree":
                trees.append(child)
                if child.get("ID") is not None:
                    self.trees.add(child.get("ID") or "")
            elif child.tag == "TreeNodesModel":
                self.declared.update(m.get("ID") or "" for m in child if isinstance(m.tag, str))
            elif child.tag == "include" and child.get("path"):
                target = os.path.join(os.path.dirname(path), child.get("path") or "")
                if os.path.isfile(target):  # (a missing include is the front end's to report)
                    if depth >= MAX_INCLUDE_DEPTH:
                        raise UserError.at(src.loc(child), f"includes nested deeper than {MAX_INCLUDE_DEPTH} files")
                    self.read(
                        target,
                        os.path.normpath(os.path.join(os.path.dirname(shown), child.get("path") or "")),
                        depth + 1,
                    )
        self.sources.append((src, trees))

    def collect(self, declared_in: Optional[dict[str, set[str]]] = None) -> None:
        """Every node the trees use and nothing declares; `declared_in`: for a project, what is
        declared for each file (real path) the way `btgen check` loads it, which may be less than what
        some file of the project declares (another folder's TreeNodesModel does not count for it)."""
        for src, trees in self.sources:
            declared = None if declared_in is None else declared_in.get(os.path.realpath(src.path))
            for tree in trees:
                stack = [c for c in tree if isinstance(c.tag, str)]
                while stack:
                    elem = stack.pop()
                    kids = [c for c in elem if isinstance(c.tag, str)]
                    stack.extend(kids)
                    self._use(elem, len(kids), src, declared)

    def _use(self, elem: etree._Element, children: int, src: Source, declared: Optional[set[str]] = None) -> None:
        tag = src.tag(elem)
        if tag == "SubTree" or (tag in KINDS and elem.get("ID") is None):
            return
        node_id = elem.get("ID") if tag in _ELEMENT_KINDS else tag
        if node_id in _LOOP_QUEUES and node_id in self.builtins:
            key = _key_of(elem.get("queue") or "")
            if key:
                self.queue_keys.setdefault(key, set()).add(_LOOP_QUEUES[node_id])
        known = self.declared if declared is None else declared
        if not node_id or node_id in self.builtins or node_id in known or node_id in self.trees:
            return
        if node_id.startswith("{"):  # a namespaced element: the front end reports it
            return
        use = self.uses.get(node_id)
        if use is None:
            use = self.uses[node_id] = _Use(first=src.loc(elem))
        if tag in _ELEMENT_KINDS:
            use.kinds.add(tag)
            use.kind_at.setdefault(tag, src.loc(elem))
        else:
            use.children.add(children)
            use.children_at.setdefault(children, src.loc(elem))
        for name, value in elem.attrib.items():
            if name in ("name", "ID") or not is_port_name(name, self.sem):
                continue  # not a port for this release: the library ignores the attribute
            if not _PORT_NAME_RE.match(name) or name in RESERVED_PORT_NAMES:
                # read as a port by this release, but no model can declare it: say so, write none
                self.warnings.append(
                    Diagnostic(
                        src.attr_loc(elem, name),
                        f"attribute `{name}` of `{node_id}` is read as a port, but no <TreeNodesModel> can "
                        "declare a port of that name; it is left out",
                        "warning",
                    )
                )
                continue
            use.ports.add(name)
            if not (len(value) >= 2 and value.startswith("{") and value.endswith("}")):
                use.literal.add(name)
            elif _key_of(value):
                use.keys.setdefault(name, set()).add(_key_of(value))


# A built-in Loop reads its `queue` entry as a SharedQueue of its type: a port of a node the program
# registers that is only ever given that entry gets that type (with an untyped port, btgen would take
# the entry for text, which no Loop reads as a queue on 4.6.2).
_LOOP_QUEUES = {
    "LoopInt": "BT::SharedQueue<int>",
    "LoopDouble": "BT::SharedQueue<double>",
    "LoopBool": "BT::SharedQueue<bool>",
    "LoopString": "BT::SharedQueue<std::string>",
}


def _key_of(value: str) -> str:
    """The entry a `{key}` value names ("" for anything else: a literal, `{=}`, `{}`)."""
    if len(value) > 2 and value.startswith("{") and value.endswith("}") and value[1:-1].strip() not in ("", "="):
        return value[1:-1].strip().lstrip("@")
    return ""


def _kind(node_id: str, use: _Use, warnings: list[Diagnostic], project: bool = False) -> str:
    if project:  # over several files: the conflict is told at both of its places
        return _project_kind(node_id, use, warnings)
    if use.kinds:
        kind = sorted(use.kinds)[0]
        if len(use.kinds) > 1:
            warnings.append(
                Diagnostic(
                    use.first,
                    f"`{node_id}` is written as "
                    + " and ".join(f"<{k}>" for k in sorted(use.kinds))
                    + f"; <{kind}> is written",
                    "warning",
                )
            )
        return kind
    most = max(use.children)
    kind = "Action" if most == 0 else "Decorator" if most == 1 else "Control"
    if 0 in use.children and most > 0:
        warnings.append(
            Diagnostic(
                use.first,
                f"`{node_id}` is used with and without children; written as a {kind}",
                "warning",
            )
        )
    return kind


def _project_kind(node_id: str, use: _Use, warnings: list[Diagnostic]) -> str:
    if use.kinds:
        kinds = sorted(use.kinds, key=lambda k: (use.kind_at[k].path, use.kind_at[k].line, use.kind_at[k].col))
        kind = sorted(use.kinds)[0]
        if len(kinds) > 1:
            first, second = kinds[0], kinds[1]
            warnings.append(
                Diagnostic(
                    use.kind_at[second],
                    f"`{node_id}` is written <{second}> here and <{first}> at {use.kind_at[first]}; "
                    f"<{kind}> is written",
                    "warning",
                )
            )
        return kind
    most = max(use.children)
    kind = "Action" if most == 0 else "Decorator" if most == 1 else "Control"
    if 0 in use.children and most > 0:
        leaf, parent = use.children_at[0], use.children_at[most]
        warnings.append(
            Diagnostic(
                parent,
                f"`{node_id}` has {most} {'child' if most == 1 else 'children'} here and none at {leaf}; "
                f"written as a {kind}",
                "warning",
            )
        )
    return kind


def _text(reader: _Reader, about: str, project: bool) -> tuple[str, list[Diagnostic]]:
    warnings: list[Diagnostic] = list(reader.warnings)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>\n',
        f"<!-- Node models inferred by `btgen models` from how {about} uses them.\n",
        "     Review them: a <Condition> is written as <Action> (use cannot tell them apart), and\n",
        '     ports are untyped (give each its type="..."), but for one given only the entry a built-in\n',
        "     Loop reads as its queue. A port given a literal somewhere is an input_port; one only\n",
        "     ever given {key} is an inout_port. -->\n",
        '<root BTCPP_format="4">\n',
        "  <TreeNodesModel>\n",
    ]
    for node_id in sorted(reader.uses):
        use = reader.uses[node_id]
        kind = _kind(node_id, use, warnings, project)
        ports = sorted(use.ports)
        if not ports:
            lines.append(f"    <{kind} ID={quoteattr(node_id)}/>\n")
            continue
        lines.append(f"    <{kind} ID={quoteattr(node_id)}>\n")
        for port in ports:
            tag = "input_port" if port in use.literal else "inout_port"
            types = {t for k in use.keys.get(port, ()) for t in reader.queue_keys.get(k, ())}
            typed = f" type={quoteattr(types.pop())}" if tag == "inout_port" and len(types) == 1 else ""
            lines.append(f"      <{tag} name={quoteattr(port)}{typed}/>\n")
        lines.append(f"    </{kind}>\n")
    lines += ["  </TreeNodesModel>\n", "</root>\n"]
    return "".join(lines), warnings


def infer_project_models(
    paths: list[str], opts: pipeline.CompileOptions, output: Optional[str] = None
) -> tuple[str, list[Diagnostic], list[str]]:
    """One models file for every node the BehaviorTree.CPP files under `paths` (found by content, as
    `btgen check` finds them) use and none of them declares, merged across the files; a file that does
    not parse is passed over (`btgen check` reports it). `output`, the file to be written, is not read."""
    from btgen.tools.check import discovery

    reader = _Reader(opts.btcpp)
    skip = {os.path.realpath(output)} if output else set()
    for path in discovery.walk(paths) + list(opts.models) + list(opts.trees):
        if os.path.realpath(path) in skip or not os.path.isfile(path):
            continue
        try:
            reader.read(path, path)
        except UserError:
            continue
    reader.collect(_declared_per_file(paths, opts, skip))
    about = "the files under " + ", ".join(paths) if len(paths) > 1 else f"the files under {paths[0]}"
    text, warnings = _text(reader, about, True)
    return text, warnings, reader.shown


def _declared_per_file(paths: list[str], opts: pipeline.CompileOptions, skip: set[str]) -> dict[str, set[str]]:
    """For each file of trees, the node IDs declared where `btgen check` loads it: the TreeNodesModel
    of the models files and Groot2 projects it is loaded with, of its includes and tree libraries, and
    those given with --models (a file several loads read counts what all of them declare)."""
    from btgen.tools.check import discovery

    project = discovery.survey(paths, lambda p, is_dir: not is_dir and os.path.realpath(p) in skip)
    extra: set[str] = set()
    for m in opts.models:
        extra |= set(discovery.read(m).models)  # (a file it cannot read declares nothing)
    out: dict[str, set[str]] = {}
    for unit in discovery.plan(project):
        f = project.files[os.path.realpath(unit.path)]
        files = discovery._closure(project, f)
        for t in unit.trees:
            files += discovery._closure(project, project.files[os.path.realpath(t)])
        ids = set(extra)
        for g in files:
            ids |= g.models
        for m in unit.models:
            models_file = project.files.get(os.path.realpath(m))
            if models_file is not None:
                ids |= models_file.models
        for g in files:
            out[g.real] = out[g.real] & ids if g.real in out else set(ids)
    return out


def infer_models(mission_path: str, opts: pipeline.CompileOptions) -> tuple[str, list[Diagnostic], list[str]]:
    """The models file text, the warnings, and the files read (shown paths)."""
    reader = _Reader(opts.btcpp)
    reader.read(mission_path, mission_path)
    for trees in opts.trees:
        if os.path.isdir(trees):
            for f in sorted(os.listdir(trees)):
                full = os.path.join(trees, f)
                if f.endswith(".xml") and os.path.isfile(full):
                    reader.read(full, full)
        elif os.path.isfile(trees):
            reader.read(trees, trees)
        else:
            raise UserError.at(Loc(trees, 1, 1), "--trees: no such file or folder")
    for models in opts.models:
        reader.read(models, models)
    reader.collect()
    text, warnings = _text(reader, os.path.basename(mission_path), False)
    return text, warnings, reader.shown


def models_command(args: argparse.Namespace) -> int:
    opts = pipeline.options_from_args(args)
    pipeline.check_options(opts)  # as validate checks them
    paths = list(args.paths)
    for p in paths:
        if not os.path.exists(p):
            from btgen.cmdline import error

            raise error(args, p, f"no such file or folder `{p}`")
    if len(paths) == 1 and os.path.isfile(paths[0]):
        text, warnings, files = infer_models(paths[0], opts)
    else:
        text, warnings, files = infer_project_models(paths, opts, args.output)
    print_diagnostics(warnings)
    if args.output is None:
        sys.stdout.write(text)
        return 0
    write_output(
        args.output,
        text.encode("utf-8"),
        files,
        message=f"`btgen models -o {args.output}` would overwrite this input file: choose another output file",
    )
    return 0
