"""The C++ engine of `btgen run --engine cpp`: generate, build (cached), run.

`run_cpp(mission, scenario)` compiles the mission to C++, builds it with the
system compiler together with the scenario runner (runtime/src/main_driver.cpp)
and runs it on the scenario; its trace and diagnostics go to this process's
stdout/stderr and its exit status is returned.

Executables are cached in `$BTGEN_CACHE_DIR`, else `$XDG_CACHE_HOME/btgen`,
else `~/.cache/btgen`, under a key hashing the generated sources, the runtime
headers, the driver, the compiler's identity and the flags: a mission is built
once until any of them changes. Builds go to a private directory that is
renamed into place, so concurrent runs never see a half-written executable.

`BTGEN_SANITIZE=1` in the environment builds with AddressSanitizer and
UBSan (any finding aborts the run with a non-zero status); the flags are part
of the cache key, so sanitized and plain executors are cached side by side.
"""

from __future__ import annotations

import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import tempfile
from functools import cache
from pathlib import Path
from typing import Optional

from btgen import pipeline, resources
from btgen.backend_cpp import naming
from btgen.backend_cpp.emit import render
from btgen.compiler import mission_stem
from btgen.diagnostics import Diagnostic, InternalError, Loc, UserError
from btgen.pipeline import DEFAULTS, CompileOptions

ROOT = resources.ROOT
RUNTIME_INCLUDE = resources.RUNTIME_INCLUDE
DRIVER = resources.RUNTIME_SRC / "main_driver.cpp"
CXX_FLAGS = ("-std=c++17", "-O1")
SANITIZE_FLAGS = ("-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer")
BINARY = "mission"


def sanitizing() -> bool:
    """True when `BTGEN_SANITIZE=1`: executors are built with ASan and UBSan."""
    return os.environ.get("BTGEN_SANITIZE", "") == "1"


def cxx_flags() -> tuple[str, ...]:
    """The flags executors are built with (part of the cache key). `BTGEN_STRAIGHT_LINE_BUDGET=N`
    in the environment sets the engine's straight-line budget (btgen/engine.hpp): a small one
    makes the tests cross from straight-line code into the table interpreter."""
    budget = os.environ.get("BTGEN_STRAIGHT_LINE_BUDGET", "")
    extra = (f"-DBTGEN_STRAIGHT_LINE_BUDGET={int(budget)}",) if budget.strip().isdigit() else ()
    return CXX_FLAGS + (SANITIZE_FLAGS if sanitizing() else ()) + extra


