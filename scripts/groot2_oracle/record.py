"""RECORDER, not a test: records the real BehaviorTree.CPP Groot2Publisher's answers.

Builds scripts/groot2_oracle/recorder.cpp against an oracle install of BehaviorTree.CPP
(the tag's own src/loggers/groot2_publisher.cpp, taken from a git mirror, is compiled
next to it, since the oracle is built without ZeroMQ), runs tests/groot2/<stem>.xml with
its .scenario, sends each step of STEPS[stem] (a Groot2 request, or a tick) and writes
what came back to tests/groot2/<stem>.hooks410.json: for a request its reply (the error
text, the bare header, or HOOKS_DUMP's JSON sorted by (uid, position)), for a tick its
result, then STATUS and GET_TRANSITIONS (UID, status) pairs.

    python scripts/groot2_oracle/record.py ORACLE_PREFIX MIRROR_GIT_DIR [TAG]
    e.g. python scripts/groot2_oracle/record.py ORACLE_410_PREFIX \\
             BehaviorTree.CPP/.git 4.10.0

tests/python/test_groot2.py replays the same steps on the executor compiled with
`--btcpp 4.10.0` and compares (it needs neither the oracle nor this script).
"""

from __future__ import annotations

import json
import socket
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

import zmq

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "tests" / "groot2"


def hook(uid: int, status: str = "FAILURE", *, pos: int = 1, mode: int = 1, once: bool = False, enabled: bool = True):
    return {"enabled": enabled, "uid": uid, "mode": mode, "once": once, "desired_status": status, "position": pos}


# UIDs: monitored 4 ready (Condition), 5 move (Action), 10/17 Move, 12/19 IsReady, 13 Parallel,
# 6 RetryUntilSuccessful, 11 Inverter. builtins: 12 Work under RunOnce, 16 the Inner SubTree,
# 21 Check with _skipIf, 6 Script with _onSuccess, 9 ForceSuccess.
STEPS: dict[str, list] = {
    "monitored": [
        "tick",  # move RUNNING
        ("I", hook(5, "FAILURE")),  # POST: move ticks (onRunning: SUCCESS), then is forced FAILURE
        ("D",),
        "tick",
        ("I", hook(5, "SUCCESS", pos=0)),  # a PRE hook beside the POST one on the same node
        ("D",),
        "tick",  # PRE forces SUCCESS (not ticked), POST then forces FAILURE
        ("R", {"uid": 5, "position": 1}),  # the POST one
        ("R", {"uid": 5, "position": 1}),  # gone
        ("D",),
        "tick",
        ("R", {"uid": 5, "position": 0}),
        ("I", [hook(4, "SUCCESS", once=True), hook(10, "RUNNING"), hook(12, "SUCCESS"), hook(13, "FAILURE")]),
        ("D",),
        "tick",
        ("D",),  # the `once` POST hook of 4 is gone
        ("U", {"uid": 10, "position": 1, "desired_status": "FAILURE", "remove_when_done": False}),
        ("D",),
        "tick",
        ("U", {"uid": 99, "position": 1, "desired_status": "FAILURE", "remove_when_done": False}),
        ("U", {"uid": 4, "position": 1, "desired_status": "FAILURE", "remove_when_done": False}),
        ("I", hook(6, "SUCCESS", enabled=False)),
        "tick",
        ("X",),
        ("D",),
        "tick",
        ("I", hook(19, "FAILURE")),  # re-inserted: enabled again
        ("D",),
        ("A",),
        ("D",),
        "tick",
        "tick",
    ],
    "builtins": [
        ("I", [hook(12, "SUCCESS", once=True), hook(21, "SUCCESS")]),
        "tick",  # Work under RunOnce: RUNNING, forced SUCCESS after its tick
        ("D",),
        "tick",
        ("I", hook(16, "FAILURE")),  # the Inner SubTree, forced FAILURE while its Work runs
        "tick",
        ("R", {"uid": 16, "position": 1}),
        "tick",
        "tick",  # 21: its _skipIf decides SKIPPED, then its POST hook gives SUCCESS
        "tick",
        ("I", [hook(9, "FAILURE"), hook(6, "FAILURE"), hook(16, "RUNNING", pos=0)]),
        "tick",  # 6 Script: its _onSuccess runs, then FAILURE; 9 ForceSuccess: FAILURE
        ("D",),
        ("A",),
        "tick",
        "tick",
        "tick",
    ],
    # error handling: replies only (no ticks needed)
    "errors": [
        ("I", b"{not json"),
        ("I", {"uid": 5, "position": 1}),  # fields missing
        ("I", {"enabled": True, "uid": "5", "mode": 1, "once": False, "desired_status": "FAILURE", "position": 1}),
        ("I", [hook(5, "FAILURE"), {"uid": 10, "position": 1}]),  # the first is inserted, then an error
        ("D",),
        ("I", hook(4, "BOGUS")),
        ("I", hook(999, "FAILURE")),  # no such node
        ("D",),
        ("R", {"uid": 5}),
        ("R", b"[]"),
        ("U", {"uid": 5, "position": 1}),
        ("U", {"uid": 5, "position": 1, "desired_status": "SUCCESS", "remove_when_done": 1}),
        ("R", {"uid": 5, "position": 1}),
        ("I", hook(5, "FAILURE", pos=2)),
        ("D",),
        ("A",),
    ],
}
MISSION = {"monitored": "monitored", "builtins": "builtins", "errors": "monitored"}


