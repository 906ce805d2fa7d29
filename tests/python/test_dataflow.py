"""The data side at compile time (dataflow.py): entries resolved to slots, their types and
capacities, and the missions it rejects, each with its exact diagnostics (tests/bad_data)."""

import glob
import os
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.backend_cpp.data_cpp import port_type, slot_init, slot_type
from btgen.backend_cpp.script_cpp import compile_scripts
from btgen.frontend.loader import load_mission
from btgen.ir import dataops as ops
from btgen.ir.data.records import DataOptions
from btgen.ir.dataflow import analyze
from conftest import CASES, ROOT, case_file, conformance_stems

BAD = os.path.join(ROOT, "tests", "bad_data")
BAD_STEMS = sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(BAD, "*.xml")))
# Missions BehaviorTree.CPP loads and throws on when a script runs: compiled, with a warning.
WARNED = os.path.join(ROOT, "tests", "warned_data")
WARNED_STEMS = sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(WARNED, "*.xml")))


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def _mission(body, models="", extra="", main="Main"):
    return (
        f'<root BTCPP_format="4" main_tree_to_execute="{main}"><BehaviorTree ID="Main">{body}</BehaviorTree>'
        f"{extra}<TreeNodesModel>{models}</TreeNodesModel></root>\n"
    )


def _slots(path, options=None):
    ir, sink = analyze(load_mission(path), options)
    assert not sink.errors, [str(d) for d in sink.items]
    return {(s.owner, s.key): s for s in ir.slots}, ir


# ------------------------------------------------------------------ bad missions
def test_bad_data_folder_is_complete():
    assert len(BAD_STEMS) >= 4 and len(WARNED_STEMS) >= 4
    for stem in BAD_STEMS:
        assert os.path.exists(os.path.join(BAD, stem + ".stderr")), stem
        with open(os.path.join(BAD, stem + ".xml"), encoding="utf-8") as f:
            assert "<!--" in f.read(), f"{stem}: say what is wrong in a comment"


@pytest.mark.parametrize("stem", BAD_STEMS)
def test_bad_data_mission_is_rejected_by_compile_and_validate_alike(stem, tmp_path):
    rel = os.path.join("tests", "bad_data", stem + ".xml")
    args_file = os.path.join(BAD, stem + ".args")
    extra = Path(args_file).read_text(encoding="utf-8").split() if os.path.exists(args_file) else []
    # BehaviorTree.CPP would load it, but a CI gate on `btgen validate` must mean what compile means.
    valid = subprocess.run(
        [sys.executable, "-m", "btgen", "validate", "-q", rel, *extra],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    with open(os.path.join(BAD, stem + ".stderr"), encoding="utf-8") as f:
        assert (valid.returncode, valid.stderr) == (1, f.read())
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "compile", rel, "-o", str(tmp_path / "out"), *extra],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    with open(os.path.join(BAD, stem + ".stderr"), encoding="utf-8") as f:
        expected = f.read()
    assert proc.returncode == 1
    assert proc.stderr == expected
    assert not (tmp_path / "out").exists()  # nothing written


@pytest.mark.parametrize("stem", WARNED_STEMS)
def test_a_read_of_an_entry_nothing_creates_compiles_with_a_warning(stem, tmp_path):
    """BehaviorTree.CPP loads these and throws when the script runs (issue 44): compile and
    validate say where, alike, and compile writes the mission (its script throws there)."""
    rel = os.path.join("tests", "warned_data", stem + ".xml")
    with open(os.path.join(WARNED, stem + ".stderr"), encoding="utf-8") as f:
        expected = f.read()
    assert expected and all(": warning: " in line for line in expected.splitlines())
    for cmd in (["validate", rel], ["compile", rel, "-o", str(tmp_path / "out")]):
        proc = subprocess.run(
            [sys.executable, "-m", "btgen", *cmd], cwd=ROOT, capture_output=True, text=True, check=False
        )
        assert (proc.returncode, proc.stderr) == (0, expected)
    assert (tmp_path / "out").is_dir()


