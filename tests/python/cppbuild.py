"""One way for a test to build C++: an executable, an object or a syntax check.

Every test that compiles generated or hand-written C++ calls `build` (or `syntax_check`) instead
of spelling a compiler command line of its own, so the flags the generated code is held to
(C++17, -Wall -Wextra -Wpedantic -Werror) are the same everywhere, a failure shows the command
and the compiler's output, and a missing compiler is one clear message.

    exe = cppbuild.build([main_cpp, tmp_path / "mission.cpp"], tmp_path / "robot",
                         includes=[tmp_path])
    cppbuild.syntax_check([header_test], includes=[tmp_path], compiler="clang++")
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


def compiler(name: Optional[str] = None) -> str:
    """The compiler to use: `name`, else $CXX, else `c++`."""
    return name or os.environ.get("CXX") or "c++"


def have(name: Optional[str] = None) -> bool:
    return shutil.which(compiler(name)) is not None


def command(
    sources: Sequence[PathLike],
    output: Optional[PathLike] = None,
    *,
    compiler_name: Optional[str] = None,
    includes: Iterable[PathLike] = (),
    defines: Iterable[str] = (),
    opt: str = "-O0",
    warnings: bool = True,
    flags: Iterable[str] = (),
    libs: Iterable[str] = (),
    mode: str = "link",
) -> list[str]:
    """The command line `build` runs. mode: "link" (an executable), "object" (-c) or "syntax"
    (-fsyntax-only). The runtime's include folder is always on the path, after `includes`."""
    cmd = [compiler(compiler_name), STD, opt]
    if warnings:
        cmd += WARNINGS
    cmd += list(flags)
    cmd += [f"-D{d}" for d in defines]
    for folder in (*includes, RUNTIME_INCLUDE):
        cmd += ["-I", str(folder)]
    if mode == "syntax":
        cmd.append("-fsyntax-only")
    elif mode == "object":
        cmd.append("-c")
    elif mode != "link":
        raise ValueError(f"mode {mode!r}")
    cmd += [str(s) for s in sources]
    if output is not None:
        cmd += ["-o", str(output)]
    if mode == "link":
        cmd += list(libs)
    return cmd


def run_compiler(cmd: Sequence[str], *, cwd: Optional[PathLike] = None, timeout: float = 600) -> str:
    """Run a compiler command; its output (warnings) on success, an AssertionError naming the
    command and the compiler's messages on failure."""
    if shutil.which(cmd[0]) is None:
        raise AssertionError(f"no C++ compiler `{cmd[0]}` on PATH (scripts/setup.sh installs g++)")
    proc = subprocess.run(list(cmd), cwd=cwd, capture_output=True, text=True, timeout=timeout, check=False)
    if proc.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)}\nexit {proc.returncode}\n{proc.stdout}{proc.stderr}")
    return proc.stdout + proc.stderr


def build(
    sources: Sequence[PathLike],
    output: PathLike,
    *,
    compiler_name: Optional[str] = None,
    includes: Iterable[PathLike] = (),
    defines: Iterable[str] = (),
    opt: str = "-O0",
    warnings: bool = True,
    flags: Iterable[str] = (),
    libs: Iterable[str] = (),
    mode: str = "link",
    cwd: Optional[PathLike] = None,
    timeout: float = 600,
) -> Path:
    """Compile `sources` into `output` (an executable, or an object with mode="object") and
    return its path."""
    cmd = command(
        sources,
        output,
        compiler_name=compiler_name,
        includes=includes,
        defines=defines,
        opt=opt,
        warnings=warnings,
        flags=flags,
        libs=libs,
        mode=mode,
    )
    run_compiler(cmd, cwd=cwd, timeout=timeout)
    return Path(output)


def syntax_check(
    sources: Sequence[PathLike],
    *,
    compiler_name: Optional[str] = None,
    includes: Iterable[PathLike] = (),
    defines: Iterable[str] = (),
    warnings: bool = True,
    flags: Iterable[str] = (),
    cwd: Optional[PathLike] = None,
    timeout: float = 600,
) -> str:
    """-fsyntax-only over `sources`; the compiler's output (warnings, when not -Werror)."""
    cmd = command(
        sources,
        compiler_name=compiler_name,
        includes=includes,
        defines=defines,
        warnings=warnings,
        flags=flags,
        mode="syntax",
    )
    return run_compiler(cmd, cwd=cwd, timeout=timeout)
