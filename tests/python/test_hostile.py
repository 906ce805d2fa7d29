"""Hostile names and inputs: every mission name becomes a C++ identifier that
builds, with both compilers, optimised or not, warnings as errors."""

import os
import shutil
import subprocess
import sys
import time

import pytest

import cppbuild
import hostile_names
from btgen.backend_cpp import naming
from conftest import ROOT

DRIVER = os.path.join(ROOT, "runtime", "src", "main_driver.cpp")
# Stems whose engine is also instantiated (the rest only have their headers compiled): the
# issue's reproducers and the names the mission class template uses.
ISSUE_STEMS = frozenset("engine leaves observer clock main errno exit std btgen detail".split())


@pytest.fixture(scope="module")
def hostile_sources(tmp_path_factory):
    """The hostile mission (every hostile name as model ID, port and key) and one translation
    unit of a small mission under every hostile name as its stem."""
    from btgen.compiler import generate

    tmp = tmp_path_factory.mktemp("hostile")
    names = hostile_names.pool()
    xml = tmp / "hostile.xml"
    xml.write_text(hostile_names.mission(names), encoding="utf-8")
    for out in generate(str(xml), relative_to=str(tmp)):
        (tmp / out.name).write_text(out.text, encoding="utf-8")
    stems = tmp / "stems"
    stems.mkdir()
    (stems / "all_stems.cpp").write_text(
        hostile_names.stems_translation_unit(stems, names, ISSUE_STEMS), encoding="utf-8"
    )
    return tmp


@pytest.mark.parametrize("opt", ["-O0", "-O2"])
@pytest.mark.parametrize("compiler", ["g++", "clang++"])
def test_hostile_names_build(hostile_sources, compiler, opt):
    """The scenario runner of the hostile mission, linked with every stem's header (and the
    engines of ISSUE_STEMS, whose missions have exactly two parent-to-child edges, the
    -Warray-bounds case of g++ -O2), builds without a warning."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    tmp = hostile_sources
    cmd = cppbuild.command(
        [DRIVER, tmp / "hostile.cpp", tmp / "stems" / "all_stems.cpp"],
        tmp / f"run{opt}",
        cxx=compiler,
        opt=opt,
        includes=[tmp, tmp / "stems"],
        # NDEBUG at -O2, as every CMake Release build defines it
        defines=[*(["NDEBUG"] if opt == "-O2" else []), 'BTGEN_MISSION_HEADER="hostile.hpp"']
        + ["BTGEN_MISSION_TEMPLATE=hostile::Hostile"],
    )
    start = time.monotonic()
    proc = cppbuild.run(cmd)
    assert proc.returncode == 0, (proc.stdout + proc.stderr)[:6000]
    print(f"{compiler} {opt}: {time.monotonic() - start:.1f} s", file=sys.stderr)


def test_pool_covers_the_issue():
    pool = set(hostile_names.pool())
    assert pool >= naming.CPP_KEYWORDS
    assert set(hostile_names.compiler_macros("g++")) <= pool
    assert {
        "std",
        "btgen",
        "detail",
        "NULL",
        "errno",
        "EOF",
        "kId",
        "kKind",
        "kModel",
        "node",
        "blackboard",
        "bb_",
        "err_",
        "node_",
        "scratch0_",
    } <= pool
    assert set("engine leaves observer clock main errno time exit random remove system abs printf".split()) <= pool
    assert pool >= ISSUE_STEMS
    assert {"NDEBUG", "BTGEN_STRAIGHT_LINE_BUDGET", "BTGEN_MISSION_HEADER", "ZMQ_PUB"} <= pool


def test_compilers_define_no_macro_btgen_does_not_know():
    """cpp_reserved.py is read from the compilers: any macro they define here is in it
    (else rerun scripts/update_cpp_reserved.py)."""
    for cxx in ("g++", "clang++"):
        missing = sorted(set(hostile_names.compiler_macros(cxx)) - naming.MACROS)
        assert not missing, f"{cxx} defines {missing[:10]}: run scripts/update_cpp_reserved.py"


@pytest.mark.parametrize(
    "name,kind,expected",
    [
        ("NULL", "entry", "NULL_"),
        ("errno", "port", "errno_"),
        ("std", "model", "std_"),
        ("kId", "model", "kId_"),
        ("bb_", "port", "bb_1"),
        ("scratch0_", "port", "scratch0_1"),
        ("loop_3", "entry", "loop_3_"),
        ("loopq_3", "entry", "loopq_3_"),
        ("exit", "namespace", "exit_"),
        ("main", "namespace", "main_"),
        ("lab_tour", "namespace", "lab_tour"),
        ("Engine", "class", "Engine_"),
        ("LabTour", "class", "LabTour"),
        ("SayHello", "model", "SayHello"),
        ("message", "port", "message"),
        ("x", "entry", "x"),
        ("class", "plain", "class_"),
        ("NDEBUG", "model", "NDEBUG_"),
        ("BTGEN_STRAIGHT_LINE_BUDGET", "port", "port_BTGEN_STRAIGHT_LINE_BUDGET"),
        ("BTGEN_GENERATED_M_HPP", "entry", "e_BTGEN_GENERATED_M_HPP"),
        ("ZMQ_PUB", "entry", "e_ZMQ_PUB"),
    ],
)
def test_cpp_identifier_by_kind(name, kind, expected):
    assert naming.cpp_identifier(name, kind=kind) == expected


def test_port_identifiers_keep_getters_and_setters_apart():
    # `set_x` the port would be the setter of `x`; a port named like its model is the constructor.
    assert naming.port_identifiers(["x", "set_x", "Move"], "Move") == ("x", "set_x_2", "Move_2")
    assert naming.unique_identifiers(["NULL", "NULL_"], kind="entry") == ("NULL_", "NULL_2")


@pytest.mark.parametrize(
    "text,expected",
    [
        ("ends ??/", "ends ?_?/"),
        ("a???/b", "a?_?_?/b"),
        ("line\nbreak\r", "line?break?"),
        ("back\\", "back"),
        ("ok?", "ok?"),
    ],
)
def test_comment_text_is_escaped(text, expected):
    """`??/` would continue a // comment onto the next line (g++ -Wall: -Werror=trigraphs)."""
    assert naming.cpp_comment(text) == expected


