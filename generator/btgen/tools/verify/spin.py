"""Running SPIN: `spin -a` writes the verifier pan.c, a C compiler builds it, pan searches.

pan is compiled by tcc when it is installed (else gcc; `BTGEN_PAN_CC` chooses), with -O0
(`BTGEN_PAN_CFLAGS` changes it: a large model takes minutes with gcc -O1) and with -DCOLLAPSE,
its lossless compression of stored states.

Every property of one model is an `ltl NAME { ... }` block; pan checks one at a time
(`-a -N NAME`, acceptance cycles: safety and liveness alike). A violation leaves a trail,
which `spin -t` replays in simulation: its `@C node status` lines are the leaf choices in
call order, `@T` the tick ends, and `<<<<<START OF CYCLE>>>>>` where the lasso's loop begins.

The search is exhaustive or it is no proof: pan's depth limit is raised until the search
fits, and a search that still hits a limit (depth, memory) is reported as incomplete, never
as "holds".
"""

from __future__ import annotations

import math
import os
import re
import resource
import shutil
import subprocess
import time
from dataclasses import dataclass, field
from typing import Optional

VECTORSZ = 1 << 16
MEMLIM_MB = 4096  # pan's memory bound (BTGEN_PAN_MEMLIM_MB changes it)
DEPTHS = (100_000, 1_000_000, 10_000_000)
BITSTATE = ("-DBITSTATE",)  # compile_model's extra flags of a bitstate verifier
BITSTATE_BITS = 30  # its hash array: 2^30 bits, 128 MB (at most a quarter of the memory bound)


def memlim_mb() -> int:
    v = os.environ.get("BTGEN_PAN_MEMLIM_MB", "")
    return int(v) if v.isdigit() and int(v) > 0 else MEMLIM_MB


def bitstate_bits() -> int:
    """-w of a bitstate search: 2^30 bits, or a quarter of the memory bound when that is less."""
    return min(BITSTATE_BITS, (memlim_mb() << 23).bit_length() - 3)


class Incomplete(Exception):
    """A search that hit a limit: no answer."""


class SpinMissing(Exception):
    """spin or a C compiler is not installed (scripts/setup.sh installs spin and tcc)."""


@dataclass
class SpinResult:
    holds: Optional[bool]  # None: the search was incomplete
    states: int = 0
    transitions: int = 0
    depth: int = 0
    memory_mb: float = 0.0
    seconds: float = 0.0
    compile_seconds: float = 0.0
    vector_bytes: int = 0
    lines: list[str] = field(default_factory=list)  # pan's output (with -DPRINTF, the model's printfs)
    incomplete: str = ""
    partial: str = ""  # a bitstate search that found no violation: what it covered (no proof)
    trail: Optional[str] = None  # the trail replayed by `spin -t`, when violated


def pan_cc() -> Optional[str]:
    """The C compiler of pan: BTGEN_PAN_CC, else tcc (it builds pan.c tens of times faster than
    gcc -O0, and the verifier searches about 1.5 times slower: balanced 1,000 nodes 0.4 against
    36 CPU s of build), else $CC or gcc."""
    chosen = os.environ.get("BTGEN_PAN_CC")
    if chosen:
        return shutil.which(chosen)
    return shutil.which("tcc") or shutil.which(os.environ.get("CC", "gcc"))


def tools() -> tuple[str, str]:
    s, cc = shutil.which("spin"), pan_cc()
    if s is None or cc is None:
        raise SpinMissing("spin" if s is None else os.environ.get("BTGEN_PAN_CC") or "gcc")
    return s, cc


