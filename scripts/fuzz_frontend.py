#!/usr/bin/env python3
"""Front-end fuzzing: mutated and random missions and knowledge bases (reliability).

    scripts/fuzz_frontend.py [--iterations N] [--seed S] [--target mission|kb|config|models|types|
                             enums|enums_file|trace|btlog|all]
                             [--cli K] [--keep DIR] [--time-limit S]

Inputs are mutations of a seed corpus (the conformance cases, missions/,
tests/bad_missions/, random missions of btgen.tools.fuzzgen; data/ and
tests/bad_kb/ for knowledge bases and configurations), from byte flips to
structure-aware edits (node names, attribute values, nesting, entities,
includes, BOM, encodings). Each input goes in-process through what the
command line does with it:

- missions: `btgen validate` (load_mission), and for a valid one `btgen xsd`,
  `btgen compile` (rendered in memory) and `btgen run` (a few ticks);
- knowledge bases: `btgen lint-kb` with and without a configuration;
- models files (`--models`), `--type` and `--enum` strings, `--enums` files;
- the readers of `btgen graph`: status traces and .btlog files.

The oracle: every input ends in success or in diagnostics of the form
`path:line:col: error|warning: message` with the path as given — never
another exception (a traceback, an internal error), never more than
--time-limit seconds of CPU (ITIMER_PROF: the process's own work, so a
loaded machine does not make a slow input out of a fast one), nor
WALL_FACTOR times that in wall-clock time (ITIMER_REAL: an input that blocks
without computing), never unbounded memory (RLIMIT_AS, set here). `--cli K` also
sends every K-th input through the real `btgen` executable and checks its exit status (0 or 1) and stderr.

A finding is written to --keep (default build/fuzz-frontend) with the
traceback; the exit status is 1 when there is any.
"""

from __future__ import annotations

import argparse
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path
from typing import Callable, Optional

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "generator"))
CASES = ROOT / "tests" / "conformance" / "btcpp-4.6.2"  # the recorded cases the repository holds
MEMORY_LIMIT = 2 * 1024**3

from btgen.diagnostics import UserError
from btgen.lang.catalogue import BUILTINS
from btgen.tools.fuzzgen import HOSTILE_NAMES

DIAG_RE = r"^{path}:[1-9][0-9]*:[1-9][0-9]*: (error|warning|note): .+$"


class Hang(Exception):
    pass


WALL_FACTOR = 6  # the wall-clock backstop, as a multiple of the CPU limit


def _alarm(signum, frame):  # pragma: no cover - only on a hang
    raise Hang(signum)


# ------------------------------------------------------------------ corpus
def mission_corpus() -> list[bytes]:
    from btgen.tools.fuzzgen import random_mission

    files = (
        sorted(CASES.glob("*.xml"))
        + sorted((ROOT / "missions").glob("*.xml"))
        + sorted((ROOT / "tests" / "bad_missions").glob("*.xml"))
        + sorted((ROOT / "tests" / "regressions").glob("*.xml"))
    )
    corpus = [f.read_bytes() for f in files]
    corpus += [random_mission(s, f).encode("utf-8") for s in range(8) for f in ("control", "full")]
    return corpus


def kb_corpus() -> list[bytes]:
    files = sorted((ROOT / "data").glob("*.dat")) + sorted((ROOT / "tests" / "bad_kb").glob("*.dat"))
    return [f.read_bytes() for f in files]


def config_corpus() -> list[bytes]:
    files = sorted((ROOT / "data").glob("*.ini")) + sorted((ROOT / "tests" / "bad_kb").glob("*.ini"))
    return [f.read_bytes() for f in files]


def models_corpus(missions: list[bytes]) -> list[bytes]:
    """Models files (--models): each mission's TreeNodesModel alone under <root>."""
    out = []
    for m in missions:
        found = re.search(rb"<TreeNodesModel>.*?</TreeNodesModel>", m, re.S)
        if found:
            out.append(b'<root BTCPP_format="4">\n' + found.group(0) + b"\n</root>\n")
    return out


