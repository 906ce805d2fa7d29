#!/usr/bin/env python3
"""Differential testing: random missions through the interpreter and the C++ engine.

    scripts/difftest.py --seeds 0:300 [--features control|full|dynamic] [--scenarios 3]
                        [--sanitize] [--keep DIR] [--jobs N]

For every seed, btgen.tools.fuzzgen writes a mission and scenarios. Each mission is
classified first:

- invalid: `btgen validate` rejects it (a generator bug: counted, printed,
  and the run fails);
- unsupported: `btgen compile` rejects it only with "not supported by the C++
  back end yet": counted and reported as skipped, never silently;
- rejected: `btgen compile` rejects it for another reason although the
  interpreter accepts it: a finding (the run fails);
- compiled: run on both engines.

Compiled missions are built in batches (one executable holding up to
--batch missions, dispatching on its first argument), so a few hundred
missions cost a few dozen compiler runs; executables are cached under
btgen's cache directory (see btgen.tools.cppengine) keyed by everything that goes
into them. Each scenario is run by the interpreter in-process (as `btgen run`
does: warnings, trace, run-time errors) and by the executable; exit status,
stdout and stderr must be identical. Divergent cases are written to --keep
(default: build/difftest-failures) as mission + scenario + both outputs.

Exit status: 0 when every compiled mission agrees and none was invalid or
rejected; 1 otherwise.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import hashlib
import io
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "generator"))

from btgen.backend_cpp import naming
from btgen.diagnostics import UserError
from btgen.tools import cppengine
from btgen.tools.fuzzgen import FEATURE_SETS, random_case

UNSUPPORTED_MARK = "not supported by the C++ back end yet"
RUN_TIMEOUT_S = 60


@dataclass
class Outcome:
    rc: int
    stdout: str
    stderr: str

    def key(self) -> tuple[int, str, str]:
        return self.rc, self.stdout, self.stderr


@dataclass
class Report:
    features: str
    seeds: list[int] = field(default_factory=list)
    invalid: list[tuple[int, str]] = field(default_factory=list)
    unsupported: list[int] = field(default_factory=list)
    rejected: list[tuple[int, str]] = field(default_factory=list)
    compiled: list[int] = field(default_factory=list)
    runs: int = 0
    divergences: list[tuple[int, int, str]] = field(default_factory=list)  # seed, scenario index, where kept
    builds: int = 0
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        return not (self.invalid or self.rejected or self.divergences)

    def summary(self) -> str:
        lines = [
            f"difftest ({self.features}): {len(self.seeds)} missions: {len(self.compiled)} compiled and run, "
            f"{len(self.unsupported)} skipped as not supported by the C++ back end yet, "
            f"{len(self.invalid)} invalid, {len(self.rejected)} rejected by compile",
            f"difftest ({self.features}): {self.runs} scenario runs, {len(self.divergences)} divergences, "
            f"{self.builds} batched executables, {self.seconds:.1f} s",
        ]
        for seed, msg in self.invalid:
            lines.append(f"  invalid mission of seed {seed}: {msg}")
        for seed, msg in self.rejected:
            lines.append(f"  seed {seed} rejected by `btgen compile` but run by the interpreter: {msg}")
        for seed, j, where in self.divergences:
            lines.append(f"  DIVERGENCE seed {seed} scenario {j}: {where}")
        return "\n".join(lines)


# ------------------------------------------------------------------ the interpreter
_MISSIONS: dict[str, object] = {}
# The BehaviorTree.CPP release both engines follow (`--btcpp`; lang/versions.py).
BTCPP = ["4.6.2"]


def _load(mission: str):
    """The checked mission (loaded once per path: the front end costs more than a run)."""
    from btgen.frontend.loader import load_mission

    key = f"{BTCPP[0]}:{mission}"
    if key not in _MISSIONS:
        _MISSIONS[key] = load_mission(mission, btcpp=BTCPP[0])
    return _MISSIONS[key]


def run_interp(mission: str, scenario: str) -> Outcome:
    """What `btgen run MISSION --scenario SCENARIO` prints and returns (btgen.tools.run.run_command
    and the CLI's error handling), in-process and with the mission loaded once."""
    from btgen.interp.engine import run_trace
    from btgen.interp.scenario import load_scenario

    out, err = io.StringIO(), io.StringIO()
    m = _load(mission)
    err.write("".join(str(d) + "\n" for d in m.warnings))
    try:
        sc, warnings = load_scenario(scenario, m)
        err.write("".join(str(d) + "\n" for d in warnings))
        run_trace(m, sc, out.write)
        rc = 0
    except UserError as e:
        err.write("".join(str(d) + "\n" for d in e.diagnostics))
        rc = 1
    return Outcome(rc, out.getvalue(), err.getvalue())


def run_interp_cli(mission: str, scenario: str) -> Outcome:
    """`btgen run MISSION --scenario SCENARIO` through the command line's main(), in-process."""
    from btgen import cli

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = cli.main(["run", mission, "--scenario", scenario, "--btcpp", BTCPP[0]])
    return Outcome(rc, out.getvalue(), err.getvalue())


# ------------------------------------------------------------------ batched C++ builds
def _batch_main(entries: list[tuple[str, str]]) -> str:
    """A main() running mission `argv[1]` (an index) on scenario `argv[2]`."""
    lines = [
        "// generated by scripts/difftest.py: several missions' scenario runners in one program",
        "#include <cstdlib>",
    ]
    lines += [f'#include "{header}"' for header, _ in entries]
    lines += [
        '#include "btgen/harness/driver.hpp"',
        "",
        "int main(int argc, char** argv) {",
        "  if (argc < 2) return 2;",
        "  switch (std::atoi(argv[1])) {",
    ]
    for i, (_, template) in enumerate(entries):
        lines.append(f"    case {i}: return btgen::run_scenario_main<{template}>(argc - 1, argv + 1);")
    lines += ["    default: return 2;", "  }", "}", ""]
    return "\n".join(lines)


def build_batch(missions: list[str]) -> Path:
    """One executable for `missions` (paths relative to the current directory), cached."""
    from btgen.backend_cpp.emit import render
    from btgen.compiler import mission_stem
    from btgen.ir.lower import lower

    outputs, entries = [], []
    for m in missions:
        stem = mission_stem(m)
        outs = render(lower(_load(m)), stem, os.getcwd())
        outputs.extend(outs)
        entries.append((outs[0].name, f"{naming.namespace_name(stem)}::{naming.pascal_case(stem)}"))
    main_text = _batch_main(entries)
    cxx = cppengine.compiler()
    identity = cppengine._compiler_identity(cxx)
    if not identity:
        raise SystemExit(f"difftest: no C++ compiler `{cxx}`")
    flags = cppengine.cxx_flags()
    h = hashlib.sha256()
    for part in (identity, " ".join(flags), main_text):
        h.update(part.encode("utf-8") + b"\0")
    for out in outputs:
        h.update(out.name.encode("utf-8") + b"\0" + out.text.encode("utf-8") + b"\0")
    for f in sorted(cppengine.RUNTIME_INCLUDE.rglob("*.hpp")):
        h.update(str(f.relative_to(ROOT)).encode("utf-8") + b"\0" + f.read_bytes() + b"\0")
    key = h.hexdigest()[:32]
    final = cppengine.cache_dir() / "difftest" / key
    binary = final / "missions"
    if binary.is_file():
        return binary
    final.parent.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=f".{key}.", dir=str(final.parent)))
    try:
        for out in outputs:
            (work / out.name).write_text(out.text, encoding="utf-8")
        (work / "main.cpp").write_text(main_text, encoding="utf-8")
        cmd = [
            cxx,
            *flags,
            "-I",
            str(cppengine.RUNTIME_INCLUDE),
            "-I",
            str(work),
            str(work / "main.cpp"),
            "-o",
            str(work / "missions"),
        ]
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False)
        if proc.returncode != 0:
            raise RuntimeError(
                "the generated C++ of a batch does not build:\n"
                + " ".join(cmd)
                + "\n"
                + proc.stdout.decode("utf-8", "replace")[-20000:]
            )
        try:
            os.rename(work, final)
        except OSError:
            if not binary.is_file():
                raise
    finally:
        if work.exists():
            shutil.rmtree(work, ignore_errors=True)
    return binary