def _child_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def compile_model(
    text: str, workdir: str, extra: tuple[str, ...] = (), times: Optional[dict[str, float]] = None
) -> float:
    """Write model.pml in workdir, generate and compile pan; returns the seconds it took.
    `times` receives the CPU seconds of `spin -a` and of the C compiler, and the bytes of pan's sources."""
    spin_bin, cc = tools()
    t0 = time.perf_counter()
    c0 = _child_cpu()
    os.makedirs(workdir, exist_ok=True)
    with open(os.path.join(workdir, "model.pml"), "w", encoding="utf-8") as f:
        f.write(text)
    p = subprocess.run([spin_bin, "-a", "model.pml"], cwd=workdir, capture_output=True, text=True, check=False)
    if p.returncode != 0 or not os.path.exists(os.path.join(workdir, "pan.c")):
        raise RuntimeError("spin -a failed on the generated model:\n" + p.stdout + p.stderr)
    c1 = _child_cpu()
    flags = [
        *os.environ.get("BTGEN_PAN_CFLAGS", "-O0").split(),
        "-w",
        f"-DVECTORSZ={VECTORSZ}",
        f"-DMEMLIM={memlim_mb()}",
        "-DNOREDUCE",
        *([] if "-DBITSTATE" in extra else ["-DCOLLAPSE"]),  # pan refuses the two together
        *extra,
    ]
    p = subprocess.run([cc, *flags, "-o", "pan", "pan.c"], cwd=workdir, capture_output=True, text=True, check=False)
    if p.returncode != 0:
        raise RuntimeError(f"{os.path.basename(cc)} failed on SPIN's pan.c:\n" + p.stdout[-4000:] + p.stderr[-4000:])
    if times is not None:
        times["spin_cpu"] = c1 - c0
        times["cc_cpu"] = _child_cpu() - c1
        times["pan_bytes"] = float(
            sum(os.path.getsize(os.path.join(workdir, f)) for f in os.listdir(workdir) if f.startswith("pan."))
        )
    return time.perf_counter() - t0


_NUM = {
    "states": re.compile(r"^\s*([0-9.e+]+) states, stored", re.M),
    "transitions": re.compile(r"^\s*([0-9.e+]+) transitions", re.M),
    "depth": re.compile(r"depth reached ([0-9]+)"),
    "errors": re.compile(r"errors: ([0-9]+)"),
    "memory": re.compile(r"^\s*([0-9.]+)\s+total actual memory usage", re.M),
    "seconds": re.compile(r"pan: elapsed time ([0-9.e+-]+) seconds"),
    "vector": re.compile(r"State-vector ([0-9]+) byte"),
    "hash": re.compile(r"hash factor: ([0-9.e+]+)"),
}


def _num(name: str, text: str) -> float:
    m = _NUM[name].search(text)
    return float(m.group(1)) if m else 0.0


def run_pan(workdir: str, args: list[str], wall: Optional[float] = None, bitstate: bool = False) -> SpinResult:
    """Run pan with rising depth limits until the search fits; parse its report. A bitstate
    search (pan built with -DBITSTATE) is never a proof: `holds` stays None, `partial` says so."""
    out = ""
    t0 = time.perf_counter()
    for depth in DEPTHS:
        p = subprocess.run(
            ["./pan", *args, f"-m{depth}"], cwd=workdir, capture_output=True, text=True, check=False, timeout=wall
        )
        out = p.stdout + p.stderr
        if "max search depth too small" not in out:
            break
    res = SpinResult(holds=None)
    res.seconds = time.perf_counter() - t0
    res.states = int(_num("states", out))
    res.transitions = int(_num("transitions", out))
    res.depth = int(_num("depth", out))
    res.memory_mb = _num("memory", out)
    res.vector_bytes = int(_num("vector", out))
    res.lines = out.splitlines()
    errors = int(_num("errors", out))
    if "max search depth too small" in out:
        res.incomplete = f"the search needs more than {DEPTHS[-1]} steps of depth"
    elif "out of memory" in out or "MEMLIM" in out or "hash table is full" in out.lower():
        res.incomplete = f"the search ran out of memory ({memlim_mb()} MB)"
    elif "State-vector" not in out:
        res.incomplete = "pan stopped without a report:\n" + out[-2000:]
    if errors:
        res.holds = False
    elif bitstate and not res.incomplete:
        res.partial = bitstate_summary(res.states, _num("hash", out))
    elif not res.incomplete:
        res.holds = True
    return res


