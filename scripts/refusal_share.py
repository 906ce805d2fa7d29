#!/usr/bin/env python3
"""The share of missions the C++ back end refuses while the interpreter runs them.

    scripts/refusal_share.py [--seeds N] [--markdown] [--list]
    scripts/refusal_share.py --corpus DIR [--list]      # a real-file corpus, loaded as check loads it

A mission counts as *run by the interpreter* when btgen's front end loads it for the
selected BehaviorTree.CPP release (what `btgen run` needs), and as *refused by the C++ back
end* when `btgen compile` then rejects it (lowering and rendering, no C++ compiler run).
The recorded cases are every folder under tests/conformance (each with the release it was
recorded on), the random missions recorded there, Nav2's cases (with Nav2's nodes, per distro), the
regressions, and the real files of
tests/real_files (both releases, the models `btgen models` infers, as test_real_files.py
does); the random missions are `fuzzgen`'s feature sets full, dynamic and edges, seeds
0..N-1, under both releases. `--list` prints each refusal's first line.

Prints one row per set: missions loaded, refused by the C++ back end, how many of those the
real library refuses too (a recording says it failed before printing anything), and the share
refused that the library runs (random missions have no recording: every refusal counts). The
goal (docs/btcpp-versions.md, "What the C++ back end refuses") is 0 on every row.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import io
import os
import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "generator"))

from btgen import pipeline
from btgen.backend_cpp.emit import render
from btgen.compiler import mission_stem
from btgen.diagnostics import UserError
from btgen.ir.lower import lower
from btgen.pipeline import CompileOptions

VERSIONS = ("4.6.2", "4.10.0")
CONFORMANCE = ROOT / "tests" / "conformance"
REAL = ROOT / "tests" / "real_files"


@dataclass
class Row:
    name: str
    loaded: int = 0
    refused: list[tuple[str, str]] = field(default_factory=list)  # (mission, first error line)
    # of those, missions the real library refuses too (a recording says it failed without a trace)
    library_refuses: int = 0

    @property
    def ran(self) -> int:
        """Refused by the C++ back end although the library runs them (as far as is recorded)."""
        return len(self.refused) - self.library_refuses

    @property
    def share(self) -> str:
        return f"{100.0 * self.ran / self.loaded:.1f} %" if self.loaded else "-"


def classify(path: str, opts: CompileOptions) -> str | None:
    """None when the front end refuses (neither engine runs it), "" when the C++ back end
    compiles it, else the back end's first error."""
    try:
        mission = pipeline.load(path, opts)
    except UserError:
        return None
    try:
        with tempfile.TemporaryDirectory() as out:
            render(lower(mission), mission_stem(path), out)
    except UserError as e:
        errors = [str(d) for d in e.diagnostics if d.severity == "error"] or [str(e)]
        return errors[0].splitlines()[0]
    return ""


def library_refuses(path: str, version: str) -> bool:
    """Whether a recording says the real library of `version` refuses the mission (fails
    without printing a trace line): `.refused` beside it, a btcpp-4.10.0 stem without `.trace`,
    `<version>/<stem>.error` with an empty trace, or a real file's expected `.refused`."""
    base = path[: -len(".xml")]
    folder, stem = os.path.split(base)
    if os.path.exists(base + ".refused"):
        return True
    if folder.endswith("btcpp-4.10.0") and not os.path.exists(base + ".trace"):
        return True
    per_version = os.path.join(folder, version, stem)
    if os.path.exists(per_version + ".error"):
        with open(per_version + ".trace", encoding="utf-8") as f:
            return f.read() == ""
    if path.startswith(str(REAL)):
        flat = os.path.relpath(base, REAL).replace(os.sep, "__")
        expected = "expected" if version == "4.6.2" else "expected-4.10.0"
        return os.path.exists(REAL / expected / f"{flat}.refused")
    return False


def count(row: Row, path: str, opts: CompileOptions) -> None:
    verdict = classify(path, opts)
    if verdict is None:
        return
    row.loaded += 1
    if verdict:
        row.refused.append((path, verdict))
        if library_refuses(path, opts.btcpp):
            row.library_refuses += 1


