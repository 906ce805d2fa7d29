"""User port types (`--type NAME=CPP_TYPE@HEADER`, TYPES in btgen_add_mission): declarations,
the type checks of validate and compile, scripts, the generated C++ (by-value slots, typed
accessors, a literal converted once at construction, the static_assert on types that cannot be
copied, types that own memory end to end) and both engines' traces without `--type`."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import cppbuild
from btgen.frontend import usertypes

ROOT = Path(__file__).resolve().parents[2]
RUNTIME = ROOT / "runtime" / "include"
NAV = ROOT / "tests" / "cpp" / "user_types"
MISSION = ROOT / "tests" / "cpp" / "missions" / "user_types.xml"
POSE = ["--type", "Pose2D=nav::Pose2D@nav/pose2d.hpp"]
TYPES = POSE + ["--type", "Pose3D=nav::Pose3D@nav/pose3d.hpp"]


def _btgen(*args, cwd):
    return subprocess.run(
        [sys.executable, "-m", "btgen", *args], cwd=str(cwd), capture_output=True, text=True, check=False
    )


def _mission(tmp_path, name, body, models):
    (tmp_path / name).write_text(
        f"""<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
{body}
  </BehaviorTree>
  <TreeNodesModel>
{models}
  </TreeNodesModel>
</root>
""",
        encoding="utf-8",
    )
    return name


def _both(tmp_path, name, *types):
    """validate and compile give the same diagnostics (exit 1); the stderr."""
    v = _btgen("validate", name, *types, cwd=tmp_path)
    c = _btgen("compile", name, "-o", "out", *types, cwd=tmp_path)
    assert (v.returncode, c.returncode) == (1, 1), (v.stderr, c.stderr)
    assert v.stderr == c.stderr
    assert "Traceback" not in v.stderr
    return v.stderr


@pytest.mark.parametrize(
    "text, expected",
    [
        ("Pose2D=nav::Pose2D@nav/pose2d.hpp", ("Pose2D", "nav::Pose2D", "nav/pose2d.hpp", '"nav/pose2d.hpp"')),
        (
            " std::vector< double > = std::array<double,3> @ <array>",
            ("std::vector< double >", "std::array<double, 3>", "<array>", "<array>"),
        ),
        # (found by scripts/fuzz_frontend.py: a line break in the type ended a // comment)
        ("U=unsigned long long\nint@<cstdint>", ("U", "unsigned long long int", "<cstdint>", "<cstdint>")),
        (
            "Ms=::std::chrono::duration<long long, std::milli>@<chrono>",
            ("Ms", "::std::chrono::duration<long long, std::milli>", "<chrono>", "<chrono>"),
        ),
    ],
)
def test_declarations(text, expected):
    t = usertypes.parse(text)
    assert (t.name, t.cpp_type, t.header, t.include) == expected


def _not_type(cpp, why):
    return f"`{cpp}` is not a C++ type btgen can use for `P`: {why}"


def _not_header(header):
    return (
        f"`{header}` is not a header name: write path/to/header.hpp or <path/to/header.hpp> "
        "(letters, digits and `_ . + - /`)"
    )


@pytest.mark.parametrize(
    "spec, message",
    [
        (
            "Pose2D=nav::Pose2D",
            "`Pose2D=nav::Pose2D` is not a type declaration: write NAME=CPP_TYPE@HEADER "
            "(for example Pose2D=nav::Pose2D@nav/pose2d.hpp)",
        ),
        (
            "std::string=my::Text@t.hpp",
            "`std::string` is a type btgen already knows (string); --type declares only types that are not built in",
        ),
        (
            "Pose2D=nav:Pose2D@p.hpp",
            "`nav:Pose2D` is not a C++ type btgen can use for `Pose2D`: `:` cannot appear in a C++ type name here",
        ),
        (
            "Pose2D=nav::Pose2D*@p.hpp",
            "`nav::Pose2D*` is not a C++ type btgen can use for `Pose2D`: pointers and "
            "references cannot live in the blackboard by value",
        ),
        (
            "Pose2D=std::array<double,@p.hpp",
            "`std::array<double,` is not a C++ type btgen can use for `Pose2D`: it is incomplete",
        ),
        (
            "Pose2D=struct Pose@p.hpp",
            "`struct Pose` is not a C++ type btgen can use for `Pose2D`: `struct` is a C++ keyword",
        ),
        (
            "Pose2D=nav::Pose2D@<p.hpp",
            "`<p.hpp` is not a header name: write path/to/header.hpp or <path/to/header.hpp> "
            "(letters, digits and `_ . + - /`)",
        ),
        # Spellings that are not types, and header names that break the build, were taken.
        ("P=double double@p.hpp", _not_type("double double", "`double double` is not a C++ type")),
        ("P=signed double@p.hpp", _not_type("signed double", "`signed double` is not a C++ type")),
        ("P=NULL@p.hpp", _not_type("NULL", "`NULL` is a macro (the preprocessor replaces it)")),
        ("P=std::EOF@p.hpp", _not_type("std::EOF", "`EOF` is a macro (the preprocessor replaces it)")),
        ("P=nav::Pose2D long@p.hpp", _not_type("nav::Pose2D long", "`long` follows a complete type")),
        ("P=a::NDEBUG@p.hpp", _not_type("a::NDEBUG", "`NDEBUG` is a macro (the preprocessor replaces it)")),
        (
            "P=__int128@p.hpp",
            _not_type("__int128", "`__int128` is reserved in C++ (a double underscore, or `_` and a capital)"),
        ),
        ("P=nav::Pose2D@a??/pose.hpp", _not_header("a??/pose.hpp")),
        ("P=nav::Pose2D@<nav>pose.hpp>", _not_header("<nav>pose.hpp>")),
        ("P=nav::Pose2D@a//b.hpp", _not_header("a//b.hpp")),
    ],
)
def test_bad_declarations_are_clean_errors(tmp_path, spec, message):
    name = _mission(tmp_path, "m.xml", "    <AlwaysSuccess/>", "")
    stderr = _both(tmp_path, name, "--type", spec)
    assert stderr == f"--type:1:1: error: {message}\n"


def test_a_type_declared_twice_differently(tmp_path):
    name = _mission(tmp_path, "m.xml", "    <AlwaysSuccess/>", "")
    stderr = _both(tmp_path, name, *POSE, "--type", "Pose2D=geo::Pose@geo.hpp")
    assert stderr == (
        "--type:1:1: error: type `Pose2D` is declared twice, as nav::Pose2D@nav/pose2d.hpp and as geo::Pose@geo.hpp\n"
    )


CLASH_MODELS = """    <Action ID="ComputeGoal"><output_port name="goal" type="Pose2D"/></Action>
    <Action ID="Turn"><input_port name="heading" type="{type}"/></Action>"""


@pytest.mark.parametrize("other", ["Pose3D", "double"])
def test_a_type_clash_across_a_subtree_remap(tmp_path, other):
    (tmp_path / "m.xml").write_text(
        f"""<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <ComputeGoal goal="{{target}}"/>
      <SubTree ID="Follow" pose="{{target}}"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Follow">
    <Turn heading="{{pose}}"/>
  </BehaviorTree>
  <TreeNodesModel>
{CLASH_MODELS.format(type=other)}
  </TreeNodesModel>
