"""btgen as a package: the wheel, installed in a fresh virtual environment outside
the checkout, works from any directory, and its CMake package builds
examples/user_project (a mission without TreeNodesModel, a models file, a
NAMESPACE) with plain cmake in a directory outside the checkout.

The wheel is built from a copy of what packaging reads (pyproject.toml,
setup.py, generator/ and the folders setup.py maps into the wheel), so the
checkout is never written, with `pip wheel --no-build-isolation` (setuptools
and wheel of .venv: no download). Installing it fetches btgen's dependencies
at the versions of requirements.txt (from pip's cache when setup.sh ran).
"""

import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from btgen import resources
from btgen.version import __version__
from conftest import ROOT, free_port_pair

USER_PROJECT = Path(ROOT) / "examples" / "user_project"
PACKAGING = (
    "pyproject.toml",
    "setup.py",
    "MANIFEST.in",
    "requirements.txt",
    "README.md",
    "LICENSE",
    "CHANGELOG.md",
    "generator",
)


def _run(cmd, cwd, env=None, check=True):
    proc = subprocess.run([str(c) for c in cmd], cwd=str(cwd), env=env, capture_output=True, text=True, check=False)
    if check and proc.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, cmd))} exited with {proc.returncode}:\n{proc.stdout}\n{proc.stderr}")
    return proc


def _clean_env(tmp: Path) -> dict:
    """The environment of a user: no PYTHONPATH to the checkout, no .venv on PATH, a private cache."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "BTGEN_EXECUTABLE")}
    venv_bin = os.path.dirname(sys.executable)
    env["PATH"] = os.pathsep.join(
        p for p in env.get("PATH", "").split(os.pathsep) if p and os.path.realpath(p) != os.path.realpath(venv_bin)
    )
    env["BTGEN_CACHE_DIR"] = str(tmp / "cache")
    return env


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(venv's btgen, environment, tmp): the wheel built and installed in a fresh venv."""
    tmp = tmp_path_factory.mktemp("package")
    assert not str(tmp).startswith(os.path.realpath(ROOT))
    src = tmp / "src"
    src.mkdir()
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info")
    for name in PACKAGING + tuple({folder.split("/")[0] for folder, _ in resources.DATA_FILES}):
        path = Path(ROOT) / name
        if path.is_dir():
            shutil.copytree(path, src / name, ignore=ignore)
        else:
            shutil.copy2(path, src / name)
    wheels = tmp / "wheels"
    _run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "-q",
            "--disable-pip-version-check",
            "--no-build-isolation",
            "--no-deps",
            "-w",
            wheels,
            src,
        ],
        cwd=tmp,
    )
    (wheel,) = wheels.glob("btgen-*.whl")
    venv = tmp / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", venv], cwd=tmp)
    python = venv / "bin" / "python"
    _run(
        [
            sys.executable,
            "-m",
            "pip",
            "--python",
            python,
            "install",
            "-q",
            "--disable-pip-version-check",
            "-c",
            Path(ROOT) / "requirements.txt",
            wheel,
        ],
        cwd=tmp,
    )
    work = tmp / "work"
    work.mkdir()
    return venv / "bin" / "btgen", _clean_env(tmp), tmp, wheel


def test_wheel_holds_every_mapped_file(installed):
    wheel = installed[3]
    names = set(zipfile.ZipFile(wheel).namelist())
    expected = set()
    for folder, pattern in resources.DATA_FILES:
        for f in (Path(ROOT) / folder).glob(pattern):
            if f.is_file():
                expected.add(f"btgen/{resources.INSTALLED_DATA}/{f.relative_to(ROOT).as_posix()}")
    assert expected and expected <= names
    assert "btgen/_data/cmake/btgenConfig.cmake" in names and "btgen/_data/templates/mission.hpp.j2" in names
    # the package is typed (mypy runs in CI), and every stage's subpackage is in the wheel
    assert "btgen/py.typed" in names
    sources = {
        f"btgen/{f.relative_to(Path(ROOT) / 'generator' / 'btgen').as_posix()}"
        for f in (Path(ROOT) / "generator" / "btgen").rglob("*.py")
    }
    assert "btgen/ir/lower.py" in sources and sources <= names


