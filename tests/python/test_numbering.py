"""One numbering of the nodes (ir/numbering.py), used by every stage that says "node i"."""

from __future__ import annotations

import ast
import re
from pathlib import Path

from btgen.frontend.loader import load_mission
from btgen.ir.lower import creation_order, lower
from btgen.ir.numbering import number_nodes
from btgen.tools.graph import walk
from conftest import ROOT

PACKAGE = Path(ROOT) / "generator" / "btgen"

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="a := 1"/>
      <SubTree ID="Inner" name="first" x="{a}"/>
      <Fallback>
        <SubTree ID="Inner" x="{a}"/>
        <AlwaysFailure/>
      </Fallback>
      <SubTree ID="Outer"/>
      <Script code="a += 1"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Outer">
    <Sequence>
      <SubTree ID="Inner" x="7"/>
      <Script code="b := 'hello'"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Inner">
    <Sequence>
      <Script code="y := x"/>
      <ScriptCondition code="y != 0"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def _mission(tmp_path: Path):
    path = tmp_path / "m.xml"
    path.write_text(MISSION)
    return load_mission(str(path))


def test_creation_order_is_depth_first_subtree_before_its_tree(tmp_path):
    numbering = number_nodes(_mission(tmp_path))
    assert [(n.uid, n.reg_id, n.tree, n.instance) for n in numbering] == [
        (1, "Sequence", "Main", -1),
        (2, "Script", "Main", -1),
        (3, "SubTree", "Main", -1),
        (4, "Sequence", "Inner", 2),
        (5, "Script", "Inner", 2),
        (6, "ScriptCondition", "Inner", 2),
        (7, "Fallback", "Main", -1),
        (8, "SubTree", "Main", -1),
        (9, "Sequence", "Inner", 7),
        (10, "Script", "Inner", 7),
        (11, "ScriptCondition", "Inner", 7),
        (12, "AlwaysFailure", "Main", -1),
        (13, "SubTree", "Main", -1),
        (14, "Sequence", "Outer", 12),
        (15, "SubTree", "Outer", 12),
        (16, "Sequence", "Inner", 14),
        (17, "Script", "Inner", 14),
        (18, "ScriptCondition", "Inner", 14),
        (19, "Script", "Outer", 12),
        (20, "Script", "Main", -1),
    ]
    assert numbering[0].children == (1, 2, 6, 12, 19)
    assert numbering[2].children == (3,)  # a SubTree node's child: the root of its tree
    assert numbering.instance_paths() == {-1: "", 2: "first", 7: "Inner::8", 12: "Outer::13", 14: "Outer::13/Inner::15"}


def test_every_stage_numbers_nodes_alike(tmp_path):
    """The node table, the data analysis, the Groot2 tree and `btgen graph` all speak of
    the nodes by the one numbering."""
    mission = _mission(tmp_path)
    numbering = number_nodes(mission)
    program = lower(mission)
    assert [(n.index, n.uid, n.id, n.name, n.parent, n.children) for n in program.nodes] == [
        (n.index, n.uid, n.reg_id, n.node.display_name, n.parent, n.children) for n in numbering
    ]
    assert creation_order(mission) == [(n.uid, n.reg_id, n.node.display_name) for n in numbering]
    # scripts: each ScriptIR names its node by index, and the code is that node's
    assert program.data is not None and program.groot2 is not None
    by_node = {(s.node, s.script.code) for s in program.data.scripts}
    expected = {
        (n.index, n.node.port("code").value)  # type: ignore[union-attr]
        for n in numbering
        if n.reg_id in ("Script", "ScriptCondition")
    }
    assert by_node == expected
    # Groot2: each instance's nodes, and each node's _uid in document order per instance
    groot = program.groot2
    assert [i.nodes for i in groot.instances] == [
        tuple(n.index for n in numbering if n.instance == inst) for inst in numbering.instances()
    ]
    assert [i.path for i in groot.instances] == list(numbering.instance_paths().values())
    uids = [int(u) for u in re.findall(r'_uid="(\d+)"', groot.xml)]
    assert uids == [n.uid for inst in numbering.instances() for n in numbering if n.instance == inst]
    # btgen graph
    nodes, clusters = walk(mission)
    assert [(g.uid, g.parent) for g in nodes] == [(n.uid, n.parent + 1) for n in numbering]
    assert [path for _, path in clusters] == list(numbering.instance_paths().values())


def _walks_subtrees(path: Path) -> bool:
    """Does the module follow a SubTree node into its tree (`….tree(<node>.target)`)?"""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "tree":
            if any(isinstance(a, ast.Attribute) and a.attr == "target" for a in node.args):
                return True
    return False


def test_only_numbering_walks_the_expanded_tree():
    """The stages after the front end never number nodes themselves: they read ir/numbering.py.
    (lang/model.py visits each tree once to find the models used, and the interpreter builds its
    own running tree: neither numbers nodes for the generated code.)"""
    walkers = {
        str(p.relative_to(PACKAGE))
        for layer in ("ir", "backend_cpp", "tools")
        for p in (PACKAGE / layer).rglob("*.py")
        if _walks_subtrees(p)
    }
    walkers |= {str(p.relative_to(PACKAGE)) for p in PACKAGE.glob("*.py") if _walks_subtrees(p)}
    assert walkers == {"ir/numbering.py"}