</root>
""",
        encoding="utf-8",
    )
    stderr = _both(tmp_path, "m.xml", *TYPES)
    assert stderr == (
        f"m.xml:9:20: error: port `heading` of `Turn`: blackboard entry `pose` was created as Pose2D, "
        f"but port `heading` uses it as {other} (created as Pose2D by port `goal` of `ComputeGoal` "
        f'"ComputeGoal" at m.xml:4:26)\n'
    )


def test_a_user_port_reading_a_string_entry(tmp_path):
    name = _mission(
        tmp_path,
        "m.xml",
        """    <Sequence>
      <Describe text="{target}"/>
      <MoveTo goal="{target}"/>
    </Sequence>""",
        """    <Action ID="Describe"><output_port name="text" type="std::string"/></Action>
    <Action ID="MoveTo"><input_port name="goal" type="Pose2D"/></Action>""",
    )
    stderr = _both(tmp_path, name, *POSE)
    assert stderr == (
        'm.xml:5:21: error: port `goal` of `MoveTo` "MoveTo" (Pose2D) reads blackboard entry '
        "`target`, which holds a string (first written by output port `text` of `Describe` "
        '"Describe" at m.xml:4:23); a Pose2D port reads only Pose2D entries in the C++ back end '
        "(BehaviorTree.CPP would convert a string with convertFromString<Pose2D> on every read)\n"
    )


@pytest.mark.parametrize(
    "code, column, verb", [("x := 1; target := target + 1", 29, "writes"), ("ok := target == 2", 27, "reads")]
)
def test_scripts_cannot_use_user_typed_entries(tmp_path, code, column, verb):
    name = _mission(
        tmp_path,
        "m.xml",
        f"""    <Sequence>
      <ComputeGoal goal="{{target}}"/>
      <Script code="{code}"/>
    </Sequence>""",
        """    <Action ID="ComputeGoal"><output_port name="goal" type="Pose2D"/></Action>""",
    )
    stderr = _both(tmp_path, name, *POSE)
    assert stderr == (
        f'm.xml:5:{column}: error: `code` of `Script` "Script" {verb} `target`, an entry of user type '
        f"Pose2D (nav::Pose2D, --type Pose2D); scripts cannot use user-typed entries (read and write "
        f"them from your nodes through their typed ports)\n"
    )


def _untyped_mission(tmp_path):
    """user_types.xml without its SetBlackboard copy (without --type, a copy of text into an entry of an
    unknown type is refused, as before)."""
    text = MISSION.read_text(encoding="utf-8")
    text = text.replace('      <SetBlackboard output_key="saved" value="{target}"/>\n', "")
    text = text.replace('goal="{saved}"', 'goal="{target}"')
    assert "saved" not in text
    (tmp_path / "untyped.xml").write_text(text, encoding="utf-8")
    return "untyped.xml"


def test_without_type_an_unknown_port_type_stays_text(tmp_path):
    r = _btgen("compile", _untyped_mission(tmp_path), "-o", "out", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "out" / "untyped.hpp").read_text(encoding="utf-8")
    assert "btgen::Input<std::string_view> goal()" in header and "Pose2D>" not in header
    r = _btgen("compile", str(MISSION), "-o", "typed", *POSE, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "typed" / "user_types.hpp").read_text(encoding="utf-8")
    assert '#include "nav/pose2d.hpp"' in header
    assert "btgen::Input<::nav::Pose2D> goal()" in header and "bool set_goal(const ::nav::Pose2D& value)" in header
    assert "btgen::Slot<::nav::Pose2D> target" in header
    assert "static void init(" in header


def test_both_engines_agree_without_type(tmp_path):
    """`btgen run` scripts the leaves: a user-typed port's literal is opaque text to it."""
    (tmp_path / "m.scenario").write_text("ticks 2\nleaf again FAILURE SUCCESS\n", encoding="utf-8")
    name = _untyped_mission(tmp_path)
    runs = [_btgen("run", name, "--scenario", "m.scenario", "--engine", e, cwd=tmp_path) for e in ("interp", "cpp")]
    for r in runs:
        assert r.returncode == 0, r.stderr
    assert runs[0].stdout == runs[1].stdout
    assert 'MoveTo "again"' in runs[0].stdout


