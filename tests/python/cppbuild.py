"""One way for a test to compile C++: an executable, an object file or a syntax check.

Tests that compile generated or hand-written C++ build the command with `command` (or call
`build` / `syntax_check`) instead of spelling a compiler command line of their own, so the
language level, the warnings the generated code is held to (-Wall -Wextra -Wpedantic -Werror)
and the runtime's include folder are the same everywhere, and a failure shows the command with
the compiler's messages.

    exe = cppbuild.build([main_cpp, tmp_path / "m.cpp"], tmp_path / "robot", includes=[tmp_path])
    cppbuild.syntax_check([tmp_path / "m.cpp"], includes=[tmp_path], cxx="clang++", flags=["-Wshadow"])
    proc = cppbuild.run(cppbuild.command([src], mode="syntax"))  # when the test expects a failure
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Optional, Union

from conftest import ROOT

PathLike = Union[str, "os.PathLike[str]"]

RUNTIME_INCLUDE = Path(ROOT) / "runtime" / "include"
STD = "-std=c++17"
WARNINGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror")
MODES = ("link", "object", "syntax")


def compiler(cxx: Optional[str] = None) -> str:
    """The compiler to use: `cxx`, else $CXX, else `c++`."""
    return cxx or os.environ.get("CXX") or "c++"


def have(cxx: Optional[str] = None) -> bool:
    return shutil.which(compiler(cxx)) is not None


def command(
    sources: Sequence[PathLike],
    output: Optional[PathLike] = None,
    *,
    cxx: Optional[str] = None,
    includes: Iterable[PathLike] = (),
    defines: Iterable[str] = (),
    opt: Optional[str] = None,
    warnings: bool = True,
    flags: Iterable[str] = (),
    libs: Iterable[str] = (),
    mode: str = "link",
    runtime: bool = True,
) -> list[str]:
    """The compiler command line. mode: "link" (an executable), "object" (-c) or "syntax"
    (-fsyntax-only); `defines` without their -D (`'BTGEN_MISSION_HEADER="m.hpp"'`); the
    runtime's include folder first unless runtime=False, then `includes`; `libs` last."""
    if mode not in MODES:
        raise ValueError(f"mode {mode!r} is not one of {MODES}")
    cmd = [compiler(cxx), STD]
    if opt:
        cmd.append(opt)
    if warnings:
        cmd += WARNINGS
    cmd += list(flags)
    cmd += [f"-D{d}" for d in defines]
    for folder in ([RUNTIME_INCLUDE] if runtime else []) + list(includes):
        cmd += ["-I", str(folder)]
    if mode == "syntax":
        cmd.append("-fsyntax-only")
    elif mode == "object":
        cmd.append("-c")
    cmd += [str(s) for s in sources]
    if output is not None:
        cmd += ["-o", str(output)]
    if mode == "link":
        cmd += list(libs)
    return cmd


def run(cmd: Sequence[str], *, cwd: Optional[PathLike] = None, timeout: float = 900) -> subprocess.CompletedProcess:
    """Run a compiler command; stdout and stderr are captured as text. A missing compiler is
    an AssertionError saying so, not a FileNotFoundError."""
    if shutil.which(cmd[0]) is None:
        raise AssertionError(f"no C++ compiler `{cmd[0]}` on PATH (scripts/setup.sh installs g++)")
    return subprocess.run(list(cmd), cwd=cwd, capture_output=True, text=True, timeout=timeout, check=False)


def check(cmd: Sequence[str], *, cwd: Optional[PathLike] = None, timeout: float = 900) -> subprocess.CompletedProcess:
    """`run`, and an AssertionError with the command and the compiler's messages if it fails."""
    proc = run(cmd, cwd=cwd, timeout=timeout)
    if proc.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)}\nexit {proc.returncode}\n{proc.stdout}{proc.stderr[-8000:]}")
    return proc


def build(
    sources: Sequence[PathLike],
    output: PathLike,
    *,
    cwd: Optional[PathLike] = None,
    timeout: float = 900,
    **options,
) -> Path:
    """Compile `sources` into `output` (an executable, or an object file with mode="object");
    the options are `command`'s. Returns the output's path."""
    check(command(sources, output, **options), cwd=cwd, timeout=timeout)
    return Path(output)


def syntax_check(
    sources: Sequence[PathLike], *, cwd: Optional[PathLike] = None, timeout: float = 900, **options
) -> subprocess.CompletedProcess:
    """-fsyntax-only over `sources` (`command`'s options); fails the test on any error."""
    return check(command(sources, mode="syntax", **options), cwd=cwd, timeout=timeout)