def cache_dir() -> Path:
    if os.environ.get("BTGEN_CACHE_DIR"):
        return Path(os.environ["BTGEN_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "btgen"


def compiler() -> str:
    return os.environ.get("CXX") or "c++"


@cache
def _compiler_identity(cxx: str) -> str:
    """`c++ --version` (which compiler, which version): part of the cache key."""
    path = shutil.which(cxx)
    if path is None:
        return ""
    try:
        out = subprocess.run(
            [path, "--version"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False, timeout=60
        ).stdout
    except (OSError, subprocess.SubprocessError):
        out = b""
    return os.path.realpath(path) + "\n" + out.decode("utf-8", "replace")


def _runtime_headers() -> list[Path]:
    return sorted(RUNTIME_INCLUDE.rglob("*.hpp"))


def build_cpp(
    mission_path: str,
    warnings: Optional[list] = None,
    opts: CompileOptions = DEFAULTS,
) -> Path:
    """The scenario-runner executable of a mission, built if not cached. UserError when
    the mission cannot be compiled; InternalError when the generated code does not build.
    The mission's warnings are appended to `warnings` when it is given; `opts`: the
    mission options of every command (btgen.pipeline; `opts.substitute`: a test build)."""
    return build_mission_executable(mission_path, (DRIVER,), cxx_flags(), warnings, opts)


def _check_no_user_nodes(mission) -> None:
    """The scenario runner scripts leaves only: a Control or Decorator of the mission's own
    TreeNodesModel needs robot code (the interpreter says the same)."""
    from btgen.ir.numbering import number_nodes
    from btgen.lang.leaves import user_node_kind, user_node_message

    for n in number_nodes(mission):
        node = n.node
        kind = user_node_kind(mission, node)
        if kind is not None:
            raise UserError(Diagnostic(node.loc, user_node_message(node.id, kind)))


def build_mission_executable(
    mission_path: str,
    sources: tuple[Path, ...],
    flags: tuple[str, ...],
    warnings: Optional[list] = None,
    opts: CompileOptions = DEFAULTS,
) -> Path:
    """An executable of the generated mission compiled with `sources` (a main that
    includes BTGEN_MISSION_HEADER and uses BTGEN_MISSION_TEMPLATE, and its helpers)
    and `flags`, built if not cached. Errors as build_cpp."""
    mission = pipeline.load(mission_path, opts)
    if warnings is not None:
        warnings.extend(mission.warnings)
    _check_no_user_nodes(mission)
    # Paths as the interpreter prints them (as given), so run-time errors read the same.
    program = pipeline.program(mission, opts)  # (with opts.substitute's rules: a test build)
    outputs = render(program, mission_stem(mission_path), None, opts.namespace)
    stem = mission_stem(mission_path)
    cxx = compiler()
    identity = _compiler_identity(cxx)
    if not identity:
        raise UserError(
            Diagnostic(
                Loc(mission_path, 1, 1),
                f"cannot build the C++ executor: no C++ compiler `{cxx}` on PATH (install g++ or clang++, or set CXX)",
            )
        )
    template = f"{naming.mission_namespace(stem, opts.namespace)}::{naming.pascal_case(stem)}"
    header = outputs[0].name
    defines = (f'-DBTGEN_MISSION_HEADER="{header}"', f"-DBTGEN_MISSION_TEMPLATE={template}")

    h = hashlib.sha256()
    for part in (identity, " ".join(tuple(flags) + defines)):
        h.update(part.encode("utf-8") + b"\0")
    for out in outputs:
        h.update(out.name.encode("utf-8") + b"\0" + out.text.encode("utf-8") + b"\0")
    for f in _runtime_headers() + list(sources):
        h.update(str(f.relative_to(ROOT)).encode("utf-8") + b"\0" + f.read_bytes() + b"\0")
    key = h.hexdigest()[:32]

    final = cache_dir() / "cpp" / key
    binary = final / BINARY
    if binary.is_file():
        return binary
    try:
        final.parent.mkdir(parents=True, exist_ok=True)
        work = Path(tempfile.mkdtemp(prefix=f".{key}.", dir=str(final.parent)))
    except OSError as e:
        raise UserError(
            Diagnostic(
                Loc(mission_path, 1, 1),
                f"cannot build the C++ executor: the cache directory `{cache_dir()}` is not "
                f"usable ({e.strerror or e}); set BTGEN_CACHE_DIR to a writable directory",
            )
        ) from None
    try:
        for out in outputs:
            (work / out.name).write_text(out.text, encoding="utf-8")
        cmd = [
            cxx,
            *flags,
            *defines,
            "-I",
            str(RUNTIME_INCLUDE),
            "-I",
            str(work),
            *(str(s) for s in sources),
            "-o",
            str(work / BINARY),
        ]
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False)
        if proc.returncode != 0:
            raise InternalError(
                f"the generated C++ for {mission_path} does not build:\n"
                + " ".join(cmd)
                + "\n"
                + proc.stdout.decode("utf-8", "replace")
            )
        try:
            os.rename(work, final)
        except OSError:
            if not binary.is_file():  # not a concurrent build that won the race
                raise
    finally:
        if work.exists():
            shutil.rmtree(work, ignore_errors=True)
    return binary


def _fileno(stream) -> Optional[int]:
    try:
        return stream.fileno()
    except (AttributeError, io.UnsupportedOperation, ValueError):
        return None


def _inherited_fd(path: str) -> Optional[int]:
    """N when `path` is /dev/fd/N or /proc/self/fd/N of an open descriptor of this process."""
    m = re.fullmatch(r"/(?:dev|proc/self)/fd/([0-9]+)", path)
    if m is None:
        return None
    fd = int(m.group(1))
    try:
        os.fstat(fd)
    except OSError:
        return None
    return fd


def run_cpp(mission_path: str, scenario_path: str, opts: CompileOptions = DEFAULTS) -> int:
    """Build (or reuse) the mission's executor, run it on the scenario, stream its
    output to stdout/stderr and return its exit status."""
    warnings: list = []
    binary = build_cpp(mission_path, warnings, opts)
    for w in warnings:
        print(str(w), file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    out_fd, err_fd = _fileno(sys.stdout), _fileno(sys.stderr)
    # `--scenario <(...)` names one of this process's descriptors (/dev/fd/63): the
    # executor inherits it, so it reads the same pipe under the same name.
    inherited = _inherited_fd(scenario_path)
    pass_fds = (inherited,) if inherited is not None else ()
    if out_fd is not None and err_fd is not None:
        return subprocess.run(
            [str(binary), scenario_path], stdout=out_fd, stderr=err_fd, check=False, pass_fds=pass_fds
        ).returncode
    proc = subprocess.run([str(binary), scenario_path], capture_output=True, check=False, pass_fds=pass_fds)
    sys.stdout.write(proc.stdout.decode("utf-8", "replace"))
    sys.stderr.write(proc.stderr.decode("utf-8", "replace"))
    return proc.returncode