CHAIN = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="t := 'ab'"/>
      <Script code="t := t .. t"/>
      <Script code="u := t .. t .. t .. t .. t"/>
      <ScriptCondition code="u == 'abababababababababab'"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def test_long_concatenation_chain_has_a_linear_stack_frame(tmp_path):
    """`u := t .. t .. t .. t .. t` with --string-capacity 1048576 made one buffer per `..`,
    1+2+3+4+5 MiB, and the executor died of a stack overflow (SIGSEGV); one buffer of 5 MiB
    serves the chain now."""
    mission = tmp_path / "chain.xml"
    mission.write_text(CHAIN, encoding="utf-8")
    (tmp_path / "one.scenario").write_text("ticks 1\n", encoding="utf-8")
    out = tmp_path / "out"
    subprocess.run(
        [sys.executable, "-m", "btgen", "compile", str(mission), "-o", str(out), "--string-capacity", "1048576"],
        check=True,
    )
    header = (out / "chain.hpp").read_text(encoding="utf-8")
    assert header.count("btgen::FixedString<5242880>") == 1 and "FixedString<3145728>" not in header
    exe = tmp_path / "chain"
    cppbuild.build(
        [DRIVER],
        exe,
        opt="-O0",
        warnings=False,
        includes=[out],
        defines=['BTGEN_MISSION_HEADER="chain.hpp"', "BTGEN_MISSION_TEMPLATE=chain::Chain"],
    )
    proc = subprocess.run([str(exe), str(tmp_path / "one.scenario")], capture_output=True, text=True, check=False)
    assert (proc.returncode, proc.stdout.splitlines()[-1]) == (0, "result SUCCESS"), proc.stderr


DOUBLING = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="s := 'ab'"/>
      <Repeat num_cycles="40"><Script code="s := s .. s"/></Repeat>
    </Sequence>
  </BehaviorTree>
