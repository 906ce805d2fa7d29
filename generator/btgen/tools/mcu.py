"""Missions on a microcontroller: build scenario runs for a Cortex-M4 board and run them in QEMU.

The board is ARM's MPS2+ with the AN386 image (a Cortex-M4), which Debian's
`qemu-system-arm -M mps2-an386` emulates; its board support is `mcu/bsp/`,
its toolchain file `cmake/toolchain/arm-none-eabi-cortex-m4.cmake`,
its CMake targets `cmake/btgen_mcu.cmake` (mcu/README.md).

`run_cases(cases)` compiles each mission to C++ (as `btgen compile` does),
writes each scenario as constant data for `btgen/harness/static_scenario.hpp`
(the scenario runner that allocates nothing), batches the cases into a few
firmware images (one CMake build with the toolchain file, kept in
`<cache>/mcu/`, so that a second run rebuilds only what changed), runs every
image in QEMU and returns each case's trace, run-time error lines and exit
status as the host's scenario runner would give them.

    python -m btgen.tools.mcu MISSION.xml SCENARIO [MISSION.xml SCENARIO ...]

prints the traces (each after a `== MISSION` line).

The images print on the board's UART; a case's output is framed by
`@@case <n>` and `@@exit <status>` lines, and a run-time error's line (the
host runner's stderr) is sent as `@@stderr <line>`.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from btgen import cmdline, resources
from btgen.backend_cpp import naming
from btgen.backend_cpp.emit import render
from btgen.backend_cpp.literals import cpp_view  # outside the mission namespace, where `"..."sv` is declared
from btgen.compiler import mission_stem
from btgen.diagnostics import InternalError, UserError

ROOT = resources.ROOT
RUNTIME_INCLUDE = resources.RUNTIME_INCLUDE
TOOLCHAIN_FILE = ROOT / "cmake" / "toolchain" / "arm-none-eabi-cortex-m4.cmake"
QEMU = "qemu-system-arm"
MACHINE = "mps2-an386"
# What the tests and scripts/test_mcu.sh need (Debian: gcc-arm-none-eabi,
# libstdc++-arm-none-eabi-newlib, qemu-system-arm; and cmake).
TOOLS = ("arm-none-eabi-g++", "arm-none-eabi-gcc", "arm-none-eabi-size", QEMU, "cmake")
# The optimisation of the images (the build type's flags are replaced by this).
OPT = "-Os"
WARNINGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror")
# Cases per image: a few images keep a crash local and the link small.
BATCH = 12
# Most seconds an image may run in QEMU.
TIMEOUT = 120


def missing_tools() -> list[str]:
    """The tools of TOOLS not on PATH."""
    return [t for t in TOOLS if shutil.which(t) is None]


def qemu_command(elf: Path | str, extra: Sequence[str] = ()) -> list[str]:
    """QEMU running `elf` on the board: UART0 on stdout, semihosting for the exit status."""
    return [
        QEMU,
        "-M",
        MACHINE,
        "-display",
        "none",
        "-monitor",
        "none",
        "-serial",
        "stdio",
        "-semihosting-config",
        "enable=on,target=native",
        *extra,
        "-kernel",
        str(elf),
    ]


def cache_dir() -> Path:
    from btgen.tools.cppengine import cache_dir as host_cache

    return host_cache() / "mcu"


@dataclass(frozen=True)
class Case:
    mission: str
    scenario: str
    name: str = ""

    @property
    def label(self) -> str:
        return self.name or mission_stem(self.mission)


@dataclass
class Result:
    case: Case
    status: int
    stdout: str
    stderr: str


@dataclass
class Image:
    """One firmware image: its cases and its sources (file name -> text)."""

    name: str
    cases: list[Case]
    sources: dict[str, str] = field(default_factory=dict)


# ------------------------------------------------------------------ sources


def _status(s: str) -> str:
    return f"btgen::Status::{s}"


def scenario_cpp(scenario, prefix: str, program=None) -> str:
    """`scenario` (btgen.interp.scenario.Scenario) as a btgen::StaticScenario named `prefix`;
    with the lowered `program`, with the leaf line of every node matched here (by name, the
    last line naming it), so that the board needs no node names."""
    if scenario.queues:  # (btgen::StaticScenario holds statuses only)
        q = scenario.queues[0]
        raise UserError.at(
            q.loc,
            f"the `queue` line of `{q.name}` is not supported on a microcontroller image (its scenarios "
            "set statuses only)",
        )
    lines = []
    for k, leaf in enumerate(scenario.leaves):
        statuses = ", ".join(_status(s) for s in leaf.statuses)
        lines.append(f"constexpr btgen::Status {prefix}_leaf{k}[] = {{{statuses}}};")
    if scenario.leaves:
        rows = ",\n    ".join(
            f"btgen::LeafScript{{{cpp_view(leaf.name)}, {prefix}_leaf{k}, {len(leaf.statuses)}}}"
            for k, leaf in enumerate(scenario.leaves)
        )
        lines.append(f"constexpr btgen::LeafScript {prefix}_leaves[] = {{\n    {rows}}};")
        leaves, count = f"{prefix}_leaves", len(scenario.leaves)
    else:
        leaves, count = "nullptr", 0
    node_scripts = "nullptr"
    if program is not None:
        line_of = {leaf.name: k for k, leaf in enumerate(scenario.leaves)}
        scripts = [
            str(line_of.get(n.name, 0xFFFF)) if n.kind in ("Action", "Condition") else "0xFFFF" for n in program.nodes
        ]
        lines.append(f"constexpr std::uint16_t {prefix}_node_scripts[] = {{{', '.join(scripts)}}};")
        node_scripts = f"{prefix}_node_scripts"
    lines.append(
        f"constexpr btgen::StaticScenario {prefix}{{{scenario.ticks}, {scenario.clock_ms}, "
        f"{_status(scenario.default)}, {leaves}, {count}, {node_scripts}}};"
    )
    return "\n".join(lines) + "\n"


SINK_HPP = """\
// The cases' output: the board's UART, framed for btgen.tools.mcu.
#pragma once
#include <cstddef>

