"""`btgen compile`: mission -> C++17 header and source.

    load_mission (front end) -> lower (IR) -> render (templates) -> write

Everything is rendered in memory first. Then the outputs are written all or
none, and only those whose bytes changed: each new file is written and
synced under a temporary name in the same directory, and only when all of
them are ready are they renamed into place; if a rename fails, the outputs
already replaced get their previous content back. So an unchanged mission
does not touch timestamps, a failed generation leaves the previous outputs
as they were, and a killed one leaves each output complete (at worst a
hidden `.NAME.*.tmp` file).

Also a small entry point for build systems:

    python -m btgen.compiler --deps MISSION.xml      # the mission and every file it includes
    python -m btgen.compiler --outputs MISSION.xml   # the file names `compile` writes
    python -m btgen.compiler --inputs                # generator sources, templates, schemas
    python -m btgen.compiler --template MISSION.xml  # the mission's class template (ns::Class)
    python -m btgen.compiler --check MISSION.xml     # exit 0 when the C++ back end compiles it
    python -m btgen.compiler --update-generated      # refresh the committed generated/ directory

(`btgen build-info ...` is the same, through the installed `btgen` command:
CMake's btgen_add_mission runs that.) --models, --main-tree and --namespace
are those of `btgen compile`.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Optional

from btgen import cmdline, pipeline, resources
from btgen.backend_cpp import naming
from btgen.backend_cpp.emit import TEMPLATE_DIR, Output, output_names, render
from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.fileio import check_output
from btgen.frontend import usertypes
from btgen.ir.data.records import DataOptions
from btgen.ir.lower import Program
from btgen.lang.model import Mission
from btgen.pipeline import DEFAULTS, CompileOptions, options_from_args

PACKAGE_DIR = resources.PACKAGE_DIR
SCHEMA_DIR = resources.SCHEMA_DIR


def mission_stem(path: str) -> str:
    return Path(path).stem


def generate(
    mission_path: str,
    relative_to: Optional[str] = None,
    options: Optional[DataOptions] = None,
    models: Sequence[str] = (),
    main_tree: Optional[str] = None,
    namespace: Optional[str] = None,
    opts: Optional[CompileOptions] = None,
) -> tuple[Output, ...]:
    """Render the outputs of a mission in memory; UserError when it cannot be compiled.

    `opts`: every mission option (btgen.pipeline); the other keywords are a shorthand for
    the few that tests and scripts set."""
    if opts is None:
        opts = CompileOptions(models=tuple(models), main_tree=main_tree, namespace=namespace)
        if options is not None:
            opts = replace(opts, string_capacity=options.string_capacity, queue_capacity=options.queue_capacity)
    return generate_checked(mission_path, opts, relative_to)[1]


def generate_checked(
    mission_path: str,
    opts: CompileOptions = DEFAULTS,
    relative_to: Optional[str] = None,
    loaded: Optional[Callable[[Mission], None]] = None,
    lowered: Optional[Callable[[Program], None]] = None,
) -> tuple[Mission, tuple[Output, ...]]:
    """The checked mission and its outputs rendered in memory: every step of `btgen compile` but
    the writing, so that `validate` and `build-info --check` run every check it runs (a
    problem found only while rendering is found by all three). `loaded` is called with the
    mission once the front end has read it (its warnings come before the IR's errors);
    `lowered` is called with the program (its warnings: what throws only when a node runs);
    `opts.substitute`: a file of substitution rules (a test build, ir/substitute.py)."""
    mission = pipeline.load(mission_path, opts)
    # Ports of types btgen does not know hold text: loaded as BehaviorTree.CPP loads them,
    # but the C++ interface they get deserves a word (the commands that compile say it).
    mission = replace(mission, warnings=mission.warnings + usertypes.unknown_type_warnings(mission))
    if loaded is not None:
        loaded(mission)
    program = pipeline.program(mission, opts)
    if lowered is not None:
        lowered(program)
    outputs = render(program, mission_stem(mission_path), relative_to or os.getcwd(), opts.namespace)
    return mission, outputs


def _file_mode() -> int:
    """What a new file gets under the current umask (mkstemp's files are 0600)."""
    umask = os.umask(0o022)
    os.umask(umask)
    return 0o666 & ~umask


def _stage(path: Path, data: bytes, mode: int) -> str:
    """`data` written and synced to a temporary file beside `path`; its name."""
    path.parent.mkdir(parents=True, exist_ok=True)
    # (the name's first 64 characters: a long output name plus mkstemp's part would pass the
    # file system's 255-byte limit, though the output's own name is legal)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:64]}.", suffix=".tmp", dir=str(path.parent))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, mode)
    except BaseException:
        _unlink_quietly(tmp)
        raise
    return tmp


def _unlink_quietly(path: str) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)


def write_all_if_changed(files: Sequence[tuple[Path, str]]) -> list[Path]:
    """Replace each path with its text where the bytes differ, all or none; the paths written.

    OSError (nothing changed, or everything put back) when one cannot be written."""
    mode = _file_mode()
    staged: list[tuple[str, Path, Optional[bytes]]] = []  # temporary file, target, previous bytes
    replaced: list[tuple[str, Path, Optional[bytes]]] = []
    old_stat: dict[Path, os.stat_result] = {}
    try:
        for path, text in files:
            data = text.encode("utf-8")
            if path.is_dir():
                raise IsADirectoryError(21, "a directory is in the way", str(path))
            try:
                # (only enough of the old file to tell whether it differs: an output path
                # may name anything, /dev/zero included)
                with open(path, "rb") as f:
                    old: Optional[bytes] = f.read(len(data) + 1)
                old_stat[path] = path.stat()
            except FileNotFoundError:
                old = None
            if old == data:
                continue
            staged.append((_stage(path, data, mode), path, old))
        for entry in staged:
            os.replace(entry[0], entry[1])
            replaced.append(entry)
    except BaseException:
        for tmp, path, old in staged:
            if (tmp, path, old) not in replaced:
                _unlink_quietly(tmp)
        for _, path, old in reversed(replaced):  # put back what was already replaced
            try:
                if old is None:
                    os.unlink(path)
                else:  # its bytes, mode and times as they were
                    st = old_stat[path]
                    os.replace(_stage(path, old, st.st_mode & 0o7777), path)
                    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns))
            except OSError:
                pass
        raise
    return [path for _, path, _ in staged]


