"""Blackboards, remapping and port access, checked against BehaviorTree.CPP 4.6.2."""

import pytest

from btgen.lang.blackboard import (
    Blackboard,
    BlackboardError,
    Entry,
    create_port_entry,
    get_input,
    is_blackboard_pointer,
    remapped_key,
    set_blackboard,
    set_output,
    strip_blackboard_pointer,
)
from btgen.lang.script import evaluate, parse_script
from btgen.lang.status import NodeStatus
from btgen.lang.values import Queue


def run(bb, code):
    return evaluate(parse_script(code), bb)


def state(entry):
    return (entry.type_name, entry.value, entry.sequence_id)


# ----------------------------------------------------------------- look-up


def test_lookup_order_local_then_remapping_then_autoremap():
    root = Blackboard()
    root.set("target", "kitchen")
    root.set("visits", 3)
    child = Blackboard(root)
    child.add_remapping("goal", "target")
    assert child.get_entry("goal") is root.get_entry("target")
    assert child.get_entry("visits") is None  # no autoremap: isolated
    auto = Blackboard(root, autoremap=True)
    assert auto.get_entry("visits") is root.get_entry("visits")
    auto.set("visits", "local")  # not yet local: created through autoremap, so in the parent
    assert root.get("visits") == "local"
    assert auto.local_keys() == ()
    assert child.get_entry("nothing") is None


def test_local_entry_shadows_the_parent_and_at_reaches_the_root():
    # root_blackboard_at: `visits` inside the subtree is local, `@visits` the root's.
    root = Blackboard()
    run(root, "visits := 0; log := 'log'")
    mid = Blackboard(root, autoremap=True)
    sub = Blackboard(mid)
    run(sub, "visits := 100; log := 'local'")
    run(sub, "@visits += 1; @log := @log .. '+' .. 'lab'")
    assert sub.get("visits") == 100 and sub.get("log") == "local"
    assert root.get("visits") == 1 and root.get("log") == "log+lab"
    assert sub.get_entry("@visits") is root.get_entry("visits")


def test_private_keys_are_not_autoremapped():
    # blackboard.cpp IsPrivateKey: autoremapping skips keys starting with `_`.
    root = Blackboard()
    root.set("_secret", 1)
    sub = Blackboard(root, autoremap=True)
    assert sub.get_entry("_secret") is None
    sub.create_entry("_secret", "int")
    assert sub.local_keys() == ("_secret",)
    explicit = Blackboard(root)
    explicit.add_remapping("_secret", "_secret")
    assert explicit.get_entry("_secret") is root.get_entry("_secret")


def test_get_reports_missing_and_unset_values():
    bb = Blackboard()
    bb.create_entry("n", "int")
    with pytest.raises(BlackboardError, match="^no blackboard entry `m`$"):
        bb.get("m")
    with pytest.raises(BlackboardError, match="^blackboard entry `n` has no value yet$"):
        bb.get("n")


# ---------------------------------------------------------------- creation


def test_create_entry_types():
    bb = Blackboard()
    e = bb.create_entry("n", "int")
    assert state(e) == ("int", None, 0)
    assert bb.create_entry("n", "int") is e
    assert bb.create_entry("n", "any") is e  # `any` never conflicts
    with pytest.raises(BlackboardError) as err:
        bb.create_entry("n", "double")
    assert err.value.message == "blackboard entry `n` is declared as int; it cannot be used as double"
    a = bb.create_entry("a", "any")
    assert bb.create_entry("a", "string") is a and a.type_name == "any"


def test_create_entry_follows_at_remapping_and_autoremap():
    root = Blackboard()
    sub = Blackboard(root)
    sub.add_remapping("goal", "target")
    e = sub.create_entry("goal", "string")
    assert root.get_entry("target") is e and sub.local_keys() == ()
    sub.create_entry("@mode", "int")
    assert root.get_entry("mode").type_name == "int"
    auto = Blackboard(sub, autoremap=True)
    auto.create_entry("x", "double")
    assert sub.get_entry("x") is not None and auto.local_keys() == ()
    with pytest.raises(BlackboardError, match="the character `@` may appear only once"):
        sub.create_entry("@a@b", "int")


def test_remapping_to_at_key_creates_on_the_root():
    # 4.6.2 created a literal `@foo` key in the parent here (fixed upstream by #1192).
    root = Blackboard()
    mid = Blackboard(root)
    sub = Blackboard(mid)
    sub.add_remapping("param", "@foo")
    e = sub.create_entry("param", "int")
    assert root.get_entry("foo") is e and mid.local_keys() == ()
    assert sub.get_entry("param") is e


# ------------------------------------------------------------------- set
# blackboard.h Blackboard::set<T>


