"""What BehaviorTree.CPP 4.6.2 loads and btgen used to refuse: models written for editors or
for documentation, editor attributes, anonymous trees. Each is loaded, with a warning where
btgen assumes something (the traces of the runnable ones are in tests/regressions/, recorded
on the real 4.6.2)."""

import pytest

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission


def write(tmp_path, text, name="m.xml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def warnings_of(path, **kw):
    return [str(w) for w in load_mission(path, **kw).warnings]


def test_bidirectional_port_is_an_inout_port(tmp_path):
    p = write(
        tmp_path,
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M"><Keep idx="{i}"><AlwaysSuccess/></Keep></BehaviorTree>\n'
        '  <TreeNodesModel>\n    <Control ID="Keep">\n'
        '      <bidirectional_port name="idx" type="int">Index</bidirectional_port>\n'
        "    </Control>\n  </TreeNodesModel>\n</root>\n",
    )
    m = load_mission(p)
    port = m.spec("Keep").port("idx")
    assert port is not None and port.direction == "inout" and port.type == "int"
    assert [str(w) for w in m.warnings] == [
        f"{p}:5:7: warning: <bidirectional_port> (port `idx` of `Keep`) is not an element of "
        f"BehaviorTree.CPP's models; btgen reads it as <inout_port>"
    ]


def test_default_that_does_not_convert_is_documentation(tmp_path):
    # Nav2's nav2_tree_nodes.xml: default="numeric_limits<double>::infinity()"
    p = write(
        tmp_path,
        '<root BTCPP_format="4">\n'
        '  <BehaviorTree ID="M"><Sequence><Trunc/><Trunc dist="2.5"/></Sequence></BehaviorTree>\n'
        '  <TreeNodesModel>\n    <Action ID="Trunc">\n'
        '      <input_port name="dist" type="double" default="numeric_limits&lt;double&gt;::infinity()"/>\n'
        "    </Action>\n  </TreeNodesModel>\n</root>\n",
    )
    m = load_mission(p)
    [w] = [str(w) for w in m.warnings]
    assert w.startswith(f"{p}:5:54: warning: default of port `dist` of `Trunc`: ")
    assert "BehaviorTree.CPP uses the default of the C++ providedPorts()" in w
    assert m.spec("Trunc").port("dist").default is None
    from btgen.ir.lower import lower

    lower(m)  # compiles: a node leaving the port unset gets no default


def test_behavior_tree_attributes_are_ignored(tmp_path):
    p = write(
        tmp_path,
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M" _favorite="true" _hardcoded="false" goal="{goal}">\n'
        '    <AlwaysSuccess _collapsed="true" _external="x"/>\n  </BehaviorTree>\n</root>\n',
    )
    assert warnings_of(p) == [
        f"{p}:2:60: warning: attribute `goal` of <BehaviorTree> is ignored: BehaviorTree.CPP reads "
        f"only `ID` there (a SubTree's ports and their defaults are declared in <TreeNodesModel>)"
    ]


def test_anonymous_tree_alone_in_its_file_is_the_main_tree(tmp_path):
    p = write(tmp_path, '<root BTCPP_format="4"><BehaviorTree><AlwaysSuccess/></BehaviorTree></root>')
    m = load_mission(p)
    assert m.main_tree == "BehaviorTree_0" and [t.id for t in m.trees] == ["BehaviorTree_0"]


def test_anonymous_tree_with_siblings_is_refused(tmp_path):
    p = write(
        tmp_path,
        '<root BTCPP_format="4">\n<BehaviorTree><AlwaysSuccess/></BehaviorTree>\n'
        '<BehaviorTree ID="B"><AlwaysSuccess/></BehaviorTree>\n</root>',
    )
    with pytest.raises(UserError) as e:
        load_mission(p)
    assert [str(d) for d in e.value.diagnostics] == [
        f"{p}:2:1: error: <BehaviorTree> needs an ID attribute: BehaviorTree.CPP accepts a tree "
        f"without one only when it is the only element of its file"
    ]


def test_shared_blackboard_of_v3_is_named(tmp_path):
    p = write(
        tmp_path,
        '<root BTCPP_format="4" main_tree_to_execute="M">\n'
        '  <BehaviorTree ID="M"><SubTree ID="S" __shared_blackboard="true"/></BehaviorTree>\n'
        '  <BehaviorTree ID="S"><AlwaysSuccess/></BehaviorTree>\n</root>\n',
    )
    [w] = warnings_of(p)
    assert w.startswith(f"{p}:2:40: warning: `__shared_blackboard` is BehaviorTree.CPP v3's and v4 ignores it")