TYPE_CORPUS = [
    b"Pose2D=nav::Pose2D@nav/pose2d.hpp",
    b"Ms=::std::chrono::duration<long long, std::milli>@<chrono>",
    b"W=wchar_t@<cwchar>",
    b"L=std::less<>@<functional>",
    b"A=std::array<unsigned char, 3>@<array>",
    b"U=unsigned long long int@<cstdint>",
]
ENUM_CORPUS = [b"Color=RED,GREEN,BLUE", b"Size = SMALL=5, MEDIUM ,LARGE", b"M=A=-1,B,C=0x10,D", b"E=X=0b101,Y=0o17"]
# (tokens of C++ types, enum declarations and file names that once slipped through)
STRING_TOKENS = [
    b"::",
    b"<",
    b">",
    b"<>",
    b",",
    b"*",
    b"&",
    b"@",
    b"=",
    b" ",
    b"\t",
    b"\n",
    b"long",
    b"unsigned",
    b"signed",
    b"double",
    b"char",
    b"wchar_t",
    b"char32_t",
    b"int",
    b"NULL",
    b"EOF",
    b"NDEBUG",
    b"BTGEN_X",
    b"std",
    b"btgen",
    b"const",
    b"struct",
    b"_X",
    b"__y",
    b"??/",
    b"//",
    b'"',
    b"\\",
    b"\xd9\xa5",
    b"\xef\xbc\x91",
    b"1_000",
    b"0x",
    b"-",
    b"+",
    b"9" * 40,
    b"9" * 4400,  # (past int()'s 4,300 digits)
    b"\xc2\xb2",
    b";",
    b"#",
    b"\xef\xbb\xbf",
    b"\x00",
    b"\xff",
]


def trace_corpus() -> tuple[list[bytes], list[bytes]]:
    """A status trace and a .btlog of tests/groot2/monitored.xml, as `btgen graph` reads them."""
    import struct

    from btgen.frontend.loader import load_mission
    from btgen.interp.engine import run_trace
    from btgen.interp.scenario import parse_scenario
    from btgen.ir.treexml import groot2_tree

    mission = load_mission(str(GRAPH_MISSION))
    lines: list[str] = []
    run_trace(mission, parse_scenario(str(GRAPH_MISSION.with_suffix(".scenario"))), lines.append)
    trace = ("\n".join(lines) + "\n").encode()
    xml = groot2_tree(mission).xml.encode()
    records = [(1, 1), (2, 1), (2, 2), (3, 1), (4, 3), (5, 1)]
    body = b"".join(struct.pack("<Q", 10 * i)[:6] + struct.pack("<HB", uid, st) for i, (uid, st) in enumerate(records))
    btlog = b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + body
    return [trace], [btlog]


GRAPH_MISSION = ROOT / "tests" / "groot2" / "monitored.xml"
HOSTILE_NUMBERS = [b"\xc2\xb2", b"\xd9\xa1", b"\xef\xbc\x91\xef\xbc\x92", b"9" * 4400, b"-1", b"1_000", b"0x10", b""]


def mutate_numbers(data: bytes, rng: random.Random) -> bytes:
    """A number of the input (a UID, a tick, a value) becomes one that str.isdigit or int()
    takes differently from an ASCII reader: Unicode digits, 4,400 digits, signs, separators."""
    spans = [m.span() for m in re.finditer(rb"[0-9]+", data)]
    if not spans:
        return data
    a, b = rng.choice(spans)
    return data[:a] + rng.choice(HOSTILE_NUMBERS) + data[b:]


