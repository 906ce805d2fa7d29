"""`btgen init DIR`: a starter robot project that builds as it is.

    btgen init DIR [--name NAME]

DIR/ gets a mission (mission/mission.xml, as Groot2 saves one, without models), its node
models in a file of their own (mission/models.xml), a scenario for `btgen run`, the leaves in
C++ with every hook the generated code calls (src/main.cpp: `check` for a Condition,
`onStart`/`onRunning`/`onHalted` for an Action that takes time, `tick` for one that finishes in
the call, the port accessors), a CMakeLists.txt that finds
the installed btgen (find_package, btgen_add_mission) and a README that says what to run. DIR
must not exist, or be empty; the files appear all at once (written in a sibling folder, then
renamed), never half a project. NAME (default: DIR's name) becomes the CMake project, the
executable and the C++ namespace.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile

from btgen import cmdline
from btgen.backend_cpp.naming import namespace_name

MISSION = """<?xml version="1.0" encoding="UTF-8"?>
<!-- The mission, as Groot2 saves it. Its node models are in models.xml: give that file to
     btgen with its models option (CMake: MODELS). -->
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="Errand">
      <BatteryOk/>
      <RetryUntilSuccessful num_attempts="2">
        <MoveTo goal="kitchen" arrived_at="{{where}}"/>
      </RetryUntilSuccessful>
      <Say message="{{where}}"/>
    </Sequence>
  </BehaviorTree>
</root>
"""

MODELS = """<?xml version="1.0" encoding="UTF-8"?>
<!-- What the robot's C++ implements (src/main.cpp), as BT::writeTreeNodesModelXML or
     Groot2's palette writes it. -->
<root BTCPP_format="4">
  <TreeNodesModel>
    <Condition ID="BatteryOk"/>
    <Action ID="MoveTo">
      <input_port name="goal" type="std::string">where to drive</input_port>
      <output_port name="arrived_at" type="std::string">where the robot stopped</output_port>
    </Action>
    <Action ID="Say">
      <input_port name="message" type="std::string">what to say</input_port>
    </Action>
  </TreeNodesModel>
</root>
"""

SCENARIO = """# `btgen run mission/mission.xml --models mission/models.xml --scenario mission/mission.scenario`
# As src/main.cpp: the first drive fails, the retry drives two ticks and gets there; the
# mission ends SUCCESS at tick 4.
ticks 10
default SUCCESS
leaf MoveTo FAILURE RUNNING RUNNING SUCCESS
"""

CMAKE = """cmake_minimum_required(VERSION 3.16)
project({name} LANGUAGES CXX)

# The btgen installed with pip: found from its environment's bin/ on PATH (an active virtual
# environment), else give -Dbtgen_DIR="$(btgen --cmake-dir)".
find_package(btgen CONFIG REQUIRED)

# mission/mission.xml -> {name}_mission: a static library, #include "mission.hpp".
# Regenerated when the mission or the models change; a mission error fails the build with
# btgen's path:line:col diagnostic.
btgen_add_mission({name}_mission
  MISSION mission/mission.xml
  MODELS mission/models.xml
  NAMESPACE {name})

add_executable({name} src/main.cpp)
target_link_libraries({name} PRIVATE {name}_mission)
target_compile_options({name} PRIVATE -Wall -Wextra -Wpedantic -Werror)
"""

MAIN = """// {name}: the leaves of the mission (one hook per thing the mission asks of the robot) and
// the loop that ticks it. Replace the bodies with your robot's code.
#include <cstdio>
#include <string>

#include "mission.hpp"  // generated from mission/mission.xml by btgen_add_mission

namespace {{

namespace leaf = {name}::leaf;
using btgen::NodeInfo;
using btgen::Status;

struct Leaves {{
  int drives = 0;     // MoveTo calls so far (the first one fails, for the retry to show)
  int ticks_to_go = 0;

  // A Condition answers in one call: SUCCESS or FAILURE, never RUNNING.
  Status check(leaf::BatteryOk&, const NodeInfo&) {{ return Status::SUCCESS; }}

  // An Action that takes time (BehaviorTree.CPP's StatefulActionNode): onStart when it is
  // ticked while idle, onRunning while it is RUNNING, onHalted when its parent stops it.
  // Ports are typed accessors: node.goal() gives the input (empty when it cannot be read),
  // node.set_arrived_at(value) writes the output.
  Status onStart(leaf::MoveTo& node, const NodeInfo& info) {{
    const auto goal = node.goal();
    if (!goal) return Status::FAILURE;
    std::printf("{name}: %.*s: driving to %s\\n", static_cast<int>(info.name.size()), info.name.data(),
                std::string(*goal).c_str());
    if (++drives == 1) return Status::FAILURE;  // the first attempt fails
    ticks_to_go = 1;
    return Status::RUNNING;
  }}
  Status onRunning(leaf::MoveTo& node, const NodeInfo&) {{
    if (ticks_to_go-- > 0) return Status::RUNNING;
    const auto goal = node.goal();
    return goal && node.set_arrived_at(*goal) ? Status::SUCCESS : Status::FAILURE;
  }}
  void onHalted(leaf::MoveTo&, const NodeInfo&) {{ std::printf("{name}: stopped driving\\n"); }}