def test_wheel_metadata_has_description_licence_and_urls(installed):
    wheel = installed[3]
    with zipfile.ZipFile(wheel) as z:
        (meta,) = [n for n in z.namelist() if n.endswith(".dist-info/METADATA")]
        text = z.read(meta).decode("utf-8")
        names = z.namelist()
    headers, _, body = text.partition("\n\n")
    assert f"Version: {__version__}" in headers.splitlines()
    assert "Summary: Compile BehaviorTree.CPP v4 missions to static, allocation-free C++17" in headers
    assert "License: Apache-2.0" in headers
    assert "Classifier: License :: OSI Approved :: Apache Software License" in headers
    assert "Project-URL: BehaviorTree.CPP, https://www.behaviortree.dev/" in headers
    assert "Description-Content-Type: text/markdown" in headers
    assert body.startswith("# btgen")  # the README is the long description
    assert any(n.endswith(".dist-info/LICENSE") for n in names)


def test_cmake_package_version_is_the_generators():
    text = (Path(ROOT) / "cmake" / "btgenConfigVersion.cmake").read_text()
    assert re.search(r'set\(PACKAGE_VERSION "([^"]+)"\)', text).group(1) == __version__


def test_every_command_works_from_another_directory(installed):
    btgen, env, tmp, _ = installed
    work = tmp / "work"
    for f in (
        "missions/Reception.xml",
        "missions/scenarios/Reception.scenario",
        "data/environmentKnowledgeBaseInput.dat",
        "data/environmentKnowledgeBaseConfiguration.ini",
    ):
        shutil.copy2(Path(ROOT) / f, work / os.path.basename(f))
    site = _run([btgen.parent / "python", "-c", "import btgen, sys; print(btgen.__file__)"], work, env).stdout
    assert site.startswith(str(tmp / "venv"))  # the installed package, not the checkout

    assert _run([btgen, "--version"], work, env).stdout == f"btgen {__version__}\n"
    cmake_dir = Path(_run([btgen, "--cmake-dir"], work, env).stdout.strip())
    assert cmake_dir.is_relative_to(tmp / "venv") and (cmake_dir / "btgenConfig.cmake").is_file()

    assert (
        _run([btgen, "validate", "Reception.xml"], work, env).stdout
        == "Reception.xml: ok (6 trees, main `ReceptionGuide`)\n"
    )
    assert "<xs:schema" in _run([btgen, "xsd", "Reception.xml"], work, env).stdout
    _run([btgen, "compile", "Reception.xml", "-o", "out", "--namespace", "front_desk"], work, env)
    assert "namespace front_desk {" in (work / "out" / "reception.hpp").read_text()
    interp = _run([btgen, "run", "Reception.xml", "--scenario", "Reception.scenario"], work, env).stdout
    assert interp.endswith("result SUCCESS\n")
    assert (
        _run([btgen, "run", "Reception.xml", "--scenario", "Reception.scenario", "--engine", "cpp"], work, env).stdout
        == interp
    )
    lint = _run(
        [
            btgen,
            "lint-kb",
            "environmentKnowledgeBaseInput.dat",
            "--config",
            "environmentKnowledgeBaseConfiguration.ini",
            "--mission",
            "Reception.xml",
        ],
        work,
        env,
        check=False,
    )
    assert lint.returncode == 0 and "error" not in lint.stderr
    bench = _run([btgen, "bench", "Reception.xml", "--ticks", "50"], work, env).stdout
    assert "ticks 50\n" in bench and "allocs_per_tick 0" in bench
    refused = _run([btgen, "build-info", "--update-generated"], work, env, check=False)
    assert refused.returncode == 1 and "this btgen is installed" in refused.stderr
    # The same with the user project's mission, whose models are in another file.
    mission, models = USER_PROJECT / "mission" / "patrol.xml", USER_PROJECT / "mission" / "nodes.xml"
    assert _run([btgen, "validate", mission, "--models", models], work, env).returncode == 0
    (work / "patrol.scenario").write_text("ticks 5\ndefault SUCCESS\n")
    runs = [
        _run(
            [
                btgen,
                "run",
                mission,
                "--models",
                models,
                "--main-tree",
                "Patrol",
                "--scenario",
                "patrol.scenario",
                "--engine",
                engine,
            ],
            work,
            env,
        ).stdout
        for engine in ("interp", "cpp")
    ]
    assert runs[0] == runs[1] and runs[0].endswith("result SUCCESS\n") and 'MoveTo "MoveTo"' in runs[0]
    bad = _run([btgen, "validate", mission], work, env, check=False)
    assert bad.returncode == 1 and re.match(rf"{re.escape(str(mission))}:\d+:\d+: error: ", bad.stderr)