def test_valid_types_that_were_refused_build(tmp_path):
    # wchar_t, char16_t, char32_t and std::less<> are types; the grammar refused them.
    models = "\n".join(
        f'    <Action ID="Use{t}"><inout_port name="v" type="{t}"/></Action>' for t in ("W", "U16", "U32", "Less")
    )
    body = "    <Sequence>\n" + "\n".join(f'      <Use{t} v="{{{t.lower()}}}"/>' for t in ("W", "U16", "U32", "Less"))
    name = _mission(tmp_path, "chars.xml", body + "\n    </Sequence>", models)
    types = ["W=wchar_t@<cwchar>", "U16=char16_t@<cstddef>", "U32=char32_t@<cstddef>", "Less=std::less<>@<functional>"]
    r = _btgen("compile", name, "-o", "out", *[a for t in types for a in ("--type", t)], cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "out" / "chars.hpp").read_text(encoding="utf-8")
    assert "::std::less<>" in header and "wchar_t" in header and "char32_t" in header
    proc = cppbuild.run(cppbuild.command([tmp_path / "out" / "chars.cpp"], cxx="c++", mode="syntax"))
    assert proc.returncode == 0, proc.stderr[:4000]


def _cxx(tmp_path, out, main, *extra, compiler="c++"):
    (tmp_path / "main.cpp").write_text(main, encoding="utf-8")
    return cppbuild.run(
        cppbuild.command([out / "user_types.cpp", tmp_path / "main.cpp"], cxx=compiler, includes=[NAV, tmp_path, out])
        + list(extra)
    )