  // An Action that finishes in the call (BehaviorTree.CPP's SyncActionNode): tick() alone,
  // SUCCESS or FAILURE, called each time the node is ticked.
  Status tick(leaf::Say& node, const NodeInfo&) {{
    const auto message = node.message();
    if (!message) return Status::FAILURE;
    std::printf("{name}: says \\"arrived at %s\\"\\n", std::string(*message).c_str());
    return Status::SUCCESS;
  }}
}};

}}  // namespace

int main() {{
  Leaves leaves;
  {name}::Mission<Leaves> mission(leaves);  // mission.xml; its whole state is this object, no heap
  Status status = Status::RUNNING;
  int tick = 0;
  while (status == Status::RUNNING && tick < 100) {{
    status = mission.tick();
    ++tick;
  }}
  std::printf("{name}: mission %s after %d ticks\\n", status == Status::SUCCESS ? "SUCCESS" : "FAILURE", tick);
  return status == Status::SUCCESS ? 0 : 1;
}}
"""

README = """# {title}

A robot project made by `btgen init`: the mission in `mission/` (edit it in Groot2), the
robot's code in `src/main.cpp`. Its CMake project, executable and C++ namespace are `{name}`.

    btgen validate mission/mission.xml --models mission/models.xml
    btgen run mission/mission.xml --models mission/models.xml --scenario mission/mission.scenario
    btgen graph mission/mission.xml --models mission/models.xml -o mission.svg
    cmake -S . -B build && cmake --build build && ./build/{name}

CMake finds btgen from the active virtual environment (its `bin/` on `PATH`); otherwise add
`-Dbtgen_DIR="$(btgen --cmake-dir)"`. A node added to the mission needs its model in
`mission/models.xml` and its hooks in `src/main.cpp`; the build says which are missing.
"""

GITIGNORE = "/build/\n"


def project_files(name: str, title: str = "") -> dict[str, str]:
    return {
        "CMakeLists.txt": CMAKE.format(name=name),
        "README.md": README.format(name=name, title=title or name),
        ".gitignore": GITIGNORE,
        "mission/mission.xml": MISSION.format(),
        "mission/models.xml": MODELS,
        "mission/mission.scenario": SCENARIO,
        "src/main.cpp": MAIN.format(name=name),
    }


# Target names CMake reserves (policy CMP0037, and the targets its generators make: `ninja
# test`, `make help`, Visual Studio's ALL_BUILD, ...) and those btgen's CMake package defines:
# a project named so would not configure, so its name gets `_robot`.
CMAKE_RESERVED = frozenset(
    {
        "all",
        "clean",
        "help",
        "install",
        "test",
        "package",
        "package_source",
        "edit_cache",
        "rebuild_cache",
        "depend",
        "preinstall",
        "list_install_components",
        "all_build",
        "zero_check",
        "run_tests",
        "continuous",
        "experimental",
        "nightly",
        "nightlymemorycheck",
        "btgen_runtime",
        "btgen_scenario",
        "btgen_kb",
        "btgen_btlog",
        "btgen_groot2",
        "btgen_bsp",
    }
)


def project_name(wanted: str) -> str:
    """The CMake project, executable and namespace name of `btgen init` for `wanted` (DIR's
    name or --name): a C++ identifier (naming.namespace_name) that is no target name CMake
    reserves, nor one of btgen's."""
    name = namespace_name(wanted)
    low = name.lower()
    if low in CMAKE_RESERVED or low.startswith("cmake_") or f"{low}_mission" in CMAKE_RESERVED:
        name += "_robot"
    return name


def init_command(args) -> int:
    target = os.path.normpath(args.directory)
    exists = os.path.exists(target)
    if exists and (not os.path.isdir(target) or os.listdir(target)):
        what = "is not a folder" if not os.path.isdir(target) else "is not empty"
        raise cmdline.error(args, args.directory, f"{args.directory} {what}: `btgen init` writes a new project")
    title = args.name or os.path.basename(os.path.abspath(target))
    name = project_name(title)
    # A new folder is written beside it and renamed into place; an empty folder (`.` among
    # them, which cannot be renamed onto) gets the files written in a folder inside it, then
    # moved up, and removed again if one cannot be.
    parent = os.path.abspath(target) if exists else os.path.dirname(os.path.abspath(target))
    try:
        os.makedirs(parent, exist_ok=True)
        work = tempfile.mkdtemp(prefix=".btgen-init-", dir=parent)
    except OSError as e:
        raise cmdline.error(
            args, args.directory, f"{args.directory}: cannot create the project: {e.strerror or e}"
        ) from None
    moved: list[str] = []
    try:
        for rel, text in project_files(name, title).items():
            path = os.path.join(work, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(work, 0o777 & ~umask)  # what a new folder gets (mkdtemp's is 0700)
        if not exists:
            os.replace(work, target)  # onto a missing folder: all the files at once
        else:
            for entry in sorted(os.listdir(work)):
                os.rename(os.path.join(work, entry), os.path.join(target, entry))
                moved.append(os.path.join(target, entry))
            os.rmdir(work)
    except OSError as e:
        for path in moved:  # the folder is empty again, as it was
            with contextlib.suppress(OSError):
                shutil.rmtree(path) if os.path.isdir(path) else os.unlink(path)
        with contextlib.suppress(OSError):
            shutil.rmtree(work)
        raise cmdline.error(
            args, args.directory, f"{args.directory}: cannot create the project: {e.strerror or e}"
        ) from None
    readme = os.path.join(args.directory, "README.md")
    print(f"btgen init: wrote the project `{name}` into {args.directory} (next: read {readme})")
    return 0