def test_set_creates_entries_typed_by_the_writer():
    bb = Blackboard()
    assert state(bb.set("s", "hello")) == ("any", "hello", 1)  # a string creates a generic entry
    assert state(bb.set("n", 5)) == ("int", 5, 1)
    assert state(bb.set("d", 2.5)) == ("double", 2.5, 1)
    assert state(bb.set("st", NodeStatus.SUCCESS)) == ("NodeStatus", NodeStatus.SUCCESS, 1)
    assert state(bb.set("u", 7, "unsigned")) == ("unsigned", 7, 1)
    assert state(bb.set("a", "text", "any")) == ("string", "text", 1)  # set<BT::Any> types by the value


def test_set_on_a_generic_entry_fixes_its_type():
    bb = Blackboard()
    bb.set("x", "hello")
    assert state(bb.set("x", 3)) == ("int", 3, 2)
    with pytest.raises(BlackboardError) as err:
        bb.set("x", 2.5)
    assert err.value.message == "blackboard entry `x` is declared as int; it cannot be written with a double"


def test_set_on_a_typed_entry_converts_or_rejects():
    bb = Blackboard()
    bb.create_entry("n", "int")
    assert state(bb.set("n", "42")) == ("int", 42, 1)  # the entry's convertFromString
    assert state(bb.set("n", 7.0)) == ("int", 7, 2)  # isCastingSafe, then copyInto keeps an integer
    assert state(bb.set("n", 9)) == ("int", 9, 3)
    with pytest.raises(BlackboardError) as err:
        bb.set("n", "many")
    assert err.value.message == "cannot write 'many' to `n` (int): `many` is not a valid int"
    with pytest.raises(BlackboardError, match="is declared as int; it cannot be written with a double"):
        bb.set("n", 7.5)
    with pytest.raises(BlackboardError) as err:
        bb.set("n", 2**40)
    assert err.value.message == (
        "cannot write 1099511627776 to `n`: cannot convert 1099511627776 (int) to int: the value is out of range"
    )
    assert bb.get("n") == 9 and bb.get_entry("n").sequence_id == 3
    e = bb.set("n", True)  # isCastingSafe(int, true) holds; the entry keeps its type
    assert state(e) == ("int", 1, 4) and type(e.value) is int
    bb.create_entry("q", "queue<int>")
    q = bb.set("q", "10;20;30").value
    assert isinstance(q, Queue) and list(q) == [10, 20, 30]


def test_set_through_remapping_stores_without_checks_as_4_6_2():
    # Blackboard::set only looks at its own storage: a remapped key goes through
    # createEntryImpl, which returns the parent's entry, and the value is stored as is.
    root = Blackboard()
    root.create_entry("target", "int")
    sub = Blackboard(root)
    sub.add_remapping("goal", "target")
    e = sub.set("goal", "7")
    assert state(e) == ("int", "7", 1) and e is root.get_entry("target")
    assert get_input(sub, "{goal}", "int") == 7  # readers convert the string
    with pytest.raises(BlackboardError, match="declared as int; it cannot be used as double"):
        sub.set("goal", 2.5)


def test_set_with_at_writes_the_root_and_every_write_counts():
    root = Blackboard()
    sub = Blackboard(Blackboard(root))
    sub.set("@last_room", "office")
    sub.set("@last_room", "lab")
    # The first write creates a generic entry; the second gives it the writer's type.
    assert state(root.get_entry("last_room")) == ("string", "lab", 2)


def test_unset_removes_only_local_entries():
    root = Blackboard()
    root.set("target", 4)
    root.unset("target")
    assert root.get_entry("target") is None
    root.unset("never_written")  # no error
    root.set("target", 9)
    assert state(root.get_entry("target")) == ("int", 9, 1)  # a new entry, a new counter
    sub = Blackboard(root)
    sub.add_remapping("t", "target")
    sub.unset("t")
    sub.unset("@target")
    assert root.get("target") == 9


# --------------------------------------------------------------- subtrees
# xml_parsing.cpp recursivelyCreateSubtree


def test_for_subtree_remaps_and_sets_constants():
    root = Blackboard()
    run(root, "target := 'kitchen'; visits := 0")
    sub = Blackboard.for_subtree(root, [("goal", "{target}"), ("visits", "{=}"), ("room", "dock")])
    assert sub.remapping == {"goal": "target", "visits": "visits"}
    assert sub.local_keys() == ("room",)
    assert state(sub.get_entry("room")) == ("any", "dock", 1)
    run(sub, "visits += 1; last_goal := goal")
    assert root.get("visits") == 1 and sub.get("last_goal") == "kitchen"
    assert root.get_entry("last_goal") is None