#include "btgen_bsp.hpp"

struct CaseSink {
  bool line_start = true;
  void write(const char* data, std::size_t size) { btgen_bsp::write(data, size); }
  // A run-time error's line (the host runner's stderr), sent as `@@stderr <line>`.
  void error(const char* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      if (line_start) btgen_bsp::write("@@stderr ");
      btgen_bsp::write(data + i, 1);
      line_start = data[i] == '\\n';
    }
  }
};
"""


def case_cpp(index: int, header: str, template: str, scenario, program) -> str:
    return (
        f"// Case {index}: {header}, its scenario compiled in.\n"
        f'#include "{header}"\n\n'
        '#include "btgen/harness/static_scenario.hpp"\n'
        '#include "case_sink.hpp"\n\n'
        "namespace {\n"
        + scenario_cpp(scenario, "kScenario", program)
        + f"alignas(8) unsigned char storage[btgen::static_run_storage<{template}, CaseSink>()];\n"
        "}  // namespace\n\n"
        f"int btgen_mcu_case_{index}(CaseSink& sink) {{\n"
        f"  return btgen::run_static_scenario<{template}>(kScenario, sink, storage);\n"
        "}\n"
    )


def main_cpp(indices: Sequence[int]) -> str:
    decls = "".join(f"int btgen_mcu_case_{i}(CaseSink& sink);\n" for i in indices)
    calls = "".join(
        f'  btgen_bsp::write("@@case {i}\\n");\n'
        f"  status = btgen_mcu_case_{i}(sink);\n"
        f'  btgen_bsp::write(sink.line_start ? "@@exit " : "\\n@@exit ");\n'
        "  btgen_bsp::write_unsigned(static_cast<unsigned>(status));\n"
        '  btgen_bsp::write("\\n");\n'
        "  sink.line_start = true;\n"
        for i in indices
    )
    return (
        '#include "btgen_bsp.hpp"\n#include "case_sink.hpp"\n\n'
        + decls
        + "\nint main() {\n  btgen_bsp::init();\n  CaseSink sink;\n  int status = 0;\n"
        + calls
        + '  btgen_bsp::write("@@stack ");\n'
        "  btgen_bsp::write_unsigned(btgen_bsp::stack_used());\n"
        '  btgen_bsp::write("\\n@@done\\n");\n'
        "  return 0;\n}\n"
    )


def _load(case: Case):
    from btgen import pipeline
    from btgen.interp.scenario import load_scenario
    from btgen.tools.cppengine import _check_no_user_nodes

    mission = pipeline.load(case.mission)
    _check_no_user_nodes(mission)
    scenario, _ = load_scenario(case.scenario, mission)
    return pipeline.program(mission), scenario


def images(cases: Sequence[Case], batch: int = BATCH) -> list[Image]:
    """The cases' sources, `batch` cases to an image. UserError when a mission does not compile."""
    out: list[Image] = []
    seen: dict[str, int] = {}
    for start in range(0, len(cases), batch):
        image = Image(f"batch{len(out)}", list(cases[start : start + batch]))
        image.sources["case_sink.hpp"] = SINK_HPP
        indices = []
        for index, case in enumerate(image.cases, start):
            program, scenario = _load(case)
            stem = mission_stem(case.mission)
            # One namespace per case: two missions of one stem do not meet in an image.
            ns = f"{naming.namespace_name(stem)}_{index}"
            header, source = render(program, f"{stem}_{index}", None, ns)
            if header.name in seen:
                raise InternalError(f"two cases give the header {header.name}")
            seen[header.name] = index
            image.sources[header.name] = header.text
            template = f"{ns}::{naming.pascal_case(stem + '_' + str(index))}"
            image.sources[f"case_{index}.cpp"] = case_cpp(index, header.name, template, scenario, program)
            indices.append(index)
        image.sources["main.cpp"] = main_cpp(indices)
        out.append(image)
    return out


