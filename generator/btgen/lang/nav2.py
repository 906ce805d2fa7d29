"""Nav2's own Controls and Decorators, as built-in node families, and what changed between
Nav2 distros.

Nav2 (ros-navigation/navigation2) registers these nodes from `nav2_behavior_tree/plugins`
in C++; its `nav2_tree_nodes.xml` only documents them. The ones whose code needs nothing
but BehaviorTree.CPP are built into both btgen engines when a mission selects Nav2's
nodes (`--nodes nav2[:DISTRO]`, or a models file that is Nav2's: `detect`). Their
behaviour was recorded from Nav2's own sources compiled against the real library
(`scripts/nav2_oracle/`, `tests/conformance/nav2/`), never read from them.

Five Decorators read one fact of the robot's world from ROS 2 (tf2, odometry, the goal, a
path): they are built in too, that fact an input of the scenario (`ENV_INPUTS`), recorded on
Nav2's code with scripts/nav2_oracle/ros_shim.hpp. PauseResumeController (ROS 2 services)
stays the user's (`ROS_NODES` says why).

`RENAMES` is the one table of what a tree written for one distro must change to mean the
same on the next (node IDs renamed, a port default that changed behaviour).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Optional

from btgen.lang import catalogue
from btgen.lang.catalogue import NodeSpec, PortSpec

DISTROS = ("jazzy", "kilted", "lyrical")  # oldest first
NEWEST = DISTROS[-1]
# The values of `--nodes`: BehaviorTree.CPP's nodes only, or Nav2's families of a distro.
NODES_CHOICES = ("btcpp", "nav2") + tuple(f"nav2:{d}" for d in DISTROS)


def _control(
    id_: str, ports: tuple[PortSpec, ...] = (), lo: int = 1, hi: Optional[int] = None, d: str = ""
) -> NodeSpec:
    return NodeSpec(id_, "Control", ports, True, lo, hi, d)


def _decorator(id_: str, ports: tuple[PortSpec, ...] = (), d: str = "") -> NodeSpec:
    return NodeSpec(id_, "Decorator", ports, True, 1, 1, d)


_PIPELINE = _control(
    "PipelineSequence", d="Nav2: a sequence that ticks again, on every tick, the children before the RUNNING one"
)
_RECOVERY = _control(
    "RecoveryNode",
    (PortSpec("number_of_retries", "input", "int", "1", description="times the recovery child may run"),),
    2,
    2,
    "Nav2: ticks the first child; when it fails, the second (the recovery), then the first again",
)
_ROUND_ROBIN_ALWAYS_WRAPS = _control(
    "RoundRobin", d="Nav2: ticks one child per run, starting after the last one that succeeded"
)
_ROUND_ROBIN = _control(
    "RoundRobin",
    (
        PortSpec(
            "wrap_around",
            "input",
            "bool",
            "false",
            description="go on from the last child to the first when a run started past the first",
        ),
    ),
    d="Nav2: ticks one child per run, starting after the last one that succeeded",
)
_NONBLOCKING = _control(
    "NonblockingSequence", d="Nav2: ticks every child on every tick; succeeds when all succeed on one tick"
)
_PERSISTENT = _control(
    "PersistentSequence",
    (
        PortSpec(
            "current_child_idx",
            "inout",
            "int",
            None,
            True,
            description="the child to run, kept on the blackboard (set it with a Script first)",
        ),
    ),
    d="Nav2: a sequence whose place is a blackboard entry, so it survives a halt",
)
_RATE = _decorator(
    "RateController",
    (PortSpec("hz", "input", "double", "10.0", description="most runs of the child per second"),),
    "Nav2: ticks its child at most `hz` times a second (a RUNNING child on every tick)",
)
_SINGLE = _decorator("SingleTrigger", d="Nav2: ticks its child once while it stays active, then fails")


# Nav2's Decorators whose code reads ROS 2 for one fact (how far the robot went, whether a
# period set by its speed passed, whether the goal changed, whether the new path is longer on
# approach): that fact is an *input of the environment*, scripted per consultation as a
# Condition's result is (`leaf NAME SUCCESS FAILURE ...`, SUCCESS meaning yes), explored and
# covered like one. Each node consults it once on every tick, where Nav2's code reads that
# fact; the node's control logic around it is Nav2's (interp/nav2.py, runtime btgen/nav2.hpp).
# ENV_INPUTS says what the input of each means (SUCCESS: yes).
def _port(name: str, direction: str = "input", type_: str = "any", default: Optional[str] = None) -> PortSpec:
    return PortSpec(name, direction, type_, default)


_FRAMES = (_port("global_frame", type_="string"), _port("robot_base_frame", type_="string"))
_DISTANCE = _decorator(
    "DistanceController",
    (_port("distance", type_="double", default="1.0"), *_FRAMES),
    "Nav2: ticks its child again once the robot has travelled `distance` (an input of the scenario)",
)
_GOAL_PORTS = (_port("goal"), _port("goals"))
_SPEED = _decorator(
    "SpeedController",
    (
        _port("min_rate", type_="double", default="0.1"),
        _port("max_rate", type_="double", default="1.0"),
        _port("min_speed", type_="double", default="0.0"),
        _port("max_speed", type_="double", default="0.5"),
        *_GOAL_PORTS,
    ),
    "Nav2: ticks its child again when a period set by the robot's speed has passed (an input of the scenario)",
)
_GOAL_UPDATED = _decorator(
    "GoalUpdatedController",
    _GOAL_PORTS,
    "Nav2: ticks its child when the goal changed (an input of the scenario) or while it runs",
)
_LONGER = _decorator(
    "PathLongerOnApproach",
    (
        _port("path"),
        _port("prox_len", type_="double", default="3.0"),
        _port("length_factor", type_="double", default="2.0"),
    ),
    "Nav2: ticks its child when a new path is much longer near the goal (an input of the scenario), else succeeds",
)
_UPDATER_JAZZY = _decorator(
    "GoalUpdater",
    (_port("input_goal"), _port("output_goal", "output")),
    "Nav2: writes the goal (input_goal, or a newer one from a topic) to output_goal, then ticks its child",
)
_UPDATER = _decorator(
    "GoalUpdater",
    (_port("input_goal"), _port("input_goals"), _port("output_goal", "output"), _port("output_goals", "output")),
    "Nav2: writes the goal (input_goal, or a newer one from a topic) to output_goal, then ticks its child",
)
_ROS_JAZZY = (_DISTANCE, _SPEED, _GOAL_UPDATED, _LONGER, _UPDATER_JAZZY)
_ROS_LYRICAL = (_DISTANCE, _SPEED, _GOAL_UPDATED, _LONGER, _UPDATER)

# What the scripted input of each means (SUCCESS: yes), and when the node consults it.
ENV_INPUTS = {
    "DistanceController": "the robot is `distance` or more from where it was when the node started or its "
    "child last succeeded",
    "SpeedController": "the period set by the robot's speed has passed since the child was last ticked for it, "
    "or the goal (`goal`/`goals`) changed",
    "GoalUpdatedController": "the goal (`goal`/`goals`) changed since the last tick",
    "PathLongerOnApproach": "a new path came, the robot is within `prox_len` of the goal and the new path is "
    "longer than `length_factor` times the old one",
}
# GoalUpdater has no scripted input: no goal ever arrives on its topic in a scenario (so
# output_goal is input_goal, as in Nav2 when nothing is published).
ENV_NODES = frozenset(ENV_INPUTS) | {"GoalUpdater"}

_FAMILIES: dict[str, tuple[NodeSpec, ...]] = {
    "jazzy": (_PIPELINE, _RECOVERY, _ROUND_ROBIN_ALWAYS_WRAPS, _RATE, _SINGLE, *_ROS_JAZZY),
    "kilted": (_PIPELINE, _RECOVERY, _ROUND_ROBIN_ALWAYS_WRAPS, _RATE, _SINGLE, *_ROS_JAZZY),
    "lyrical": (_PIPELINE, _RECOVERY, _ROUND_ROBIN, _NONBLOCKING, _PERSISTENT, _RATE, _SINGLE, *_ROS_LYRICAL),
}
ALL_FAMILY_IDS = frozenset(s.id for specs in _FAMILIES.values() for s in specs)


def families(distro: str) -> dict[str, NodeSpec]:
    """The Nav2 Controls and Decorators btgen builds in for a distro."""
    return {s.id: s for s in _FAMILIES[distro]}


def round_robin_wraps_always(distro: str) -> bool:
    """Before lyrical RoundRobin always went on from the last child to the first."""
    return families(distro)["RoundRobin"].port("wrap_around") is None


# Nav2's Controls and Decorators whose code needs ROS 2 and that btgen does not build in: what
# for (the reason they stay the user's): it does not compile without ROS 2 headers
# (scripts/nav2_oracle/record.py), and its pause and resume come from service calls.
ROS_NODES = {
    "PauseResumeController": "it offers ROS 2 services to pause and resume",
}


def ros_node_message(node_id: str, kind: str) -> str:
    """Why a Nav2 node stays the user's, and how to declare it."""
    return (
        f"`{node_id}` is a Nav2 {kind} that needs ROS 2 ({ROS_NODES[node_id]}), so btgen does not build it "
        f"in: declare it in TreeNodesModel (Nav2's nav2_tree_nodes.xml does) and give it your "
        f"implementation (its tick() hook in the C++ that `btgen compile` generates)"
    )