# ------------------------------------------------------------------ mutations
TOKENS = [
    b"<",
    b">",
    b"/>",
    b"</",
    b"&",
    b"&amp;",
    b"&#0;",
    b"&#x110000;",
    b"&#9;",
    b"&lt;",
    b"&bogus;",
    b'"',
    b"'",
    b"=",
    b"{",
    b"}",
    b"{=}",
    b"{@x}",
    b"@",
    b";",
    b":=",
    b"..",
    b"\x00",
    b"\xff",
    b"\xc3",
    b"\xe2\x82",
    b"\r",
    b"\r\n",
    b"\t",
    b" ",
    b"\n",
    b"<!-- c -->",
    b"<![CDATA[x]]>",
    b"<?pi x?>",
    b"<!DOCTYPE r>",
    b'<!ENTITY e "x">',
    b"\xef\xbb\xbf",
    b"-1",
    b"0",
    b"99999999999999999999",
    b"1e308",
    b"nan",
    b"-0",
    b"true",
    b"FAILURE",
    b"SKIPPED",
    b"RUNNING",
    b"IV. Act",
    b"name",
    b"ID",
    b"_skipIf",
    b"_autoremap",
    b'<include path="missing.xml"/>',
    b'<include path="."/>',
    b'<include path="/dev/null"/>',
    b'<include ros_pkg="p" path="x"/>',
    b'<SubTree ID="Main"/>',
    b"main_tree_to_execute",
    b'BTCPP_format="3"',
    b"<TreeNodesModel>",
    b"</TreeNodesModel>",
    b'<BehaviorTree ID="X">',
    b"</BehaviorTree>",
    b'<MetadataFields><Metadata k="v"/></MetadataFields>',
    b"<MetadataFields>",
    b'editable="true"',
    b'_uid="7"',
    b'_fullpath="A::3"',
    b"\xf0\x9f\x98\x80",
    b"\xe2\x80\xae",
    b"x" * 300,
    b"\\",
    b"%s%n",
    b"${x}",
]
NODE_NAMES = [n.encode() for n in BUILTINS] + [
    b"Action",
    b"Condition",
    b"Control",
    b"Decorator",
    b"SubTree",
    b"root",
    b"BehaviorTree",
    b"TreeNodesModel",
    b"input_port",
    b"output_port",
    b"inout_port",
    b"include",
    b"MetadataFields",
    b"Metadata",
    b"Bogus",
]
ATTR_VALUES = [
    b"",
    b" ",
    b"-1",
    b"0",
    b"1",
    b"2",
    b"65536",
    b"4294967296",
    b"-2147483649",
    b"1.5",
    b"0x10",
    b"abc",
    b"{key}",
    b"{}",
    b"{=}",
    b"{ key }",
    b"{@key}",
    b"a;b;c",
    b";;",
    b"x := 1",
    b"x == 1",
    b"x = = 1",
    b"((((((((((1))))))))))",
    b"(" * 300 + b"1" + b")" * 300,
    b"a &lt; b",
    b"'unterminated",
    b"1 ? 2 : 3",
    b"SUCCESS",
    b"FAILURE",
    b"SKIPPED",
    b"RUNNING",
    b"IDLE",
    b"true",
    b"false",
    b"nan",
    b"inf",
    b"\xc3\xa9",
    b"&#10;",
    b"&quot;",
    b"{a}{b}",
]
# Hostile names: C++ keywords, macros, the runtime's and the generated code's own names
# and IDs with white space, quotes, backslashes or a trigraph, as tokens, attribute values, keys.
HOSTILE = [n.encode() for n in HOSTILE_NAMES] + [b"a\nb", b"a b", b'a"b', b"a\\b", b"ends ??/", b"bt_node"]
TOKENS += HOSTILE
NODE_NAMES += [n.encode() for n in HOSTILE_NAMES[:12]]
ATTR_VALUES += HOSTILE + [b"{" + n + b"}" for n in HOSTILE[:20]] + [b"'a' .. 1e300", b"1 | 2.5", b"~1e30"]
KB_TOKENS = [
    b"robotLocationPose",
    b"robotLocationDescription",
    b"gestureTarget",
    b"tour",
    b"culturalKnowledge",
    b"preGestureMessageEnglish",
    b"postGestureMessageIsiZulu",
    b"knowledgeBase",
    b"verboseMode",
    b"-1",
    b"0",
    b"00",
    b"1e9",
    b"nan",
    b"inf",
    b"99999999999999999999",
    b"1.5",
    b"-0.0",
    b",",
    b"#",
    b"\t",
    b"  ",
    b"\r",
    b"\n",
    b"\x00",
    b"\xff",
    b"\xc3",
    b"x" * 400,
    b"No message in isiZulu",
    b"=",
    b"environmentKnowledgeBaseInput.dat",
    b"/dev/zero",
    b"..",
    b"true",
    b"false",
]