def cmakelists(images_: Sequence[Image], opt: str = OPT, defines: Sequence[str] = ()) -> str:
    root = ROOT.as_posix()
    lines = [
        "cmake_minimum_required(VERSION 3.16)",
        "project(btgen_mcu_cases C CXX)",
        f'include("{root}/cmake/btgen.cmake")',
        f'include("{root}/cmake/btgen_mcu.cmake")',
        f'set(CMAKE_CXX_FLAGS_RELEASE "{opt}")',
        f'set(CMAKE_C_FLAGS_RELEASE "{opt}")',
        f"target_compile_options(btgen_bsp PRIVATE {' '.join(WARNINGS)})",
    ]
    for image in images_:
        cpps = " ".join(f"{image.name}/{n}" for n in sorted(image.sources) if n.endswith(".cpp"))
        lines += [
            f"add_executable({image.name} {cpps})",
            f"target_include_directories({image.name} PRIVATE ${{CMAKE_CURRENT_SOURCE_DIR}}/{image.name})",
            f"target_link_libraries({image.name} PRIVATE btgen::runtime btgen::bsp)",
            f"target_compile_options({image.name} PRIVATE {' '.join(WARNINGS)})",
        ]
        if defines:
            lines.append(f"target_compile_definitions({image.name} PRIVATE {' '.join(defines)})")
    return "\n".join(lines) + "\n"


def _write_if_changed(path: Path, text: str) -> None:
    if path.is_file() and path.read_text(encoding="utf-8") == text:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def _run(cmd: Sequence[str], what: str, cwd: Optional[Path] = None) -> str:
    proc = subprocess.run(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False, cwd=cwd)
    out = proc.stdout.decode("utf-8", "replace")
    if proc.returncode != 0:
        raise InternalError(f"{what} failed ({proc.returncode}):\n{' '.join(cmd)}\n{out}")
    return out


def default_build_root(opt: str = OPT, defines: Sequence[str] = ()) -> Path:
    """Where `build` puts the images of `opt` and `defines` unless told otherwise."""
    key = hashlib.sha256("\0".join((ROOT.as_posix(), opt, *defines)).encode("utf-8")).hexdigest()[:16]
    return cache_dir() / f"cases-{key}"