</root>
"""


def test_interpreter_bounds_a_doubling_string(tmp_path):
    """A script doubling a string 40 times ended the interpreter in MemoryError (exit 3); it
    stops at MAX_STRING_BYTES with a run-time error at the operator (the C++ engine stops
    much earlier, at the entry's capacity)."""
    from btgen.lang.script import MAX_STRING_BYTES

    (tmp_path / "m.xml").write_text(DOUBLING, encoding="utf-8")
    (tmp_path / "s.scenario").write_text("ticks 60\n", encoding="utf-8")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "m.xml", "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 1
    assert proc.stderr == (
        f'm.xml:5:52: error: script error in `code` of `Script` "Script": `..` would make a '
        f"string of {2 * MAX_STRING_BYTES} bytes; the interpreter holds strings of at most "
        f"{MAX_STRING_BYTES} bytes\n"
    )
    assert proc.stdout.splitlines()[-1] == "tick 26"


TWO_EDGES = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Fallback><AlwaysFailure/><AlwaysSuccess/></Fallback>
  </BehaviorTree>
</root>
"""
TWO_EDGES_TRACE = """tick 1
1 Fallback "Fallback" IDLE -> RUNNING
2 AlwaysFailure "AlwaysFailure" IDLE -> FAILURE
3 AlwaysSuccess "AlwaysSuccess" IDLE -> SUCCESS
2 AlwaysFailure "AlwaysFailure" FAILURE -> IDLE
3 AlwaysSuccess "AlwaysSuccess" SUCCESS -> IDLE
1 Fallback "Fallback" RUNNING -> SUCCESS
1 Fallback "Fallback" SUCCESS -> IDLE
result SUCCESS
"""


def _run(tmp_path, engine, scenario, env=None, shell=False):
    (tmp_path / "two.xml").write_text(TWO_EDGES, encoding="utf-8")
    cmd = [sys.executable, "-m", "btgen", "run", "two.xml", "--scenario", scenario, "--engine", engine]
    if shell:  # bash for `<(...)`
        cmd = ["bash", "-c", " ".join(cmd[:6]) + f" {scenario} --engine {engine}"]
    return subprocess.run(cmd, cwd=tmp_path, capture_output=True, timeout=600, env=env, check=False)


@pytest.mark.parametrize("engine", ["interp", "cpp"])
def test_scenario_limits_apply_to_pipes_and_devices(tmp_path, engine):
    """`--scenario /dev/zero` read 16 MiB and printed one 67 MB diagnostic; a pipe's size shows
    only while reading, so the limit is applied there (a 17 MB piped scenario was truncated
    silently by the interpreter)."""
    proc = _run(tmp_path, engine, "/dev/zero")
    assert (proc.returncode, proc.stderr.decode()) == (
        1,
        "/dev/zero:1:1: error: file is larger than 16777216 bytes; scenarios are limited to 16777216 bytes\n",
    )
    proc = _run(tmp_path, engine, "<(head -c 17000000 /dev/zero)", shell=True)
    assert proc.returncode == 1 and proc.stderr.decode().endswith(
        ":1:1: error: file is larger than 16777216 bytes; scenarios are limited to 16777216 bytes\n"
    )


@pytest.mark.parametrize("engine", ["interp", "cpp"])
def test_scenario_through_process_substitution(tmp_path, engine):
    """`--scenario <(...)` worked with the interpreter only: the executor did not inherit the pipe."""
    proc = _run(tmp_path, engine, "<(printf 'ticks 1\\n')", shell=True)
    assert (proc.returncode, proc.stdout.decode(), proc.stderr.decode()) == (0, TWO_EDGES_TRACE, "")


@pytest.mark.parametrize("engine", ["interp", "cpp"])
@pytest.mark.parametrize(
    "text,expected",
    [
        (
            "ticks " + "9" * 3_000_000 + "\n",
            "s.scenario:1:7: error: ticks " + "9" * 4075 + "... (cut: 3000040 bytes in all)\n",
        ),
        (
            "ticks 1\n" + "y" * 3_000_000 + "\n",
            "s.scenario:2:1: error: unknown keyword `" + "y" * 4079 + "... (cut: 3000078 bytes in all)\n",
        ),
    ],
)
def test_long_diagnostics_are_cut_alike(tmp_path, engine, text, expected):
    """A 3-million-digit `ticks` crashed the interpreter (int() digit limit: exit 3) and was
    quoted whole by the C++ runner; quotes of megabytes of input are cut at 4096 bytes, the same
    way by both engines."""
    (tmp_path / "s.scenario").write_text(text, encoding="utf-8")
    proc = _run(tmp_path, engine, "s.scenario")
    stderr = proc.stderr.decode()
    assert proc.returncode == 1
    assert stderr.split(":", 3)[3].startswith(expected.split(":", 3)[3][:60]) and stderr.endswith(expected[-40:])
    assert len(stderr) < 4300


@pytest.mark.parametrize("bad", ["file", "dir_under_file"])
def test_cpp_engine_with_an_unusable_cache_dir(tmp_path, bad):
    """A cache path that is a file (or lies under one) ended `run --engine cpp` in a traceback (exit 3)."""
    (tmp_path / "afile").write_text("", encoding="utf-8")
    cache = tmp_path / "afile" if bad == "file" else tmp_path / "afile" / "sub"
    (tmp_path / "one.scenario").write_text("ticks 1\n", encoding="utf-8")
    proc = _run(tmp_path, "cpp", "one.scenario", env={**os.environ, "BTGEN_CACHE_DIR": str(cache)})
    assert (proc.returncode, proc.stderr.decode()) == (
        1,
        f"two.xml:1:1: error: cannot build the C++ executor: the cache directory `{cache}` is not usable "
        f"(Not a directory); set BTGEN_CACHE_DIR to a writable directory\n",
    )


def _compile(mission, out, cwd):
    return subprocess.run(
        [sys.executable, "-m", "btgen", "compile", str(mission), "-o", str(out)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_compile_refuses_to_overwrite_its_input(tmp_path):
    """A mission named mission.hpp compiled with -o its own folder was overwritten by the
    generated header (exit 0: the mission was lost)."""
    (tmp_path / "mission.hpp").write_text(TWO_EDGES, encoding="utf-8")
    proc = _compile("mission.hpp", ".", tmp_path)
    assert (proc.returncode, proc.stderr) == (
        1,
        "mission.hpp:1:1: error: `btgen compile -o .` would overwrite this input file with the generated "
        "mission.hpp: choose another output directory\n",
    )
    assert (tmp_path / "mission.hpp").read_text(encoding="utf-8") == TWO_EDGES


def test_compile_a_very_long_stem(tmp_path):
    """A 245-character stem failed with 'File name too long' from the temporary file's name,
    though the outputs' names (249 characters) are legal."""
    stem = "m" * 245
    (tmp_path / f"{stem}.xml").write_text(TWO_EDGES, encoding="utf-8")
    proc = _compile(f"{stem}.xml", "out", tmp_path)
    assert (proc.returncode, proc.stderr) == (0, "")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [f"{stem}.cpp", f"{stem}.hpp"]


def test_header_and_source_of_two_runs_do_not_build(tmp_path):
    """Two compiles of same-stem missions into one folder at once (or a kill between the two
    renames) could leave m.hpp of one and m.cpp of the other, which built into a mix; both
    files carry the generation, and the source checks it."""
    for name, text in (("a", TWO_EDGES), ("b", TWO_EDGES.replace("AlwaysFailure", "AlwaysSuccess"))):
        (tmp_path / name).mkdir()
        (tmp_path / name / "m.xml").write_text(text, encoding="utf-8")
        assert _compile(f"{name}/m.xml", name, tmp_path).returncode == 0
    cmd = cppbuild.command([tmp_path / "a" / "m.cpp"], mode="syntax", warnings=False, includes=[tmp_path / "a"])
    cppbuild.check(cmd)
    (tmp_path / "a" / "m.hpp").write_bytes((tmp_path / "b" / "m.hpp").read_bytes())  # the mix
    proc = cppbuild.run(cmd)
    assert proc.returncode != 0
    assert "m.hpp and m.cpp come from different btgen runs: run btgen compile again" in proc.stderr


def test_two_missions_in_one_namespace_do_not_link(tmp_path):
    """a/patrol.xml and b/patrol.xml (default namespace `patrol`) linked into one program ran
    each other's code: the linker kept one copy of the engine, and mission b (AlwaysFailure)
    returned SUCCESS. A definition in the namespace makes that a link error."""
    for name, text in (("a", TWO_EDGES), ("b", TWO_EDGES.replace("AlwaysSuccess", "AlwaysFailure"))):
        (tmp_path / name).mkdir()
        (tmp_path / name / "patrol.xml").write_text(text, encoding="utf-8")
        assert _compile(f"{name}/patrol.xml", name, tmp_path).returncode == 0
    (tmp_path / "main.cpp").write_text("int main() { return 0; }\n", encoding="utf-8")
    objects = [
        cppbuild.build(
            [tmp_path / name / "patrol.cpp"],
            tmp_path / f"{name}.o",
            mode="object",
            warnings=False,
            includes=[tmp_path / name],
        )
        for name in ("a", "b")
    ]
    proc = cppbuild.run(
        cppbuild.command([tmp_path / "main.cpp", *objects], tmp_path / "both", warnings=False, runtime=False)
    )
    assert proc.returncode != 0
    assert "btgen_one_mission_per_namespace" in proc.stderr


_PROJECT = "cmake_minimum_required(VERSION 3.16)\nproject(two LANGUAGES CXX)\nfind_package(btgen CONFIG REQUIRED)\n"


def _configure(src, build: str) -> subprocess.CompletedProcess:
    """CMake's configure step of the project in `src` (build folder `src`/`build`), btgen found by its package."""
    return subprocess.run(
        ["cmake", "-S", str(src), "-B", str(src / build), f"-Dbtgen_DIR={ROOT}/cmake"],
        capture_output=True,
        text=True,
        check=False,
    )


@pytest.mark.skipif(shutil.which("cmake") is None, reason="no cmake")
def test_two_missions_in_one_namespace_are_refused_at_configure(tmp_path):
    """The same through btgen_add_mission: refused when configuring, naming both."""
    for name in ("a", "b"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "patrol.xml").write_text(TWO_EDGES, encoding="utf-8")
    (tmp_path / "CMakeLists.txt").write_text(
        _PROJECT
        + "btgen_add_mission(mission_a MISSION a/patrol.xml)\nbtgen_add_mission(mission_b MISSION b/patrol.xml)\n",
        encoding="utf-8",
    )
    proc = _configure(tmp_path, "build")
    assert proc.returncode != 0
    err = " ".join(proc.stderr.split())
    assert "btgen_add_mission: mission_b" in err and "would generate namespace patrol" in err
    assert "which mission_a" in err and "give one of them NAMESPACE <another>" in err
    # One of them in another namespace: configures.
    (tmp_path / "CMakeLists.txt").write_text(
        (tmp_path / "CMakeLists.txt").read_text().replace("b/patrol.xml)", "b/patrol.xml NAMESPACE patrol_b)")
    )
    proc = _configure(tmp_path, "build2")
    assert proc.returncode == 0, proc.stderr
    # A NAMESPACE whose inner part would hide ::std: refused when configuring (it built C++
    # that did not compile).
    (tmp_path / "CMakeLists.txt").write_text(
        (tmp_path / "CMakeLists.txt").read_text().replace("NAMESPACE patrol_b)", "NAMESPACE robot::std)")
    )
    proc = _configure(tmp_path, "build3")
    assert proc.returncode != 0
    assert "`std` inside the mission's namespace would hide `::std`" in " ".join(proc.stderr.split())


@pytest.mark.skipif(shutil.which("cmake") is None, reason="no cmake")
def test_one_mission_for_two_programs_configures(tmp_path):
    """The same mission file with the same options built for two programs is one mission, not a
    collision (the top-level project and examples/lab_tour_robot both build missions/LabTour.xml:
    `scripts/demo.sh` failed to configure when this was refused)."""
    (tmp_path / "patrol.xml").write_text(TWO_EDGES, encoding="utf-8")
    (tmp_path / "CMakeLists.txt").write_text(
        _PROJECT + "btgen_add_mission(for_robot MISSION patrol.xml)\nbtgen_add_mission(for_tests MISSION patrol.xml)\n",
        encoding="utf-8",
    )
    proc = _configure(tmp_path, "build")
    assert proc.returncode == 0, proc.stderr
    # The same file with other options generates other code: refused.
    (tmp_path / "CMakeLists.txt").write_text(
        (tmp_path / "CMakeLists.txt")
        .read_text()
        .replace("MISSION patrol.xml)\n", "MISSION patrol.xml STRING_CAPACITY 64)\n")
        .replace("for_robot MISSION patrol.xml STRING_CAPACITY 64", "for_robot MISSION patrol.xml"),
        encoding="utf-8",
    )
    proc = _configure(tmp_path, "build2")
    assert proc.returncode != 0
    assert "btgen_add_mission: for_tests" in " ".join(proc.stderr.split())
