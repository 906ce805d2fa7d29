"""One pipeline for every command: the options, and sources -> checked mission -> program.

Every command that reads a mission (`validate`, `compile`, `run`, `bench`, `graph`, `xsd`,
`build-info`) takes the same loading, typing and capacity options, parsed by
`add_mission_options` into one frozen `CompileOptions`, and reads the mission through
`load` (front end: the file, its includes, models files, scripting enums, user port types)
and `build` (`load`, then the IR: blackboard analysis and lowering). A command never
assembles the stages itself, so a mission that `compile` accepts is accepted by
`build-info --check` and `validate` with the same options, and the reverse.

The command line and CMake's `btgen_add_mission()` (which runs `btgen build-info` and
`btgen compile`) go through here alike.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Optional

if TYPE_CHECKING:  # the stages are imported when used: `btgen --help` stays quick
    from btgen.ir.data.records import DataOptions
    from btgen.ir.lower import Program
    from btgen.lang.model import Mission

from btgen.lang.nav2 import NODES_CHOICES
from btgen.lang.versions import SUPPORTED_VERSIONS

CAPACITY_MAX = 1 << 20


@dataclass(frozen=True)
class CompileOptions:
    """What a user may say about how a mission is read and compiled, as given (files and
    declarations are read by `load`, so their errors carry their own positions)."""

    models: tuple[str, ...] = ()  # --models FILE.xml: files of <TreeNodesModel>
    main_tree: Optional[str] = None  # --main-tree ID
    trees: tuple[str, ...] = ()  # --trees FILE|DIR: BehaviorTrees the mission's SubTrees may use
    entries: tuple[str, ...] = ()  # --entry [TREE:]NAME=TYPE: entries the application provides
    enum_decls: tuple[str, ...] = ()  # --enum Type=A,B=3
    enum_files: tuple[str, ...] = ()  # --enums FILE
    types: tuple[str, ...] = ()  # --type NAME=CPP_TYPE@HEADER
    namespace: Optional[str] = None  # --namespace a::b (C++ outputs only)
    string_capacity: Optional[int] = None  # --string-capacity N (None: the IR's default)
    queue_capacity: Optional[int] = None  # --queue-capacity N
    btcpp: str = "4.6.2"  # --btcpp 4.6.2|4.10.0: the BehaviorTree.CPP release followed (lang/versions.py)
    ros_packages: tuple[tuple[str, str], ...] = ()  # package -> folder (btgen check's `ros-packages`)
    nodes: Optional[str] = None  # --nodes btcpp|nav2[:DISTRO] (lang/nav2.py); None: Nav2's if a models file is
    substitute: Optional[str] = None  # --substitute FILE.json: substitution rules, a test build (ir/substitute.py)
    # those of `models` that `btgen check` found in the project rather than was told to use: their
    # SubTree models document the trees of the whole project (Groot2's palette), not only this mission's
    palettes: tuple[str, ...] = ()

    @property
    def data(self) -> DataOptions:
        from btgen.ir.data.records import DataOptions

        options = DataOptions()
        if self.string_capacity is not None:
            options = replace(options, string_capacity=self.string_capacity)
        if self.queue_capacity is not None:
            options = replace(options, queue_capacity=self.queue_capacity)
        return options


DEFAULTS = CompileOptions()


def _capacity(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not a whole number") from None
    if not 1 <= value <= CAPACITY_MAX:
        raise argparse.ArgumentTypeError(f"{value} is out of range (1 to {CAPACITY_MAX})")
    return value


def _namespace(text: str) -> str:
    from btgen.backend_cpp.naming import namespace_problem

    problem = namespace_problem(text)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return text


def add_mission_options(p: argparse.ArgumentParser, *, capacities: bool = True, namespace: bool = False) -> None:
    """The options of every command that reads a mission (one place, one spelling).
    `capacities`: the command lowers the mission (its strings and queues are sized);
    `namespace`: it writes C++ a user includes (`compile`, `build-info`). A command is
    offered only the options that change what it does."""
    g = p.add_argument_group("mission options (the same wherever a command takes them)")
    g.add_argument(
        "--models",
        action="append",
        default=[],
        metavar="FILE.xml",
        help="a file whose <root> holds only <TreeNodesModel>: its node models count as declared in "
        "the mission (repeatable; identical repeated declarations are accepted)",
    )
    g.add_argument(
        "--main-tree",
        metavar="ID",
        help="the BehaviorTree to run (when the mission has no main_tree_to_execute, or to override it)",
    )
    g.add_argument(
        "--trees",
        action="append",
        default=[],
        metavar="FILE|DIR",
        help="a file of BehaviorTrees, or a folder of such files (*.xml), whose trees the mission's "
        "SubTrees may use, as registerBehaviorTreeFromFile registers them (repeatable)",
    )
    g.add_argument(
        "--entry",
        action="append",
        default=[],
        metavar="[TREE:]NAME=TYPE",
        help="a blackboard entry the application sets before the first tick (on the root "
        "blackboard, or on that of every instance of BehaviorTree TREE), e.g. server_timeout=int; "
        "the generated mission gets a setter for it (repeatable)",
    )
    g.add_argument(
        "--enum",
        action="append",
        default=[],
        metavar="Type=NAME,NAME=VALUE,...",
        help="register scripting enum values, as BehaviorTree.CPP's registerScriptingEnum: "
        "Color=RED,GREEN,BLUE gives 0, 1, 2; NAME=VALUE sets a value (the next one counts on)",
    )
    g.add_argument(
        "--enums",
        action="append",
        default=[],
        metavar="FILE",
        help="a file of such declarations, one per line (# comments)",
    )
    g.add_argument(
        "--type",
        action="append",
        default=[],
        metavar="NAME=CPP_TYPE@HEADER",
        help="map the port type NAME of TreeNodesModel to a C++ type held by value (default constructible "
        "and copyable; it may own memory, as a ROS message does), declared with its "
        '`bool convertFromString(std::string_view, T&)` in HEADER (#include "HEADER"; '
        "@<HEADER> for #include <HEADER>), e.g. Pose2D=nav::Pose2D@nav/pose2d.hpp (repeatable)",
    )
    if namespace:
        g.add_argument(
            "--namespace",
            type=_namespace,
            metavar="NS",
            help="C++ namespace of the generated code, e.g. `robot` or `robot::missions` (default: "
            "from the file name; `main.xml` gives `main_`)",
        )
    g.add_argument(
        "--btcpp",
        choices=SUPPORTED_VERSIONS,
        default=None,
        metavar="VERSION",
        help="the BehaviorTree.CPP release whose semantics to follow: "
        + " or ".join(SUPPORTED_VERSIONS)
        + " (default 4.6.2); it decides loading, the script grammar, both engines and the generated C++",
    )
    g.add_argument(
        "--nodes",
        choices=NODES_CHOICES,
        default=None,
        metavar="FAMILY",
        help="built-in node families besides BehaviorTree.CPP's: nav2 (Nav2's PipelineSequence, RecoveryNode, "
        "RoundRobin, RateController, SingleTrigger, ... of its newest distro) or nav2:jazzy, nav2:kilted, "
        "nav2:lyrical; btcpp: none. Default: Nav2's when a models file is Nav2's nav2_tree_nodes.xml",
    )
    if capacities:
        g.add_argument(
            "--string-capacity",
            type=_capacity,
            default=None,
            metavar="N",
            help="most bytes of a blackboard string (default 128): strings written by robot code or "
            "growing without bound get N, literals at most N, computed strings the longest value "
            "they can take; a longer value fails the node that writes it",
        )
        g.add_argument(
            "--queue-capacity",
            type=_capacity,
            default=None,
            metavar="N",
            help="most elements of a blackboard queue written by robot code (default 16)",
        )


def options_from_args(args: Optional[argparse.Namespace]) -> CompileOptions:
    """The CompileOptions of parsed command-line arguments (defaults for what is absent)."""

    def get(name: str, default=None):
        value = getattr(args, name, None)
        return default if value is None else value

    return CompileOptions(
        models=tuple(get("models", ())),
        main_tree=get("main_tree"),
        trees=tuple(get("trees", ())),
        entries=tuple(get("entry", ())),
        enum_decls=tuple(get("enum", ())),
        enum_files=tuple(get("enums", ())),
        types=tuple(get("type", ())),
        namespace=get("namespace"),
        string_capacity=get("string_capacity"),
        queue_capacity=get("queue_capacity"),
        btcpp=get("btcpp", "4.6.2"),
        nodes=get("nodes"),
        substitute=get("substitute"),
    )


def check_options(opts: CompileOptions) -> None:
    """The option values parsed as `load` parses them (UserError as `load` gives it), for a
    command that reads the mission's files without loading it (`models`, which must not
    refuse the unknown nodes it is there to describe)."""
    from btgen.frontend import entries, enums, usertypes

    entries.load(opts.entries)
    enums.load(opts.enum_decls, opts.enum_files)
    usertypes.load(opts.types)


def load(path: str, opts: CompileOptions = DEFAULTS) -> Mission:
    """The checked mission (front end only); UserError with every problem found."""
    from btgen.frontend import entries, enums, usertypes
    from btgen.frontend.loader import load_mission

    types = usertypes.load(opts.types)
    provided = entries.load(opts.entries, {t.name for t in types})
    mission = load_mission(
        path,
        opts.models,
        opts.main_tree,
        opts.trees,
        btcpp=opts.btcpp,
        ros_packages=opts.ros_packages,
        nodes=opts.nodes,
        palettes=opts.palettes,
    )
    mission = entries.apply(mission, provided)
    mission = enums.apply(mission, enums.load(opts.enum_decls, opts.enum_files))
    mission = usertypes.apply(mission, types)
    return mission


def build(path: str, opts: CompileOptions = DEFAULTS) -> tuple[Mission, Program]:
    """The checked mission and its lowered program: everything `compile` checks."""
    mission = load(path, opts)
    return mission, program(mission, opts)


def program(mission: Mission, opts: CompileOptions = DEFAULTS) -> Program:
    """The lowered program of a loaded mission: the one call of the IR's `lower` (with the
    substitution rules of `opts.substitute` applied: a test build, ir/substitute.py)."""
    from btgen.ir.lower import lower

    if opts.substitute is None:
        return lower(mission, opts.data)
    from btgen.frontend.substitution import load_rules
    from btgen.ir import substitute

    plan = substitute.prepare(mission, load_rules(opts.substitute, mission.semantics.script_grammar_49))
    return substitute.apply(plan, lower(plan.mission, opts.data))