def mutate(
    data: bytes,
    rng: random.Random,
    corpus: list[bytes],
    tokens: list[bytes],
    structured: Callable[[bytes, random.Random], bytes],
) -> bytes:
    """One to a few random edits of `data`."""
    for _ in range(rng.choice((1, 1, 1, 1, 2, 3))):
        op = rng.randrange(16)  # 8..15: format-aware, which keeps more inputs valid
        n = len(data)
        pos = rng.randint(0, n)
        if op == 0 and n:  # flip a bit
            i = rng.randrange(n)
            data = data[:i] + bytes([data[i] ^ (1 << rng.randrange(8))]) + data[i + 1 :]
        elif op == 1:  # insert a token
            data = data[:pos] + rng.choice(tokens) + data[pos:]
        elif op == 2 and n:  # delete a span
            end = min(n, pos + rng.choice((1, 1, 2, 8, 64, 512)))
            data = data[:pos] + data[end:]
        elif op == 3 and n:  # duplicate a span
            end = min(n, pos + rng.choice((1, 16, 128, 2048)))
            data = data[:end] + data[pos:end] + data[end:]
        elif op == 4:  # splice with another input
            other = rng.choice(corpus)
            j = rng.randint(0, len(other))
            data = data[:pos] + other[j : j + rng.choice((16, 256, 4096))] + data[pos:]
        elif op == 5 and n:  # truncate
            data = data[:pos]
        elif op == 6:  # lines: delete, duplicate or swap
            lines = data.split(b"\n")
            if len(lines) > 1:
                i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
                what = rng.randrange(3)
                if what == 0:
                    del lines[i]
                elif what == 1:
                    lines.insert(i, lines[j])
                else:
                    lines[i], lines[j] = lines[j], lines[i]
                data = b"\n".join(lines)
        elif op == 7 and n:  # replace a byte by an interesting one
            i = rng.randrange(n)
            data = (
                data[:i]
                + bytes([rng.choice((0, 9, 10, 13, 32, 34, 38, 39, 60, 62, 0x7F, 0x80, 0xC0, 0xFF))])
                + data[i + 1 :]
            )
        else:  # format-aware edits
            data = structured(data, rng)
    return data


_ATTR_RE = re.compile(rb'([A-Za-z_:][-A-Za-z0-9_:.]*)\s*=\s*"([^"]*)"')
_TAG_RE = re.compile(rb"<(/?)([A-Za-z_:][-A-Za-z0-9_:.]*)")


