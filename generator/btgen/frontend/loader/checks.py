"""Mission checks: the trees and their nodes (IDs, ports, literals, scripts, children) and the
whole-mission checks (SubTree cycles, the 16-bit node count, later releases' rules, the
mission XSD)."""

from __future__ import annotations

import dataclasses
import re
from typing import Optional

from lxml import etree

from btgen.diagnostics import Loc, did_you_mean, suggestion
from btgen.frontend import version_rules
from btgen.frontend.hints import model_advice
from btgen.frontend.loader.base import (
    _KEY_RE,
    _SUBTREE_REMAP_RE,
    MAX_NODES,
    LoaderBase,
    is_remap,
    remap_key,
)
from btgen.frontend.xmlsource import Source
from btgen.lang import script as script_lang
from btgen.lang import values
from btgen.lang.catalogue import (
    EDITOR_ATTRIBUTES,
    ENTRY_PORTS,
    KEY_NAME_PORTS,
    KINDS,
    METADATA_ATTRIBUTES,
    POST_CONDITIONS,
    PRE_CONDITIONS,
    SCRIPT_PORTS,
    SPECIAL_ATTRIBUTES,
    STATUS_READ_WHEN_TICKED,
    NodeSpec,
)
from btgen.lang.model import Attr, Mission, Node, SubTreeNode, TreeDef

# The script ports an empty text loads in (and throws when ticked); _with_script.
_EMPTY_LOADS = frozenset({("ScriptCondition", "code"), ("Precondition", "if")})


