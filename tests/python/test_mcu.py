"""The missions on a microcontroller: a Cortex-M4 (QEMU's mps2-an386) prints the host's traces.

Every public conformance case of BehaviorTree.CPP 4.6.2 (tests/conformance/btcpp-4.6.2/)
and every regression case (tests/regressions/: run-time errors, doubles, scripts) is
compiled to C++, built for the board with the toolchain file
(cmake/toolchain/arm-none-eabi-cortex-m4.cmake), -fno-exceptions -fno-rtti, no heap
(the board's _sbrk stops the image), its scenario compiled in
(btgen/harness/static_scenario.hpp), batched a dozen to a firmware image, and run in
QEMU; its trace must be the recording's and the reference interpreter's, byte for
byte, and its run-time error lines and exit status the host runner's.

Needs arm-none-eabi-g++ (gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib) and
qemu-system-arm (scripts/test_mcu.sh installs them): skipped without them, except in
CI, where it must run. The first run builds about 75 missions for the board (about a
minute and a half on two cores); later runs rebuild only what changed
(`<cache>/btgen/mcu/`).
"""

import hashlib
import os
import re
import subprocess
import sys

import pytest

import cppbuild
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import load_scenario
from btgen.tools import mcu
from conftest import ROOT, case_stems

MISSING = mcu.missing_tools()
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")
pytestmark = pytest.mark.skipif(
    bool(MISSING) and not IN_CI,
    reason=f"{', '.join(MISSING)} not installed (bash scripts/test_mcu.sh installs them)",
)

CONFORMANCE = os.path.join("tests", "conformance", "btcpp-4.6.2")
REGRESSIONS = os.path.join("tests", "regressions")

# Cases that cannot run on the board, and why. (Size is no reason: an image of a
# dozen missions takes well under the board's 4 MB.)
DOES_NOT_FIT: dict[str, str] = {
    "scenario_huge_number": "its scenario has errors, which are reported where a scenario is compiled into "
    "an image (on the host, by the same reader), so no image is built",
}

CONFORMANCE_STEMS = case_stems(os.path.join(ROOT, CONFORMANCE), ".trace")
REGRESSION_STEMS = case_stems(os.path.join(ROOT, REGRESSIONS), ".trace")
CASES = [(CONFORMANCE, s) for s in CONFORMANCE_STEMS] + [(REGRESSIONS, s) for s in REGRESSION_STEMS]
IDS = [f"{os.path.basename(d)}/{s}" for d, s in CASES]


def _read(path: str, default=None):
    if not os.path.exists(path):
        return default
    with open(path, encoding="utf-8", newline="") as f:
        return f.read()


@pytest.fixture(scope="module")
def results():
    """Every case, run on the board (paths relative to the repository, as the recordings give them)."""
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        cases = [
            mcu.Case(os.path.join(d, s + ".xml"), os.path.join(d, s + ".scenario"), f"{os.path.basename(d)}/{s}")
            for d, s in CASES
            if s not in DOES_NOT_FIT
        ]
        return {r.case.name: r for r in mcu.run_cases(cases)}
    finally:
        os.chdir(cwd)


def test_cases_present():
    assert len(CONFORMANCE_STEMS) >= 40, f"conformance cases missing in {CONFORMANCE}"
    assert REGRESSION_STEMS, f"regression cases missing in {REGRESSIONS}"
    assert set(DOES_NOT_FIT) <= set(CONFORMANCE_STEMS + REGRESSION_STEMS)


@pytest.mark.parametrize("folder,stem", CASES, ids=IDS)
def test_trace_on_the_board_is_the_hosts(folder, stem, results, monkeypatch):
    if stem in DOES_NOT_FIT:
        pytest.skip(f"does not fit the board: {DOES_NOT_FIT[stem]}")
    got = results[f"{os.path.basename(folder)}/{stem}"]
    base = os.path.join(folder, stem)
    recorded = _read(os.path.join(ROOT, base + ".trace"))
    assert got.stdout == recorded
    assert got.status == int(_read(os.path.join(ROOT, base + ".exit"), "0").strip())
    # Scenario warnings are the host's (the scenario is read and checked there, then compiled in).
    stderr = _read(os.path.join(ROOT, base + ".stderr"), "")
    assert got.stderr == "".join(line for line in stderr.splitlines(True) if ": warning: " not in line)
    # The reference interpreter gives the same trace (it stops at a run-time error as the runner does).
    monkeypatch.chdir(ROOT)
    mission = load_mission(base + ".xml")
    scenario, _ = load_scenario(base + ".scenario", mission)
    if got.status == 0:
        assert got.stdout == trace_text(mission, scenario)


def test_no_image_links_the_heap(results):
    """Not one allocation function is linked into the case images (the runtime's number <->
    text conversions included): nothing in them can allocate, whatever path a mission takes."""
    elves = sorted((mcu.default_build_root() / "build").glob("batch*.elf"))
    assert len(elves) >= len(results) // mcu.BATCH
    for elf in elves:
        symbols = subprocess.run(["arm-none-eabi-nm", str(elf)], capture_output=True, text=True, check=True).stdout
        linked = {line.split()[-1] for line in symbols.splitlines() if line.strip()}
        assert not linked & {"malloc", "_malloc_r", "calloc", "realloc", "_sbrk_r", "free", "_free_r"}, elf