def mutate_mission_structure(data: bytes, rng: random.Random) -> bytes:
    attrs = list(_ATTR_RE.finditer(data))
    tags = list(_TAG_RE.finditer(data))
    op = rng.randrange(6)
    if op == 0 and attrs:  # change an attribute value
        m = rng.choice(attrs)
        return data[: m.start(2)] + rng.choice(ATTR_VALUES) + data[m.end(2) :]
    if op == 1 and attrs:  # rename an attribute
        m = rng.choice(attrs)
        name = rng.choice(
            [
                b"name",
                b"ID",
                b"_skipIf",
                b"_while",
                b"_post",
                b"_autoremap",
                b"num_cycles",
                b"msec",
                b"code",
                b"if",
                b"else",
                b"value",
                b"output_key",
                b"queue",
                b"port",
                b"x y",
                b"1bad",
                b"_uid",
                b"_fullpath",
                b"_description",
                b"editable",
            ]
        )
        return data[: m.start(1)] + name + data[m.end(1) :]
    if op == 2 and tags:  # rename an element (open or close tag)
        m = rng.choice(tags)
        return data[: m.start(2)] + rng.choice(NODE_NAMES) + data[m.end(2) :]
    if op == 3 and tags:  # wrap the rest of the file in deep nesting
        m = rng.choice(tags)
        depth = rng.choice((10, 100, 255, 256, 257, 600, 5000))
        return data[: m.start()] + b"<Inverter>" * depth + data[m.start() :]
    if op == 4 and tags:  # add an attribute to a start tag
        m = rng.choice([t for t in tags if not t.group(1)] or tags)
        return (
            data[: m.end()]
            + b" "
            + rng.choice([b"name", b"ID", b"_skipIf", b"_onHalted", b"extra", b"name"])
            + b'="'
            + rng.choice(ATTR_VALUES)
            + b'"'
            + data[m.end() :]
        )
    if op == 5:  # many siblings
        i = data.find(b"<AlwaysSuccess")
        if i < 0:
            i = data.find(b"<Sequence>")
        if i >= 0:
            return data[:i] + b"<AlwaysSuccess/>" * rng.choice((100, 5000)) + data[i:]
    return data


def mutate_kb_structure(data: bytes, rng: random.Random) -> bytes:
    lines = data.split(b"\n")
    if not lines:
        return data
    i = rng.randrange(len(lines))
    words = lines[i].split()
    op = rng.randrange(4)
    if op == 0 and words:  # replace a word
        words[rng.randrange(len(words))] = rng.choice(KB_TOKENS)
    elif op == 1:  # add a word
        words.insert(rng.randint(0, len(words)), rng.choice(KB_TOKENS))
    elif op == 2 and words:  # drop a word
        del words[rng.randrange(len(words))]
    else:  # repeat the line many times
        lines[i:i] = [lines[i]] * rng.choice((2, 50, 1000))
        return b"\n".join(lines)
    lines[i] = b" ".join(words)
    return b"\n".join(lines)


# ------------------------------------------------------------------ oracles
def _check_diagnostics(text: str, path: str, what: str) -> Optional[str]:
    pattern = re.compile(DIAG_RE.format(path=re.escape(path)))
    for line in text.splitlines():
        if not pattern.match(line):
            return f"{what}: a diagnostic not of the form `{path}:line:col: severity: message`: {line!r}"
    return None


def check_mission(path: str) -> tuple[Optional[str], bool]:
    """(None when every stage ends in success or user diagnostics, else what went wrong;
    whether the mission was valid)."""
    from btgen.backend_cpp.emit import render
    from btgen.compiler import mission_stem
    from btgen.frontend.loader import load_mission
    from btgen.frontend.xsd import mission_xsd
    from btgen.interp.engine import run_trace
    from btgen.interp.scenario import parse_scenario_text
    from btgen.ir.lower import lower

    try:
        mission = load_mission(path)
    except UserError as e:
        return (
            _check_diagnostics("\n".join(str(d) for d in e.diagnostics), path, "validate")
            or (None if e.diagnostics else "validate: UserError without diagnostics")
        ), False
    problem = _check_diagnostics("\n".join(str(d) for d in mission.warnings), path, "validate warnings")
    if problem:
        return problem, True
    mission_xsd(mission)
    try:
        render(lower(mission), mission_stem(path), os.path.dirname(path) or ".")
    except UserError as e:
        problem = _check_diagnostics("\n".join(str(d) for d in e.diagnostics), path, "compile")
        if problem:
            return problem, True
    try:
        run_trace(mission, parse_scenario_text("ticks 3\nclock_ms 10\n", "s.scenario"), lambda s: None)
    except UserError as e:
        return _check_diagnostics("\n".join(str(d) for d in e.diagnostics), path, "run"), True
    return None, True