def run_cpp(binary: Path, index: int, mission: str, scenario: str) -> Outcome:
    """The batch executable's run of one mission; the mission's warnings first, as `btgen run
    --engine cpp` prints them."""
    warnings = "".join(str(w) + "\n" for w in _load(mission).warnings)
    env = dict(os.environ)
    env.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=0")
    env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
    try:
        proc = subprocess.run(
            [str(binary), str(index), scenario], capture_output=True, check=False, timeout=RUN_TIMEOUT_S, env=env
        )
    except subprocess.TimeoutExpired:
        return Outcome(-1, "", f"timed out after {RUN_TIMEOUT_S} s")
    return Outcome(
        proc.returncode, proc.stdout.decode("utf-8", "replace"), warnings + proc.stderr.decode("utf-8", "replace")
    )


# ------------------------------------------------------------------ the driver
def classify(mission: str) -> tuple[str, str]:
    """("invalid" | "unsupported" | "rejected" | "compiled", message)."""
    from btgen.backend_cpp.emit import render
    from btgen.compiler import mission_stem
    from btgen.ir.lower import lower

    try:
        m = _load(mission)
    except UserError as e:
        return "invalid", str(e).splitlines()[0]
    try:
        render(lower(m), mission_stem(mission), os.getcwd())  # what `btgen compile` does after loading
    except UserError as e:
        if all(UNSUPPORTED_MARK in d.message for d in e.diagnostics if d.severity == "error"):
            return "unsupported", str(e).splitlines()[0]
        return "rejected", str(e)
    return "compiled", ""