def free_port_pair() -> int:
    for _ in range(50):
        with socket.socket() as a:
            a.bind(("127.0.0.1", 0))
            port = a.getsockname()[1]
            if port >= 65534:
                continue
            with socket.socket() as b:
                try:
                    b.bind(("127.0.0.1", port + 1))
                except OSError:
                    continue
            return port
    raise RuntimeError("no two consecutive free ports")


def payload(step) -> list[bytes]:
    if len(step) < 2:
        return []
    return [step[1] if isinstance(step[1], bytes) else json.dumps(step[1]).encode()]


def answer(reply: list[bytes]) -> list:
    if reply[0] == b"error":
        return ["error", reply[1].decode()]
    if len(reply) == 1:
        return ["ok"]
    return ["ok", sorted(json.loads(reply[1]), key=lambda h: (h["uid"], h["position"]))]


def run(exe: Path, stem: str) -> list[dict]:
    port = free_port_pair()
    mission = MISSION[stem]
    proc = subprocess.Popen(
        [str(exe), str(CASES / f"{mission}.xml"), str(CASES / f"{mission}.scenario"), str(port)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout.readline().strip() == "ready"
    ctx = zmq.Context()
    sock = ctx.socket(zmq.REQ)
    sock.setsockopt(zmq.RCVTIMEO, 3000)
    sock.setsockopt(zmq.LINGER, 0)
    sock.connect(f"tcp://127.0.0.1:{port}")

    def request(kind: str, *extra: bytes) -> list[bytes]:
        sock.send_multipart([struct.pack("<BBI", 2, ord(kind), 77), *extra])
        return sock.recv_multipart()

    def pairs(buf: bytes, width: int, at: int) -> list[list[int]]:
        return [
            [int.from_bytes(buf[i + at : i + at + 2], "little"), buf[i + at + 2]] for i in range(0, len(buf), width)
        ]

    out = []
    request("r", b"start")
    for step in STEPS[stem]:
        if step == "tick":
            proc.stdin.write("tick\n")
            proc.stdin.flush()
            result = proc.stdout.readline().split()[1]
            status = pairs(request("S")[1], 3, 0)
            trans = pairs(request("t")[1], 9, 6)
            out.append({"tick": result, "status": status, "transitions": trans})
        else:
            data = payload(step)
            reply = answer(request(step[0], *data))
            out.append({"request": step[0], "data": data[0].decode() if data else None, "reply": reply})
    proc.stdin.write("quit\n")
    proc.stdin.flush()
    assert proc.wait(timeout=10) == 0
    sock.close()
    ctx.term()
    return out


def main() -> int:
    prefix, mirror = Path(sys.argv[1]), sys.argv[2]
    tag = sys.argv[3] if len(sys.argv) > 3 else "4.10.0"
    with tempfile.TemporaryDirectory() as tmp:
        t = Path(tmp)
        for name in ("src/loggers/groot2_publisher.cpp", "3rdparty/cppzmq/zmq_addon.hpp"):
            show = ["git", "--git-dir", mirror, "show", f"{tag}:{name}"]
            blob = subprocess.run(show, check=True, capture_output=True)
            (t / Path(name).name).write_bytes(blob.stdout)
        exe = t / "recorder"
        subprocess.run(
            ["g++", "-std=c++17", "-O1", "-o", str(exe), str(Path(__file__).with_name("recorder.cpp")),
             str(t / "groot2_publisher.cpp"), f"-I{t}", f"-I{prefix / 'include'}", f"-L{prefix / 'lib'}",
             f"-Wl,-rpath,{prefix / 'lib'}", "-lbehaviortree_cpp", "-lzmq", "-pthread"],
            check=True,
        )  # fmt: skip
        for stem in STEPS:
            steps = run(exe, stem)
            fixture = {
                "recorded_with": f"BehaviorTree.CPP {tag} Groot2Publisher (scripts/groot2_oracle/record.py)",
                "mission": f"{MISSION[stem]}.xml",
                "steps": steps,
            }
            (CASES / f"{stem}.hooks410.json").write_text(json.dumps(fixture, indent=1) + "\n")
            print(f"{stem}: {len(steps)} steps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