def check_kb(path: str, config: Optional[str]) -> Optional[str]:
    from btgen.kb.lint import lint_kb

    diags = lint_kb(path, config_path=config)
    for d in diags:
        if d.loc.path not in (path, config):
            return f"lint-kb: a diagnostic about another file: {d}"
        if d.loc.line < 1 or d.loc.col < 1 or not d.message:
            return f"lint-kb: a malformed diagnostic: {d!r}"
    return None


def check_cli(args: list[str], path: str, timeout: float) -> Optional[str]:
    """The real executable: exit 0 or 1, every stderr line a diagnostic about `path` (or the config)."""
    exe = shutil.which("btgen", path=str(ROOT / ".venv" / "bin")) or "btgen"
    try:
        proc = subprocess.run([exe, *args], capture_output=True, timeout=timeout, check=False, preexec_fn=_limit_memory)
    except subprocess.TimeoutExpired:
        return f"btgen {' '.join(args)}: no answer within {timeout} s"
    err = proc.stderr.decode("utf-8", "replace")
    if proc.returncode not in (0, 1):
        return f"btgen {' '.join(args)}: exit {proc.returncode}: {err[-2000:]}"
    paths = [a for a in args if not a.startswith("-") and a not in ("validate", "lint-kb", "-q")]
    alt = "|".join(re.escape(p) for p in paths)
    pattern = re.compile(DIAG_RE.replace("{path}", f"(?:{alt})"))
    for line in err.splitlines():
        if not pattern.match(line):
            return f"btgen {' '.join(args)}: stderr line is no diagnostic: {line!r}"
    return None


def check_models(path: str) -> Optional[str]:
    """A models file (--models) beside a mission that uses none of it: validate's diagnostics."""
    from btgen.frontend.loader import load_mission

    mission = str(ROOT / "tests" / "groot2" / "monitored.xml")
    try:
        load_mission(mission, models=[path])
    except UserError as e:
        for d in e.diagnostics:
            if d.loc.path not in (path, mission, "--models"):
                return f"--models: a diagnostic about another file: {d}"
        return _check_diagnostics("\n".join(str(d) for d in e.diagnostics if d.loc.path == path), path, "--models")
    return None


def check_string_option(option: str, text: str) -> Optional[str]:
    """One --type or --enum string: accepted, or diagnostics at `--type:1:C` / `--enum:1:C`."""
    from btgen.frontend import enums, usertypes

    try:
        if option == "--type":
            for t in usertypes.load([text]):
                # (what is accepted is a plain C++ spelling: ASCII, one line, no macro start)
                if not t.cpp_type.isascii() or "\n" in t.cpp_type or "??" in t.header or "//" in t.header:
                    return f"--type accepted {text!r} as {t.cpp_type!r}@{t.header!r}"
        else:
            for name, value in enums.load([text]):
                if not (-(2**31) <= value < 2**31) or not name.isascii():
                    return f"--enum accepted {text!r} as {name}={value}"
    except UserError as e:
        return _check_diagnostics("\n".join(str(d) for d in e.diagnostics), option, option)
    return None


def check_enums_file(path: str) -> Optional[str]:
    from btgen.frontend import enums

    try:
        enums.load(files=[path])
    except UserError as e:
        return _check_diagnostics("\n".join(str(d) for d in e.diagnostics), path, "--enums")
    return None


def check_graph_input(kind: str, path: str) -> Optional[str]:
    """`btgen graph --trace/--btlog` over a mutated trace or log of tests/groot2/monitored.xml."""
    from btgen.frontend.loader import load_mission
    from btgen.tools.graph import btlog_statuses, trace_statuses, walk

    nodes, _ = walk(load_mission(str(GRAPH_MISSION)))
    try:
        if kind == "trace":
            trace_statuses(path, None, nodes)
        else:
            btlog_statuses(path, None, nodes)
    except UserError as e:
        return _check_diagnostics("\n".join(str(d) for d in e.diagnostics), path, f"graph --{kind}")
    return None


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