# ------------------------------------------------------------------ resolution
def test_subtree_remapping_autoremap_and_root_keys_resolve_to_one_slot_each():
    slots, _ = _slots(os.path.join(CASES, "subtree_remap_nested.xml"))
    # `goal` of the first GoTo instance is the parent's `target`; of the second a constant.
    assert ("root", "target") in slots and ("root", "visits") in slots
    goal = slots[("GoToDock", "goal")]
    assert (goal.initial, goal.kind, goal.capacity) == ("dock", "string", 4)
    assert slot_init(goal).startswith('{btgen::FixedString<4>(std::string_view("dock", 4)), 1,')
    assert ("GoToKitchen", "goal") not in slots  # remapped: the parent's entry
    # `last_goal` is written inside GoTo without remapping: one slot per instance.
    assert ("GoToKitchen", "last_goal") in slots and ("GoToDock", "last_goal") in slots
    slots, _ = _slots(os.path.join(CASES, "root_blackboard_at.xml"))
    assert slots[("root", "visits")].kind == "int"
    assert slots[("VisitLab", "visits")].kind == "int"  # the local shadow
    assert slots[("root", "last_room")].kind == "string"


def test_autoremap_writes_land_in_the_parent_and_private_keys_stay(tmp_path):
    path = _write(
        tmp_path,
        "m.xml",
        _mission(
            '<Sequence><Script code="n := 1"/><SubTree ID="Sub" _autoremap="true"/></Sequence>',
            extra='<BehaviorTree ID="Sub"><Script code="n += 1; m := 2; _p := 3"/></BehaviorTree>',
        ),
    )
    slots, _ = _slots(path)
    assert set(slots) == {("root", "n"), ("root", "m"), ("Sub", "_p")}


def test_types_come_from_ports_then_from_the_first_write(tmp_path):
    path = _write(
        tmp_path,
        "m.xml",
        _mission(
            "<Sequence><Script code=\"d := 1.5; s := 'a'; c := 0; c := c + 1\"/>"
            '<Go goal="{g}" speed="{v}" name_out="{who}"/><Script code="v := 2.5"/></Sequence>',
            models='<Action ID="Go"><input_port name="goal" type="unsigned"/><input_port name="speed" type="double"/>'
            '<output_port name="name_out" type="std::string"/></Action>',
        ),
    )
    slots, _ = _slots(path)
    kinds = {k[1]: (s.kind, s.declared, slot_type(s)) for k, s in slots.items()}
    assert kinds == {
        "d": ("double", "any", "double"),
        "s": ("string", "any", "btgen::FixedString<1>"),
        "c": ("int", "any", "std::int64_t"),
        "g": ("int", "unsigned", "std::int64_t"),
        "v": ("double", "double", "double"),
        "who": ("string", "string", "btgen::FixedString<128>"),
    }


def test_string_capacities_are_computed_and_capped(tmp_path):
    path = _write(
        tmp_path,
        "m.xml",
        _mission(
            "<Sequence><Script code=\"a := 'kitchen'; b := a .. '-' .. 7; grow := 'x'; grow := grow .. a; "
            "f := 'v=' .. 0.5\"/></Sequence>"
        ),
    )
    slots, _ = _slots(path, DataOptions(string_capacity=40))
    caps = {k[1]: s.capacity for k, s in slots.items()}
    # 20: an int's text; f: 2 + 317, a known bound above the capacity (`'a' .. 1e300` needs it);
    # grow: grows without a bound, so the capacity
    assert caps == {"a": 7, "b": 7 + 1 + 20, "grow": 40, "f": 2 + 317}


@pytest.mark.parametrize("piece", ["'x'", "u .. 'y'"])
def test_a_string_growing_by_little_per_write_gets_the_capacity(tmp_path, piece):
    """`s := s .. 'x'` grows its bound by one byte per round of the capacity fixed point; it crashed
    the compiler ("string capacities do not settle", found by front-end fuzzing) when the capacity
    needed more rounds than the mission has slots."""
    setup = "u := ''; " if piece.startswith("u") else ""
    path = _write(
        tmp_path,
        "m.xml",
        _mission(
            f'<Sequence><Script code="{setup}s := \'\'"/><Repeat num_cycles="3"><Script code="s := s .. {piece}"/>'
            f"</Repeat><Script code=\"t := s .. '!'\"/></Sequence>"
        ),
    )
    slots, _ = _slots(path, DataOptions(string_capacity=300))
    caps = {k[1]: s.capacity for k, s in slots.items()}
    assert caps["s"] == 300 and caps["t"] in (300, 301)  # t follows s: widened with it, or s + 1


