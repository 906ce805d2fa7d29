#!/usr/bin/env python3
"""End-to-end checks of lab_tour_robot, run by ctest (one case per test).

    check_robot.py --robot PATH --repo REPO CASE

The expectations come from the knowledge base as btgen's Python reader sees
it (btgen.kb.lint), not from the robot's own C++ code:

  tour_yes      --answer yes: the robot navigates to every exhibit of the tour
                in order, then to the tour's last stop, then home (the tour's
                first stop); it points at each exhibit after saying its
                pre-gesture message and before its post-gesture message;
                the mission ends SUCCESS with Pepper at home.
  tour_no       --answer no: the robot never navigates nor points, says
                "maybe another time", and the mission ends SUCCESS.
  English, isiZulu, Kinyarwanda
                a whole tour in that language: every exhibit's messages are
                said in it, or in English after "[no <language> translation]"
                where the base has a placeholder; a placeholder is never said.
  scenario_yes, scenario_no
                --scenario missions/scenarios/LabTour.*.scenario --trace: the
                status trace is byte for byte `btgen run`'s (the reference
                interpreter) for the same scenario.
  bad_options   mistakes on the command line exit 2 with one error line.
  bad_kb        every knowledge base of tests/bad_kb with errors makes the
                robot exit 2 printing exactly the linter's errors; so do bad
                configuration files.
  max_ticks     a mission cut short by --max-ticks is halted and exits 1.
  btlog         --btlog writes the records of the trace and says where.
  monitors      --groot2 lists the blackboards' names and lingers after the end.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Callable, NoReturn

from btgen.kb import lint as kbmod

CONFIG = "data/environmentKnowledgeBaseConfiguration.ini"
NAV_RE = re.compile(r"^\[tick +\d+\] navigating to (\d+) ")
POINT_RE = re.compile(r"^\[tick +\d+\] points at (\d+) ")
SAYS_RE = re.compile(r'^\[tick +\d+\] says: "(.*)"$')
ARRIVED_RE = re.compile(r"^\[tick +\d+\] arrived at (\d+) ")


def fail(message: str, output: str = "") -> NoReturn:
    if output:
        sys.stderr.write("---- robot output ----\n" + output + "\n----------------------\n")
    sys.stderr.write(f"FAIL: {message}\n")
    sys.exit(1)


class Run:
    def __init__(self, robot: str, args: list[str]) -> None:
        self.args = args
        proc = subprocess.run([robot, *args], capture_output=True, text=True, timeout=120, check=False)
        self.rc = proc.returncode
        self.out = proc.stdout
        self.err = proc.stderr
        self.lines = self.out.splitlines()

    def check(self, ok: bool, message: str) -> None:
        if not ok:
            fail(f"lab_tour_robot {' '.join(self.args)}: {message}", self.out + "\n[stderr]\n" + self.err)

    def matches(self, regex: re.Pattern[str]) -> list[str]:
        return [m.group(1) for m in map(regex.match, self.lines) if m]


def shipped_kb(repo: Path) -> kbmod.KnowledgeBase:
    config = kbmod.load_config(str(repo / CONFIG))
    return kbmod.load_kb(config.knowledge_base_path)


def expected_text(base: kbmod.KnowledgeBase, loc_id: int, phase: str, language: str) -> str:
    loc = base.location(loc_id)
    assert loc is not None
    msgs = loc.pre_gesture if phase == "pre" else loc.post_gesture
    placeholders = set(kbmod.iter_placeholders(base))
    key_lang = {"English": "English", "isiZulu": "IsiZulu", "Kinyarwanda": "Kinyarwanda"}[language]
    if (loc_id, f"{phase}GestureMessage{key_lang}") in placeholders:
        return f"[no {language} translation] {msgs.english}"
    return msgs.in_language(key_lang)


def check_full_tour(robot: str, repo: Path, language: str) -> None:
    base = shipped_kb(repo)
    tour = list(base.tour)
    home, end, exhibits = tour[0], tour[-1], tour[1:-1]
    run = Run(robot, ["--answer", "yes", "--language", language])
    run.check(run.rc == 0, f"exit status {run.rc}, expected 0")
    navigations = [int(i) for i in run.matches(NAV_RE)]
    run.check(
        navigations == [*exhibits, end, home],
        f"navigated to {navigations}, expected the exhibits {exhibits} of the tour {tour}, "
        f"then its end {end}, then home {home}",
    )
    arrivals = [int(i) for i in run.matches(ARRIVED_RE)]
    run.check(arrivals == navigations, f"arrived at {arrivals}, expected {navigations}")
    pointed = [int(i) for i in run.matches(POINT_RE)]
    run.check(pointed == [*exhibits, end], f"pointed at {pointed}, expected {[*exhibits, end]}")
    last = run.lines[-1] if run.lines else ""
    run.check(
        re.match(
            rf"lab_tour_robot: mission SUCCESS at tick \d+ after {len(tour)} navigations; "
            rf"Pepper is at {home} \(.*\), home: ",
            last,
        )
        is not None,
        f"last line `{last}` does not say the mission succeeded with Pepper at home {home}",
    )
    # Per exhibit, in order: navigate, pre-gesture message, point, post-gesture message.
    said = run.matches(SAYS_RE)
    pos = 0
    for ex in exhibits:
        want = [
            ("nav", ex),
            ("say", expected_text(base, ex, "pre", language)),
            ("point", ex),
            ("say", expected_text(base, ex, "post", language)),
        ]
        for kind, value in want:
            for i in range(pos, len(run.lines)):
                line = run.lines[i]
                m = (NAV_RE if kind == "nav" else POINT_RE if kind == "point" else SAYS_RE).match(line)
                if m and (m.group(1) == str(value)):
                    pos = i + 1
                    break
            else:
                run.check(False, f"exhibit {ex}: no `{kind} {value}` after line {pos + 1}")
    for text in said:
        run.check(
            not re.fullmatch(r"(?i)no (message|translation|text)\b.*", text),
            f"the robot said a placeholder aloud: `{text}`",
        )
    if language != "English":
        marker = f"[no {language} translation]"
        key_lang = {"isiZulu": "IsiZulu", "Kinyarwanda": "Kinyarwanda"}[language]
        if any(key.endswith(key_lang) for _, key in kbmod.iter_placeholders(base)):
            run.check(
                any(t.startswith(marker + " ") for t in said),
                f"no `{marker}` marker although the base lacks {language} texts",
            )


def case_tour_yes(robot: str, repo: Path) -> None:
    check_full_tour(robot, repo, "English")


def case_tour_no(robot: str, repo: Path) -> None:
    run = Run(robot, ["--answer", "no"])
    run.check(run.rc == 0, f"exit status {run.rc}, expected 0")
    run.check(not run.matches(NAV_RE), "the robot navigated although the visitor said no")
    run.check(not run.matches(POINT_RE), "the robot pointed at something although the visitor said no")
    said = run.matches(SAYS_RE)
    run.check(any("another time" in s for s in said), "the robot did not say `maybe another time`")
    run.check(
        re.match(r"lab_tour_robot: mission SUCCESS at tick \d+ after 0 navigations", run.lines[-1]) is not None,
        f"last line `{run.lines[-1]}`",
    )


def trace_lines(lines: list[str]) -> list[str]:
    return [ln for ln in lines if not ln.startswith("[tick") and not ln.startswith("lab_tour_robot:")]


def check_scenario(robot: str, repo: Path, name: str) -> None:
    scenario = f"missions/scenarios/LabTour.{name}.scenario"
    run = Run(robot, ["--scenario", scenario, "--trace"])
    run.check(run.rc == 0, f"exit status {run.rc}, expected 0")
    ref = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "missions/LabTour.xml", "--scenario", scenario],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=repo,
        check=False,
    )
    if ref.returncode != 0:
        fail(f"btgen run failed ({ref.returncode}): {ref.stderr}")
    got = trace_lines(run.lines)
    want = ref.stdout.splitlines()
    if got != want:
        for i, (g, w) in enumerate(zip(got, want)):
            if g != w:
                fail(f"{scenario}: trace line {i + 1} is `{g}`, the interpreter's is `{w}`", run.out)
        fail(f"{scenario}: {len(got)} trace lines, the interpreter prints {len(want)}", run.out)
    navigations = len(run.matches(NAV_RE))
    expected = 5 if name == "yes" else 0
    run.check(navigations == expected, f"{navigations} navigations, the scenario's story has {expected}")


def case_scenario_yes(robot: str, repo: Path) -> None:
    check_scenario(robot, repo, "yes")


def case_scenario_no(robot: str, repo: Path) -> None:
    check_scenario(robot, repo, "no")


def case_bad_options(robot: str, repo: Path) -> None:
    no_scenario = "missions/scenarios/LabTour.no.scenario"
    line = next(
        i
        for i, text in enumerate((repo / no_scenario).read_text(encoding="utf-8").splitlines(), 1)
        if text.split()[:2] == ["leaf", "IsVisitorResponseYes"]
    )
    for args, message in [
        (["--language", "French"], "unknown language `French`: use English, isiZulu or Kinyarwanda"),
        (["--answer", "maybe"], "`--answer` is yes or no, not `maybe`"),
        (["--tick-ms", "x"], "`--tick-ms` is a whole number of milliseconds from 0 to 60000, not `x`"),
        (["--bogus"], "unknown option `--bogus`"),
        (["--groot2", "65535"], "`--groot2` is a TCP port from 1 to 65534 (it also uses the next one), not `65535`"),
        (["--btlog", "run.log"], "`--btlog` needs a file name ending in .btlog, not `run.log`"),
        (
            ["--scenario", no_scenario, "--answer", "yes"],
            f"--answer yes contradicts {no_scenario}:{line}, which scripts IsVisitorResponseYes FAILURE",
        ),
    ]:
        run = Run(robot, args)
        run.check(run.rc == 2, f"exit status {run.rc}, expected 2")
        run.check(f"lab_tour_robot: error: {message}" in run.err.splitlines(), f"stderr lacks `{message}`")
    run = Run(robot, ["--help"])
    run.check(run.rc == 0 and run.out.startswith("usage: lab_tour_robot"), "--help")


def case_bad_kb(robot: str, repo: Path) -> None:
    bad = repo / "tests" / "bad_kb"
    checked = 0
    with tempfile.TemporaryDirectory() as tmp:
        for dat in sorted(bad.glob("*.dat")):
            expected_path = bad / (dat.stem + ".stderr")
            if not expected_path.exists():
                continue
            rel = f"tests/bad_kb/{dat.name}"
            errors = [ln for ln in expected_path.read_text(encoding="utf-8").splitlines() if ": error: " in ln]
            if not errors:
                continue
            shutil.copyfile(dat, os.path.join(tmp, dat.name))
            ini = os.path.join(tmp, "kb.ini")
            Path(ini).write_text(f"knowledgeBase {dat.name}\n", encoding="utf-8")
            run = Run(robot, ["--kb-config", ini])
            run.check(run.rc == 2, f"{rel}: exit status {run.rc}, expected 2")
            want = [ln.replace(rel, os.path.join(tmp, dat.name)) for ln in errors]
            got = [ln for ln in run.err.splitlines() if ": error: " in ln and not ln.startswith("lab_tour_robot:")]
            run.check(got == want, f"{rel}: errors\n  " + "\n  ".join(got) + "\nexpected\n  " + "\n  ".join(want))
            run.check(not run.matches(NAV_RE) and "[tick" not in run.out, f"{rel}: the mission ran")
            checked += 1
    if checked < 10:
        fail(f"only {checked} bad knowledge bases found in {bad}")
    for ini in ("config_equals", "config_missing_file", "config_unknown_key", "config_no_knowledge_base"):
        rel = f"tests/bad_kb/{ini}.ini"
        run = Run(robot, ["--kb-config", rel])
        want = [ln for ln in (bad / f"{ini}.stderr").read_text(encoding="utf-8").splitlines() if ": error: " in ln]
        got = [ln for ln in run.err.splitlines() if ": error: " in ln and not ln.startswith("lab_tour_robot:")]
        run.check(run.rc == 2, f"{rel}: exit status {run.rc}, expected 2")
        run.check(got == want, f"{rel}: errors {got}, expected {want}")
    run = Run(robot, ["--kb-config", "no/such/config.ini"])
    run.check(run.rc == 2 and "no/such/config.ini:1:1: error: " in run.err, "a missing configuration file")


def case_max_ticks(robot: str, repo: Path) -> None:
    run = Run(robot, ["--answer", "yes", "--max-ticks", "25"])
    run.check(run.rc == 1, f"exit status {run.rc}, expected 1")
    run.check(any("no result after 25 ticks: halting the mission" in ln for ln in run.lines), "no halting line")
    run.check(
        run.lines[-1].startswith("lab_tour_robot: mission still RUNNING after 25 ticks (halted)"),
        f"last line `{run.lines[-1]}`",
    )


def case_btlog(robot: str, repo: Path) -> None:
    """--btlog writes FileLogger2's format: header, the tree XML, the first timestamp, then one
    9-byte record per status change, the same changes as the trace, in its order."""
    import struct

    statuses = {"IDLE": 0, "RUNNING": 1, "SUCCESS": 2, "FAILURE": 3}
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "tour.btlog")
        run = Run(robot, ["--scenario", "missions/scenarios/LabTour.yes.scenario", "--trace", "--btlog", path])
        run.check(run.rc == 0, f"exit status {run.rc}, expected 0")
        data = Path(path).read_bytes()
    run.check(data[:19] == b"BTCPP4-FileLogger2\x01", "no FileLogger2 header")
    n = struct.unpack_from("<i", data, 19)[0]
    xml = data[23 : 23 + n].decode()
    run.check(xml.startswith('<root BTCPP_format="4">') and '_uid="1"' in xml, "no tree XML with _uid")
    body = data[31 + n :]
    run.check(len(body) % 9 == 0, f"{len(body)} bytes of records, not a multiple of 9")
    got = [(int.from_bytes(body[i + 6 : i + 8], "little"), body[i + 8]) for i in range(0, len(body), 9)]
    want = []
    for line in trace_lines(run.lines):
        words = line.split()
        if len(words) >= 4 and words[-2] == "->":
            want.append((int(words[0]), statuses[words[-1]]))
    run.check(got == want, f"{len(got)} records; the trace has {len(want)} changes, or they differ")
    wrote = f"lab_tour_robot: wrote {path} (replay it in Groot2; `btgen graph --btlog` draws it)"
    run.check(wrote in run.lines, f"no line `{wrote}`")


def case_monitors(robot: str, repo: Path) -> None:
    """--groot2 lists the blackboards by the names Groot2 asks for (the main tree's ID, else the
    SubTree's path, as btgen's Python side names the instances), and the publisher stays up
    --linger-ms after the last line, so monitors see the end: the process is still running
    when it has said so."""
    import socket

    from btgen.frontend.loader import load_mission
    from btgen.ir.treexml import groot2_tree

    mission = load_mission(str(repo / "missions" / "LabTour.xml"))
    names = [i.path or mission.main_tree for i in groot2_tree(mission).instances]
    port = 0
    for _ in range(50):
        with socket.socket() as a, socket.socket() as b:
            a.bind(("127.0.0.1", 0))
            port = a.getsockname()[1]
            try:
                b.bind(("127.0.0.1", port + 1))
            except OSError:
                continue
            break
    args = ["--scenario", "missions/scenarios/LabTour.no.scenario", "--groot2", str(port)]
    args += ["--groot2-address", "127.0.0.1", "--linger-ms", "4000"]
    proc = subprocess.Popen([robot, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    lines = []
    try:
        for line in proc.stdout:
            lines.append(line.rstrip("\n"))
            if line.startswith("lab_tour_robot: the Groot2 publisher stays up"):
                break
        alive = proc.poll() is None
        rest, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    lines += rest.splitlines()
    out = "\n".join(lines)
    if proc.returncode != 0:
        fail(f"exit status {proc.returncode}: {err}", out)
    listed = "lab_tour_robot: blackboards: " + ", ".join(f'"{n}"' for n in names)
    if listed not in lines:
        fail(f"no line `{listed}`", out)
    said = "lab_tour_robot: the Groot2 publisher stays up 4000 ms more so monitors show the end (--linger-ms)"
    if lines[-1] != said:
        fail(f"the last line is not `{said}`", out)
    if not alive:
        fail("the robot had exited when it said the publisher stays up", out)


CASES: dict[str, Callable[[str, Path], None]] = {
    "tour_yes": case_tour_yes,
    "tour_no": case_tour_no,
    "English": lambda r, p: check_full_tour(r, p, "English"),
    "isiZulu": lambda r, p: check_full_tour(r, p, "isiZulu"),
    "Kinyarwanda": lambda r, p: check_full_tour(r, p, "Kinyarwanda"),
    "scenario_yes": case_scenario_yes,
    "scenario_no": case_scenario_no,
    "bad_options": case_bad_options,
    "bad_kb": case_bad_kb,
    "max_ticks": case_max_ticks,
    "btlog": case_btlog,
    "monitors": case_monitors,
}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robot", required=True)
    ap.add_argument("--repo", required=True, type=Path)
    ap.add_argument("case", choices=sorted(CASES))
    args = ap.parse_args()
    os.chdir(args.repo)
    CASES[args.case](os.path.abspath(args.robot), args.repo.resolve())
    print(f"ok: {args.case}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