# ------------------------------------------------------------------ the loop
def fuzz(
    iterations: int,
    seed: int,
    target: str = "all",
    cli_every: int = 0,
    keep: Optional[Path] = None,
    time_limit: float = 10.0,
    log=lambda s: None,
) -> dict:
    """Run the fuzzer; returns counts and findings (never raises on a finding)."""
    rng = random.Random(seed)
    keep = (keep or ROOT / "build" / "fuzz-frontend").resolve()
    missions, kbs, configs = mission_corpus(), kb_corpus(), config_corpus()
    models = models_corpus(missions)
    traces: list[bytes] = []
    btlogs: list[bytes] = []
    stats = {
        "missions": 0,
        "kbs": 0,
        "configs": 0,
        "models": 0,
        "types": 0,
        "enums": 0,
        "enums_files": 0,
        "traces": 0,
        "btlogs": 0,
        "cli": 0,
        "valid_missions": 0,
        "findings": [],
    }
    kinds = (
        "mission",
        "mission",
        "mission",
        "kb",
        "config",
        "models",
        "types",
        "enums",
        "enums_file",
        "trace",
        "btlog",
    )
    work = Path(tempfile.mkdtemp(prefix="fuzz-frontend."))
    old = signal.signal(signal.SIGALRM, _alarm)
    old_prof = signal.signal(signal.SIGPROF, _alarm)
    old_limit = sys.getrecursionlimit()
    try:
        # A neighbour file for `<include path="..."/>` mutations.
        (work / "missing.xml").write_bytes(missions[0])
        for it in range(iterations):
            kind = target if target != "all" else rng.choice(kinds)
            text_option = None
            if kind == "models":
                data = mutate(rng.choice(models), rng, models, TOKENS + NODE_NAMES, mutate_mission_structure)
                path = str(work / "palette.xml")
            elif kind in ("types", "enums"):
                corpus = TYPE_CORPUS if kind == "types" else ENUM_CORPUS
                data = mutate(rng.choice(corpus), rng, corpus, STRING_TOKENS, mutate_numbers)
                path = str(work / "unused")
                text_option = data.decode("utf-8", "replace")
            elif kind == "enums_file":
                data = b"\n".join(
                    mutate(rng.choice(ENUM_CORPUS), rng, ENUM_CORPUS, STRING_TOKENS, mutate_numbers)
                    for _ in range(rng.randint(1, 4))
                )
                path = str(work / "e.enums")
            elif kind in ("trace", "btlog"):
                if not traces:  # (built on first use: it loads and runs a mission)
                    traces, btlogs = trace_corpus()
                corpus = traces if kind == "trace" else btlogs
                data = mutate(rng.choice(corpus), rng, corpus, STRING_TOKENS + TOKENS, mutate_numbers)
                path = str(work / ("t.trace" if kind == "trace" else "l.btlog"))
            elif kind == "mission":
                data = mutate(rng.choice(missions), rng, missions, TOKENS + NODE_NAMES, mutate_mission_structure)
                path = str(work / f"m{it % 7}.xml")
            elif kind == "kb":
                data = mutate(rng.choice(kbs), rng, kbs, KB_TOKENS, mutate_kb_structure)
                path = str(work / "kb.dat")
            else:
                data = mutate(rng.choice(configs), rng, configs, KB_TOKENS, mutate_kb_structure)
                path = str(work / "kb.ini")
                (work / "environmentKnowledgeBaseInput.dat").write_bytes(kbs[0])
            Path(path).write_bytes(data)
            problem = None
            signal.setitimer(signal.ITIMER_PROF, time_limit)
            signal.setitimer(signal.ITIMER_REAL, time_limit * WALL_FACTOR)
            try:
                if kind == "mission":
                    stats["missions"] += 1
                    problem, valid = check_mission(path)
                    stats["valid_missions"] += valid
                elif kind == "kb":
                    stats["kbs"] += 1
                    problem = check_kb(path, None)
                elif kind == "models":
                    stats["models"] += 1
                    problem = check_models(path)
                elif kind in ("types", "enums"):
                    stats[kind] += 1
                    problem = check_string_option("--type" if kind == "types" else "--enum", text_option or "")
                elif kind == "enums_file":
                    stats["enums_files"] += 1
                    problem = check_enums_file(path)
                elif kind in ("trace", "btlog"):
                    stats[kind + "s"] += 1
                    problem = check_graph_input(kind, path)
                else:
                    stats["configs"] += 1
                    problem = check_kb(str(work / "environmentKnowledgeBaseInput.dat"), path)
            except Hang as e:
                problem = (
                    f"no answer within {time_limit} s of CPU"
                    if e.args[0] == signal.SIGPROF
                    else f"no answer within {time_limit * WALL_FACTOR} s of wall-clock time"
                )
            except MemoryError:
                problem = f"ran out of memory (limit {MEMORY_LIMIT >> 20} MiB)"
            except BaseException as e:
                if isinstance(e, KeyboardInterrupt):
                    raise
                problem = "exception:\n" + "".join(traceback.format_exception(type(e), e, e.__traceback__)[-6:])
            finally:
                signal.setitimer(signal.ITIMER_PROF, 0)
                signal.setitimer(signal.ITIMER_REAL, 0)
                sys.setrecursionlimit(old_limit)
            if problem is None and cli_every and it % cli_every == 0 and kind in ("mission", "kb", "config"):
                stats["cli"] += 1
                args = {
                    "mission": ["validate", "-q", path],
                    "kb": ["lint-kb", path],
                    "config": ["lint-kb", str(work / "environmentKnowledgeBaseInput.dat"), "--config", path],
                }[kind]
                problem = check_cli(args, path, max(30.0, time_limit * 3))
            if problem is not None:
                keep.mkdir(parents=True, exist_ok=True)
                ext = {"mission": ".xml", "kb": ".dat", "config": ".ini", "models": ".models.xml"}.get(kind, f".{kind}")
                saved = keep / f"finding_{seed}_{it}{ext}"
                saved.write_bytes(data)
                saved.with_suffix(ext + ".txt").write_text(problem, encoding="utf-8")
                stats["findings"].append((str(saved), problem.splitlines()[-1] if problem else ""))
                log(f"FINDING {saved}: {problem}")
    finally:
        signal.signal(signal.SIGALRM, old)
        signal.signal(signal.SIGPROF, old_prof)
        shutil.rmtree(work, ignore_errors=True)
    return stats


