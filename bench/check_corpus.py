"""How fast `btgen check` goes over a repository: the real files of tests/real_files and N generated
missions, in one process. Prints numbers; it is not a test (nothing here passes or fails).

    .venv/bin/python bench/check_corpus.py [--missions 1000] [--no-analysis]

Three measures, each in a fresh process so start-up counts once:
- the first file: `btgen check` on one small mission (interpreter start, imports, one load);
- tests/real_files: every folder in one `btgen check` call (files found, loads, files/s);
- N missions of tools/fuzzgen.py (seeds 0..N-1) in one folder, in one `btgen check` call;
the last two with `-j 1` and `-j 2`. Wall-clock and CPU seconds both: on a shared machine the
load average (printed first) decides the wall-clock ones.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "generator"))

from btgen.tools.fuzzgen import random_mission


def timed(args: list[str], cwd: Path) -> tuple[float, float, str]:
    """Wall-clock and CPU seconds (user + system of the process and its workers), and its stderr."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "generator"))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    r = subprocess.run(
        [sys.executable, "-m", "btgen", "check", *args], cwd=cwd, env=env, capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, r.stderr


def line(what: str, n: int, wall: float, cpu: float, err: str) -> str:
    summary = err.strip().splitlines()[-1] if err.strip() else "clean"
    return (
        f"{what:<34} {wall:7.2f} s wall {cpu:7.2f} s CPU  {n / wall:6.1f} files/s ({n / cpu:6.1f} per CPU s)  {summary}"
    )


def files_found(args: list[str], cwd: Path) -> int:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "generator"))
    r = subprocess.run(
        [sys.executable, "-m", "btgen", "check", "--show-files", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    return len(r.stdout.splitlines())


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--missions", type=int, default=1000, help="generated missions (default 1000)")
    p.add_argument("--no-analysis", action="store_true", help="leave out the A1xx analysis (--ignore A)")
    args = p.parse_args()
    extra = ["--ignore", "A"] if args.no_analysis else []
    print(f"# {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}, Python {sys.version.split()[0]}")
    with tempfile.TemporaryDirectory() as tmp:
        one = Path(tmp) / "one"
        one.mkdir()
        (one / "m.xml").write_text(
            '<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n'
        )
        wall, cpu, err = timed([".", *extra], one)
        print(line("first file (one process, 1 file)", 1, wall, cpu, err))

        real = ROOT / "tests" / "real_files"
        n = files_found(["."], real)
        for jobs in ("1", "2"):
            wall, cpu, err = timed([".", "-j", jobs, *extra], real)
            print(line(f"tests/real_files, {n} files, -j {jobs}", n, wall, cpu, err))

        gen = Path(tmp) / "generated"
        gen.mkdir()
        for seed in range(args.missions):
            (gen / f"m{seed:05d}.xml").write_text(random_mission(seed))
        for jobs in ("1", "2"):
            wall, cpu, err = timed([".", "-j", jobs, *extra], gen)
            print(line(f"{args.missions} generated missions, -j {jobs}", args.missions, wall, cpu, err))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