def _generator():
    return ["-G", "Ninja"] if shutil.which("ninja") else []


def _cmake_build(src, build, btgen, env, check=True):
    gen = _generator()
    if not (build / "CMakeCache.txt").exists():
        cmake_dir = _run([btgen, "--cmake-dir"], src, env).stdout.strip()
        _run(["cmake", "-S", src, "-B", build, *gen, f"-Dbtgen_DIR={cmake_dir}"], build.parent, env)
    return _run(["cmake", "--build", build], build.parent, env, check=check)


def test_user_project_builds_with_find_package(installed):
    btgen, env, tmp, _ = installed
    src, build = tmp / "user_project", tmp / "user_build"
    shutil.copytree(USER_PROJECT, src)
    _cmake_build(src, build, btgen, env)
    cache = (build / "CMakeCache.txt").read_text()
    assert f"BTGEN_EXECUTABLE:FILEPATH={btgen}" in cache  # the command installed with the package
    run = _run([build / "patrol_robot"], tmp, env)
    assert run.stdout == "patrol_robot: SUCCESS after 5 ticks, route kitchen;door;\n"
    assert "namespace robot::patrol {" in (build / "btgen" / "patrol_mission" / "patrol.hpp").read_text()

    # A mission error fails the build with btgen's own diagnostic; fixing it builds again.
    mission = src / "mission" / "patrol.xml"
    good = mission.read_text()
    mission.write_text(good.replace('goal="door"', 'gaol="door"'))
    failed = _cmake_build(src, build, btgen, env, check=False)
    assert failed.returncode != 0
    line = next(i for i, text in enumerate(good.splitlines(), 1) if 'goal="door"' in text)
    col = good.splitlines()[line - 1].index('goal="door"') + 1
    assert (
        f"{mission}:{line}:{col}: error: `MoveTo` has no port `gaol` (its ports: `goal`, `arrived_at`); "
        f"did you mean `goal`?"
    ) in failed.stdout + failed.stderr
    mission.write_text(good)
    _cmake_build(src, build, btgen, env)
    assert _run([build / "patrol_robot"], tmp, env).returncode == 0

    # The models file is a dependency: changing a port's type regenerates (and here fails).
    models = src / "mission" / "nodes.xml"
    models.write_text(models.read_text().replace('name="goal" type="std::string"', 'name="goal" type="int"'))
    failed = _cmake_build(src, build, btgen, env, check=False)
    assert failed.returncode != 0 and "`kitchen` is not a valid int" in failed.stdout + failed.stderr


RUNTIME_ONLY = """cmake_minimum_required(VERSION 3.16)
project(runtime_only LANGUAGES CXX)
{find}
add_executable(runtime_only main.cpp)
target_link_libraries(runtime_only PRIVATE btgen::runtime)
if(TARGET btgen::kb)
  message(FATAL_ERROR "btgen::kb is defined although Eigen was not to be found")
endif()
"""


def _runtime_only_project(tmp, find):
    src = tmp / "runtime_only"
    src.mkdir()
    (src / "CMakeLists.txt").write_text(RUNTIME_ONLY.format(find=find))
    (src / "main.cpp").write_text(
        "#include <btgen/status.hpp>\n#include <btgen/version.hpp>\n"
        "int main() { return btgen::Status::SUCCESS == btgen::Status::FAILURE; }\n"
    )
    return src


def test_the_runtime_needs_no_eigen(tmp_path):
    """runtime/CMakeLists.txt required Eigen of everyone; only btgen::kb needs it."""
    src = _runtime_only_project(tmp_path, f'add_subdirectory("{Path(ROOT).as_posix()}/runtime" runtime)')
    build = tmp_path / "build"
    _run(["cmake", "-S", src, "-B", build, *_generator(), "-DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON"], tmp_path)
    _run(["cmake", "--build", build], tmp_path)
    _run([build / "runtime_only"], tmp_path)


def test_package_kb_component_requires_eigen(installed):
    btgen, env, tmp, _ = installed
    cmake_dir = _run([btgen, "--cmake-dir"], tmp, env).stdout.strip()
    src = _runtime_only_project(tmp, "find_package(btgen CONFIG REQUIRED)")
    _run(
        [
            "cmake",
            "-S",
            src,
            "-B",
            tmp / "runtime_only_build",
            *_generator(),
            f"-Dbtgen_DIR={cmake_dir}",
            "-DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON",
        ],
        tmp,
        env,
    )
    (src / "CMakeLists.txt").write_text(RUNTIME_ONLY.format(find="find_package(btgen CONFIG REQUIRED COMPONENTS kb)"))
    failed = _run(
        [
            "cmake",
            "-S",
            src,
            "-B",
            tmp / "kb_build",
            *_generator(),
            f"-Dbtgen_DIR={cmake_dir}",
            "-DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON",
        ],
        tmp,
        env,
        check=False,
    )
    assert failed.returncode != 0 and "component kb needs Eigen 3.3" in failed.stderr