def main(argv: Optional[list[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--iterations", type=int, default=2000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument(
        "--target",
        choices=("mission", "kb", "config", "models", "types", "enums", "enums_file", "trace", "btlog", "all"),
        default="all",
    )
    p.add_argument("--cli", type=int, default=0, metavar="K", help="also run every K-th input through `btgen`")
    p.add_argument("--keep", type=Path, default=None)
    p.add_argument("--time-limit", type=float, default=10.0, help="CPU seconds per input (default 10)")
    args = p.parse_args(argv)
    _limit_memory()
    start = time.monotonic()
    stats = fuzz(
        args.iterations,
        args.seed,
        args.target,
        args.cli,
        args.keep,
        args.time_limit,
        log=lambda s: print(s, file=sys.stderr, flush=True),
    )
    print(
        f"fuzz-frontend: seed {args.seed}: {stats['missions']} missions ({stats['valid_missions']} valid), "
        f"{stats['kbs']} knowledge bases, {stats['configs']} configurations, {stats['models']} models files, "
        f"{stats['types']} --type, {stats['enums']} --enum, {stats['enums_files']} --enums files, "
        f"{stats['traces']} traces, {stats['btlogs']} .btlogs, {stats['cli']} through the CLI, "
        f"{len(stats['findings'])} findings, {time.monotonic() - start:.1f} s"
    )
    for saved, last in stats["findings"]:
        print(f"  {saved}: {last}")
    return 1 if stats["findings"] else 0


if __name__ == "__main__":
    sys.exit(main())