def write_if_changed(path: Path, text: str) -> bool:
    """Atomically replace `path` with `text` unless it already holds exactly that. True: written."""
    return bool(write_all_if_changed([(path, text)]))


def compile_command(args: argparse.Namespace) -> int:
    """The `compile` subcommand: 0 on success; UserError propagates to the CLI."""
    from btgen.diagnostics import print_diagnostics

    opts = options_from_args(args)
    substitute = opts.substitute  # a test build: substitution rules (ir/substitute.py)
    mission, outputs = generate_checked(
        args.mission,
        opts,
        args.relative_to,
        lambda m: print_diagnostics(m.warnings),
        lambda p: print_diagnostics(p.warnings),
    )
    out_dir = Path(args.output_dir)
    for out in outputs:  # `-o` the mission's own folder, and the mission is named like an output
        check_output(
            str(out_dir / out.name),
            (*mission.files, *([substitute] if substitute else [])),
            message=f"`btgen compile -o {args.output_dir}` would overwrite this input file with the generated "
            f"{out.name}: choose another output directory",
            folders=False,  # (write_all_if_changed says so, naming the generated file)
        )
    try:  # rendered completely before anything is written; then all outputs or none
        write_all_if_changed([(out_dir / out.name, out.text) for out in outputs])
    except OSError as e:
        where = e.filename if isinstance(e.filename, str) else str(out_dir / outputs[0].name)
        if os.path.basename(where).startswith("."):  # a temporary file: name the output it was for
            where = next(
                (str(out_dir / o.name) for o in outputs if os.path.basename(where)[1:].startswith(o.name[:64] + ".")),
                where,
            )
        raise UserError(Diagnostic(Loc(where, 1, 1), f"cannot write the generated file: {e.strerror or e}")) from None
    return 0


def generator_inputs() -> list[str]:
    """Files whose change changes the output of every mission: sources, templates, schemas."""
    files = sorted(str(p) for p in PACKAGE_DIR.rglob("*.py"))
    files += sorted(str(p) for p in TEMPLATE_DIR.glob("*.j2"))
    files += sorted(str(p) for p in SCHEMA_DIR.glob("*.xsd"))
    return files


def mission_files(mission_path: str, opts: CompileOptions = DEFAULTS) -> list[str]:
    """The mission, every file it includes, the models, --trees and enums files (absolute),
    also when it does not load: every file the loader reached (an include that stopped
    loading stays a dependency, so the build regenerates and reports its errors instead of
    keeping the old header)."""
    from btgen.frontend.loader import files_read

    files = files_read(mission_path, opts.models, opts.main_tree, opts.trees, opts.btcpp)
    files += [t for t in opts.trees if os.path.isfile(t) and t not in files]
    files += [f for f in opts.enum_files if f not in files]
    return [os.path.abspath(f) for f in files]