def test_find_package_from_the_environment_on_path(installed):
    """The wheel installs <venv>/share/cmake/btgen/, where CMake looks for every PATH entry
    ending in bin/: with the environment's bin/ on PATH (an activated venv) no -Dbtgen_DIR is
    needed. Without it on PATH, nothing finds the package."""
    btgen, env, tmp, _ = installed
    venv = btgen.parent.parent
    assert (venv / "share" / "cmake" / "btgen" / "btgenConfig.cmake").is_file()
    (tmp / "on_path").mkdir()
    src = _runtime_only_project(tmp / "on_path", "find_package(btgen CONFIG REQUIRED)")
    active = dict(env, PATH=f"{venv / 'bin'}{os.pathsep}{env['PATH']}")
    build = tmp / "on_path" / "build"
    no_eigen = "-DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON"  # what the project checks (RUNTIME_ONLY)
    _run(["cmake", "-S", src, "-B", build, *_generator(), no_eigen], tmp, active)
    cache = (build / "CMakeCache.txt").read_text()
    assert f"btgen_DIR:PATH={venv / 'share' / 'cmake' / 'btgen'}" in cache
    assert f"BTGEN_EXECUTABLE:FILEPATH={btgen}" in cache
    _run(["cmake", "--build", build], tmp, active)
    inactive = _run(
        ["cmake", "-S", src, "-B", tmp / "on_path" / "build2", *_generator(), no_eigen], tmp, env, check=False
    )
    assert inactive.returncode != 0 and "btgenConfig.cmake" in inactive.stderr


def test_lab_tour_robot_builds_as_the_readme_tells_users(installed):
    """examples/lab_tour_robot on its own, the way a user's project is built: find_package of
    the installed btgen (no btgen_DIR, no checkout on the module path, the environment's
    Python for btgen), then the robot runs a scenario to its end."""
    btgen, env, tmp, _ = installed
    venv = btgen.parent.parent
    active = dict(env, PATH=f"{venv / 'bin'}{os.pathsep}{env['PATH']}")
    build = tmp / "robot_build"
    source = Path(ROOT) / "examples" / "lab_tour_robot"
    configure = _run(["cmake", "-S", source, "-B", build, *_generator(), "-DBTGEN_BUILD_TESTS=OFF"], tmp, active)
    assert "does not compile" not in configure.stdout + configure.stderr
    assert "btgen_DIR" not in configure.stderr  # no "manually-specified variable not used" warning
    cache = (build / "CMakeCache.txt").read_text()
    assert f"btgen_DIR:PATH={venv / 'share' / 'cmake' / 'btgen'}" in cache  # the installed package
    assert f"BTGEN_EXECUTABLE:FILEPATH={btgen}" in cache  # and its command, not the checkout's
    _run(["cmake", "--build", build, "--target", "lab_tour_robot", "-j", "2"], tmp, active)
    run = _run([build / "lab_tour_robot", "--scenario", "missions/scenarios/LabTour.yes.scenario"], Path(ROOT), active)
    assert run.stdout.splitlines()[-1].startswith("lab_tour_robot: mission SUCCESS at tick")


def test_init_writes_a_project_that_builds_and_runs(installed):
    """`btgen init` from the installed package: the project builds with find_package from the
    active environment, and the robot prints what the scenario of the project predicts."""
    btgen, env, tmp, _ = installed
    venv = btgen.parent.parent
    active = dict(env, PATH=f"{venv / 'bin'}{os.pathsep}{env['PATH']}")
    _run([btgen, "init", "starter-bot"], tmp, active)
    project = tmp / "starter-bot"
    _run(["cmake", "-S", project, "-B", project / "build", *_generator()], tmp, active)
    _run(["cmake", "--build", project / "build"], tmp, active)
    run = _run([project / "build" / "starter_bot"], project, active)
    assert run.stdout.splitlines() == [
        "starter_bot: MoveTo: driving to kitchen",
        "starter_bot: MoveTo: driving to kitchen",
        'starter_bot: says "arrived at kitchen"',
        "starter_bot: mission SUCCESS after 4 ticks",
    ]
    models = ["--models", "mission/models.xml"]
    trace = _run(
        [btgen, "run", "mission/mission.xml", *models, "--scenario", "mission/mission.scenario"], project, active
    ).stdout
    assert trace.endswith("result SUCCESS\n") and "tick 4\n" in trace and "tick 5\n" not in trace