def test_for_subtree_constants_stay_local_even_with_autoremap():
    root = Blackboard()
    root.set("room", "hall")
    sub = Blackboard.for_subtree(root, [("room", "lab")], autoremap=True)
    assert sub.autoremap and sub.get("room") == "lab" and root.get("room") == "hall"
    run(sub, "first := 1")  # a key first written inside lands in the parent
    assert root.get("first") == 1 and "first" not in sub.local_keys()


def test_nested_subtrees_with_autoremap_share_the_outer_remapping():
    # subtree_remap_nested: GoTo(goal={target}) -> NavigateTo(_autoremap) reads `goal`.
    root = Blackboard()
    run(root, "target := 'kitchen'; visits := 0")
    goto = Blackboard.for_subtree(root, [("goal", "{target}"), ("visits", "{visits}")])
    nav = Blackboard.for_subtree(goto, [], autoremap=True)
    assert evaluate(parse_script("goal != ''"), nav) == 1.0
    assert nav.get_entry("goal") is root.get_entry("target")
    goto2 = Blackboard.for_subtree(root, [("goal", "dock"), ("visits", "{visits}")])
    nav2 = Blackboard.for_subtree(goto2, [], autoremap=True)
    assert nav2.get("goal") == "dock"


# ------------------------------------------------------------ port helpers
# tree_node.h getInputStamped / setOutput, tree_node.cpp isBlackboardPointer


@pytest.mark.parametrize(
    "text, key",
    [
        ("{goal}", "goal"),
        ("  {goal} ", "goal"),
        ("{@mode}", "@mode"),
        ("{ goal }", " goal "),
        ("{}", None),
        ("{a", None),
        ("goal", None),
        ("x{a}", None),
        ("\t{a}", None),
    ],
)
def test_blackboard_pointer(text, key):
    assert strip_blackboard_pointer(text) == key
    assert is_blackboard_pointer(text) == (key is not None)


def test_remapped_key():
    assert remapped_key("value", "{=}") == "value"
    assert remapped_key("value", "=") == "value"
    assert remapped_key("value", "{wp}") == "wp"
    assert remapped_key("value", "3") is None
    with pytest.raises(BlackboardError, match="needs the port name"):
        remapped_key("", "{=}")


def test_get_input_literals():
    bb = Blackboard()
    assert get_input(bb, "3", "int") == 3
    assert get_input(bb, "SKIPPED", "NodeStatus") == NodeStatus.SKIPPED
    assert get_input(bb, "hello", "any") == "hello"
    assert list(get_input(bb, "1;2;3", "queue<int>")) == [1, 2, 3]
    with pytest.raises(BlackboardError) as err:
        get_input(bb, "three", "int", "num_cycles")
    assert err.value.message == "port `num_cycles`: `three` is not a valid int"


def test_get_input_from_entries():
    bb = Blackboard()
    run(bb, "level := 7; ratio := 7.0; zone := 'B'; count_text := '42'")
    assert get_input(bb, "{level}", "string") == "7"  # Any::cast<std::string>
    assert get_input(bb, "{ratio}", "string") == "7.000000"
    assert get_input(bb, "{count_text}", "int") == 42  # a string goes through convertFromString
    assert get_input(bb, "{level}", "double") == 7.0
    assert get_input(bb, "{ratio}", "int") == 7
    assert get_input(bb, "{zone}", "any") == "B"
    assert get_input(bb, "{@level}", "int") == 7
    assert get_input(bb, "{=}", "string", "zone") == "B"
    with pytest.raises(BlackboardError) as err:
        get_input(bb, "{zone}", "int", "variable")
    assert err.value.message == "port `variable` reads blackboard entry `zone`: `B` is not a valid int"
    with pytest.raises(BlackboardError) as err:
        get_input(bb, "{ratio2}", "int", "x")
    assert err.value.message == "port `x` reads blackboard entry `ratio2`, which does not exist"
    bb.create_entry("later", "int")
    with pytest.raises(BlackboardError) as err:
        get_input(bb, "{later}", "int", "x")
    assert err.value.message == "port `x` reads blackboard entry `later`, which has no value yet"
    run(bb, "half := 3.5")
    with pytest.raises(BlackboardError, match="the value is not a whole number"):
        get_input(bb, "{half}", "int")


def test_get_input_shares_a_stored_queue():
    bb = Blackboard()
    bb.create_entry("jobs", "queue<int>")
    bb.set("jobs", "10;20;30")
    q = get_input(bb, "{jobs}", "queue<int>")
    q.popleft()
    assert list(bb.get("jobs")) == [20, 30]


