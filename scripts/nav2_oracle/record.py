"""RECORDER, not a test: records Nav2's own Controls and Decorators on the real BehaviorTree.CPP.

For each Nav2 distro (a branch of a local git mirror of ros-navigation/navigation2), takes
`nav2_behavior_tree/include` and every source of `nav2_behavior_tree/plugins/control` and
`plugins/decorator` out of the mirror (nothing of Nav2 is copied into this repository),
compiles each source as a BehaviorTree.CPP plugin (`-DBT_PLUGIN_EXPORT`, one shared
library each, as Nav2 builds them) against an oracle install of BehaviorTree.CPP, and
runs every case of tests/conformance/nav2/cases with a copy of the oracle harness extended
to load those plugins. DistanceController, SpeedController, GoalUpdatedController and
PathLongerOnApproach (SHIMMED) are compiled with `ros_shim.hpp` standing in for the few ROS 2
calls they make: the one where each reads its fact of the robot's world asks the harness,
which answers from the scenario's `leaf NAME ...` line of the node being ticked. A source that
does not compile even so is listed with the first header it misses (btgen leaves it to the
user).

Time: `clock_shim.hpp` is force-included before each plugin source; it turns the plugin's
`std::chrono::high_resolution_clock` into a clock that the harness advances by the
scenario's `clock_ms` before each tick after the first (instead of the harness's real
sleep), which is btgen's injectable clock. BehaviorTree.CPP's own timed nodes are not
used in these cases.

    python scripts/nav2_oracle/record.py ORACLE_PREFIX VERSION [--mirror GIT_DIR]
        [--harness HARNESS_CPP] [--distros jazzy,kilted,lyrical]
    e.g. python scripts/nav2_oracle/record.py PREFIX462 4.6.2

writes tests/conformance/nav2/<distro>-<VERSION>/<stem>.trace (or <stem>.refused, the
library's message, for a case the distro cannot load) and <distro>-<VERSION>/RECORDED.md
(the mirror commit, the plugins compiled and those refused).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
CASES = ROOT / "tests" / "conformance" / "nav2" / "cases"
OUT = ROOT / "tests" / "conformance" / "nav2"
# a local mirror of ros-navigation/navigation2 (a git dir): --mirror, or NAV2_MIRROR
DEFAULT_MIRROR = os.environ.get("NAV2_MIRROR", "")
DEFAULT_HARNESS = str(ROOT.parent / "shared" / "oracle" / "harness.cpp")  # the project's shared oracle
DISTROS = ("jazzy", "kilted", "lyrical")
CACHE = Path(tempfile.gettempdir()) / "btgen-nav2-oracle"

# What the harness copy gains: Nav2's plugins registered before the mission's leaves, and
# the scenario's clock_ms moving the plugins' clock instead of sleeping.
PREAMBLE = """
#include <behaviortree_cpp/bt_factory.h>
extern "C" {
long long btgen_nav2_clock_ns = 0;  // read by the plugins through clock_shim.hpp
}
static void btgen_nav2_register(BT::BehaviorTreeFactory& factory)
{
  const char* list = std::getenv("BTGEN_NAV2_PLUGINS");
  std::string rest = list ? list : "";
  while(!rest.empty())
  {
    auto colon = rest.find(':');
    factory.registerFromPlugin(rest.substr(0, colon));
    rest = colon == std::string::npos ? "" : rest.substr(colon + 1);
  }
}
"""
# The Decorators that read one fact of the robot's world on every tick (ros_shim.hpp): the
# harness answers it from the scenario's `leaf NAME ...` line of the node being ticked (a
# pre-tick callback on each of them says which), and their constructors find on the blackboard
# the ROS handles they take (stand-ins).
PREAMBLE += """
#include <functional>
#include <set>
#include "ros_shim.hpp"
static std::function<bool(const std::string&)> btgen_nav2_answer;
static std::string btgen_nav2_current;
static long btgen_nav2_serial_value = 0;
extern "C" int btgen_nav2_input()
{
  return btgen_nav2_answer && btgen_nav2_answer(btgen_nav2_current) ? 1 : 0;
}
extern "C" long btgen_nav2_serial()
{
  return btgen_nav2_serial_value;
}
static void btgen_nav2_attach(BT::Tree& tree, std::function<bool(const std::string&)> answer)
{
  btgen_nav2_answer = std::move(answer);
  tree.applyVisitor([](BT::TreeNode* node) {
    static const std::set<std::string> ids{"DistanceController", "SpeedController",
                                           "GoalUpdatedController", "PathLongerOnApproach"};
    if(ids.count(node->registrationName()))
      node->setPreTickFunction([](BT::TreeNode& n) {
        btgen_nav2_current = n.name();
        ++btgen_nav2_serial_value;
        return BT::NodeStatus::IDLE;
      });
  });
}
static BT::Blackboard::Ptr btgen_nav2_blackboard()
{
  auto bb = BT::Blackboard::create();
  bb->set("node", std::make_shared<rclcpp::Node>());
  bb->set("tf_buffer", std::make_shared<tf2_ros::Buffer>());
  bb->set("odom_smoother", std::make_shared<nav2_util::OdomSmoother>());
  return bb;
}
"""
PATCHES = (
    (
        "  BT::BehaviorTreeFactory factory;\n  auto leaves = collectLeaves(",
        "  BT::BehaviorTreeFactory factory;\n  btgen_nav2_register(factory);\n  auto leaves = collectLeaves(",
    ),
    (
        "factory.createTreeFromFile(std::filesystem::absolute(path));",
        "factory.createTreeFromFile(std::filesystem::absolute(path), btgen_nav2_blackboard());",
    ),
    (
        "  BT::Tree tree = createTree(factory, mission);\n\n  // Reject RUNNING",
        "  BT::Tree tree = createTree(factory, mission);\n"
        "  btgen_nav2_attach(tree, [&sc](const std::string& n) { return sc.next(n) == NodeStatus::SUCCESS; });\n"
        "\n  // Reject RUNNING",
    ),
    (
        "std::this_thread::sleep_for(std::chrono::milliseconds(sc.clock_ms));",
        "btgen_nav2_clock_ns += static_cast<long long>(sc.clock_ms) * 1000000LL;",
    ),
)


def sh(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, check=False, capture_output=True, text=True, **kw)


def harness_source(path: Path) -> str:
    text = path.read_text()
    for old, new in PATCHES:
        if text.count(old) != 1:
            sys.exit(f"error: {path}: the harness changed; cannot find exactly one {old!r}")
        text = text.replace(old, new)
    anchor = "namespace\n{\nusing BT::NodeStatus;"
    if text.count(anchor) != 1:
        sys.exit(f"error: {path}: the harness changed; no anchor for the Nav2 preamble")
    return text.replace(anchor, PREAMBLE + anchor)


def build_harness(prefix: Path, harness_cpp: Path, work: Path) -> Path:
    src = work / "nav2_harness.cpp"
    src.write_text(harness_source(harness_cpp))
    exe = work / "nav2_harness"
    r = sh(
        [
            "g++",
            "-std=c++17",
            "-O1",
            "-rdynamic",
            "-o",
            str(exe),
            str(src),
            f"-I{HERE}",
            f"-I{prefix}/include",
            f"-L{prefix}/lib",
            f"-Wl,-rpath,{prefix}/lib",
            "-lbehaviortree_cpp",
            "-ldl",
        ]
    )
    if r.returncode:
        sys.exit(f"error: the harness does not build:\n{r.stderr[-3000:]}")
    return exe


def export_distro(mirror: str, branch: str, dest: Path) -> str:
    commit = sh(["git", f"--git-dir={mirror}", "rev-parse", f"{branch}^{{commit}}"]).stdout.strip()
    if not commit:
        sys.exit(f"error: {mirror} has no branch or tag {branch}")
    if not (dest / "nav2_behavior_tree").is_dir():
        dest.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(
            ["git", f"--git-dir={mirror}", "archive", commit, "nav2_behavior_tree"], capture_output=True, check=True
        )
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive.stdout, check=True)
    return commit


# The plugin sources compiled with ros_shim.hpp standing in for ROS 2 (each reads one fact of
# the robot's world, which the harness answers from the scenario), with their extra flags.
SHIMMED = {
    "distance_controller": (),
    "speed_controller": (),
    "goal_updated_controller": ("-DBTGEN_SHIM_GOAL_INPUT",),
    "path_longer_on_approach": (),
}
# The headers those sources (and Nav2's bt_utils.hpp, json_utils.hpp) include from ROS 2: each
# becomes one line including ros_shim.hpp, in a folder searched before Nav2's own headers.
SHIM_HEADERS = (
    "rclcpp/rclcpp.hpp",
    "rclcpp/time.hpp",
    "rclcpp/node.hpp",
    "geometry_msgs/msg/pose_stamped.hpp",
    "geometry_msgs/msg/point.hpp",
    "geometry_msgs/msg/quaternion.hpp",
    "nav_msgs/msg/goals.hpp",
    "nav_msgs/msg/path.hpp",
    "nav_msgs/msg/odometry.hpp",
    "nav2_util/robot_utils.hpp",
    "nav2_util/geometry_utils.hpp",
    "nav2_util/odometry_utils.hpp",
    "nav2_util/path_utils.hpp",
    "nav2_ros_common/tf2_factories.hpp",
    "tf2_ros/buffer.h",
    "nav2_behavior_tree/bt_utils.hpp",
    "nav2_behavior_tree/json_utils.hpp",
)


def shim_include(out_dir: Path) -> Path:
    folder = out_dir / "ros_shim_include"
    for name in SHIM_HEADERS:
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text('#pragma once\n#include "ros_shim.hpp"\n')
    return folder


def compile_plugin(cpp: Path, include: Path, prefix: Path, out_dir: Path) -> tuple[Path, Path | None, str]:
    """One plugin source -> (source, shared library or None, the reason it did not build)."""
    shim = cpp.stem in SHIMMED
    digest = hashlib.sha256(cpp.read_bytes() + (HERE / "clock_shim.hpp").read_bytes() + str(prefix).encode())
    if shim:
        digest.update((HERE / "ros_shim.hpp").read_bytes() + " ".join(SHIM_HEADERS).encode())
    for hpp in sorted(include.rglob(cpp.stem + ".hpp")):
        digest.update(hpp.read_bytes())
    so = out_dir / f"lib{cpp.stem}-{digest.hexdigest()[:16]}.so"
    if so.exists():
        return cpp, so, ""
    extra = [f"-I{shim_include(out_dir)}", f"-I{HERE}", *SHIMMED[cpp.stem]] if shim else []
    r = sh(
        [
            "g++",
            "-std=c++17",
            "-O1",
            "-shared",
            "-fPIC",
            "-DBT_PLUGIN_EXPORT",
            "-include",
            str(HERE / "clock_shim.hpp"),
            *extra,
            f"-I{include}",
            f"-I{prefix}/include",
            "-o",
            str(so),
            str(cpp),
            f"-L{prefix}/lib",
            "-lbehaviortree_cpp",
        ]
    )
    if r.returncode == 0:
        return cpp, so, ""
    missing = re.search(r"fatal error: ([^:\n]+): No such file", r.stderr)
    return cpp, None, f"needs {missing.group(1)}" if missing else r.stderr.strip().splitlines()[0]


def build_plugins(mirror: str, distro: str, prefix: Path, work: Path, jobs: int) -> list[Path]:
    """The plugin libraries of one distro's Controls and Decorators that build (cached)."""
    src = CACHE / "src" / distro
    export_distro(mirror, distro, src)
    pkg = src / "nav2_behavior_tree"
    sources = sorted((pkg / "plugins" / "control").glob("*.cpp")) + sorted(
        (pkg / "plugins" / "decorator").glob("*.cpp")
    )
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        built = list(pool.map(lambda c: compile_plugin(c, pkg / "include", prefix, work), sources))
    return [so for _, so, _ in built if so]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("prefix", type=Path, help="oracle install prefix (has include/, lib/)")
    ap.add_argument("version", help="its BehaviorTree.CPP version, e.g. 4.6.2")
    ap.add_argument("--mirror", default=DEFAULT_MIRROR, required=not DEFAULT_MIRROR)
    ap.add_argument("--harness", type=Path, default=Path(DEFAULT_HARNESS))
    ap.add_argument("--distros", default=",".join(DISTROS))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument(
        "--plugins-only",
        action="store_true",
        help="build the plugins of the first distro only and print their paths, `;`-separated (the CMake "
        "list BTGEN_PLUGINS of a `btgen tests` suite): no harness, nothing recorded",
    )
    args = ap.parse_args()

    work = CACHE / args.version
    work.mkdir(parents=True, exist_ok=True)
    if args.plugins_only:
        print(";".join(str(p) for p in build_plugins(args.mirror, args.distros.split(",")[0], args.prefix, work, 1)))
        return 0
    exe = build_harness(args.prefix, args.harness, work)
    stems = sorted(p.stem for p in CASES.glob("*.xml"))
    for distro in args.distros.split(","):
        src = CACHE / "src" / distro
        commit = export_distro(args.mirror, distro, src)
        pkg = src / "nav2_behavior_tree"
        sources = sorted((pkg / "plugins" / "control").glob("*.cpp")) + sorted(
            (pkg / "plugins" / "decorator").glob("*.cpp")
        )
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            include = pkg / "include"
            built = list(pool.map(lambda c, inc=include: compile_plugin(c, inc, args.prefix, work), sources))
        plugins = [so for _, so, _ in built if so]
        dest = OUT / f"{distro}-{args.version}"
        if dest.exists():
            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        env = {"BTGEN_NAV2_PLUGINS": ":".join(str(p) for p in plugins), "PATH": "/usr/bin:/bin"}
        refused = 0
        for stem in stems:
            r = sh([str(exe), "trace", str(CASES / f"{stem}.xml"), str(CASES / f"{stem}.scenario")], env=env)
            if r.returncode == 0:
                (dest / f"{stem}.trace").write_text(r.stdout)
            else:
                refused += 1
                msg = [ln for ln in r.stderr.splitlines() if ln.startswith("error: ")]
                (dest / f"{stem}.refused").write_text((msg[-1] if msg else r.stderr.strip()) + "\n")
        lines = [
            f"# Nav2 {distro} on BehaviorTree.CPP {args.version}",
            "",
            f"Recorded by `scripts/nav2_oracle/record.py` from ros-navigation/navigation2 `{distro}` at `{commit}`.",
            "",
            "| plugin source | built |",
            "|---|---|",
        ]
        for cpp, so, why in built:
            built_as = "yes, with ros_shim.hpp for ROS 2" if cpp.stem in SHIMMED else "yes"
            lines.append(f"| `{cpp.relative_to(pkg)}` | {built_as if so else 'no: ' + why} |")
        (dest / "RECORDED.md").write_text("\n".join(lines) + "\n")
        print(f"{distro} {args.version}: {len(plugins)} plugins, {len(stems) - refused} traces, {refused} refused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