def _diff(a: str, b: str) -> str:
    import difflib

    return "".join(difflib.unified_diff(a.splitlines(True), b.splitlines(True), "interpreter", "C++", n=2))


def _keep(keep: Path, seed: int, j: int, mission: str, scenario: str, interp: Outcome, cpp: Outcome) -> str:
    keep.mkdir(parents=True, exist_ok=True)
    stem = keep / f"seed{seed}_s{j}"
    shutil.copyfile(mission, f"{stem}.xml")
    shutil.copyfile(scenario, f"{stem}.scenario")
    for name, o in (("interp", interp), ("cpp", cpp)):
        Path(f"{stem}.{name}.out").write_text(o.stdout, encoding="utf-8")
        Path(f"{stem}.{name}.err").write_text(f"exit {o.rc}\n{o.stderr}", encoding="utf-8")
    diff = _diff(interp.stdout, cpp.stdout) or (
        f"stderr/exit differ: interpreter exit {interp.rc} {interp.stderr!r} / C++ exit {cpp.rc} {cpp.stderr!r}"
    )
    Path(f"{stem}.diff").write_text(diff, encoding="utf-8")
    return f"{stem}.xml"


def difftest(
    seeds: range | list[int],
    features: str = "control",
    n_scenarios: int = 3,
    batch: int = 25,
    jobs: int = 2,
    keep: Optional[Path] = None,
    workdir: Optional[Path] = None,
    log=lambda s: None,
    btcpp: str = "4.6.2",
) -> Report:
    """Run the seeds; returns the report (never raises on a divergence). `btcpp`: the
    BehaviorTree.CPP release both engines follow."""
    start = time.monotonic()
    BTCPP[0] = btcpp
    report = Report(features)
    keep = (keep or ROOT / "build" / "difftest-failures").resolve()
    own_dir = workdir is None
    work = Path(tempfile.mkdtemp(prefix="difftest.")) if own_dir else workdir
    work.mkdir(parents=True, exist_ok=True)
    # Run inside the work directory: missions are then named by bare file names, so the
    # generated code (whose banner names the mission) and the cache keys do not depend on
    # where the work directory is, and a re-run finds its executables in the cache.
    old_cwd = os.getcwd()
    os.chdir(work)
    cases = {}
    try:
        for seed in seeds:
            case = random_case(seed, features, n_scenarios, btcpp)
            rel = f"fz_{features}_{seed}.xml"
            Path(rel).write_text(case.mission, encoding="utf-8")
            scen = []
            for j, text in enumerate(case.scenarios):
                p = f"fz_{features}_{seed}_{j}.scenario"
                Path(p).write_text(text, encoding="utf-8")
                scen.append(p)
            cases[seed] = (rel, scen)
            report.seeds.append(seed)
            kind, msg = classify(rel)
            if kind == "invalid":
                report.invalid.append((seed, msg))
            elif kind == "unsupported":
                report.unsupported.append(seed)
            elif kind == "rejected":
                report.rejected.append((seed, msg))
            else:
                report.compiled.append(seed)
        log(f"difftest: {len(report.compiled)} of {len(report.seeds)} missions compile; building in batches of {batch}")
        chunks = [report.compiled[i : i + batch] for i in range(0, len(report.compiled), batch)]
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            futures = {pool.submit(build_batch, [cases[s][0] for s in chunk]): chunk for chunk in chunks}
            binaries = {}
            for f in concurrent.futures.as_completed(futures):
                binaries[tuple(futures[f])] = f.result()
        report.builds = len(chunks)
        for chunk in chunks:
            binary = binaries[tuple(chunk)]
            for index, seed in enumerate(chunk):
                mission, scenarios = cases[seed]
                for j, scenario in enumerate(scenarios):
                    a = run_interp(mission, scenario)
                    b = run_cpp(binary, index, mission, scenario)
                    report.runs += 1
                    if a.key() != b.key():
                        where = _keep(keep, seed, j, mission, scenario, a, b)
                        report.divergences.append((seed, j, where))
                        log(f"DIVERGENCE seed {seed} scenario {j}: kept as {where}")
    finally:
        for seed in report.seeds:
            _MISSIONS.pop(f"{btcpp}:{cases[seed][0]}", None)
        BTCPP[0] = "4.6.2"
        os.chdir(old_cwd)
        if own_dir:
            shutil.rmtree(work, ignore_errors=True)
    report.seconds = time.monotonic() - start
    return report