@dataclass(frozen=True)
class Rename:
    """One change a tree written for `old` needs to mean the same on `new`."""

    old: str  # distro
    new: str
    node: str  # node ID on `old`
    to: str  # node ID on `new` (the same when only a port changed)
    port: str = ""  # a port whose meaning changed
    note: str = ""


# Nav2 #5991 renamed three Conditions for lyrical; #5308 gave RoundRobin `wrap_around` (default
# false), where it had always wrapped: a tree keeps its behaviour with wrap_around="true".
RENAMES: tuple[Rename, ...] = (
    Rename("kilted", "lyrical", "IsPathValid", "ValidatePath"),
    Rename("kilted", "lyrical", "IsStopped", "CheckStopStatus"),
    Rename("kilted", "lyrical", "IsPoseOccupied", "CheckPoseOccupancy"),
    Rename(
        "kilted",
        "lyrical",
        "RoundRobin",
        "RoundRobin",
        "wrap_around",
        'RoundRobin always wrapped around before lyrical: write wrap_around="true" to keep that',
    ),
)


def renames(old: str, new: str) -> tuple[Rename, ...]:
    """The changes between two distros (old before new), in order."""
    lo, hi = DISTROS.index(old), DISTROS.index(new)
    steps = {(DISTROS[i], DISTROS[i + 1]) for i in range(lo, hi)}
    return tuple(r for r in RENAMES if (r.old, r.new) in steps)