# The smallest build (bench/mcu: the Lab Tour under 16 KB of flash): no node text, every node
# on the table interpreter. A dozen cases whose missions cover controls, decorators, time and
# scripts.
SMALL_DEFINES = ("BTGEN_NODE_TEXT=0", "BTGEN_STRAIGHT_LINE_BUDGET=0")
SMALL_STEMS = [s for s in CONFORMANCE_STEMS if s not in DOES_NOT_FIT][::4]
_TRACE_LINE = re.compile(r'^(\d+) \S+ ".*" (\w+ -> \w+)$', re.M)


def test_small_build_keeps_every_status(monkeypatch):
    """-DBTGEN_NODE_TEXT=0 leaves IDs and names out of the image: the trace shows them empty,
    and every uid and status change is the recording's."""
    monkeypatch.chdir(ROOT)
    cases = [
        mcu.Case(os.path.join(CONFORMANCE, s + ".xml"), os.path.join(CONFORMANCE, s + ".scenario"), s)
        for s in SMALL_STEMS
    ]
    results = mcu.run_cases(cases, batch=len(cases), defines=SMALL_DEFINES)
    for r in results:
        expected = _TRACE_LINE.sub(r'\1  "" \2', _read(os.path.join(ROOT, CONFORMANCE, r.case.name + ".trace")))
        assert (r.status, r.stderr) == (0, "")
        assert r.stdout == expected, r.case.name


def test_an_allocation_stops_the_image(tmp_path):
    """The board has no heap: malloc reaches _sbrk, which says so and exits with kHeapExit (86)."""
    src = tmp_path / "src"
    src.mkdir()
    (src / "main.cpp").write_text(
        '#include <cstdlib>\n#include "btgen_bsp.hpp"\n'
        'int main() {\n  btgen_bsp::init();\n  btgen_bsp::write("before\\n");\n'
        '  void* volatile p = std::malloc(24);\n  btgen_bsp::write(p != nullptr ? "got memory\\n" : "null\\n");\n'
        "  return 0;\n}\n"
    )
    (src / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(heap C CXX)\n"
        f'include("{mcu.ROOT.as_posix()}/cmake/btgen_mcu.cmake")\n'
        "add_executable(heap main.cpp)\ntarget_link_libraries(heap PRIVATE btgen::bsp)\n"
    )
    build = tmp_path / "build"
    for cmd in (
        ["cmake", "-S", str(src), "-B", str(build), f"-DCMAKE_TOOLCHAIN_FILE={mcu.TOOLCHAIN_FILE}"],
        ["cmake", "--build", str(build)],
    ):
        proc = subprocess.run(cmd, capture_output=True, check=False)
        assert proc.returncode == 0, proc.stdout.decode() + proc.stderr.decode()
    status, out = mcu.run_image(build / "heap.elf", timeout=60)
    assert out.startswith("before\nbtgen bsp: heap allocation of "), out
    assert out.endswith(" bytes attempted; this image has no heap\n"), out
    assert status == 86


def test_os_only_headers_refuse_the_bare_metal_build(tmp_path):
    """Groot2, .btlog and AsyncCall need threads or sockets: under BTGEN_BARE_METAL they do not compile."""
    for header in ("groot2", "btlog", "async_call"):
        src = tmp_path / f"{header}.cpp"
        src.write_text(f'#include "btgen/{header}.hpp"\n')
        proc = cppbuild.run(
            cppbuild.command(
                [src], cxx="arm-none-eabi-g++", defines=["BTGEN_BARE_METAL=1"], mode="syntax", warnings=False
            )
        )
        assert proc.returncode != 0
        assert f"btgen/{header}.hpp needs an operating system" in proc.stderr


def _checkout_key() -> str:
    return hashlib.sha256(os.path.realpath(ROOT).encode("utf-8")).hexdigest()[:16]


def test_lab_tour_example_runs_on_the_board():
    """examples/mcu: btgen_add_mission() and the toolchain file build the Lab Tour for the board,
    with simulated leaves on the SysTick clock; run.sh runs it in QEMU and the tour succeeds."""
    proc = subprocess.run(
        # Built in the cache (as the cases are), so that a second run rebuilds only what changed;
        # one build folder per checkout, since CMake refuses a folder made for other sources.
        ["bash", os.path.join(ROOT, "examples", "mcu", "run.sh"), str(mcu.cache_dir() / f"example-{_checkout_key()}")],
        capture_output=True,
        check=False,
        timeout=900,
        env={**os.environ, "Python3_EXECUTABLE": sys.executable},
    )
    out = proc.stdout.decode("utf-8", "replace")
    assert proc.returncode == 0, out + proc.stderr.decode("utf-8", "replace")
    assert out.startswith("Lab Tour on a Cortex-M4: 149 nodes")
    # Three exhibits, the entrance, home: five journeys, each RUNNING for a while.
    assert out.count("] Navigate RUNNING -> SUCCESS\n") == 5
    assert out.count("] IsListWithExhibit IDLE -> FAILURE\n") == 1
    last = out.splitlines()[-1]
    assert last.startswith("mission SUCCESS after ") and "; errors 0;" in last, last