BAD_LITERAL_MAIN = r"""#include <cstdio>
#include "user_types.hpp"
struct Leaves {
  int kconversion = 0;
  btgen::Status tick(user_types::leaf::MoveTo& m, const btgen::NodeInfo&) {
    const auto goal = m.goal();
    if (!goal && goal.error() == btgen::PortError::kConversion) ++kconversion;
    return goal ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  btgen::Status tick(user_types::leaf::ComputeGoal& m, const btgen::NodeInfo&) {
    return m.set_goal(nav::Pose2D{1, 2, 3}) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
};
struct Print {
  void on_status_change(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept {}
  void on_error(const btgen::RuntimeError& e) noexcept {
    std::printf("%.*s: error: %.*s\n", static_cast<int>(e.where.size()), e.where.data(),
                static_cast<int>(e.message.size()), e.message.data());
  }
};
int main() {
  Leaves leaves;
  const int before = nav::convert_calls;
  user_types::UserTypes<Leaves, btgen::ManualClock, Print> mission(leaves);
  std::printf("errors %d calls %d\n", static_cast<int>(mission.errors()), nav::convert_calls - before);
  const btgen::Status s = mission.tick();
  std::printf("tick %s kConversion %d calls %d\n", s == btgen::Status::FAILURE ? "FAILURE" : "other",
              leaves.kconversion, nav::convert_calls - before);
  return 0;
}
"""


