"""What a mission costs on a Cortex-M4: flash, RAM, stack and instructions per tick; prints a table.

    .venv/bin/python bench/mcu/run_mcu_bench.py                  # every mission, -Os and -O2
    .venv/bin/python bench/mcu/run_mcu_bench.py --update         # ... and put the table into docs/microcontroller.md
    .venv/bin/python bench/mcu/run_mcu_bench.py missions/LabTour.xml --opt=-Os

Missions: `missions/*.xml` that compile, then `bench/missions/balanced_100.xml` and
`balanced_1000.xml`. Each is built with the toolchain file for the MPS2 AN386 board
(mcu/README.md) together with bench/mcu/bench_mcu.cpp (leaves that answer at once with
SUCCESS read from a volatile, a counter for a clock, no observer, the mission object built
in .bss at start-up) at -Os, at -O2, and "small": -Os without node text
(`-DBTGEN_NODE_TEXT=0`, btgen/node.hpp: no IDs, names or source positions in the image)
and with every node on the table interpreter (`-DBTGEN_STRAIGHT_LINE_BUDGET=0`);
the same main without a mission is the baseline (board support, start-up, this main).
Each image runs in QEMU with `-icount shift=0`. Columns:

- flash: text + data of the image less the baseline's: the executor (engine, node table,
  generated code and the library code it pulls in), leaves excluded (they are one-liners);
- RAM: data + bss less the baseline's (the mission object: statuses, counters, timers,
  blackboard, the interpreter's stacks), plus the worst stack: the painted stack's
  high-water mark after the ticks (the whole program's, so main's frame is in it);
- state: sizeof the mission object;
- instr/tick: instructions per tick, leaves included. QEMU does not model a Cortex-M4's
  timing; with -icount each instruction is 1 ns of virtual time, so the SysTick counter
  (25 MHz) counts instructions, calibrated by a loop of known length; 2,000 ticks,
  less the same loop without them. A Cortex-M4 runs about 1.2 to 1.5 cycles per
  instruction from zero-wait-state memory.

The build goes to build/mcu-bench (kept, so a second run rebuilds only what changed).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(ROOT / "generator"))

from btgen.backend_cpp import naming
from btgen.backend_cpp.emit import render
from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.ir.lower import lower
from btgen.tools import mcu

OPTS = ("-Os", "-O2")
# The smallest build: -Os, no node text (btgen/node.hpp: BTGEN_NODE_TEXT=0: no IDs, names or
# source positions in the image) and every node on the table interpreter (no straight-line code).
SMALL = ("-Os", "-DBTGEN_NODE_TEXT=0", "-DBTGEN_STRAIGHT_LINE_BUDGET=0")
SMALL_LABEL = "-Os, small"
BENCH_MISSIONS = ("bench/missions/balanced_100.xml", "bench/missions/balanced_1000.xml")
README_BEGIN = "<!-- mcu-bench:begin (bench/mcu/run_mcu_bench.py --update) -->"
README_END = "<!-- mcu-bench:end -->"


def default_missions() -> list[str]:
    shipped = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "missions").glob("*.xml"))
    return shipped + list(BENCH_MISSIONS)


def target_name(stem: str, opt: str) -> str:
    return f"{naming.snake_case(stem)}_{'small' if opt == SMALL_LABEL else opt.lstrip('-')}"


def flags(opt: str) -> str:
    return " ".join(SMALL) if opt == SMALL_LABEL else opt


def write_if_changed(path: Path, text: str) -> None:
    if path.is_file() and path.read_text(encoding="utf-8") == text:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def generate(missions: list[str], opts: tuple[str, ...], src: Path) -> dict[str, str]:
    """The CMake project: the generated missions and a target per mission and optimisation.
    Returns mission -> its stem for the ones that compile."""
    lines = [
        "cmake_minimum_required(VERSION 3.16)",
        "project(btgen_mcu_bench C CXX)",
        f'include("{ROOT.as_posix()}/cmake/btgen.cmake")',
        f'include("{ROOT.as_posix()}/cmake/btgen_mcu.cmake")',
        "target_compile_options(btgen_bsp PRIVATE -Os)",
    ]
    bench = (HERE / "bench_mcu.cpp").as_posix()
    for opt in opts:
        t = target_name("baseline", opt)
        lines += [
            f'add_executable({t} "{bench}")',
            f"target_compile_definitions({t} PRIVATE BTGEN_MCU_BASELINE)",
            f"target_compile_options({t} PRIVATE {flags(opt)})",
            f"target_link_libraries({t} PRIVATE btgen::bsp)",
        ]
    stems: dict[str, str] = {}
    for path in missions:
        stem = Path(path).stem
        try:
            program = lower(load_mission(str(ROOT / path)))
        except UserError as e:
            print(f"# {path}: does not compile, left out: {e}", file=sys.stderr)
            continue
        header, source = render(program, stem, str(ROOT))
        write_if_changed(src / "gen" / header.name, header.text)
        stems[path] = stem
        template = f"{naming.namespace_name(stem)}::{naming.pascal_case(stem)}"
        for opt in opts:
            t = target_name(stem, opt)
            lines += [
                f'add_executable({t} "{bench}")',
                f"target_include_directories({t} PRIVATE gen)",
                f'target_compile_definitions({t} PRIVATE "BTGEN_MISSION_HEADER=\\"{header.name}\\"" '
                f"BTGEN_MISSION_TEMPLATE={template})",
                f"target_compile_options({t} PRIVATE {flags(opt)})",
                f"target_link_libraries({t} PRIVATE btgen::runtime btgen::bsp)",
            ]
    write_if_changed(src / "CMakeLists.txt", "\n".join(lines) + "\n")
    return stems


def sections(elf: Path) -> dict[str, int]:
    out = subprocess.run(["arm-none-eabi-size", "-A", str(elf)], capture_output=True, text=True, check=True).stdout
    sizes: dict[str, int] = {}
    for line in out.splitlines():
        m = re.match(r"^(\.\S+)\s+(\d+)\s+\d+", line)
        if m:
            sizes[m.group(1)] = int(m.group(2))
    return sizes


def flash_ram(elf: Path) -> tuple[int, int]:
    s = sections(elf)
    flash = sum(v for k, v in s.items() if k in (".text", ".ARM.exidx", ".ARM.extab", ".data"))
    ram = s.get(".data", 0) + s.get(".bss", 0)
    return flash, ram


def run(elf: Path) -> dict[str, int]:
    proc = subprocess.run(
        mcu.qemu_command(elf, ("-icount", "shift=0")), capture_output=True, text=True, check=False, timeout=1800
    )
    if proc.returncode != 0:
        raise SystemExit(f"{elf} failed in QEMU ({proc.returncode}):\n{proc.stdout}{proc.stderr}")
    return {k: int(v) for k, v in re.findall(r"^(\w+) (\d+)$", proc.stdout, re.M)}


def nodes_of(path: str) -> int:
    return len(lower(load_mission(str(ROOT / path))).nodes)


def table(rows: list[dict]) -> str:
    head = (
        "| mission | nodes | opt | flash B | RAM B (static + stack) | state B | instr/tick |\n"
        "|---|---:|---|---:|---:|---:|---:|\n"
    )
    body = "".join(
        f"| {r['mission']} | {r['nodes']:,} | {r['opt']} | {r['flash']:,} | "
        f"{r['ram'] + r['stack']:,} ({r['ram']:,} + {r['stack']:,}) | {r['state']:,} | {r['instr']:,.0f} |\n"
        for r in rows
    )
    return head + body


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("missions", nargs="*", help="missions (default: shipped and the 100/1,000-node ones)")
    parser.add_argument(
        "--opt", action="append", choices=(*OPTS, "small"), help="optimisation (default: -Os, -O2 and small)"
    )
    parser.add_argument("--build-dir", default=str(ROOT / "build" / "mcu-bench"))
    parser.add_argument(
        "--update", "--update-readme", action="store_true", help="put the table into docs/microcontroller.md"
    )
    args = parser.parse_args(argv)
    missing = mcu.missing_tools()
    if missing:
        raise SystemExit(f"needs {', '.join(missing)} (bash scripts/test_mcu.sh --install-only installs them)")
    opts = tuple(SMALL_LABEL if o == "small" else o for o in (args.opt or (*OPTS, "small")))
    missions = args.missions or default_missions()
    build = Path(args.build_dir)
    stems = generate(missions, opts, build / "src")
    bld = build / "build"
    subprocess.run(
        ["cmake", "-S", str(build / "src"), "-B", str(bld), f"-DCMAKE_TOOLCHAIN_FILE={mcu.TOOLCHAIN_FILE}"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    subprocess.run(["cmake", "--build", str(bld), "-j", str(min(2, os.cpu_count() or 1))], check=True)
    base = {}
    for opt in opts:
        elf = bld / f"{target_name('baseline', opt)}.elf"
        base[opt] = (flash_ram(elf), run(elf))
    rows = []
    for path, stem in stems.items():
        n = nodes_of(path)
        for opt in opts:
            elf = bld / f"{target_name(stem, opt)}.elf"
            (flash, ram), got = flash_ram(elf), run(elf)
            (bflash, bram), bgot = base[opt]
            ratio = got["calibration_instructions"] / got["calibration_counts"]
            instr = (got["counts"] - bgot["counts"]) * ratio / got["ticks"]
            rows.append(
                dict(
                    mission=Path(path).name,
                    nodes=n,
                    opt=opt,
                    flash=flash - bflash,
                    ram=ram - bram,
                    stack=got["stack_bytes"],
                    state=got["state_bytes"],
                    instr=instr,
                )
            )
            print(
                f"{Path(path).name} {opt}: flash {flash - bflash} B, RAM {ram - bram} + stack "
                f"{got['stack_bytes']} B, state {got['state_bytes']} B, {instr:.0f} instr/tick",
                file=sys.stderr,
            )
    (bflash, bram), bgot = base[opts[0]]
    text = table(rows) + (
        f"\nBaseline ({opts[0]}: board support, start-up and the benchmark's main, no mission): "
        f"{bflash:,} B of flash, {bram:,} B of static RAM, {bgot['stack_bytes']:,} B of stack.\n"
    )
    print(text)
    if args.update:
        readme = ROOT / "docs" / "microcontroller.md"
        old = readme.read_text(encoding="utf-8")
        if README_BEGIN not in old or README_END not in old:
            raise SystemExit(f"{readme} has no {README_BEGIN} ... {README_END} block")
        start = old.index(README_BEGIN) + len(README_BEGIN)
        readme.write_text(old[:start] + "\n" + text + old[old.index(README_END) :], encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