def parse_nodes(value: str) -> Optional[str]:
    """`--nodes` -> the Nav2 distro (None for `btcpp`)."""
    if value == "btcpp":
        return None
    return NEWEST if value == "nav2" else value.split(":", 1)[1]


def detect(models: Iterable[NodeSpec]) -> Optional[str]:
    """The Nav2 distro of a set of TreeNodesModel declarations that are Nav2's (its
    nav2_tree_nodes.xml declares PipelineSequence, RecoveryNode and RateController beside its
    ComputePathToPose and FollowPath Actions; a mission that declares only the first three is
    taken to implement them itself), else None.
    The distro is the one whose families those declarations match: RoundRobin's `wrap_around`
    or NonblockingSequence mean lyrical, CheckStopStatus lyrical, IsStopped kilted."""
    by_id = {m.id: m for m in models}
    signature = {
        "PipelineSequence": "Control",
        "RecoveryNode": "Control",
        "RateController": "Decorator",
        "ComputePathToPose": "Action",
        "FollowPath": "Action",
    }
    if not all(i in by_id and by_id[i].kind == k for i, k in signature.items()):
        return None
    rr = by_id.get("RoundRobin")
    if (
        (rr is not None and rr.port("wrap_around") is not None)
        or "NonblockingSequence" in by_id
        or "CheckStopStatus" in by_id
    ):
        return "lyrical"
    if "IsStopped" in by_id:
        return "kilted"
    return "jazzy"


_WITH_NAV2: dict[tuple[str, str], dict[str, NodeSpec]] = {}


def builtins_for(version: str, nav2: Optional[str] = None) -> dict[str, NodeSpec]:
    """The built-in nodes a version registers (lang/catalogue.py), with Nav2's families of
    distro `nav2` when a mission selects them."""
    if nav2 is None:
        return catalogue.builtins_for(version)
    key = (version, nav2)
    if key not in _WITH_NAV2:
        _WITH_NAV2[key] = {**catalogue.builtins_for(version), **families(nav2)}
    return _WITH_NAV2[key]