@pytest.mark.parametrize(
    "case, compiler", [("literal", "g++"), ("literal", "clang++"), ("constant", "g++"), ("set", "g++")]
)
def test_a_literal_that_does_not_convert_is_reported_at_construction(tmp_path, case, compiler):
    text = MISSION.read_text(encoding="utf-8")
    tick = "tick FAILURE kConversion 1 calls 3\n"
    if case == "literal":
        text = text.replace('goal="1.5;-2;0.25"', 'goal="1.5;north;0.25"')
        first = (
            'user_types.xml:5:33: error: port `goal` of `MoveTo` "home": `1.5;north;0.25` does not convert to '
            "Pose2D (nav::Pose2D): its convertFromString returned false\n"
        )
    elif case == "constant":  # a SubTree's constant port read by a Pose2D port: converted once too
        text = text.replace('pose="0;1;2"', 'pose="0;1"')
        first = (
            'user_types.xml:10:47: error: port `goal` of `MoveTo` "follow_goal": `0;1` (the constant port '
            "`pose` of its SubTree) does not convert to Pose2D (nav::Pose2D): its convertFromString returned "
            "false\n"
        )
    else:  # a SetBlackboard literal into a Pose2D entry: converted once; the node fails when it runs
        text = text.replace('value="7;8;9"', 'value="7;8"')
        first = (
            'user_types.xml:11:49: error: `value` of `SetBlackboard` "SetBlackboard" (`7;8`, for `target`) '
            "does not convert to Pose2D (nav::Pose2D): its convertFromString returned false\n"
        )
        tick = (
            'user_types.xml:11:49: error: `SetBlackboard` "SetBlackboard": `7;8` does not convert to Pose2D '
            "(nav::Pose2D) for `target`\ntick FAILURE kConversion 0 calls 3\n"
        )
    (tmp_path / "user_types.xml").write_text(text, encoding="utf-8")
    r = _btgen("compile", "user_types.xml", "-o", "out", *POSE, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    built = _cxx(tmp_path, tmp_path / "out", BAD_LITERAL_MAIN, "-o", str(tmp_path / "run"), compiler=compiler)
    assert built.returncode == 0, built.stderr
    run = subprocess.run([str(tmp_path / "run")], capture_output=True, text=True, check=True)
    assert run.stdout == first + "errors 1 calls 3\n" + tick


def test_a_type_that_is_not_copyable_is_a_clear_compile_error(tmp_path):
    # (A type that owns memory is fine: test_types_that_own_memory_work_end_to_end.)
    (tmp_path / "nav").mkdir()
    (tmp_path / "nav" / "named.hpp").write_text(
        """#pragma once
#include <memory>
#include <string_view>
namespace nav {
struct Named { std::unique_ptr<int> id; };
inline bool convertFromString(std::string_view t, Named& out) { out.id.reset(new int(int(t.size()))); return true; }
}  // namespace nav
""",
        encoding="utf-8",
    )
    r = _btgen("compile", str(MISSION), "-o", "out", "--type", "Pose2D=nav::Named@nav/named.hpp", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    built = _cxx(tmp_path, tmp_path / "out", '#include "user_types.hpp"\n', "-fsyntax-only")
    assert built.returncode != 0
    assert (
        "port type `Pose2D` (btgen compile --type Pose2D=nav::Named@nav/named.hpp): nav::Named must be copyable: "
        "a write copies the value into the blackboard, a read copies it out"
    ) in built.stderr


UNTYPED_MAIN = r"""#include <cstdio>
#include "m.hpp"
struct Leaves {
  bool wrong = false;
  btgen::Status tick(m::leaf::Plan& m, const btgen::NodeInfo&) {
    if (wrong) return m.set_out(1.0) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
    return m.set_out(nav::Pose2D{1, 2, 3}) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  btgen::Status tick(m::leaf::Compute&, const btgen::NodeInfo&) { return btgen::Status::SUCCESS; }
  btgen::Status tick(m::leaf::Use& m, const btgen::NodeInfo&) {
    const auto pose = m.goal<nav::Pose2D>();
    const auto number = m.goal<double>();
    std::printf("use %d %g %g %d\n", pose.has_value(), pose->y, pose->theta,
                number.error() == btgen::PortError::kConversion);
    return btgen::Status::SUCCESS;
  }
};
struct Print {
  void on_status_change(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept {}
  void on_error(const btgen::RuntimeError& e) noexcept {
    std::printf("%.*s: error: %.*s\n", static_cast<int>(e.where.size()), e.where.data(),
                static_cast<int>(e.message.size()), e.message.data());
  }
};
int main(int argc, char**) {
  Leaves leaves;
  leaves.wrong = argc > 1;
  m::M<Leaves, btgen::ManualClock, Print> mission(leaves);
  std::printf("%s\n", mission.tick() == btgen::Status::SUCCESS ? "SUCCESS" : "FAILURE");
}
"""


def test_untyped_ports_take_a_user_typed_entry_as_its_own_type_only(tmp_path):
    name = _mission(
        tmp_path,
        "m.xml",
        """    <Sequence>
      <Plan out="{p}"/>
      <Compute goal="{p}"/>
      <Use goal="{p}"/>
    </Sequence>""",
        """    <Action ID="Plan"><output_port name="out"/></Action>
    <Action ID="Compute"><output_port name="goal" type="Pose2D"/></Action>
    <Action ID="Use"><input_port name="goal"/></Action>""",
    )
    r = _btgen("compile", name, "-o", "out", *POSE, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    (tmp_path / "out" / "user_types.cpp").symlink_to(tmp_path / "out" / "m.cpp")
    built = _cxx(tmp_path, tmp_path / "out", UNTYPED_MAIN, "-o", str(tmp_path / "run"))
    assert built.returncode == 0, built.stderr
    ok = subprocess.run([str(tmp_path / "run")], capture_output=True, text=True, check=True)
    assert ok.stdout == "use 1 2 3 1\nSUCCESS\n"
    wrong = subprocess.run([str(tmp_path / "run"), "x"], capture_output=True, text=True, check=True)
    assert wrong.stdout == (
        'm.xml:4:18: error: output port `out` of `Plan` "Plan" writes a value of another type '
        "than Pose2D (nav::Pose2D) to `p`\nFAILURE\n"
    )


def test_generated_names_never_capture_user_names(tmp_path):
    """The blackboard's `ulit<k>_` members (converted literals) never collide with an entry's member, and a
    user type named like a generated one (`Blackboard`, at global scope) is named from `::`."""
    (tmp_path / "board.hpp").write_text(
        """#pragma once
#include <string_view>
struct Blackboard { double width; };
inline bool convertFromString(std::string_view text, Blackboard& out) { out.width = double(text.size()); return true; }
""",
        encoding="utf-8",
    )
    name = _mission(
        tmp_path,
        "m.xml",
        """    <Sequence>
      <MoveTo goal="1;2;3" board="wide"/>
      <Script code="ulit0_ := 1"/>
    </Sequence>""",
        """    <Action ID="MoveTo">
      <input_port name="goal" type="Pose2D"/><input_port name="board" type="Board"/>
    </Action>""",
    )
    r = _btgen("compile", name, "-o", "out", *POSE, "--type", "Board=Blackboard@board.hpp", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    (tmp_path / "out" / "user_types.cpp").symlink_to(tmp_path / "out" / "m.cpp")
    built = _cxx(tmp_path, tmp_path / "out", '#include "m.hpp"\n', "-fsyntax-only")
    assert built.returncode == 0, built.stderr


# ---------------------------------------------------------------- types that own memory
# Nav2's data: a PoseStamped (a std::string frame_id) and a Path (a std::vector of them). Their
# copies and conversion run inside msgs::TypeCode, which counts the allocations made there: every
# other allocation between the mission's construction and its last tick would be btgen's own.
OWNING_TYPES = r"""#pragma once
#include <cstddef>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "btgen/testing/alloc_counter.hpp"

namespace msgs {
inline int depth = 0;
inline std::size_t type_allocations = 0;
// The type's own code (and the test's): the allocations made inside are the type's.
struct TypeCode {
  std::size_t start = btgen_test::allocation_count();
  TypeCode() { ++depth; }
  ~TypeCode() {
    if (--depth == 0) type_allocations += btgen_test::allocation_count() - start;
  }
  TypeCode(const TypeCode&) = delete;
  TypeCode& operator=(const TypeCode&) = delete;
};
}  // namespace msgs

namespace geometry_msgs::msg {
struct PoseStamped {
  std::string frame_id;
  double x = 0, y = 0, theta = 0;
  PoseStamped() = default;
  PoseStamped(const PoseStamped& o) { *this = o; }
  PoseStamped(PoseStamped&&) noexcept = default;
  PoseStamped& operator=(PoseStamped&&) noexcept = default;
  ~PoseStamped() = default;
  PoseStamped& operator=(const PoseStamped& o) {
    msgs::TypeCode counted;
    frame_id = o.frame_id;
    x = o.x;
    y = o.y;
    theta = o.theta;
    return *this;
  }
};

// "frame;x;y;theta"
inline bool convertFromString(std::string_view text, PoseStamped& out) {
  msgs::TypeCode counted;
  const std::size_t a = text.find(';');
  if (a == std::string_view::npos || a == 0) return false;
  out.frame_id.assign(text.substr(0, a));
  double* fields[3] = {&out.x, &out.y, &out.theta};
  std::string rest(text.substr(a + 1));
  const char* p = rest.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    *fields[i] = std::strtod(p, &end);
    if (end == p || *end != (i < 2 ? ';' : '\0')) return false;
    p = end + (i < 2 ? 1 : 0);
  }
  return true;
}
}  // namespace geometry_msgs::msg

namespace nav_msgs::msg {
struct Path {
  std::string frame_id;
  std::vector<geometry_msgs::msg::PoseStamped> poses;
  Path() = default;
  Path(const Path& o) { *this = o; }
  Path(Path&&) noexcept = default;
  Path& operator=(Path&&) noexcept = default;
  ~Path() = default;
  Path& operator=(const Path& o) {
    msgs::TypeCode counted;
    frame_id = o.frame_id;
    poses = o.poses;
    return *this;
  }
};
}  // namespace nav_msgs::msg
"""

OWNING_MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <ComputePath goal="{goal}" path="{path}"/>
      <SetBlackboard output_key="saved" value="{path}"/>
      <FollowPath path="{saved}"/>
      <SubTree ID="Go" target="map_frame_of_the_second_floor;4;5;0.5"/>
      <SetBlackboard output_key="goal" value="odom_frame_of_the_second_floor;1;-1;0"/>
      <ComputePath goal="{goal}" path="{path}"/>
      <FollowPath path="{path}"/>
      <UnsetBlackboard key="saved"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Go">
    <MoveTo goal="{target}"/>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="ComputePath">
      <input_port name="goal" type="geometry_msgs::msg::PoseStamped"/>
      <output_port name="path" type="nav_msgs::msg::Path"/>
    </Action>
    <Action ID="FollowPath"><input_port name="path" type="nav_msgs::msg::Path"/></Action>
    <Action ID="MoveTo"><input_port name="goal" type="geometry_msgs::msg::PoseStamped"/></Action>
    <SubTree ID="Go"><input_port name="target" type="geometry_msgs::msg::PoseStamped"/></SubTree>
  </TreeNodesModel>
</root>
"""
OWNING_OPTIONS = [
    "--type",
    "geometry_msgs::msg::PoseStamped=geometry_msgs::msg::PoseStamped@msgs.hpp",
    "--type",
    "nav_msgs::msg::Path=nav_msgs::msg::Path@msgs.hpp",
    "--entry",
    "goal=geometry_msgs::msg::PoseStamped",
]

OWNING_MAIN = r"""#include <cstdio>

#include "nav.hpp"

using geometry_msgs::msg::PoseStamped;
using nav_msgs::msg::Path;

struct Leaves {
  Path planned;
  btgen::Status tick(nav::leaf::ComputePath& m, const btgen::NodeInfo&) {
    const auto goal = m.goal();
    if (!goal) return btgen::Status::FAILURE;
    std::printf("ComputePath to %s %g %g\n", goal->frame_id.c_str(), goal->x, goal->y);
    {
      msgs::TypeCode counted;  // the robot's own code
      planned.frame_id = goal->frame_id;
      planned.poses.push_back(*goal);
    }
    return m.set_path(planned) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  btgen::Status tick(nav::leaf::FollowPath& m, const btgen::NodeInfo&) {
    const auto path = m.path();
    if (!path) return btgen::Status::FAILURE;
    std::printf("FollowPath %s, %zu poses, last at %g %g %g\n", path->frame_id.c_str(), path->poses.size(),
                path->poses.back().x, path->poses.back().y, path->poses.back().theta);
    return btgen::Status::SUCCESS;
  }
  btgen::Status tick(nav::leaf::MoveTo& m, const btgen::NodeInfo&) {
    const auto goal = m.goal();
    if (!goal) return btgen::Status::FAILURE;
    std::printf("MoveTo %s %g %g %g\n", goal->frame_id.c_str(), goal->x, goal->y, goal->theta);
    return btgen::Status::SUCCESS;
  }
};

int main() {
  std::printf("start\n");  // (stdout's buffer is allocated before the count starts)
  Leaves leaves;
  PoseStamped goal;
  {
    msgs::TypeCode counted;
    goal.frame_id = "map_frame_of_the_first_floor";
    goal.x = 2;
    goal.y = 3;
  }
  msgs::type_allocations = 0;
  const std::size_t before = btgen_test::allocation_count();
  {
    nav::Nav<Leaves, btgen::ManualClock> mission(leaves);
    std::printf("errors %d\n", static_cast<int>(mission.errors()));
    mission.provide_goal(goal);
    for (int i = 0; i < 3; ++i) {
      const btgen::Status s = mission.tick();
      std::printf("tick %d: %s\n", i + 1, s == btgen::Status::SUCCESS ? "SUCCESS" : "not SUCCESS");
    }
    const std::size_t all = btgen_test::allocation_count() - before;
    std::printf("the types allocated: %s; btgen's own allocations: %zu\n", msgs::type_allocations > 0 ? "yes" : "no",
                all - msgs::type_allocations);
  }
  return 0;
}
"""

OWNING_OUTPUT = "".join(
    f"{line}\n"
    for line in [
        "start",
        "errors 0",
        "ComputePath to map_frame_of_the_first_floor 2 3",
        "FollowPath map_frame_of_the_first_floor, 1 poses, last at 2 3 0",
        "MoveTo map_frame_of_the_second_floor 4 5 0.5",
        "ComputePath to odom_frame_of_the_second_floor 1 -1",
        "FollowPath odom_frame_of_the_second_floor, 2 poses, last at 1 -1 0",
        "tick 1: SUCCESS",
        # the second tick reads `goal` as the first SetBlackboard left it
        "ComputePath to odom_frame_of_the_second_floor 1 -1",
        "FollowPath odom_frame_of_the_second_floor, 3 poses, last at 1 -1 0",
        "MoveTo map_frame_of_the_second_floor 4 5 0.5",
        "ComputePath to odom_frame_of_the_second_floor 1 -1",
        "FollowPath odom_frame_of_the_second_floor, 4 poses, last at 1 -1 0",
        "tick 2: SUCCESS",
        "ComputePath to odom_frame_of_the_second_floor 1 -1",
        "FollowPath odom_frame_of_the_second_floor, 5 poses, last at 1 -1 0",
        "MoveTo map_frame_of_the_second_floor 4 5 0.5",
        "ComputePath to odom_frame_of_the_second_floor 1 -1",
        "FollowPath odom_frame_of_the_second_floor, 6 poses, last at 1 -1 0",
        "tick 3: SUCCESS",
        "the types allocated: yes; btgen's own allocations: 0",
    ]
)


@pytest.mark.parametrize(
    "compiler, flags",
    [
        ("g++", ["-O2"]),  # malloc counted too
        ("g++", ["-O1", "-fsanitize=address,undefined", "-fno-sanitize-recover=all"]),  # operator new only
        ("clang++", ["-O0"]),
    ],
    ids=["g++-O2", "g++-asan-ubsan", "clang++-O0"],
)
def test_types_that_own_memory_work_end_to_end(tmp_path, compiler, flags):
    """A PoseStamped-like and a Path-like type as entries (provided, written by a leaf, copied by
    SetBlackboard, a literal converted at construction, a SubTree's constant, unset): the mission
    compiles, builds with -Werror, runs, is clean under ASan and UBSan, and btgen's own code
    allocates nothing (the types' copies do)."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    (tmp_path / "nav.xml").write_text(OWNING_MISSION, encoding="utf-8")
    (tmp_path / "msgs.hpp").write_text(OWNING_TYPES, encoding="utf-8")
    (tmp_path / "main.cpp").write_text(OWNING_MAIN, encoding="utf-8")
    assert _btgen("validate", "-q", "nav.xml", *OWNING_OPTIONS, cwd=tmp_path).returncode == 0
    r = _btgen("compile", "nav.xml", "-o", "out", *OWNING_OPTIONS, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "out" / "nav.hpp").read_text(encoding="utf-8")
    assert "btgen::Slot<::nav_msgs::msg::Path> path" in header
    assert "a type that owns memory (std::string, std::vector, a ROS" in header
    built = subprocess.run(
        [compiler, "-std=c++17", "-Wall", "-Wextra", "-Wpedantic", "-Werror", *flags]
        + ["-I", str(RUNTIME), "-I", str(tmp_path), "-I", str(tmp_path / "out")]
        + [str(tmp_path / "main.cpp"), str(tmp_path / "out" / "nav.cpp")]
        + [str(ROOT / "runtime" / "src" / "testing" / "alloc_counter.cpp"), "-o", str(tmp_path / "run")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert built.returncode == 0, built.stderr[:4000]
    run = subprocess.run([str(tmp_path / "run")], capture_output=True, text=True, check=False)
    assert (run.returncode, run.stderr) == (0, "")
    assert run.stdout == OWNING_OUTPUT


def test_a_port_type_btgen_does_not_know_is_loaded_with_a_warning(tmp_path, capsys):
    """Without --type, a port of a type btgen does not know is loaded (as BehaviorTree.CPP loads
    it) and holds text; validate and compile say so once per type, at the port that declares it,
    and what to do; `run` (scripted leaves, for which text is all there is) does not."""
    from btgen.cli import main

    name = _untyped_mission(tmp_path)
    path = str(tmp_path / name)
    warning = (
        f"{MISSION}:19:7: warning: port type `Pose2D` (port `goal` of `MoveTo`) is not built in and no --type "
        "declares it: its values are text here (robot code reads and writes std::string_view), a Pose2D in "
        "BehaviorTree.CPP; to compile it as that C++ type, declare it: --type Pose2D=CPP_TYPE@HEADER\n"
    ).replace(str(MISSION), path)
    assert main(["validate", path]) == 0
    assert capsys.readouterr().err == warning
    assert main(["validate", "-q", path]) == 0  # -q: errors only
    assert capsys.readouterr().err == ""
    assert main(["compile", path, "-o", str(tmp_path / "out")]) == 0
    assert capsys.readouterr().err == warning
    assert main(["validate", "-q", path, *POSE]) == 0
    assert main(["compile", path, "-o", str(tmp_path / "typed"), *POSE]) == 0
    assert capsys.readouterr().err == ""
    (tmp_path / "m.scenario").write_text("ticks 1\n", encoding="utf-8")
    assert main(["run", path, "--scenario", str(tmp_path / "m.scenario")]) == 0
    assert capsys.readouterr().err == ""
