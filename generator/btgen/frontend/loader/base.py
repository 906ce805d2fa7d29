"""The loader's state and what every part of it uses: limits, the name patterns, the
`{key}` reading of a port value, and the files read so far (their order sorts diagnostics)."""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from typing import Optional

from lxml import etree

from btgen.diagnostics import DiagnosticSink
from btgen.frontend.hints import SiblingIndex
from btgen.frontend.xmlsource import Source
from btgen.lang import blackboard as bbmod
from btgen.lang import nav2, values
from btgen.lang.catalogue import (
    NodeSpec,
)
from btgen.lang.nav2 import builtins_for
from btgen.lang.versions import DEFAULT_VERSION, semantics

MAX_INCLUDE_DEPTH = 32
MAX_NODES = 65535  # BehaviorTree.CPP UIDs are 16-bit (see also the instance count check)

_KEY_RE = re.compile(r"^@?[A-Za-z_][A-Za-z0-9_.\-:]*$")
_PORT_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_SUBTREE_REMAP_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+)*$")
# FORMAT.md: node IDs contain no tab, line break, `"` or `\` (the trace prints them unquoted and
# a line of it must read back); a space loads (`<Action ID="Grasp Cup"/>`, recorded on 4.6.2 and
# 4.10.0: tests/conformance/both-releases/space_in_node_id).
_ID_FORBIDDEN = re.compile(r'[^\S ]|["\\]')
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


class LoaderBase:
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
        self.palettes: set[str] = set()  # real paths of the models files that are a project's palette
        self.siblings = SiblingIndex(self.files)
        # (tree ID, file, first line, last line) of each BehaviorTree the main tree never runs
        self.uncreated: list[tuple[str, str, int, int]] = []
        self.left_out: set[str] = set()  # those of them left out of the mission (loader errors)
        self.undeclared: list[int] = []  # sink indexes of unknown nodes in a mission without models
        self.anonymous = 0  # <BehaviorTree> elements without ID so far

    def _position(self, i: int) -> tuple[int, int, int]:
        d = self.sink.items[i]
        return (self._shown_files.get(d.loc.path, len(self.files)), d.loc.line, d.loc.col)

    def _sorted(self, diags):
        order = {f: i for i, f in enumerate(self.files)}
        return sorted(diags, key=lambda d: (order.get(d.loc.path, len(order)), d.loc.line, d.loc.col))

    def _add_file(self, shown: str) -> None:
        self._shown_files.setdefault(shown, len(self.files))
        self.files.append(shown)
        self._real_files.add(os.path.realpath(shown))

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