def bitstate_summary(states: int, hash_factor: float) -> str:
    """What a bitstate search without a violation covered. Each state sets 3 bits (pan's -k3) of
    m = hash_factor * states; a new state is taken for one already seen with the chance
    (1 - e^(-3n/m))^3 at the end of the search, so 1 minus that is an estimate of the share of
    the reachable states visited (Holzmann's estimate; an estimate, not a bound)."""
    miss = (1.0 - math.exp(-3.0 / hash_factor)) ** 3 if hash_factor > 0 else 1.0
    cover = f"{100.0 * (1.0 - miss):.6g}"
    cover = ">99.9999" if cover == "100" else cover  # never printed as whole
    return (
        f"no violation found in {states} states (bitstate, hash factor {hash_factor:.4g}, "
        f"coverage estimate {cover}%): not a proof"
    )


def reachable(text: str, workdir: str, print_states: bool = False) -> SpinResult:
    """Exhaustive reachability of a model without properties (the state count)."""
    extra = ("-DSAFETY", "-DPRINTF") if print_states else ("-DSAFETY",)
    c = compile_model(text, workdir, extra)
    res = run_pan(workdir, ["-n"])
    res.compile_seconds = c
    if res.holds is None:
        raise Incomplete(f"SPIN's search is incomplete: {res.incomplete}")
    return res


def check(workdir: str, name: str, bitstate: bool = False) -> SpinResult:
    """One ltl property of the compiled model: acceptance cycles (-a), its trail replayed.
    `bitstate`: pan in workdir was built with -DBITSTATE (`compile_model(..., BITSTATE)`), and
    searches with a hash array of 2^bitstate_bits() bits: a violation is real, its absence no proof."""
    trail = os.path.join(workdir, "model.pml.trail")
    if os.path.exists(trail):
        os.remove(trail)
    args = ["-a", "-n", "-N", name, *([f"-w{bitstate_bits()}"] if bitstate else [])]
    res = run_pan(workdir, args, bitstate=bitstate)
    if res.holds is False and os.path.exists(trail):
        # The system alone replays the trail (its claim steps are skipped): `spin -t` follows
        # the first ltl block of a model, not the one pan was asked about.
        spin_bin, _ = tools()
        with open(os.path.join(workdir, "model.pml"), encoding="utf-8") as f:
            system = "".join(line for line in f if not line.startswith("ltl "))
        with open(os.path.join(workdir, "replay.pml"), "w", encoding="utf-8") as f:
            f.write(system)
        kept = os.path.join(workdir, f"{name}.trail")
        os.replace(trail, kept)
        shutil.copyfile(kept, os.path.join(workdir, "replay.pml.trail"))
        p = subprocess.run(
            [spin_bin, "-t", "-T", "replay.pml"], cwd=workdir, capture_output=True, text=True, check=False
        )
        res.trail = p.stdout
    return res


@dataclass
class Trail:
    """A counterexample: leaf choices (node index, status) in call order, and the ticks."""

    prefix: list[tuple[int, int]]
    cycle: list[tuple[int, int]]
    prefix_ticks: int  # tick ends before the loop starts
    cycle_ticks: int  # tick ends inside the loop (0: the run ended and stays)
    lasso: bool  # the trail has a loop (else: a finite bad prefix)


_CHOICE = re.compile(r"@C ([0-9]+) ([0-9]+)")


def parse_trail(text: str) -> Trail:
    prefix: list[tuple[int, int]] = []
    cycle: list[tuple[int, int]] = []
    pt = ct = 0
    in_cycle = False
    lasso = False
    for line in text.splitlines():
        if "START OF CYCLE" in line:
            in_cycle = lasso = True
            continue
        m = _CHOICE.search(line)
        if m:
            (cycle if in_cycle else prefix).append((int(m.group(1)), int(m.group(2))))
        elif "@T" in line:
            if in_cycle:
                ct += 1
            else:
                pt += 1
    return Trail(prefix, cycle, pt, ct, lasso)
