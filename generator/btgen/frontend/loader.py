"""Front end: read a mission (and its includes), validate it, build the model.

    read (xmlsource) -> structural XSD (schema/btcpp_v4.xsd) -> semantic checks
    -> model (model.py) -> mission XSD (xsd.py) as a final backstop

Every problem becomes a diagnostic at `path:line:col`; all problems of a
mission are reported together.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import re
from collections.abc import Sequence
from typing import Optional

from lxml import etree

from btgen.diagnostics import DiagnosticSink, Loc, UserError, did_you_mean, suggestion
from btgen.frontend import version_rules
from btgen.frontend.hints import SiblingIndex, model_advice, unmapped_subtree_ports
from btgen.frontend.xmlsource import Source, read_source
from btgen.lang import blackboard as bbmod
from btgen.lang import nav2, values
from btgen.lang import script as script_lang
from btgen.lang.catalogue import (
    EDITOR_ATTRIBUTES,
    KEY_NAME_PORTS,
    KIND_CHILDREN,
    KINDS,
    METADATA_ATTRIBUTES,
    POST_CONDITIONS,
    PRE_CONDITIONS,
    RESERVED_PORT_NAMES,
    SCRIPT_PORTS,
    SPECIAL_ATTRIBUTES,
    NodeSpec,
    PortSpec,
)
from btgen.lang.model import Attr, Mission, Node, SubTreeNode, TreeDef
from btgen.lang.nav2 import builtins_for
from btgen.lang.versions import DEFAULT_VERSION, semantics

MAX_INCLUDE_DEPTH = 32
MAX_NODES = 65535  # BehaviorTree.CPP UIDs are 16-bit (see also the instance count check)

_KEY_RE = re.compile(r"^@?[A-Za-z_][A-Za-z0-9_.\-:]*$")
_PORT_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_SUBTREE_REMAP_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+)*$")
# FORMAT.md: node IDs contain no white space, `"` or `\` (the trace prints them unquoted).
_ID_FORBIDDEN = re.compile(r'[\s"\\]')
# Elements of the format: as node IDs, <root/> or <Action/> in a tree would not mean the node
# (4.6.2 reads <Action/> as the explicit form and asks for its ID attribute).
RESERVED_MODEL_IDS = frozenset(
    {"root", "BehaviorTree", "include", "TreeNodesModel", "Action", "Condition", "Control", "Decorator", "SubTree"}
)
_MODEL_PORT_TAGS = {
    "input_port": "input",
    "output_port": "output",
    "inout_port": "inout",
    "bidirectional_port": "inout",  # Nav2's nav2_tree_nodes.xml
}


def is_remap(value: str) -> bool:
    """`{key}` (or `{=}`): the port is connected to a blackboard entry. As 4.6.2's
    isBlackboardPointer: spaces around the braces are stripped, and at least 3 characters
    from `{` to `}` (`{}` is a literal; edges table B1)."""
    return bbmod.is_blackboard_pointer(value)


def remap_key(value: str, port_name: str) -> str:
    """The entry a `{key}`/`{=}` value names."""
    key = bbmod.remapped_key(port_name, value)
    assert key is not None
    return key


def _int_width(type_text: Optional[str]) -> Optional[tuple[str, int, int]]:
    """An integer type of another width than 32 bits: its spelling and range (PortSpec.int_width)."""
    r = values.integer_range(type_text)
    if r is None or r in ((values.INT_MIN, values.INT_MAX), (0, values.UNSIGNED_MAX)):
        return None
    return (" ".join((type_text or "").split()), r[0], r[1])


class _Loader:
    def __init__(
        self,
        path: str,
        models: Sequence[str] = (),
        main_tree: Optional[str] = None,
        trees: Sequence[str] = (),
        btcpp: str = DEFAULT_VERSION,
        ros_packages: Sequence[tuple[str, str]] = (),
        nodes: Optional[str] = None,
    ) -> None:
        self.path = path
        self.ros_packages = dict(ros_packages)  # package -> folder, for <include ros_pkg=...>
        self.btcpp = btcpp
        self.sem = semantics(btcpp)
        # Nav2's Controls and Decorators: the distro `--nodes` names, or (no `--nodes`) the one
        # of a models file that is Nav2's (nav2.detect, after the models are read).
        self.nav2 = nav2.parse_nodes(nodes) if nodes is not None else None
        self.detect_nav2 = nodes is None
        self.builtins = builtins_for(btcpp, self.nav2)
        self.models_paths = tuple(models)
        self.trees_paths = tuple(trees)
        self.mission_trees = 0  # tree_elems[:mission_trees] are the mission's own (file and includes)
        self.main_tree_override = main_tree
        self.sink = DiagnosticSink()
        self.sources: list[Source] = []
        self.tree_elems: list[tuple[str, etree._Element, Source]] = []
        self.models: list[NodeSpec] = []
        self.files: list[str] = []
        # the real paths and shown paths of self.files, each computed once: `--trees DIR` of
        # thousands of files deep in folders asks "read already?" once per file
        self._real_files: set[str] = set()
        self._shown_files: dict[str, int] = {}
        self._tree_ids: set[str] = set()
        self.palette_subtrees: list[NodeSpec] = []  # the SubTree models of models files
        self.siblings = SiblingIndex(self.files)
        self.undeclared: list[int] = []  # sink indexes of unknown nodes in a mission without models
        self.anonymous = 0  # <BehaviorTree> elements without ID so far

    # ---------------------------------------------------------------- files
    def load(self) -> Mission:
        try:
            return self._load()
        except UserError as e:
            raise UserError(self._sorted(e.diagnostics)) from None

    def _position(self, i: int) -> tuple[int, int, int]:
        d = self.sink.items[i]
        return (self._shown_files.get(d.loc.path, len(self.files)), d.loc.line, d.loc.col)

    def _sorted(self, diags):
        order = {f: i for i, f in enumerate(self.files)}
        return sorted(diags, key=lambda d: (order.get(d.loc.path, len(order)), d.loc.line, d.loc.col))

    def _load(self) -> Mission:
        root_source = self._load_file(self.path, self.path, ())
        self.mission_trees = len(self.tree_elems)
        for trees_path in self.trees_paths:
            self._load_tree_library(trees_path)
        for models_path in self.models_paths:
            self._load_models_file(models_path)
        if self.detect_nav2 and self.nav2 is None:
            distro = nav2.detect(self.models)
            if distro is not None:
                # Nav2's models file documents its Controls and Decorators: they are built in.
                self.nav2 = distro
                self.builtins = builtins_for(self.btcpp, distro)
                self.models = [m for m in self.models if m.id not in self.builtins]
        self.sink.raise_if_errors()
        main = self._main_tree(root_source)
        self.sink.raise_if_errors()
        tree_ids = self._check_tree_ids()
        for spec in self.palette_subtrees:
            if spec.id not in tree_ids:
                self.sink.error(
                    spec.loc or Loc(self.path),
                    f"SubTree model `{spec.id}` names no BehaviorTree of the mission{suggestion(spec.id, tree_ids)}",
                )
        trees = tuple(
            TreeDef(tid, self._tree_root(elem, src, tid), src.loc(elem))
            for tid, elem, src in self.tree_elems
            if tid in tree_ids
        )
        self._check_subtree_cycles(trees)
        if self.undeclared:
            # No model anywhere (none in the mission, no --models): most likely the models file
            # was forgotten; the first unknown node says so, once.
            first = min(self.undeclared, key=self._position)
            d = self.sink.items[first]
            self.sink.items[first] = dataclasses.replace(
                d,
                message=d.message + "; the mission declares no node models: if they are in a file of their "
                "own, pass it with `--models FILE.xml`",
            )
        self.sink.raise_if_errors()
        mission = Mission(
            self.path,
            trees,
            main,
            tuple(self.models),
            tuple(self.files),
            tuple(self._sorted(d for d in self.sink.items if d.severity == "warning")),
            btcpp=self.btcpp,
            nav2=self.nav2,
        )
        self.sink.items.extend(unmapped_subtree_ports(mission))
        self._check_instance_count(mission)
        self._check_version_rules(mission)
        self._validate_mission_xsd(mission)
        self.sink.raise_if_errors()
        warnings = tuple(self._sorted(d for d in self.sink.items if d.severity == "warning"))
        return dataclasses.replace(mission, warnings=warnings) if warnings != mission.warnings else mission

    def _add_file(self, shown: str) -> None:
        self._shown_files.setdefault(shown, len(self.files))
        self.files.append(shown)
        self._real_files.add(os.path.realpath(shown))

    def _load_file(self, path: str, shown: str, stack: tuple[str, ...], include_loc: Optional[Loc] = None) -> Source:
        self._add_file(shown)  # (before reading: a file that does not load is still a dependency)
        src = read_source(path, shown)
        self.sink.items.extend(src.warnings)  # XML that tinyxml2 reads (xmlsource.tolerated)
        self.sources.append(src)
        root = src.root
        if root.tag != "root":
            if root.tag.startswith("{"):  # lxml's `{uri}local`: a namespace BehaviorTree.CPP does not read
                q = etree.QName(root.tag)
                shown = f"{root.prefix}:{q.localname}" if root.prefix else q.localname
                raise UserError.at(
                    src.loc(root),
                    f"the root element <{shown}> is in namespace {q.namespace}; "
                    f"BehaviorTree.CPP missions use no namespaces (remove the "
                    f"xmlns declaration)",
                )
            raise UserError.at(
                src.loc(root), f'the root element is <{root.tag}>; a mission starts with <root BTCPP_format="4">'
            )
        from btgen.frontend.xsd import validate_structure

        errors = validate_structure(src)
        if errors:
            raise UserError(errors)
        fmt = root.get("BTCPP_format")
        if fmt is None:
            self.sink.warning(src.loc(root), "<root> has no BTCPP_format attribute; reading it as format 4")
        elif fmt != "4":
            self.sink.error(
                src.value_loc(root, "BTCPP_format"),
                f'BTCPP_format="{fmt}" is not supported; btgen reads BehaviorTree.CPP v4 files (BTCPP_format="4")',
            )
        self._warn_text(root, src)
        elements = [c for c in root if isinstance(c.tag, str)]
        for child in elements:
            if child.tag == "BehaviorTree":
                self.tree_elems.append((self._tree_id(child, src, len(elements)), child, src))
            elif child.tag == "TreeNodesModel":
                self._read_models(child, src)
            elif child.tag == "include":
                self._include(child, src, stack + (os.path.realpath(path),))
        return src

    def _load_tree_library(self, path: str) -> None:
        """`--trees FILE|DIR`: every <BehaviorTree> of the file (or of each `*.xml` of the
        folder, in name order) becomes available to the mission's SubTrees, as
        registerBehaviorTreeFromFile makes them; their includes and TreeNodesModel count too."""
        if os.path.isdir(path):
            files = sorted(
                os.path.join(path, f)
                for f in os.listdir(path)
                if f.endswith(".xml") and os.path.isfile(os.path.join(path, f))
            )
            if not files:
                self.sink.error(Loc(path, 1, 1), "--trees names a folder that holds no .xml file")
                return
        elif os.path.isfile(path):
            files = [path]
        else:
            self.sink.error(Loc(path, 1, 1), "--trees: no such file or folder")
            return
        for f in files:
            if os.path.realpath(f) in self._real_files:
                continue  # the mission, one of its includes, or a file given twice
            try:
                self._load_file(f, f, ())
            except UserError as e:
                self.sink.items.extend(e.diagnostics)

    def _tree_id(self, elem: etree._Element, src: Source, siblings: int) -> str:
        """The ID of a <BehaviorTree>; warns about the attributes BehaviorTree.CPP ignores."""
        for aname in src.attr_names_in_order(elem) or list(elem.attrib):
            if aname != "ID" and not aname.startswith("_"):  # `_favorite`, `_hardcoded`: editors' own
                self.sink.warning(
                    src.attr_loc(elem, aname),
                    f"attribute `{aname}` of <BehaviorTree> is ignored: BehaviorTree.CPP reads only "
                    f"`ID` there (a SubTree's ports and their defaults are declared in <TreeNodesModel>)",
                )
        tid = elem.get("ID")
        if tid is not None:
            return tid
        # 4.6.2 (VerifyXML) accepts a tree without ID only when it is the only element
        # under <root>, and names it BehaviorTree_<n>, counting such trees from 0.
        if siblings > 1:
            self.sink.error(
                src.loc(elem),
                "<BehaviorTree> needs an ID attribute: BehaviorTree.CPP accepts a tree without "
                "one only when it is the only element of its file",
            )
        tid = f"BehaviorTree_{self.anonymous}"
        self.anonymous += 1
        return tid

    def _warn_text(self, elem: etree._Element, src: Source) -> None:
        """Text between the elements of a tree or of <root>: tinyxml2 keeps it, BehaviorTree.CPP
        never reads it; btgen says so once per element."""
        parts = [elem.text or ""] + [c.tail or "" for c in elem]
        text = " ".join(p.strip() for p in parts if p.strip())
        if text:
            shown = text if len(text) <= 40 else text[:37] + "..."
            self.sink.warning(
                src.text_loc(elem),
                f"text `{shown}` inside <{elem.tag}> is ignored (BehaviorTree.CPP reads only elements here)",
            )

    def _load_models_file(self, path: str) -> None:
        """A models file (`--models`): a <root> holding only <TreeNodesModel>, whose
        declarations count as the mission's own."""
        if not path:  # (it was reported at `:1:1:`)
            self.sink.error(Loc("--models", 1, 1), "the file name is empty")
            return
        if os.path.realpath(path) in self._real_files:
            return  # given twice, or also the mission or one of its includes
        self._add_file(path)
        try:
            src = read_source(path, path)
        except UserError as e:
            self.sink.items.extend(e.diagnostics)
            return
        self.sink.items.extend(src.warnings)
        root = src.root
        if root.tag != "root":
            self.sink.error(
                src.loc(root),
                f"the root element of a models file is <{root.tag}>; it must be <root> holding only <TreeNodesModel>",
            )
            return
        from btgen.frontend.xsd import validate_structure

        errors = validate_structure(src)
        if errors:
            self.sink.items.extend(errors)
            return
        # (both were taken silently: a models file is read as format 4 and runs nothing)
        fmt = root.get("BTCPP_format")
        if fmt is not None and fmt != "4":
            self.sink.error(
                src.value_loc(root, "BTCPP_format"),
                f'BTCPP_format="{fmt}" is not supported; btgen reads BehaviorTree.CPP v4 files (BTCPP_format="4")',
            )
        if root.get("main_tree_to_execute") is not None:
            self.sink.error(
                src.attr_loc(root, "main_tree_to_execute"),
                "a models file does not choose the tree to run; main_tree_to_execute belongs to the mission "
                "(or --main-tree)",
            )
        for child in root:
            if not isinstance(child.tag, str):
                continue
            if child.tag == "TreeNodesModel":
                before = len(self.models)
                self._read_models(child, src)
                self.palette_subtrees.extend(m for m in self.models[before:] if m.kind == "SubTree")
            else:
                self.sink.error(
                    src.loc(child),
                    f"a models file (--models) holds only <TreeNodesModel>, not "
                    f"<{child.tag}>; pass a mission as the mission, or include it "
                    f"with <include path=...>",
                )

    def _include(self, elem: etree._Element, src: Source, stack: tuple[str, ...]) -> None:
        loc = src.loc(elem)
        rel = elem.get("path")
        base_real = os.path.dirname(stack[-1])
        base_shown = os.path.dirname(src.path)
        if elem.get("ros_pkg") is not None:  # the package's folder, where ROS would find it
            from btgen.frontend import ros_packages

            pkg = elem.get("ros_pkg") or ""
            folder = ros_packages.find(pkg, self.ros_packages)
            if folder is None:
                self.sink.error(src.attr_loc(elem, "ros_pkg"), ros_packages.not_found(pkg, self.ros_packages))
                return
            base_real = base_shown = folder
        target_real = os.path.realpath(os.path.join(base_real, rel))
        target_shown = os.path.normpath(os.path.join(base_shown, rel))
        if target_real in stack:
            chain = " -> ".join(
                [os.path.basename(p) for p in stack[stack.index(target_real) :]] + [os.path.basename(target_real)]
            )
            self.sink.error(src.value_loc(elem, "path"), f"include cycle: {chain}")
            return
        if len(stack) >= MAX_INCLUDE_DEPTH:
            self.sink.error(loc, f"includes nested deeper than {MAX_INCLUDE_DEPTH} files")
            return
        if not os.path.isfile(target_real):
            why = (
                "is a directory, not a mission file"
                if os.path.isdir(target_real)
                else "is not a regular file"
                if os.path.exists(target_real)
                else f"not found (looked for {target_shown})"
            )
            self.sink.error(src.value_loc(elem, "path"), f"included file `{rel}` {why}")
            return
        if target_shown in self._shown_files:
            return  # included twice along different paths: its trees are already known
        try:
            self._load_file(target_real, target_shown, stack, loc)
        except UserError as e:
            self.sink.items.extend(e.diagnostics)

    # --------------------------------------------------------------- models
    def _read_models(self, elem: etree._Element, src: Source) -> None:
        known = {m.id: m for m in self.models}
        for m in elem:
            if not isinstance(m.tag, str):
                continue
            kind, mid, loc = m.tag, m.get("ID"), src.loc(m)
            if mid in self.builtins and mid in nav2.ALL_FAMILY_IDS and self.nav2 is not None:
                continue  # Nav2's models file documents the Nav2 nodes btgen builds in
            if mid in self.builtins:
                # 4.6.2 never reads leaf, control or decorator models from XML: the
                # registered node, here the built-in, is what runs.
                self.sink.warning(
                    src.value_loc(m, "ID"),
                    f"`{mid}` is a built-in node of BehaviorTree.CPP: this declaration is ignored "
                    f"and the built-in `{mid}` is used",
                )
                continue
            # A SubTree model names a tree (`IV_VisitExhibit`); the trace prints `SubTree` for it.
            bad = _ID_FORBIDDEN.search(mid or "") if kind != "SubTree" else None
            if bad:
                what = {
                    " ": "a space",
                    "\t": "a tab",
                    "\n": "a line break",
                    "\r": "a carriage return",
                    '"': '`"`',
                    "\\": "`\\`",
                }.get(bad.group(0), "white space")
                self.sink.error(
                    src.value_loc(m, "ID"),
                    f"node ID `{mid}` contains {what}: node IDs contain no "
                    f'white space, `"` or `\\` (they appear unquoted in '
                    f"status traces)",
                )
                continue
            if mid in RESERVED_MODEL_IDS and kind != "SubTree":
                self.sink.error(
                    src.value_loc(m, "ID"),
                    f"`{mid}` cannot be a node ID: <{mid}> is an element of the file format itself",
                )
                continue
            ports: list[PortSpec] = []
            for p in m:
                if not isinstance(p.tag, str) or p.tag == "MetadataFields":
                    continue  # Groot2's <MetadataFields><Metadata .../></MetadataFields>: for the editor only
                port = self._read_model_port(p, src, mid, ports)
                if port:
                    ports.append(port)
            lo, hi = KIND_CHILDREN[kind]
            spec = NodeSpec(mid, kind, tuple(ports), False, lo, hi, (m.text or "").strip(), loc)
            if mid in known:
                # The same model declared again (a Groot2 project split over files, a
                # models file beside a mission that declares it too) is the same model;
                # only a declaration that differs is an error.
                conflict = model_conflict(known[mid], spec)
                if conflict and "SubTree" in (kind, known[mid].kind):
                    self.sink.error(
                        src.value_loc(m, "ID"),
                        f"`{mid}` is declared twice in TreeNodesModel and "
                        f"the declarations differ: {conflict} (first at "
                        f"{known[mid].loc})",
                    )
                elif conflict:
                    # The library never reads the model of a node it has registered (recorded on
                    # 4.6.2 and 4.10.0: a mission and its include declaring `Say` differently load).
                    self.sink.warning(
                        src.value_loc(m, "ID"),
                        f"`{mid}` is declared twice in TreeNodesModel and "
                        f"the declarations differ: {conflict} (first at "
                        f"{known[mid].loc}); BehaviorTree.CPP never reads the models of the nodes "
                        f"it registers: btgen takes the ports of both (untyped where the types differ)",
                    )
                    merged = merged_model(known[mid], spec)
                    self.models[self.models.index(known[mid])] = merged
                    known[mid] = merged
                continue
            known[mid] = spec
            self.models.append(spec)

    def _read_model_port(self, p: etree._Element, src: Source, mid: str, ports: list[PortSpec]) -> Optional[PortSpec]:
        name = p.get("name")
        loc = src.value_loc(p, "name")
        bad = not _PORT_NAME_RE.match(name) or name in RESERVED_PORT_NAMES
        parent = p.getparent()
        unchecked = bad and parent is not None and parent.tag == "SubTree" and not self.sem.name_validation_484
        if unchecked and name in RESERVED_PORT_NAMES:  # (`ID`, `name`: the SubTree element's own)
            self.sink.warning(
                loc,
                f"port `{name}` of SubTree model `{mid}` can never be given (not a valid port "
                f"name): BehaviorTree.CPP {self.btcpp} ignores it, btgen too (refused from 4.8.4)",
            )
            return None
        if unchecked:
            # 4.6.2 stores a SubTree model's ports unchecked (validatePortName is 4.8.4), and no
            # attribute can give this one: recorded on 4.6.2, without a default it is a mandatory
            # port no instance remaps (refused unless `_autoremap`), with one the SubTree loads.
            self.sink.warning(
                loc,
                f"port `{name}` of SubTree model `{mid}` can never be given (not a valid port "
                f"name): BehaviorTree.CPP {self.btcpp} keeps it all the same (refused from 4.8.4)",
            )
        elif not _PORT_NAME_RE.match(name):
            self.sink.error(
                loc, f"invalid port name `{name}` in `{mid}`: use letters, digits and `_`, not starting with a digit"
            )
            return None
        elif name in RESERVED_PORT_NAMES:
            self.sink.error(loc, f"`{name}` is reserved and cannot be a port name (in `{mid}`)")
            return None
        if any(q.name == name for q in ports):
            self.sink.error(loc, f"port `{name}` of `{mid}` is declared twice")
            return None
        type_text = p.get("type")
        type_name = values.normalize_type(type_text) if type_text is not None else "any"
        int_width = _int_width(type_text)
        default = p.get("default")
        if p.tag == "bidirectional_port":
            self.sink.warning(
                src.loc(p),
                f"<bidirectional_port> (port `{name}` of `{mid}`) is not an element of "
                f"BehaviorTree.CPP's models; btgen reads it as <inout_port>",
            )
        direction = _MODEL_PORT_TAGS[p.tag]
        default_problem = ""
        if default is not None and direction != "output" and not is_remap(default):
            try:
                values.convert_from_string(type_name, default, double_from_chars=self.sem.double_from_chars)
            except values.ConversionError as e:
                # A model in XML documents a node registered in C++ (4.6.2 reads the default
                # of providedPorts(), never this text): keep it, and report it only where a
                # node of this mission would use it.
                default_problem = f"{e}"
                self.sink.warning(
                    src.value_loc(p, "default"),
                    f"default of port `{name}` of `{mid}`: {e}; btgen keeps it as documentation "
                    f"and gives a node that leaves the port unset no default (its code finds the "
                    f"port unset; BehaviorTree.CPP uses the default of the C++ providedPorts())",
                )
            else:  # read as 4.6.2 reads it (a number's prefix), with a warning where lenient
                self._check_literal(
                    src.value_loc(p, "default"), f"default of port `{name}` of `{mid}`", type_name, default, int_width
                )
        return PortSpec(
            name,
            direction,
            type_name,
            None if default_problem else default,
            False,
            (p.text or "").strip(),
            src.loc(p),
            default_problem=default_problem,
            int_width=int_width,
        )

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

    def _tree_root(self, elem: etree._Element, src: Source, tree_id: str) -> Node:
        self._warn_text(elem, src)
        kids = [c for c in elem if isinstance(c.tag, str)]
        if len(kids) != 1:
            self.sink.error(src.loc(elem), f"BehaviorTree `{tree_id}` must have exactly 1 child, it has {len(kids)}")
            if not kids:
                return Node("AlwaysFailure", "Action", None, (), (), (), (), src.loc(elem))
        return self._node(kids[0], src)

    def _node(self, elem: etree._Element, src: Source) -> Node:
        tag, loc = elem.tag, src.loc(elem)
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
            self._check_key(attr, value, what)
            return attr
        if (spec.id, attr.name) in version_rules.LOOP_QUEUE_PORTS:
            version_rules.check_literal_queue(self.sink, attr, spec.id, self.sem)
            return attr
        if port.direction == "output" or (port.direction == "inout" and not port.type.startswith("queue<")):
            # 4.6.2's setOutput only writes through `{key}`; a literal would silently write nothing.
            self.sink.error(
                attr.value_loc,
                f"{what} is an {port.direction} port and must name a blackboard "
                f"entry as `{{key}}` (or `{{=}}`), not the literal `{value}`",
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
        from btgen.frontend.xsd import mission_schema, validate_against_mission_xsd

        schema = mission_schema(mission)
        for src in self.sources:
            for d in validate_against_mission_xsd(mission, src, schema):
                # attributes the library ignores (not port names) were reported, if at all, above
                m = re.fullmatch(r"attribute `(.+)` is not allowed here", d.message)
                ignored = m is not None and (
                    m.group(1).startswith("_") or not version_rules.is_port_name(m.group(1), self.sem)
                )
                if not ignored:
                    self.sink.items.append(d)


def merged_model(first: NodeSpec, second: NodeSpec) -> NodeSpec:
    """One model of two declarations of a registered node that differ: the first's kind, place and
    port directions, every port of either; a port declared with two types is untyped (`any`), with
    two defaults without one."""
    ports = []
    for a in first.ports:
        b = second.port(a.name)
        if b is not None and b != a:
            a = dataclasses.replace(
                a,
                type=a.type if a.type == b.type else "any",
                default=a.default if a.default == b.default else None,
                required=a.required and b.required,
            )
        ports.append(a)
    ports += [b for b in second.ports if first.port(b.name) is None]
    return dataclasses.replace(first, ports=tuple(ports))


def model_conflict(first: NodeSpec, second: NodeSpec) -> str:
    """How two TreeNodesModel declarations of one ID differ ("" when they declare the
    same model: same kind, same ports with the same directions, types and defaults)."""
    if first.kind != second.kind:
        return f"<{first.kind}> there, <{second.kind}> here"
    a, b = {p.name: p for p in first.ports}, {p.name: p for p in second.ports}
    for name in sorted(set(a) | set(b)):
        if name not in b:
            return f"port `{name}` there, not here"
        if name not in a:
            return f"port `{name}` here, not there"
        pa, pb = a[name], b[name]
        if pa.direction != pb.direction:
            return f"port `{name}` is an {pa.direction} port there, an {pb.direction} port here"
        if pa.type != pb.type:
            return f"port `{name}` has type `{pa.type}` there, `{pb.type}` here"
        if pa.default != pb.default:

            def show(d: Optional[str]) -> str:
                return "no default" if d is None else f"default `{d}`"

            return f"port `{name}` has {show(pa.default)} there, {show(pb.default)} here"
    return ""


def files_read(
    path: str,
    models: Sequence[str] = (),
    main_tree: Optional[str] = None,
    trees: Sequence[str] = (),
    btcpp: str = DEFAULT_VERSION,
) -> list[str]:
    """The files loading the mission reads: the mission, its includes, the models files and
    the --trees files, also when it does not load (a build system then keeps depending on an
    include that stopped loading, and the build reports its errors instead of keeping a
    stale output)."""
    loader = _Loader(path, models, main_tree, trees, btcpp)
    with contextlib.suppress(UserError):
        loader.load()
    read = list(loader.files)
    return read + [m for m in models if m not in read]


def load_mission(
    path: str,
    models: Sequence[str] = (),
    main_tree: Optional[str] = None,
    trees: Sequence[str] = (),
    btcpp: str = DEFAULT_VERSION,
    ros_packages: Sequence[tuple[str, str]] = (),
    nodes: Optional[str] = None,
) -> Mission:
    """Read, validate and model a mission; raises UserError with every problem found.

    `models`: files whose root holds only <TreeNodesModel> (`--models`); their
    declarations count as the mission's. `main_tree`: the tree to run
    (`--main-tree`), overriding main_tree_to_execute. `trees`: files or folders of
    BehaviorTrees the mission's SubTrees may use (`--trees`). `btcpp`: the release to follow (lang/versions.py).
    `ros_packages`: folders of ROS packages for <include ros_pkg=...> (frontend/ros_packages.py).
    `nodes`: `--nodes` (lang/nav2.py NODES_CHOICES); None: Nav2's nodes when a models file is Nav2's."""
    return _Loader(path, models, main_tree, trees, btcpp, ros_packages, nodes).load()