def test_lab_tour_slots():
    slots, ir = _slots(os.path.join(ROOT, "missions", "LabTour.xml"))
    assert {k: slot_type(s) for k, s in slots.items()} == {
        ("root", "response"): "btgen::FixedString<128>",
        ("IV_VisitExhibit", "exhibits"): "btgen::FixedString<128>",
        ("IV_VisitExhibit", "location_id"): "std::int64_t",
        ("V_EndTour", "location_id"): "std::int64_t",
        ("V_EndTour/_GoHome", "location_id"): "std::int64_t",
    }
    ports = {p.port: p for p in ir.ports["SelectExhibit"]}
    assert ports["exhibits"].direction == "inout" and port_type(ports["exhibits"]) == "std::string_view"
    assert port_type(ports["location_id"]) == "std::int32_t" and not ports["location_id"].reads
    # the speech nodes' `message` defaults are literals, converted at generation time
    welcome = {p.port: p for p in ir.ports["WelcomeSpeech"]}["message"]
    assert [r for _, r in welcome.reads] == [ops.ReadLiteral("string", "welcome")]


def test_untyped_ports_between_robot_leaves_hold_text():
    slots, ir = _slots(os.path.join(CASES, "pick_and_place.xml"))
    loc = slots[("root", "location")]
    assert (loc.kind, loc.capacity) == ("string", 128)
    assert "untyped ports" in loc.origin
    find = {p.port: p for p in ir.ports["FindBall"]}["ball_location"]
    assert port_type(find) == "" and find.writes  # a template setter


def test_unset_entries_may_be_missing_when_a_script_runs():
    _, ir = _slots(os.path.join(CASES, "unset_blackboard.xml"))
    target = next(s for s in ir.slots if s.key == "target")
    assert target.may_be_missing
    compiled, _ = compile_scripts(ir)
    check = next(c for c in compiled if c.comment.startswith('ScriptCondition "CheckTarget"'))
    assert any("if (!bb.target.exists)" in line for line in check.body)
    unset = next(c for c in ir.data_leaves if "ForgetTarget" in c.comment)
    assert isinstance(unset.op, ops.Unset) and ir.slots[unset.op.slot].key == "target"
    unknown = next(c for c in ir.data_leaves if "ForgetUnknown" in c.comment)
    assert isinstance(unknown.op, ops.Unset) and unknown.op.slot is None


def test_every_conformance_case_compiles():
    stems = conformance_stems()
    assert len(stems) >= 40
    for path in [case_file(stem, ".xml") for stem in stems]:
        _, sink = analyze(load_mission(path))
        assert not sink.items, (path, [str(d) for d in sink.items])


@pytest.mark.parametrize(
    "body, models, message, rc",
    [
        (
            '<Sequence><Produce value="{x}"/><Consume value="{x}"/></Sequence>',
            '<Action ID="Produce"><output_port name="value" type="int"/></Action>'
            '<Action ID="Consume"><input_port name="value" type="double"/></Action>',
            "blackboard entry `x` was created as int, but port `value` uses it as double",
            1,
        ),
        # The library loads it and throws when the script runs: a warning of both (issue 44).
        ('<Script code="color := RED"/>', "", 'warning: `code` of `Script` "Script" reads `RED`, but nothing', 0),
    ],
)
def test_validate_runs_the_data_side_checks_of_compile(body, models, message, rc, tmp_path):
    """A port type clash passed `btgen validate`, then failed compile; an undeclared name, which
    only fails when the script runs, is said alike by both."""
    path = tmp_path / "m.xml"
    path.write_text(
        f'<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">{body}'
        f"</BehaviorTree><TreeNodesModel>{models}</TreeNodesModel></root>\n",
        encoding="utf-8",
    )
    results = [
        subprocess.run(
            [sys.executable, "-m", "btgen", *cmd], cwd=str(tmp_path), capture_output=True, text=True, check=False
        )
        for cmd in (["validate", "m.xml"], ["compile", "m.xml", "-o", "out"])
    ]
    for r in results:
        assert r.returncode == rc and message in r.stderr, r.stderr
    assert results[0].stderr == results[1].stderr