MONITORED = """cmake_minimum_required(VERSION 3.16)
project(monitored_patrol LANGUAGES CXX)
find_package(btgen CONFIG REQUIRED COMPONENTS btlog groot2)
btgen_add_mission(patrol_mission MISSION mission/patrol.xml MODELS mission/nodes.xml NAMESPACE robot::patrol)
add_executable(monitored main.cpp)
target_link_libraries(monitored PRIVATE patrol_mission btgen::groot2)
target_compile_options(monitored PRIVATE -Wall -Wextra -Wpedantic -Werror)
"""

MONITORED_MAIN = """#include <cstdio>
#include <cstdlib>
#include <string>

#include <btgen/btlog.hpp>
#include <btgen/groot2.hpp>
#include <btgen/monitor.hpp>

#include "patrol.hpp"

struct Leaves {
  btgen::Status check(robot::patrol::leaf::BatteryOk&, const btgen::NodeInfo&) { return btgen::Status::SUCCESS; }
  btgen::Status onStart(robot::patrol::leaf::MoveTo&, const btgen::NodeInfo&) { return btgen::Status::RUNNING; }
  btgen::Status onRunning(robot::patrol::leaf::MoveTo& node, const btgen::NodeInfo&) {
    auto goal = node.goal();
    return goal && node.set_arrived_at(*goal) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  void onHalted(robot::patrol::leaf::MoveTo&, const btgen::NodeInfo&) {}
};

using Mission = robot::patrol::Patrol<Leaves, btgen::SteadyClock, btgen::MonitorObserver<>>;

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  Leaves leaves;
  static Mission mission(leaves);
  btgen::Status status = btgen::Status::RUNNING;
  {
    btgen::groot2::Publisher groot2(mission, static_cast<unsigned>(std::atoi(argv[2])), "127.0.0.1");
    btgen::btlog::FileLogger log(mission, argv[1]);
    for (int tick = 0; status == btgen::Status::RUNNING && tick < 100; ++tick) {
      status = mission.tick();
      groot2.sync();
    }
  }
  std::printf("%s\\n", status == btgen::Status::SUCCESS ? "SUCCESS" : "FAILURE");
  return status == btgen::Status::SUCCESS ? 0 : 1;
}
"""


def test_package_gives_the_groot2_monitors(installed):
    """find_package(btgen COMPONENTS btlog groot2): a user project attaches the Groot2
    publisher and the .btlog logger from the installed package."""
    btgen, env, tmp, _ = installed
    src = tmp / "monitored"
    shutil.copytree(USER_PROJECT / "mission", src / "mission")
    (src / "CMakeLists.txt").write_text(MONITORED)
    (src / "main.cpp").write_text(MONITORED_MAIN)
    build = tmp / "monitored_build"
    _cmake_build(src, build, btgen, env)
    log = tmp / "patrol.btlog"
    run = _run([build / "monitored", log, free_port_pair()], tmp, env)
    assert run.stdout == "SUCCESS\n"
    data = log.read_bytes()
    assert data.startswith(b"BTCPP4-FileLogger2")
    assert b'BTCPP_format="4"' in data and b"MoveTo" in data


ENUM_PROJECT = """cmake_minimum_required(VERSION 3.16)
project(enum_user LANGUAGES CXX)
find_package(btgen CONFIG REQUIRED)
btgen_add_mission(lights MISSION lights.xml {enums})
add_executable(lights_run main.cpp)
target_link_libraries(lights_run PRIVATE lights)
target_compile_options(lights_run PRIVATE -Wall -Wextra -Wpedantic -Werror)
"""

ENUM_MISSION = """<root BTCPP_format="4" main_tree_to_execute="Lights">
  <BehaviorTree ID="Lights">
    <Sequence>
      <Script code="light := GREEN; mode := FAST"/>
      <ScriptCondition code="light == 1 &amp;&amp; mode == 10"/>
    </Sequence>
  </BehaviorTree>
</root>
"""

