"""Models: models files (`--models`) and <TreeNodesModel> declarations, read into NodeSpecs;
a node declared twice (merged_model, model_conflict)."""

from __future__ import annotations

import dataclasses
import os
from typing import Optional

from lxml import etree

from btgen.diagnostics import Loc, UserError
from btgen.frontend.loader.base import (
    _ID_FORBIDDEN,
    _MODEL_PORT_TAGS,
    _PORT_NAME_RE,
    RESERVED_MODEL_IDS,
    _int_width,
    is_remap,
)
from btgen.frontend.loader.checks import MissionChecks
from btgen.frontend.xmlsource import Source, read_source
from btgen.lang import nav2, values
from btgen.lang.catalogue import (
    KIND_CHILDREN,
    RESERVED_PORT_NAMES,
    NodeSpec,
    PortSpec,
)


class ModelsReader(MissionChecks):
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
                if os.path.realpath(path) not in self.palettes:
                    self.palette_subtrees.extend(m for m in self.models[before:] if m.kind == "SubTree")
            else:
                self.sink.error(
                    src.loc(child),
                    f"a models file (--models) holds only <TreeNodesModel>, not "
                    f"<{child.tag}>; pass a mission as the mission, or include it "
                    f"with <include path=...>",
                )

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
                    f"node ID `{mid}` contains {what}: node IDs contain no tab, "
                    f'line break, `"` or `\\` (they appear unquoted in '
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
                if conflict and "SubTree" in (kind, known[mid].kind) and os.path.realpath(src.path) in self.palettes:
                    # a models file `btgen check` found in the project, which the library never reads:
                    # the mission's own SubTree model counts
                    self.sink.warning(
                        src.value_loc(m, "ID"),
                        f"`{mid}` is declared twice in TreeNodesModel and the declarations differ: {conflict} "
                        f"(first at {known[mid].loc}); BehaviorTree.CPP never reads this models file: the "
                        f"first declaration counts",
                    )
                    continue
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