def parse_seeds(text: str) -> range:
    a, sep, b = text.partition(":")
    if not sep or not a.isdigit() or not b.isdigit() or int(b) <= int(a):
        raise argparse.ArgumentTypeError(f"expected A:B with A < B (seeds A to B-1), got `{text}`")
    return range(int(a), int(b))


def main(argv: Optional[list[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=parse_seeds, required=True, metavar="A:B", help="seeds A to B-1")
    p.add_argument("--features", choices=FEATURE_SETS, default="control")
    p.add_argument("--scenarios", type=int, default=3, help="scenarios per mission (default 3)")
    p.add_argument("--batch", type=int, default=25, help="missions per executable (default 25)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 2, help="parallel compiler runs")
    p.add_argument("--sanitize", action="store_true", help="build with ASan+UBSan (BTGEN_SANITIZE=1)")
    p.add_argument("--keep", type=Path, default=None, help="where divergent cases go")
    p.add_argument("--btcpp", choices=("4.6.2", "4.10.0"), default="4.6.2", help="BehaviorTree.CPP release")
    args = p.parse_args(argv)
    if args.sanitize:
        os.environ["BTGEN_SANITIZE"] = "1"
    total = Report(args.features)
    # Chunks of 500 seeds keep the work directory and memory small on long runs.
    seeds = list(args.seeds)
    for i in range(0, len(seeds), 500):
        r = difftest(
            seeds[i : i + 500],
            args.features,
            args.scenarios,
            args.batch,
            args.jobs,
            args.keep,
            log=lambda s: print(s, file=sys.stderr, flush=True),
            btcpp=args.btcpp,
        )
        for name in ("seeds", "invalid", "unsupported", "rejected", "compiled", "divergences"):
            getattr(total, name).extend(getattr(r, name))
        total.runs += r.runs
        total.builds += r.builds
        total.seconds += r.seconds
        print(
            f"difftest: seeds {seeds[i]}..{seeds[min(i + 500, len(seeds)) - 1]} done, "
            f"{len(total.divergences)} divergences so far",
            file=sys.stderr,
            flush=True,
        )
    print(total.summary())
    return 0 if total.ok else 1


if __name__ == "__main__":
    sys.exit(main())