def test_set_output():
    bb = Blackboard()
    set_output(bb, "{wp}", 1, "int", "value")
    set_output(bb, "{wp}", 2, "int", "value")
    assert state(bb.get_entry("wp")) == ("int", 2, 2)
    set_output(bb, "{=}", 0.5, "double", "value")
    assert state(bb.get_entry("value")) == ("double", 0.5, 1)
    set_output(bb, "{anything}", "x", "any")
    assert state(bb.get_entry("anything")) == ("any", "x", 1)
    with pytest.raises(BlackboardError) as err:
        set_output(bb, "wp", 3, "int", "value")
    assert err.value.message == "output port `value` must name a blackboard entry, as `{key}`, not `wp`"


def test_create_port_entry():
    # xml_parsing.cpp createNodeFromXML: entries of {key} ports exist from load time.
    root = Blackboard()
    e = create_port_entry(root, "{wp}", "int", "value")
    assert state(e) == ("int", None, 0)
    assert create_port_entry(root, "{wp}", "int", "value") is e
    assert create_port_entry(root, "{wp}", "any", "x") is e
    assert create_port_entry(root, "3", "int", "num_cycles") is None
    with pytest.raises(BlackboardError) as err:
        create_port_entry(root, "{wp}", "double", "value")
    assert err.value.message == "blackboard entry `wp` was created as int, but port `value` uses it as double"
    root.set("s", "x", "any")  # a string-typed entry may feed any port (converted on reading)
    assert create_port_entry(root, "{s}", "int", "n").type_name == "string"
    sub = Blackboard.for_subtree(root, [("goal", "{target}")])
    g = create_port_entry(sub, "{goal}", "string", "goal")
    assert root.get_entry("target") is g and sub.local_keys() == ()
    m = create_port_entry(sub, "{@mode}", "string", "variable")
    assert root.get_entry("mode") is m
    v = create_port_entry(sub, "{=}", "double", "value")
    assert sub.get_entry("value") is v and v.type_name == "double"


# ------------------------------------------------------------ SetBlackboard


def test_set_blackboard_literal_and_copy():
    # set_blackboard_always: a literal, then a copy, read back by a script.
    bb = Blackboard()
    assert set_blackboard(bb, "greeting", "hello")
    assert state(bb.get_entry("greeting")) == ("any", "hello", 1)
    assert set_blackboard(bb, "copy", "{greeting}")
    assert state(bb.get_entry("copy")) == ("any", "hello", 1)
    assert evaluate(parse_script("copy == 'hello' && greeting == copy"), bb) == 1.0
    assert set_blackboard(bb, "count_text", "42")
    assert evaluate(parse_script("count_text == 42"), bb) == 1.0
    assert set_blackboard(bb, "copy", "{greeting}")
    assert bb.get_entry("copy").sequence_id == 2  # a copy counts as an update (4.7.0, FORMAT.md)


def test_set_blackboard_literals_convert_copies_do_not():
    # loop_int_queue: `jobs` got its type from LoopInt's queue port at load time.
    bb = Blackboard()
    create_port_entry(bb, "{jobs}", "queue<int>", "queue")
    assert set_blackboard(bb, "jobs", "10;20;30")
    assert state(bb.get_entry("jobs")) == ("queue<int>", Queue("int", [10, 20, 30]), 1)
    create_port_entry(bb, "{n}", "int", "value")
    run(bb, "text := '12'")
    assert set_blackboard(bb, "n", "{text}")
    # 4.6.2 copies the string as it is: the int entry holds '12' (conversions/set_copy_*)
    assert state(bb.get_entry("n")) == ("int", "12", 1)
    with pytest.raises(BlackboardError) as err:
        set_blackboard(bb, "n", "lots")
    assert err.value.message == "cannot write 'lots' to `n` (int): `lots` is not a valid int"


def test_set_blackboard_errors_and_empty_source():
    bb = Blackboard()
    with pytest.raises(BlackboardError) as err:
        set_blackboard(bb, "x", "{missing}")
    assert err.value.message == "SetBlackboard: `value` reads blackboard entry `missing`, which does not exist"
    bb.create_entry("empty", "double")
    # 4.6.2 copies the empty value and succeeds (4.7.0 and later fail the node)
    assert set_blackboard(bb, "x", "{empty}") is True
    assert state(bb.get_entry("x")) == ("double", None, 0)
    bb.set("y", 2.5, "double")
    assert set_blackboard(bb, "y", "{empty}") is True
    assert state(bb.get_entry("y")) == ("double", None, 1)  # emptied; its counter stays


def test_set_blackboard_to_the_root():
    root = Blackboard()
    sub = Blackboard.for_subtree(root, [("room", "office")])
    assert set_blackboard(sub, "@last_room", "{room}")
    assert root.get("last_room") == "office"


def test_entry_repr_and_flags():
    e = Entry("NodeStatus")
    assert repr(e) == "Entry('NodeStatus', None, sequence_id=0)"
    assert e.strongly_typed and not e.has_converter  # 4.6.2 gives enums no string converter
    assert not Entry("any").strongly_typed