def cmake_path_problem(path: str) -> str:
    """Why `path` cannot be an element of a CMake list ("" when it can): a `;` separates list
    elements and a `\\` escapes, so DEPENDS would name files that do not exist."""
    bad = sorted({c for c in path if c in ";\\"})
    if not bad:
        return ""
    shown = " and ".join(f"`{c}`" for c in bad)
    return f"the path holds {shown}, which a CMake list cannot hold; btgen_add_mission cannot depend on it (rename it)"


def committed_outputs(root: Path) -> dict[str, str]:
    """What `generated/` must hold: the outputs of every `missions/*.xml` the C++
    back end compiles, banner paths relative to the project root."""
    expected: dict[str, str] = {}
    for mission in sorted((root / "missions").glob("*.xml")):
        rel = os.path.relpath(mission, os.getcwd())
        try:
            outputs = generate(rel, relative_to=str(root))
        except UserError:
            continue  # needs the data side or is broken: `btgen validate` tells
        for out in outputs:
            expected[out.name] = out.text
    return expected


def update_generated(root: Path) -> list[str]:
    """Bring `generated/` up to date; returns the files written or removed."""
    expected = committed_outputs(root)
    gen = root / "generated"
    changed = [name for name, text in sorted(expected.items()) if write_if_changed(gen / name, text)]
    for stale in sorted(p for p in gen.glob("*") if p.suffix in (".hpp", ".cpp") and p.name not in expected):
        stale.unlink()
        changed.append(stale.name)
    return changed


def build_info_parser() -> cmdline.Parser:
    """The options of `btgen build-info` (what CMake's btgen_add_mission asks)."""
    p = cmdline.Parser(
        prog="btgen build-info",
        description="What build systems (CMake's btgen_add_mission) ask of a mission: its files, "
        "outputs, class template, whether it compiles.",
    )
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--deps", metavar="MISSION.xml", help="print the mission and its included files, one per line")
    g.add_argument("--outputs", metavar="MISSION.xml", help="print the names of the files `btgen compile` writes")
    g.add_argument("--inputs", action="store_true", help="print the generator's own sources, templates and schemas")
    g.add_argument("--template", metavar="MISSION.xml", help="print the mission's C++ class template")
    g.add_argument("--check", metavar="MISSION.xml", help="exit 0 if the mission compiles, else print why and exit 1")
    g.add_argument(
        "--update-generated", action="store_true", help="regenerate the committed generated/ from missions/*.xml"
    )
    p.add_argument("--cmake", action="store_true", help="print a CMake list (`;`-separated) instead of lines")
    pipeline.add_mission_options(p, namespace=True)
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_info_parser().parse_args(argv)
    opts = options_from_args(args)
    if args.update_generated:
        if resources.installed():
            loc = cmdline.loc_of(args.argv, "--update-generated")
            print(
                f"{loc}: error: --update-generated refreshes a checkout's generated/; this btgen is installed",
                file=sys.stderr,
            )
            return 1
        for name in update_generated(resources.ROOT):
            print(f"generated/{name}")
        return 0
    if args.check:
        from btgen.diagnostics import print_diagnostics

        try:
            generate(args.check, opts=opts)
        except UserError as e:
            print_diagnostics(e.diagnostics)
            return 1
        return 0
    if args.deps:
        items = mission_files(args.deps, opts)
        if args.cmake:
            bad = [(f, cmake_path_problem(f)) for f in items if cmake_path_problem(f)]
            if bad:
                from btgen.diagnostics import Diagnostic, Loc, print_diagnostics

                print_diagnostics([Diagnostic(Loc(f, 1, 1), why) for f, why in bad])
                return 1
    elif args.template:
        stem = mission_stem(args.template)
        items = [f"{naming.mission_namespace(stem, args.namespace)}::{naming.pascal_case(stem)}"]
    elif args.outputs:
        items = list(output_names(mission_stem(args.outputs)))
    else:
        items = generator_inputs()
    if args.cmake:
        sys.stdout.write(";".join(i.replace("\\", "/") for i in items))
    else:
        sys.stdout.write("".join(i + "\n" for i in items))
    return 0


if __name__ == "__main__":
    sys.exit(main())