def _missions(folder: Path) -> list[str]:
    return sorted(str(p) for p in folder.glob("*.xml") if p.with_suffix(".scenario").exists())


def nav2_rows() -> Iterator[Row]:
    """tests/conformance/nav2: the cases of cases/ with Nav2's Controls and Decorators of each
    distro built in (`--nodes nav2:DISTRO`, as test_nav2.py loads them), under each release; a
    `.refused` recording in DISTRO-VERSION/ says the library refuses the case."""
    from btgen.lang import nav2

    folder = CONFORMANCE / "nav2"
    for distro in nav2.DISTROS:
        for version in VERSIONS:
            opts = CompileOptions(btcpp=version, nodes=f"nav2:{distro}")
            recorded = folder / f"{distro}-{version}"
            row = Row(f"tests/conformance/nav2 {distro} ({version})")
            for path in _missions(folder / "cases"):
                verdict = classify(path, opts)
                if verdict is None:
                    continue
                row.loaded += 1
                if verdict:
                    row.refused.append((path, verdict))
                    if (recorded / (Path(path).stem + ".refused")).exists():
                        row.library_refuses += 1
            yield row


def recorded_rows() -> Iterator[Row]:
    for folder in sorted(p for p in CONFORMANCE.iterdir() if p.is_dir()):
        if folder.name == "nav2":
            yield from nav2_rows()
            continue
        if all((folder / v).is_dir() for v in VERSIONS):  # recorded on both releases
            versions: tuple[str, ...] = VERSIONS
        else:
            versions = ("4.10.0",) if folder.name.endswith("4.10.0") else ("4.6.2",)
        for version in versions:
            opts = CompileOptions(btcpp=version)
            row = Row(f"tests/conformance/{folder.name} ({version})")
            for path in _missions(folder):
                count(row, path, opts)
            yield row
            for sub in sorted(p for p in folder.iterdir() if p.is_dir() and p.name not in VERSIONS):
                row = Row(f"tests/conformance/{folder.name}/{sub.name} ({version})")
                for path in _missions(sub):
                    count(row, path, opts)
                yield row
    for version in VERSIONS:
        row = Row(f"tests/regressions ({version})")
        for path in _missions(ROOT / "tests" / "regressions"):
            count(row, path, CompileOptions(btcpp=version))
        yield row
    yield from real_rows()


def real_rows() -> Iterator[Row]:
    from btgen.cli import main

    nav2_models = REAL / "nav2" / "nav2_tree_nodes.xml"
    files = sorted(
        os.path.relpath(p, REAL)
        for p in glob.glob(str(REAL / "**" / "*.xml"), recursive=True)
        if Path(p) != nav2_models and "/expected" not in p and "/scenarios/" not in p
    )
    with tempfile.TemporaryDirectory() as tmp:
        for version in VERSIONS:
            row = Row(f"tests/real_files ({version})")
            for rel in files:
                models: tuple[str, ...] = ()
                if rel.startswith("nav2/"):
                    models = (str(nav2_models),)
                elif not rel.startswith(("btcpp/trees/", "btcpp/fuzzing/")):
                    inferred = os.path.join(tmp, rel.replace("/", "__"))
                    flag = ["--btcpp", "4.10.0"] if rel.startswith("btcpp/tests-4.10.0/") else []
                    with contextlib.redirect_stderr(io.StringIO()):
                        if main(["models", str(REAL / rel), "-o", inferred, *flag]) != 0:
                            continue
                    models = (inferred,)
                count(row, str(REAL / rel), CompileOptions(btcpp=version, models=models))
            yield row