class MissionChecks(LoaderBase):
    # ---------------------------------------------------------------- trees
    def _check_tree_ids(self) -> set[str]:
        seen: dict[str, Loc] = {}
        ok: set[str] = set()
        for tid, elem, src in self.tree_elems:
            loc = src.value_loc(elem, "ID")
            if tid in seen:
                self.sink.error(loc, f"BehaviorTree `{tid}` is defined twice (first at {seen[tid]})")
                continue
            if tid.strip() != tid or not tid:
                self.sink.error(loc, f"BehaviorTree ID `{tid}` must not be empty or start or end with spaces")
            elif tid in self._registered_ids():
                self.sink.error(loc, self._registered_clash("BehaviorTree", tid))
            seen[tid] = src.loc(elem)
            ok.add(tid)
        # The first definition wins; a duplicate is dropped (and reported).
        self.tree_elems = [
            (t, e, s) for i, (t, e, s) in enumerate(self.tree_elems) if t not in [x[0] for x in self.tree_elems[:i]]
        ]
        return ok

    def _registered_ids(self) -> set[str]:
        """The IDs BehaviorTree.CPP has registered when it reads the trees: its built-ins and
        the nodes the models declare (registered in C++); a SubTree model names a tree."""
        return set(self.builtins) | {m.id for m in self.models if m.kind != "SubTree"}

    def _registered_clash(self, tag: str, tid: str) -> str:
        # Both 4.6.2 and 4.10.0 refuse it while loading the file (XMLParser::loadDocImpl).
        what = "a built-in node" if tid in self.builtins else "a node declared in TreeNodesModel"
        return (
            f"the ID of <{tag}> is `{tid}`, {what}: BehaviorTree.CPP refuses a tree or SubTree ID "
            f"that names a registered node (rename the tree)"
        )

    def _main_tree(self, src: Source) -> str:
        root = src.root
        every = [t for t, e, s in self.tree_elems]
        # The tree to run is the mission's: a tree library (--trees) only lends SubTrees.
        ids = every[: self.mission_trees]
        if self.main_tree_override is not None:
            main = self.main_tree_override
            if main not in every:
                self.sink.error(
                    src.loc(root),
                    f"--main-tree names `{main}`, but no BehaviorTree has that ID{suggestion(main, every)}",
                )
            return main
        main = root.get("main_tree_to_execute")
        if main is None:
            if len(set(ids)) == 1:
                return ids[0]
            if not ids:
                self.sink.error(src.loc(root), "the mission defines no <BehaviorTree>")
                return ""
            self.sink.error(
                src.loc(root),
                f"the mission defines {len(set(ids))} BehaviorTrees; say which one "
                f'runs with main_tree_to_execute="..." or --main-tree (one of '
                f"{', '.join('`' + i + '`' for i in sorted(set(ids)))})",
            )
            return ""
        if main not in every:
            self.sink.error(
                src.value_loc(root, "main_tree_to_execute"),
                f"main_tree_to_execute names `{main}`, but no BehaviorTree has that ID{suggestion(main, every)}",
            )
        return main

    def _created_trees(self, main: str) -> set[str]:
        """The BehaviorTrees the library creates: the main tree and, transitively, the trees
        its SubTree elements name. Only their nodes are created, so only there are ports,
        literals and scripts checked (XMLParser::createNodeFromXML); the checks of VerifyXML
        (known node IDs, a decorator's single child, a control's children, one root per
        tree) cover every tree."""
        elems = {tid: elem for tid, elem, _src in self.tree_elems}
        seen: set[str] = set()
        todo = [main]
        while todo:
            tid = todo.pop()
            if tid in seen or tid not in elems:
                continue
            seen.add(tid)
            todo.extend(e.get("ID", "") for e in elems[tid].iter("SubTree"))
        return seen

    def _left_out(self, tree_id: str, mark: int) -> bool:
        """A tree the main tree never runs with errors only its creation would find (from sink
        item `mark` on): those become warnings and the tree is left out of the mission, as the
        library never creates it. False (errors kept) when VerifyXML would refuse it too."""
        found = self.sink.items[mark:]
        errors = [d for d in found if d.severity == "error"]
        if not errors or any(_verify_xml_error(d.message) for d in errors):
            return False
        self.sink.items[mark:] = [
            d
            if d.severity != "error"
            else dataclasses.replace(
                d,
                severity="warning",
                message=f"{d.message}; BehaviorTree.CPP loads the file all the same, since the main tree "
                f"never runs BehaviorTree `{tree_id}` (it creates only the trees it runs): btgen leaves "
                f"`{tree_id}` out",
            )
            for d in found
        ]
        self.left_out.add(tree_id)
        return True

    def _tree_root(self, elem: etree._Element, src: Source, tree_id: str) -> Node:
        self._warn_text(elem, src)
        kids = [c for c in elem if isinstance(c.tag, str)]
        if len(kids) != 1:
            self.sink.error(src.loc(elem), f"BehaviorTree `{tree_id}` must have exactly 1 child, it has {len(kids)}")
            if not kids:
                return Node("AlwaysFailure", "Action", None, (), (), (), (), src.loc(elem))
        return self._node(kids[0], src)

    def _node(self, elem: etree._Element, src: Source) -> Node:
        tag, loc = src.tag(elem), src.loc(elem)  # (as written: `arm:Grasp`, xmlsource.undeclared_prefixes)
        if len(self._tree_ids) != len(self.tree_elems):  # (one set for all the nodes, not one each)
            self._tree_ids = {t for t, _, _ in self.tree_elems}
        tree_ids = self._tree_ids
        explicit = tag in KINDS
        node_id = elem.get("ID") if explicit else tag
        children = tuple(self._node(c, src) for c in elem if isinstance(c.tag, str))
        self._warn_text(elem, src)
        name = elem.get("name")
        if explicit and node_id is None:
            self.sink.error(loc, f"<{tag}> needs an ID attribute naming the node")
            node_id = tag
        spec = self._spec_for(tag, node_id, elem, src, tree_ids)
        pre: list[Attr] = []
        post: list[Attr] = []
        ports: list[Attr] = []
        autoremap = False
        for aname in src.attr_names_in_order(elem) or list(elem.attrib):
            if aname not in elem.attrib:
                continue
            value = elem.get(aname)
            attr = Attr(aname, value, src.attr_loc(elem, aname), src.value_loc(elem, aname))
            if aname == "name" or (aname == "ID" and explicit):
                continue
            if aname in PRE_CONDITIONS or aname in POST_CONDITIONS:
                attr = self._with_script(attr, elem, src, node_id)
                (pre if aname in PRE_CONDITIONS else post).append(attr)
            elif aname == "_autoremap" and tag == "SubTree":
                autoremap = self._bool_attr(attr)
            elif aname in METADATA_ATTRIBUTES or aname in EDITOR_ATTRIBUTES:
                continue
            elif aname == "ID":
                self.sink.error(attr.loc, f"unknown attribute `{aname}` on `{node_id}`")
            elif not aname[:1].isalpha():
                self._ignored_attribute(attr, tag, node_id)
            elif not version_rules.is_port_name(aname, self.sem) and (tag != "SubTree" or self.sem.attribute_names_484):
                # 4.8.4 and later ignore attributes that cannot be port names (`doc.owner`), a
                # SubTree's remaps too (`target.room="{room}"`: recorded on 4.10.0)
                self.sink.warning(
                    attr.loc,
                    f"attribute `{aname}` on `{node_id}` is ignored: BehaviorTree.CPP {self.btcpp} ignores "
                    f"attributes that are not valid port names",
                )
            elif tag == "SubTree":
                ports.append(self._subtree_remap(attr, node_id))
            elif spec is not None:
                checked = self._port(attr, spec, elem, src)
                if checked is not None:
                    ports.append(checked)
        if spec is not None:
            self._check_required(spec, ports, loc, node_id)
            self._check_children(spec, children, loc, node_id, tag)
        kind = "SubTree" if tag == "SubTree" else (spec.kind if spec else "Action")
        if tag == "SubTree":
            return SubTreeNode(
                node_id, kind, name, tuple(ports), tuple(pre), tuple(post), children, loc, autoremap, target=node_id
            )
        return Node(node_id, kind, name, tuple(ports), tuple(pre), tuple(post), children, loc, tag=tag)

    def _ignored_attribute(self, attr: Attr, tag: str, node_id: str) -> None:
        """An attribute not starting with a letter that means nothing to 4.6.2: it ignores it
        (IsAllowedPortName), so does btgen, with a warning saying what that means."""
        if attr.name == "__shared_blackboard":
            self.sink.warning(
                attr.loc,
                f"`__shared_blackboard` is BehaviorTree.CPP v3's and v4 ignores it: SubTree "
                f'`{node_id}` gets a blackboard of its own (`_autoremap="true"` shares '
                f"entries by name in v4)",
            )
            return
        specials = (
            [a for a in SPECIAL_ATTRIBUTES if a.startswith("_")]
            + list(METADATA_ATTRIBUTES)
            + (["_autoremap"] if tag == "SubTree" else [])
        )
        self.sink.warning(
            attr.loc,
            f"attribute `{attr.name}` on `{node_id}` is ignored, as BehaviorTree.CPP ignores every "
            f"attribute not starting with a letter{suggestion(attr.name, specials)}",
        )

    def _spec_for(
        self, tag: str, node_id: str, elem: etree._Element, src: Source, tree_ids: set[str]
    ) -> Optional[NodeSpec]:
        loc = src.value_loc(elem, "ID") if tag in KINDS else src.loc(elem)
        if tag == "SubTree":
            if node_id in self._registered_ids():
                self.sink.error(loc, self._registered_clash("SubTree", node_id))
            elif node_id not in tree_ids:
                beside = self.siblings.defining_tree(src.path, node_id)
                where = (
                    "; " + beside.include_advice(node_id, tree_ids)
                    if beside is not None
                    else suggestion(node_id, tree_ids)
                )
                self.sink.error(loc, f"SubTree `{node_id}` does not exist: no BehaviorTree has that ID{where}")
            return self.builtins["SubTree"]
        user = {m.id: m for m in self.models}
        spec = self.builtins.get(node_id) or user.get(node_id)
        if spec is None and node_id.startswith("{"):  # lxml's `{uri}local` of a namespaced element
            local = etree.QName(node_id).localname
            shown = f"{elem.prefix}:{local}" if elem.prefix else local
            known = local in self.builtins or local in user
            self.sink.error(
                loc,
                f"unknown node `{shown}`: BehaviorTree.CPP node elements have no namespace "
                f"(it is in {etree.QName(node_id).namespace})" + (f"; write <{local}>" if known else ""),
            )
            return None
        if spec is None:
            if node_id in tree_ids:
                self.sink.error(loc, f'`{node_id}` is a BehaviorTree, not a node: write <SubTree ID="{node_id}"/>')
                return None
            if node_id == "TryCatch" and not self.sem.trycatch:
                self.sink.error(
                    loc,
                    f"unknown node `TryCatch`: it is built in from BehaviorTree.CPP 4.9.0, not in "
                    f"{self.btcpp} (select the version with --btcpp 4.10.0)",
                )
                return None
            unknown = f"unknown node `{node_id}`: it is neither built in nor declared in TreeNodesModel"
            beside = self.siblings.declaring_model(src.path, node_id)
            if beside is not None:
                load = (
                    f"pass `--models {beside.path}`"
                    if beside.models_only
                    else f'add <include path="{beside.name}"/> to <root>'
                )
                self.sink.error(loc, f"{unknown}; `{beside.path}` beside it declares it: {load}")
                return None
            hint = did_you_mean(node_id, list(self.builtins) + list(user))
            if hint:
                where = "declared in TreeNodesModel" if hint in user else "built in"
                self.sink.error(loc, f"{unknown}; `{hint}` is {where} (did you mean it?)")
                return None
            children = sum(1 for c in elem if isinstance(c.tag, str))
            self.sink.error(loc, f"{unknown} ({model_advice(node_id, children)})")
            if not user and not self.models_paths:
                self.undeclared.append(len(self.sink.items) - 1)
            return None
        if tag in KINDS and tag != spec.kind:
            # 4.6.2 creates the registered node whatever the element says (<Action
            # ID="ScriptCondition"> is the Condition); the children are checked by its kind.
            self.sink.warning(
                src.loc(elem),
                f"`{node_id}` is {'an' if spec.kind[0] in 'AEIOU' else 'a'} {spec.kind}, but is "
                f"written <{tag}>; it runs as the {spec.kind} it is",
            )
        return spec

    def _bool_attr(self, attr: Attr) -> bool:
        try:
            return bool(values.convert_from_string("bool", attr.value))
        except values.ConversionError as e:
            self.sink.error(attr.value_loc, f"`{attr.name}`: {e}")
            return False

    def _with_script(self, attr: Attr, elem: etree._Element, src: Source, node_id: str) -> Attr:
        if node_id == "Script" and attr.name == "code" and attr.value == "":
            # 4.6.2 and 4.10.0 run `<Script code=""/>`: it does nothing and succeeds (recorded:
            # tests/conformance/both-releases/empty_script); `code="  "` and an empty `_skipIf`
            # & co. are refused at load ("Empty Script"), and stay refused here
            return Attr(attr.name, attr.value, attr.loc, attr.value_loc, script_lang.Script((), ""))
        if (node_id, attr.name) in _EMPTY_LOADS and attr.value == "":
            # Both releases load an empty ScriptCondition `code` or Precondition `if` and throw
            # when the node is ticked (bad_function_call; recorded:
            # tests/conformance/both-releases/empty_condition_*): the script gives no value,
            # which both engines report as the error it is when it runs
            self.sink.warning(
                attr.value_loc,
                f"`{attr.name}` of `{node_id}` is empty: BehaviorTree.CPP loads it and throws when the node is ticked",
            )
            return Attr(attr.name, attr.value, attr.loc, attr.value_loc, script_lang.Script((), ""))
        try:
            parsed = script_lang.parse_script(attr.value, self.sem.script_grammar_49)
        except script_lang.ScriptSyntaxError as e:
            self.sink.error(
                src.value_loc(elem, attr.name, e.offset), f"invalid script in `{attr.name}` of `{node_id}`: {e.message}"
            )
            return attr
        return Attr(attr.name, attr.value, attr.loc, attr.value_loc, parsed)

    def _check_key(self, attr: Attr, key: str, what: str, remap: bool = False) -> bool:
        if remap and key and not _KEY_RE.match(key):
            # 4.6.2 names the entry with whatever is between the braces (`{ n }` is the key
            # ` n `; edges table B1): loaded, with a warning, since it is most likely a typo
            self.sink.warning(
                attr.value_loc,
                f"`{attr.value}` in {what} names the blackboard key `{key}`, which scripts cannot "
                f"name (keys are letters, digits, `_`, optionally `@` first); BehaviorTree.CPP 4.6.2 "
                f"uses it as it is",
            )
            return True
        if not _KEY_RE.match(key):
            self.sink.error(
                attr.value_loc,
                f"`{attr.value}` in {what} is not a valid blackboard key "
                f"(use letters, digits, `_`, optionally `@` first for the root "
                f"blackboard)",
            )
            return False
        return True

    def _subtree_remap(self, attr: Attr, tree_id: str) -> Attr:
        # 4.6.2 and 4.10.0 both remap a dotted name (`target.room="{room}"`: recorded on the library)
        if not _SUBTREE_REMAP_RE.match(attr.name):
            self.sink.error(attr.loc, f"invalid port name `{attr.name}` on SubTree `{tree_id}`")
        model = next((m for m in self.models if m.id == tree_id and m.kind == "SubTree"), None)
        if model is not None and model.port(attr.name) is None:
            # 4.6.2 remaps every attribute of a SubTree element, declared or not (edges M1)
            self.sink.warning(
                attr.loc,
                f"SubTree `{tree_id}` declares no port `{attr.name}`{suggestion(attr.name, model.port_names)}; "
                f"BehaviorTree.CPP 4.6.2 remaps it all the same",
            )
        if is_remap(attr.value):
            self._check_key(attr, remap_key(attr.value, attr.name), f"port `{attr.name}`", remap=True)
        return attr

    def _port(self, attr: Attr, spec: NodeSpec, elem: etree._Element, src: Source) -> Optional[Attr]:
        port = spec.port(attr.name)
        if port is None:
            names = spec.port_names
            listed = ", ".join(f"`{n}`" for n in names) if names else "none"
            hint = did_you_mean(attr.name, names)
            extra = f"; did you mean `{hint}`?" if hint else ""
            self.sink.error(attr.loc, f"`{spec.id}` has no port `{attr.name}` (its ports: {listed}){extra}")
            return None
        value = attr.value
        what = f"port `{attr.name}` of `{spec.id}`"
        typed = port.type not in ("string", "any") and not values.is_opaque_type(port.type)
        if is_remap(value):
            if typed and value != value.strip(" "):
                # 4.6.2's load-time check sees braces only at both ends of the unstripped text
                # and converts anything else (xml_parsing.cpp): ` {n}` is no int.
                self._check_literal(attr.value_loc, what, port.type, value, port.int_width)
                return attr
            self._check_key(attr, remap_key(value, attr.name), what, remap=True)
            return attr
        if ("{" in value or "}" in value) and (value.startswith("{") or value.endswith("}")) and not typed:
            self.sink.warning(
                attr.value_loc,
                f"`{value}` in {what} is not a blackboard reference (that is `{{key}}`); "
                f"BehaviorTree.CPP {self.btcpp} reads it as this literal text",
            )
        if (spec.id, attr.name) in SCRIPT_PORTS:
            return self._with_script(attr, elem, src, spec.id)
        if (spec.id, attr.name) in KEY_NAME_PORTS:
            # These nodes read the raw text as the name of an entry (`output_key="result"`).
            # SkipUnlessUpdated, WaitValueUpdate and WasEntryUpdated take `{}` as the name of
            # an entry (recorded on 4.6.2 and 4.10.0: one nothing writes, so SKIPPED, RUNNING
            # for ever, FAILURE): loaded, with the warning above that it is literal text.
            if (spec.id, attr.name) not in ENTRY_PORTS or value != "{}":
                self._check_key(attr, value, what)
            return attr
        if (spec.id, attr.name) in version_rules.LOOP_QUEUE_PORTS:
            version_rules.check_literal_queue(self.sink, attr, spec.id, self.sem)
            return attr
        if spec.id not in self.builtins and port.direction in ("output", "inout"):
            # A node the program registers: 4.6.2 and 4.10.0 load a literal on its output or inout
            # port (recorded: tests/conformance/both-releases/output_port_literal); its setOutput
            # then fails and writes nothing, as when the port is not given. An output port is
            # loaded as not given; an inout port keeps the literal as the value it reads.
            self.sink.warning(
                attr.value_loc,
                f"{what} is an {port.direction} port given the literal `{value}`, not a blackboard entry: "
                f"BehaviorTree.CPP {self.btcpp} loads it and the node's writes to it go nowhere; "
                f"write `{{key}}` (or `{{=}}`) to keep what it writes",
            )
            # (a typed port's literal must convert all the same: the library checks it on load
            # whatever the direction, as `<LoopInt value="x">` shows)
            self._check_literal(attr.value_loc, what, port.type, value, port.int_width)
            return None if port.direction == "output" else attr
        if port.direction == "output" or (port.direction == "inout" and not port.type.startswith("queue<")):
            # 4.6.2's setOutput only writes through `{key}`; a literal would silently write nothing.
            self.sink.error(
                attr.value_loc,
                f"{what} is an {port.direction} port and must name a blackboard "
                f"entry as `{{key}}` (or `{{=}}`), not the literal `{value}`",
            )
            return attr
        if (spec.id, attr.name) in STATUS_READ_WHEN_TICKED:
            try:
                values.convert_from_string(values.NODE_STATUS, value)
            except values.ConversionError as e:
                # Recorded (tests/conformance/oracle-diff/status_literal_*): both releases load
                # it and the node throws where it reads the port (getInput<NodeStatus> fails).
                self.sink.warning(
                    attr.value_loc,
                    f"{what}: {e}; BehaviorTree.CPP {self.btcpp} loads it and the node throws when it reads the port",
                )
            return attr
        self._check_literal(attr.value_loc, what, port.type, value, port.int_width)
        return attr

    def _check_literal(
        self, loc: Loc, what: str, type_name: str, value: str, int_width: Optional[tuple[str, int, int]] = None
    ) -> None:
        """A port literal as 4.6.2 converts it: numbers are read as a prefix (`3.5` and `3abc`
        are 3 for an int, edges table I1), which loads with a warning; what 4.6.2 cannot
        convert at all is an error. An integer port of another width than 32 bits
        (`int_width`) is checked against its own range, as 4.6.2's convertFromString<T> does."""

        fc = self.sem.double_from_chars

        def convert(strict: bool = False) -> values.Value:
            if int_width is not None:
                return values.convert_integer(value, *int_width, strict=strict)
            return values.convert_from_string(type_name, value, strict=strict, double_from_chars=fc)

        try:
            convert()
        except values.ConversionError as e:
            self.sink.error(loc, f"{what}: {e}")
            return
        try:
            convert(strict=True)
        except values.ConversionError as e:
            read = convert()
            shown = values.describe(read) if not isinstance(read, values.Queue) else str(list(read))
            self.sink.warning(loc, f"{what}: {e}; BehaviorTree.CPP {self.sem.version} reads it as {shown}")

    def _check_required(self, spec: NodeSpec, ports: list[Attr], loc: Loc, node_id: str) -> None:
        given = {p.name for p in ports}
        for p in spec.ports:
            if p.required and p.name not in given:
                self.sink.error(
                    loc, f"`{node_id}` needs port `{p.name}`" + (f" ({p.description})" if p.description else "")
                )

    def _check_children(self, spec: NodeSpec, children: tuple[Node, ...], loc: Loc, node_id: str, tag: str) -> None:
        n = len(children)
        lo, hi = spec.min_children, spec.max_children
        if n < lo or (hi is not None and n > hi):
            what = {
                "Action": "an Action",
                "Condition": "a Condition",
                "Control": "a control node",
                "Decorator": "a decorator",
                "SubTree": "a SubTree",
            }[spec.kind]
            has = "no children" if n == 0 else ("1 child" if n == 1 else f"{n} children")
            self.sink.error(loc, f"`{node_id}` is {what} and takes {spec.children_text()}, but has {has}")

    # --------------------------------------------------------- whole-mission
    def _check_subtree_cycles(self, trees: tuple[TreeDef, ...]) -> None:
        by_id = {t.id: t for t in trees}

        def subtree_nodes(n: Node):
            if isinstance(n, SubTreeNode):
                yield n
            for c in n.children:
                yield from subtree_nodes(c)

        reported: set[tuple[str, ...]] = set()
        state: dict[str, int] = {}  # 1: on the stack, 2: done

        def visit(tid: str, path: list[str]) -> None:
            state[tid] = 1
            for st in subtree_nodes(by_id[tid].root):
                if st.target not in by_id:
                    continue
                if state.get(st.target) == 1:
                    cycle = path[path.index(st.target) :] + [st.target]
                    key = tuple(sorted(cycle[:-1]))
                    if key not in reported:
                        reported.add(key)
                        what = "calls itself" if len(cycle) == 2 else "recursion"
                        self.sink.error(
                            st.loc,
                            f"SubTree {what}: "
                            + " -> ".join(f"`{c}`" for c in cycle)
                            + " (BehaviorTree.CPP would recurse without end)",
                        )
                elif state.get(st.target) is None:
                    visit(st.target, path + [st.target])
            state[tid] = 2

        for t in trees:
            if t.id not in state:
                visit(t.id, [t.id])

    def _check_instance_count(self, mission: Mission) -> None:
        # Iterative: trees may nest 256 levels deep in each of many SubTrees (cycles and unknown
        # SubTree IDs were rejected before this runs).
        memo: dict[str, int] = {}

        def count(tree_id: str) -> int:
            pending = [tree_id]
            while pending:
                tid = pending[-1]
                if tid in memo:
                    pending.pop()
                    continue
                nodes, stack = 0, [mission.tree(tid).root]
                calls: list[str] = []
                while stack:
                    n = stack.pop()
                    nodes += 1
                    stack.extend(n.children)
                    if isinstance(n, SubTreeNode):
                        calls.append(n.target)
                missing = [t for t in calls if t not in memo]
                if missing:
                    pending.extend(missing)
                    continue
                memo[tid] = nodes + sum(memo[t] for t in calls)
                pending.pop()
            return memo[tree_id]

        if mission.main_tree and count(mission.main_tree) > MAX_NODES:
            self.sink.error(
                mission.main.loc,
                f"the main tree expands to {count(mission.main_tree)} nodes with its "
                f"SubTrees; BehaviorTree.CPP numbers nodes with 16 bits, so at most "
                f"{MAX_NODES} are allowed",
            )

    def _check_version_rules(self, mission: Mission) -> None:
        """What later releases refuse at load: errors when the selected version refuses it,
        warnings under 4.6.2 so that a team learns before it upgrades."""
        for finding in version_rules.loading_findings(mission):
            if getattr(self.sem, finding.switch):
                self.sink.error(finding.loc, f"{finding.message} (refused from BehaviorTree.CPP {finding.since})")
            else:
                self.sink.warning(finding.loc, f"refused from BehaviorTree.CPP {finding.since}: {finding.message}")

    def _validate_mission_xsd(self, mission: Mission) -> None:
        if self.sink.errors:
            return
        from btgen.frontend.xsd import validate_against_mission_xsd

        for src in self.sources:
            for d in validate_against_mission_xsd(mission, src):
                # attributes the library ignores (not port names) were reported, if at all, above
                m = re.fullmatch(r"attribute `(.+)` is not allowed here", d.message)
                ignored = m is not None and (
                    m.group(1).startswith("_") or not version_rules.is_port_name(m.group(1), self.sem)
                )
                if ignored:
                    continue
                tree = self._uncreated_at(d.loc)
                if tree in self.left_out:
                    continue  # reported by the loader, as a warning, with the tree left out
                if tree is not None and d.severity == "error":
                    d = dataclasses.replace(
                        d,
                        severity="warning",
                        message=f"{d.message}; BehaviorTree.CPP loads the file all the same, since the main tree "
                        f"never runs BehaviorTree `{tree}` (it creates only the trees it runs)",
                    )
                self.sink.items.append(d)

    def _line_of(self, elem: etree._Element, src: Source) -> int:
        return src.loc(elem).line

    def _uncreated_at(self, loc: Loc) -> Optional[str]:
        """The tree the main tree never runs whose element holds `loc`, if any."""
        for tid, path, first, last in self.uncreated:
            if loc.path == path and first <= loc.line <= last:
                return tid
        return None


def _verify_xml_error(message: str) -> bool:
    """An error VerifyXML reports in every tree of the file, created or not."""
    return (
        message.startswith("unknown node")
        or "is a decorator and takes" in message
        or ("is a control node and takes" in message and message.endswith("but has no children"))
        or (message.startswith("BehaviorTree `") and "must have exactly 1 child" in message)
    )
