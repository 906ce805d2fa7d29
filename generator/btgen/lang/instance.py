"""How BehaviorTree.CPP 4.6.2 turns an XML element into a node instance's ports.

One copy of the load-time rules that both engines need (the interpreter builds its
nodes with them, ir/dataflow.py types the blackboard with them); written once so
that the engines cannot drift apart. Each function names the 4.6.2 code it follows
(docs/btcpp-4.6.2-edges.md, rows M1 and M2).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from btgen.lang import blackboard as bbmod
from btgen.lang import values
from btgen.lang.catalogue import PortSpec
from btgen.lang.model import Attr, Mission, Node, SubTreeNode


def has_default(port: PortSpec) -> bool:
    """4.6.2 tests `defaultValueString().empty()`: `default=""` is no default at all
    (xml_parsing.cpp, createNodeFromXML and recursivelyCreateSubtree)."""
    return port.default is not None and port.default != ""


@dataclass(frozen=True)
class PortText:
    """A port of an instance: its text (written, or the model's default), where it was
    written (None for a default) and its declaration (None when the model has none)."""

    name: str
    raw: str
    attr: Optional[Attr]
    spec: Optional[PortSpec]


def instance_ports(mission: Mission, model: Node) -> list[PortText]:
    """createNodeFromXML: the written ports, then the model's defaults for the others (an
    input port takes any default, an output port only a `{key}` one)."""
    try:
        spec = mission.spec(model.id)
    except KeyError:
        spec = None
    ports: list[PortText] = []
    given = set()
    for a in model.ports:
        ps = spec.port(a.name) if spec is not None else None
        raw = a.value
        if (
            raw == ""
            and ps is not None
            and has_default(ps)
            and ps.type not in ("string", "any", values.NODE_STATUS)
            and not values.is_opaque_type(ps.type)
        ):
            # (not a NodeStatus port: an empty `else` / `if_empty` throws where the node reads it,
            # recorded: tests/conformance/oracle-diff/status_literal_empty)
            assert ps.default is not None
            raw = ps.default  # TreeNode::getInput: an empty value reads the model's (non-string) default
        ports.append(PortText(a.name, raw, a, ps))
        given.add(a.name)
    if spec is not None:
        for ps in spec.ports:
            if ps.name in given or not has_default(ps):
                continue
            assert ps.default is not None
            if ps.direction != "output" or bbmod.is_blackboard_pointer(ps.default):
                ports.append(PortText(ps.name, ps.default, None, ps))
    return ports


def subtree_remapping(mission: Mission, model: SubTreeNode) -> tuple[list[tuple[str, str, Optional[Attr]]], list[str]]:
    """recursivelyCreateSubtree: every attribute of the SubTree element is a remapping
    (or a constant), whether the SubTree's model declares it or not (M1); then each port
    of the model the element does not give takes its default. Returns the remapping
    (name, text, attribute or None for a default) and the model's ports that have no
    default and are not given, which 4.6.2 refuses (M2); `_autoremap` skips the model."""
    model_spec = next((m for m in mission.models if m.id == model.target and m.kind == "SubTree"), None)
    remap: list[tuple[str, str, Optional[Attr]]] = [(a.name, a.value, a) for a in model.ports]
    missing: list[str] = []
    if model_spec is not None and not model.autoremap:
        given = {a.name for a in model.ports}
        for ps in model_spec.ports:
            if ps.name in given:
                continue
            if not has_default(ps):
                missing.append(ps.name)
                continue
            assert ps.default is not None
            remap.append((ps.name, ps.default, None))
    return remap, missing
