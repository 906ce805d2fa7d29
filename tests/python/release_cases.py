"""Folders of missions recorded on both releases, with partial traces (scripts/record_releases.py).

A folder holds `<stem>.xml` and `<stem>.scenario`; `4.6.2/<stem>.trace` and `4.10.0/<stem>.trace`
are what the real library printed (cut short where it threw), `<stem>.error` its message when it
threw or refused the file. Both btgen engines must print the same trace and fail exactly where
the library failed, the compiled executor with the interpreter's message.
"""

from __future__ import annotations

import os
import sys

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.engine import run_trace
from btgen.interp.scenario import load_scenario
from conftest import ROOT, case_stems

sys.path.insert(0, os.path.join(ROOT, "scripts"))

import difftest

VERSIONS = ("4.6.2", "4.10.0")


def stems(folder: str) -> list[str]:
    return case_stems(folder, ".xml")


def recorded(folder: str) -> list[tuple[str, str]]:
    """(stem, release) of every recording."""
    return [(s, v) for v in VERSIONS for s in stems(folder) if os.path.exists(os.path.join(folder, v, s + ".trace"))]


def expected(folder: str, stem: str, version: str) -> tuple[str, bool]:
    """The library's trace, and whether it failed."""
    with open(os.path.join(folder, version, stem + ".trace"), encoding="utf-8") as f:
        trace = f.read()
    return trace, os.path.exists(os.path.join(folder, version, stem + ".error"))


def loads(folder: str, stem: str, version: str) -> bool:
    try:
        load_mission(os.path.join(folder, stem + ".xml"), btcpp=version)
    except UserError:
        return False
    return True


def interp(folder: str, stem: str, version: str) -> tuple[str, bool, str]:
    """The interpreter's trace, whether it failed, and its first error message."""
    out: list[str] = []
    try:
        mission = load_mission(os.path.join(folder, stem + ".xml"), btcpp=version)
        scenario, _ = load_scenario(os.path.join(folder, stem + ".scenario"), mission)
        run_trace(mission, scenario, out.append)
    except UserError as e:
        return "".join(out), True, e.diagnostics[0].message
    return "".join(out), False, ""


class Batches:
    """One executable per release holding every mission of the folder that loads (difftest's
    batched builds); a mission the front end refuses is left out (the library refused it too,
    which the caller checks)."""

    def __init__(self, folder: str, work, include=None) -> None:
        self.folder = folder
        self.work = work
        self.include = include  # (stem, version) -> whether to build it (default: every one that loads)
        self.built: dict[str, tuple[object, list[str]]] = {}

    def build(self) -> Batches:
        old = os.getcwd()
        os.chdir(self.work)
        try:
            for version in VERSIONS:
                difftest.BTCPP[0] = version
                missions = []
                for stem in stems(self.folder):
                    if not loads(self.folder, stem, version):
                        continue
                    if self.include is not None and not self.include(stem, version):
                        continue
                    rel = f"{stem}_{version.replace('.', '')}.xml"
                    with open(os.path.join(self.folder, stem + ".xml"), encoding="utf-8") as f:
                        (self.work / rel).write_text(f.read(), encoding="utf-8")
                    missions.append(rel)
                self.built[version] = (difftest.build_batch(missions), missions)
        finally:
            difftest.BTCPP[0] = "4.6.2"
            os.chdir(old)
        return self

    def run(self, stem: str, version: str):
        """The compiled executor's outcome (difftest.Outcome), or None when the front end refused it."""
        binary, missions = self.built[version]
        rel = f"{stem}_{version.replace('.', '')}.xml"
        if rel not in missions:
            return None
        old = os.getcwd()
        os.chdir(self.work)
        difftest.BTCPP[0] = version
        try:
            return difftest.run_cpp(binary, missions.index(rel), rel, os.path.join(self.folder, stem + ".scenario"))
        finally:
            difftest.BTCPP[0] = "4.6.2"
            os.chdir(old)


def check_interp(folder: str, stem: str, version: str) -> None:
    trace, failed, _ = interp(folder, stem, version)
    assert (trace, failed) == expected(folder, stem, version)


def check_cpp(batches: Batches, stem: str, version: str) -> None:
    folder = batches.folder
    got = batches.run(stem, version)
    if got is None:
        assert expected(folder, stem, version) == ("", True)  # the library refused it on load too
        return
    assert got.rc in (0, 1), got.stderr
    assert (got.stdout, got.rc == 1) == expected(folder, stem, version)
    if got.rc == 1:  # the interpreter's message (the library's own differs)
        _, _, message = interp(folder, stem, version)
        assert message and message in got.stderr, (message, got.stderr)