def corpus_rows(folder: str, versions: tuple[str, ...] = VERSIONS) -> Iterator[Row]:
    """Each project folder of `folder` (a real-file corpus: `btgen models .` already run in each),
    its files loaded as `btgen check` loads them (the same models, libraries and main tree), under
    each release; `folder`/../oracle_<462|410>.json, when present ({project: {file: [[tree,
    "loaded" or "refused: ..."]]}}), says which files the library refuses."""
    import json
    from dataclasses import replace

    from btgen.tools.check import config, discovery, runner

    for version in versions:
        oracle_json = Path(folder).parent / f"oracle_{version.replace('.', '')[:3]}.json"
        oracle = json.loads(oracle_json.read_text(encoding="utf-8")) if oracle_json.exists() else {}
        for project in sorted(p for p in Path(folder).iterdir() if p.is_dir()):
            row = Row(f"{project.name} ({version})")
            old = os.getcwd()
            os.chdir(project)
            try:
                s = replace(config.load_settings(None), btcpp=version)
                skip, main_for = runner.filters(s)
                units = discovery.plan(discovery.survey(["."], skip), s.models, s.trees, main_for)
                projects = runner._ProjectModels()
                try:
                    for unit in units:
                        models = tuple(projects.models_for(m) if m in unit.projects else m for m in unit.models)
                        with contextlib.redirect_stderr(io.StringIO()):
                            verdict = classify(unit.path, runner._options(s, unit, models))
                        if verdict is None:
                            continue
                        row.loaded += 1
                        if verdict:
                            rel = os.path.normpath(unit.path)
                            row.refused.append((f"{project.name}/{rel}", verdict))
                            outcomes = oracle.get(project.name, {}).get(rel)
                            if outcomes and any(o != "loaded" for _, o in outcomes):
                                row.library_refuses += 1
                finally:
                    projects.close()
            finally:
                os.chdir(old)
            yield row


def random_rows(n: int) -> Iterator[Row]:
    from btgen.tools.fuzzgen import random_case

    with tempfile.TemporaryDirectory() as tmp:
        for features in ("full", "dynamic", "edges"):
            for version in VERSIONS:
                row = Row(f"fuzzgen {features}, seeds 0..{n - 1} ({version})")
                for seed in range(n):
                    path = os.path.join(tmp, f"fz_{features}_{seed}.xml")
                    Path(path).write_text(random_case(seed, features, 1, version).mission, encoding="utf-8")
                    count(row, path, CompileOptions(btcpp=version))
                yield row


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=200, help="random missions per feature set and release")
    p.add_argument("--markdown", action="store_true", help="print a Markdown table")
    p.add_argument("--list", action="store_true", help="print every refusal's first line")
    p.add_argument("--no-random", action="store_true", help="recorded cases only")
    p.add_argument(
        "--corpus",
        metavar="DIR",
        help="instead: each project folder of DIR (`btgen models .` run in each), loaded as `btgen check` "
        "loads it; DIR/../oracle_462.json and oracle_410.json say what the library refuses",
    )
    args = p.parse_args(argv)
    rows: list[Row] = []
    if args.corpus:
        sets: list[Iterator[Row]] = [corpus_rows(os.path.abspath(args.corpus))]
    else:
        sets = [recorded_rows()] + ([] if args.no_random else [random_rows(args.seeds)])
    if args.markdown:
        print(
            "| missions | loaded | refused by the C++ back end | of which the library refuses too "
            "| share refused that the library runs |"
        )
        print("|---|---:|---:|---:|---:|")
    for it in sets:
        for row in it:
            rows.append(row)
            if args.markdown:
                print(f"| {row.name} | {row.loaded} | {len(row.refused)} | {row.library_refuses} | {row.share} |")
            else:
                print(
                    f"{row.name}: {row.loaded} loaded, {len(row.refused)} refused by the C++ back end "
                    f"({row.library_refuses} refused by the library too): {row.share} refused that the library runs"
                )
            if args.list:
                for path, msg in row.refused:
                    print(f"    {os.path.relpath(path, ROOT) if path.startswith(str(ROOT)) else path}: {msg}")
            sys.stdout.flush()
    total = sum(r.loaded for r in rows)
    refused = sum(len(r.refused) for r in rows)
    ran = sum(r.ran for r in rows)
    print(f"total: {total} loaded, {refused} refused by the C++ back end, {ran} of them run by the library")
    return 0


if __name__ == "__main__":
    sys.exit(main())