ENUM_MAIN = """#include "lights.hpp"
struct NoLeaves {};
int main() {
  NoLeaves leaves;
  lights::Lights<NoLeaves> mission(leaves);
  return mission.tick() == btgen::Status::SUCCESS ? 0 : 1;
}
"""


def test_btgen_add_mission_takes_scripting_enums(installed):
    """ENUMS and ENUM_FILES reach `btgen compile --enum/--enums`; a file of enums is a dependency."""
    btgen, env, tmp, _ = installed
    src = tmp / "enum_user"
    src.mkdir()
    (src / "lights.xml").write_text(ENUM_MISSION)
    (src / "main.cpp").write_text(ENUM_MAIN)
    (src / "modes.txt").write_text("# speeds\nMode=SLOW=5,FAST=10\n")
    (src / "CMakeLists.txt").write_text(ENUM_PROJECT.format(enums="ENUMS Color=RED,GREEN,BLUE ENUM_FILES modes.txt"))
    build = tmp / "enum_build"
    _cmake_build(src, build, btgen, env)
    assert _run([build / "lights_run"], tmp, env, check=False).returncode == 0
    # FAST is 11 now: the condition fails, so the file was read again.
    (src / "modes.txt").write_text("Mode=SLOW=5,FAST=11\n")
    _cmake_build(src, build, btgen, env)
    assert _run([build / "lights_run"], tmp, env, check=False).returncode == 1
    # Without the enums the names are entries nothing creates: the library loads the mission and
    # throws where a script reads one, so the build warns with btgen's diagnostic and the
    # mission stops there (its tick is no SUCCESS).
    (src / "CMakeLists.txt").write_text(ENUM_PROJECT.format(enums=""))
    built = _cmake_build(src, build, btgen, env, check=False)
    assert built.returncode == 0 and "reads `GREEN`" in built.stdout + built.stderr
    assert _run([build / "lights_run"], tmp, env, check=False).returncode != 0


TYPE_PROJECT = """cmake_minimum_required(VERSION 3.16)
project(type_user LANGUAGES CXX)
find_package(btgen CONFIG REQUIRED)
btgen_add_mission(poses MISSION poses.xml TYPES Pose2D=nav::Pose2D@nav/pose2d.hpp)
target_include_directories(poses PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
add_executable(poses_run main.cpp)
target_link_libraries(poses_run PRIVATE poses)
target_compile_options(poses_run PRIVATE -Wall -Wextra -Wpedantic -Werror)
"""

TYPE_MISSION = """<root BTCPP_format="4" main_tree_to_execute="Poses">
  <BehaviorTree ID="Poses">
    <MoveTo goal="1.5;2;0"/>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="MoveTo"><input_port name="goal" type="Pose2D"/></Action>
  </TreeNodesModel>
</root>
"""

TYPE_MAIN = """#include "poses.hpp"
struct Leaves {
  btgen::Status tick(poses::leaf::MoveTo& m, const btgen::NodeInfo&) {
    const btgen::Input<nav::Pose2D> goal = m.goal();
    return goal && goal->x == 1.5 && goal->y == 2.0 ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
};
int main() {
  Leaves leaves;
  poses::Poses<Leaves> mission(leaves);
  return mission.errors() == 0 && mission.tick() == btgen::Status::SUCCESS ? 0 : 1;
}
"""

TYPE_HEADER = """#pragma once
#include <cstdio>
#include <string_view>
namespace nav {
struct Pose2D { double x, y, theta; };
inline bool convertFromString(std::string_view text, Pose2D& out) {
  char buffer[64] = {};
  if (text.size() >= sizeof buffer) return false;
  text.copy(buffer, text.size());
  return std::sscanf(buffer, "%lf;%lf;%lf", &out.x, &out.y, &out.theta) == 3;
}
}  // namespace nav
"""


def test_btgen_add_mission_takes_user_port_types(installed):
    """TYPES reaches `btgen compile --type`; the installed runtime has btgen/user_type.hpp."""
    btgen, env, tmp, _ = installed
    src = tmp / "type_user"
    (src / "include" / "nav").mkdir(parents=True)
    (src / "poses.xml").write_text(TYPE_MISSION)
    (src / "main.cpp").write_text(TYPE_MAIN)
    (src / "include" / "nav" / "pose2d.hpp").write_text(TYPE_HEADER)
    (src / "CMakeLists.txt").write_text(TYPE_PROJECT)
    build = tmp / "type_build"
    _cmake_build(src, build, btgen, env)
    assert _run([build / "poses_run"], tmp, env, check=False).returncode == 0