def build(
    images_: Sequence[Image],
    build_root: Optional[Path] = None,
    opt: str = OPT,
    jobs: int = 2,
    defines: Sequence[str] = (),
) -> Path:
    """Writes the images' sources (only files whose text changed) and builds them with the
    toolchain file, `opt` and the preprocessor `defines` (NAME=VALUE); returns the build
    directory (the images are `<dir>/build/<name>.elf`)."""
    missing = missing_tools()
    if missing:
        raise InternalError(f"cannot build for the microcontroller: {', '.join(missing)} not on PATH")
    if build_root is None:
        build_root = default_build_root(opt, defines)
    src = build_root / "src"
    for image in images_:
        for name, text in image.sources.items():
            _write_if_changed(src / image.name / name, text)
    _write_if_changed(src / "CMakeLists.txt", cmakelists(images_, opt, defines))
    bld = build_root / "build"
    generator = [] if (bld / "CMakeCache.txt").is_file() else ["-G", "Ninja"] if shutil.which("ninja") else []
    if True:
        _run(
            [
                "cmake",
                "-S",
                str(src),
                "-B",
                str(bld),
                *generator,
                "-DCMAKE_BUILD_TYPE=Release",
                f"-DCMAKE_TOOLCHAIN_FILE={TOOLCHAIN_FILE}",
            ],
            "configuring the microcontroller build",
        )
    targets = [x for image in images_ for x in ("--target", image.name)]
    _run(["cmake", "--build", str(bld), "-j", str(jobs), *targets], "building the microcontroller images")
    return bld


def run_image(elf: Path, timeout: float = TIMEOUT) -> tuple[int, str]:
    """Runs an image in QEMU: its exit status and its UART output."""
    try:
        proc = subprocess.run(
            qemu_command(elf), stdin=subprocess.DEVNULL, capture_output=True, check=False, timeout=timeout
        )
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode("utf-8", "replace") if e.stdout else ""
        raise InternalError(f"{elf} ran for more than {timeout} s in QEMU; its output:\n{out}") from None
    return proc.returncode, proc.stdout.decode("utf-8", "replace") + proc.stderr.decode("utf-8", "replace")


def split_output(image: Image, first_index: int, text: str) -> dict[int, Result]:
    """The cases' results from an image's UART output (a case missing from it is absent)."""
    results: dict[int, Result] = {}
    current: Optional[int] = None
    out: list[str] = []
    err: list[str] = []
    for line in text.splitlines(keepends=True):
        if line.startswith("@@case "):
            current, out, err = int(line.split()[1]), [], []
        elif line.startswith("@@exit ") and current is not None:
            case = image.cases[current - first_index]
            results[current] = Result(case, int(line.split()[1]), "".join(out), "".join(err))
            current = None
        elif line.startswith("@@stderr "):
            err.append(line[len("@@stderr ") :])
        elif current is not None:
            out.append(line)
    return results


def run_cases(
    cases: Sequence[Case],
    batch: int = BATCH,
    build_root: Optional[Path] = None,
    opt: str = OPT,
    defines: Sequence[str] = (),
) -> list[Result]:
    """Every case run on the board in QEMU, in order (built as `build` says). InternalError
    when an image does not build, does not finish, or stops before its last case (its output
    is in the message)."""
    imgs = images(cases, batch)
    bld = build(imgs, build_root, opt, defines=defines)
    results: list[Result] = []
    first = 0
    for image in imgs:
        elf = bld / f"{image.name}.elf"
        status, text = run_image(elf)
        got = split_output(image, first, text)
        if status != 0 or "@@done\n" not in text or len(got) != len(image.cases):
            raise InternalError(f"{elf} stopped with status {status} after {len(got)} cases; its output:\n{text}")
        results += [got[i] for i in range(first, first + len(image.cases))]
        first += len(image.cases)
    return results


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = cmdline.Parser(prog="python -m btgen.tools.mcu", description=__doc__.split("\n\n")[0])
    parser.add_argument("pairs", nargs="+", metavar="MISSION SCENARIO")
    args = parser.parse_args(argv)
    if len(args.pairs) % 2:
        parser.error("give a scenario after every mission")
    cases = [Case(args.pairs[i], args.pairs[i + 1]) for i in range(0, len(args.pairs), 2)]
    try:
        results = run_cases(cases)
    except UserError as e:
        for d in e.diagnostics:
            print(str(d), file=sys.stderr)
        return 1
    worst = 0
    for r in results:
        print(f"== {r.case.mission}")
        sys.stdout.write(r.stdout)
        sys.stderr.write(r.stderr)
        worst = max(worst, r.status)
    return worst


if __name__ == "__main__":
    sys.exit(main())
