"""Sources and includes: the mission file, its <include>s (paths, `ros_pkg`, cycles, depth),
tree libraries (`--trees`), and the load that puts the parts together (load_mission)."""

from __future__ import annotations

import contextlib
import dataclasses
import os
from collections.abc import Sequence
from typing import Optional

from lxml import etree

from btgen.diagnostics import Loc, UserError, suggestion
from btgen.fileio import xml_files_of
from btgen.frontend.hints import unmapped_subtree_ports
from btgen.frontend.loader.base import MAX_INCLUDE_DEPTH
from btgen.frontend.loader.models import ModelsReader
from btgen.frontend.xmlsource import Source, read_source
from btgen.lang import nav2
from btgen.lang.model import Mission, TreeDef
from btgen.lang.nav2 import builtins_for
from btgen.lang.versions import DEFAULT_VERSION


class _Loader(ModelsReader):
    # ---------------------------------------------------------------- files
    def load(self) -> Mission:
        try:
            return self._load()
        except UserError as e:
            raise UserError(self._sorted(e.diagnostics)) from None

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
        created = self._created_trees(main)
        built: list[TreeDef] = []
        for tid, elem, src in self.tree_elems:
            if tid not in tree_ids:
                continue
            mark = len(self.sink.items)
            tree = TreeDef(tid, self._tree_root(elem, src, tid), src.loc(elem))
            if tid not in created:
                last = max((self._line_of(e, src) for e in elem.iter() if isinstance(e.tag, str)), default=0)
                self.uncreated.append((tid, src.loc(elem).path, src.loc(elem).line, last))
            if tid in created or not self._left_out(tid, mark):
                built.append(tree)
        trees = tuple(built)
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
            files = xml_files_of(path)
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
    palettes: Sequence[str] = (),
) -> Mission:
    """Read, validate and model a mission; raises UserError with every problem found.

    `models`: files whose root holds only <TreeNodesModel> (`--models`); their
    declarations count as the mission's. `main_tree`: the tree to run
    (`--main-tree`), overriding main_tree_to_execute. `trees`: files or folders of
    BehaviorTrees the mission's SubTrees may use (`--trees`). `btcpp`: the release to follow (lang/versions.py).
    `ros_packages`: folders of ROS packages for <include ros_pkg=...> (frontend/ros_packages.py).
    `nodes`: `--nodes` (lang/nav2.py NODES_CHOICES); None: Nav2's nodes when a models file is Nav2's.
    `palettes`: those of `models` found in the project by `btgen check`, whose SubTree models may name
    trees of other missions (a SubTree model of a file given with `--models` must name one of this one)."""
    loader = _Loader(path, models, main_tree, trees, btcpp, ros_packages, nodes)
    loader.palettes = {os.path.realpath(p) for p in palettes}
    return loader.load()
