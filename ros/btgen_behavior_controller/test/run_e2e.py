#!/usr/bin/env python3
"""End-to-end test of behaviorController under a real ROS master.

Starts roscore on a free port of 127.0.0.1, then for each scenario the
robot stub (robot_stub.py: every service and both topics, recording every
call) and the compiled behaviorController node, and checks the exact
sequence of service calls with their arguments against the sequence the
mission must produce for the knowledge base's tour, the node's exit status
and its log. Prints one line per scenario and `N passed, N failed`; exit
status 0 only when every scenario passed.

    run_e2e.py --node DEVEL/lib/btgen_behavior_controller/behaviorController \
                --kb data/environmentKnowledgeBaseInput.dat [--keep DIR] [-k NAME]

Run it with Debian's /usr/bin/python3 and the catkin workspace's setup
sourced (scripts/test_ros1.sh does both).
"""

import argparse
import json
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import xmlrpc.client

HERE = os.path.dirname(os.path.abspath(__file__))
STUB = os.path.join(HERE, "robot_stub.py")

SAY = "/textToSpeech/say_text"
MODE = "/overtAttention/set_mode"
ANIMATE = "/animateBehaviour/setActivation"
GESTURE = "/gestureExecution/perform_gesture"
POSE = "/robotLocalization/set_pose"
GOAL = "/robotNavigation/set_goal"
LANGUAGE = "/speechEvent/set_language"
SPEECH = "/speechEvent/set_enabled"
TABLET = "/tabletEvent/prompt_and_get_response"

# The node's utility phrases (src/phrases.cpp) in the languages the scenarios use.
PHRASES = {
    "English": {
        "1": "Please press Yes or No on my tablet.",
        "2": "Please follow me.",
        "3": "No problem. Maybe another time.",
        "4": "Hello! Welcome to the robotics lab. I am Pepper, your guide.",
        "5": "Would you like me to show you around the lab? Please say yes or no.",
        "7": "Goodbye, and thank you for your visit.",
    },
    "IsiZulu": {
        "1": "Sicela ucindezele u-Yebo noma u-Cha kuthebulethi yami.",
        "3": "Akunankinga. Mhlawumbe ngesinye isikhathi.",
        "4": "Sawubona! Wamukelekile elebhu yamarobhothi. NginguPepper, umhambisi wakho.",
    },
    "Kinyarwanda": {
        "2": "Nimunkurikire.",
        "4": "Muraho! Murakaza neza muri laboratwari ya robotikisi. Nitwa Pepper, ndi umuyobozi wanyu.",
        "5": "Mwifuza ko mbatembereza muri laboratwari? Muvuge yego cyangwa oya.",
        "7": "Murabeho, murakoze kudusura.",
    },
}


# ---- the knowledge base ------------------------------------------------------------------------
def read_kb(path):
    """{id: {key: value text}}, tour ids (the .dat format of data/README.md)."""
    locations, tour = {}, []
    with open(path, encoding="utf-8") as f:
        for line in f:
            parts = line.split(None, 2)
            if not parts or parts[0].startswith("#"):
                continue
            key = parts[0].lower()
            if key == "tourspecification":
                tour = [int(x) for x in line.split()[2:]]
                continue
            locations.setdefault(int(parts[1]), {})[key] = parts[2].rstrip("\n").strip() if len(parts) > 2 else ""
    return locations, tour


def numbers(text):
    return [float(x) for x in text.split()]


# ---- the expected calls ------------------------------------------------------------------------
class Expect:
    """The calls missions/labTour.xml makes, step by step, for one visitor."""

    def __init__(self, kb, language, asr):
        self.locations, self.tour = kb
        self.language, self.asr = language, asr
        self.calls = []

    def call(self, service, **request):
        self.calls.append((service, request))

    def say(self, text, language=None):
        self.call(SAY, message=text, language=language or self.language)

    def phrase(self, pid):
        self.say(PHRASES[self.language][pid])

    def mode(self, state):
        self.call(MODE, state=state, location_x=0.0, location_y=0.0, location_z=0.0)

    def goal(self, lid):
        x, y, theta = numbers(self.locations[lid]["robotlocationpose"])
        self.call(GOAL, goal_x=x, goal_y=y, goal_theta=theta)

    def gesture(self, kind, gid, xyz=(0.0, 0.0, 0.0)):
        self.call(
            GESTURE,
            gesture_type=kind,
            gesture_id=gid,
            gesture_duration=3000,
            bow_nod_angle=0,
            location_x=xyz[0],
            location_y=xyz[1],
            location_z=xyz[2],
        )

    def message(self, lid, which):
        loc = self.locations[lid]
        lang = {"English": "english", "IsiZulu": "isizulu", "Kinyarwanda": "kinyarwanda"}[self.language]
        text = loc.get(f"{which}gesturemessage{lang}", "")
        if not text or text.startswith("No message in"):
            self.say(loc[f"{which}gesturemessageenglish"], "English")
        else:
            self.say(text)

    def mission(self, answer, leave_at_goal=0):
        """The whole mission; returns its result."""
        home = self.tour[0]
        if self.asr:
            self.call(LANGUAGE, language=self.language)
        self.call(SPEECH, status="false")
        x, y, theta = numbers(self.locations[home]["robotlocationpose"])
        self.call(POSE, x=x, y=y, theta=theta)
        self.call(ANIMATE, state="enabled")
        self.mode("scanning")
        # EngageVisitor
        self.mode("social")
        self.call(ANIMATE, state="disabled")
        self.gesture("iconic", 1)
        self.phrase("4")
        self.mode("seeking")
        self.mode("social")
        # QueryVisitorResponse: heard at the first attempt, or pressed on the tablet
        if self.asr:
            self.phrase("5")
            self.call(SPEECH, status="true")
            self.call(SPEECH, status="false")
        else:
            self.phrase("1")
            self.call(TABLET, message="'Yes'|'No'")
        if answer == "no":
            self.phrase("3")
            return "SUCCESS"
        # VisitExhibits
        self.phrase("2")
        goals, present = 0, True
        for lid in self.tour:
            self.mode("scanning")
            if not present:  # IsVisitorPresent times out: exhibits left, go home
                self.mode("disabled")
                self.goal(home)
                return "FAILURE"
            self.mode("disabled")
            self.goal(lid)
            goals += 1
            if leave_at_goal and goals >= leave_at_goal:
                present = False
            self.mode("social")
            self.message(lid, "pre")
            target = numbers(self.locations[lid]["gesturetarget"])
            if any(target):
                self.gesture("deictic", 1, target)
            self.message(lid, "post")
        # EndTour
        self.gesture("iconic", 3)
        self.phrase("7")
        self.mode("disabled")
        self.goal(home)
        return "SUCCESS"


# ---- processes ---------------------------------------------------------------------------------
def free_port(pair=False):
    """A free TCP port of 127.0.0.1 (with pair: one whose successor is free too)."""
    while True:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if not pair or port >= 65535:
            return port
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port + 1))
                return port
            except OSError:
                continue


class Roscore:
    def __init__(self, workdir):
        self.port = free_port()
        self.uri = "http://127.0.0.1:%d" % self.port
        self.env = dict(
            os.environ,
            ROS_MASTER_URI=self.uri,
            ROS_IP="127.0.0.1",
            ROS_HOSTNAME="127.0.0.1",
            ROS_HOME=os.path.join(workdir, "ros_home"),
            ROS_LOG_DIR=os.path.join(workdir, "ros_log"),
            ROSCONSOLE_FORMAT="[${severity}] [${walltime}] ${message}",
            PYTHONUNBUFFERED="1",
        )
        self.log = open(os.path.join(workdir, "roscore.log"), "w")
        self.proc = subprocess.Popen(
            ["roscore", "-p", str(self.port)],
            env=self.env,
            stdout=self.log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        master = xmlrpc.client.ServerProxy(self.uri)
        deadline = time.time() + 30
        while True:
            try:
                master.getSystemState("/e2e_test")
                break
            except OSError:
                if time.time() > deadline or self.proc.poll() is not None:
                    raise RuntimeError("roscore did not start on port %d" % self.port)
                time.sleep(0.2)
        self.master = master

    def services(self):
        _, _, services = self.master.getSystemState("/e2e_test")[2]
        return {name for name, _ in services}

    def stop(self):
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        self.log.close()


def start(cmd, env, log_path):
    log = open(log_path, "w")
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    proc._log = log
    return proc


def stop(proc, sig=signal.SIGINT, timeout=10):
    if proc.poll() is None:
        os.killpg(proc.pid, sig)
        try:
            proc.wait(timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    proc._log.close()


ANSI = re.compile(r"\x1b\[[0-9;]*m")
LINE = re.compile(r"^\[\s*(\w+)\] \[(\d+\.\d+)\] (.*)$")


def node_log(path):
    """[(severity, time, message)] of the node's console output."""
    out = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for raw in f:
            m = LINE.match(ANSI.sub("", raw).rstrip("\n"))
            if m:
                out.append((m.group(1), float(m.group(2)), m.group(3)))
    return out


def read_calls(path):
    if not os.path.exists(path):
        return []
    with open(path, encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]


# ---- checks ------------------------------------------------------------------------------------
class Failure(Exception):
    pass


def same_value(a, b):
    if isinstance(a, float) or isinstance(b, float):
        return isinstance(a, (int, float)) and isinstance(b, (int, float)) and math.isclose(a, b, abs_tol=1e-6)
    return a == b


def check_calls(recorded, expected):
    got = [(c["service"], c["request"]) for c in recorded]
    for i, (g, e) in enumerate(zip(got, expected)):
        if g[0] != e[0] or set(g[1]) != set(e[1]) or not all(same_value(g[1][k], e[1][k]) for k in e[1]):
            raise Failure("call %d: got %s %s, expected %s %s" % (i + 1, g[0], g[1], e[0], e[1]))
    if len(got) != len(expected):
        extra = got[len(expected) :] or expected[len(got) :]
        raise Failure(
            "%d calls, expected %d; first %s: %s"
            % (len(got), len(expected), "extra" if len(got) > len(expected) else "missing", extra[0])
        )


def message_time(log, pattern):
    for _sev, t, msg in log:
        if re.search(pattern, msg):
            return t
    return None


class Scenario:
    def __init__(
        self,
        name,
        language="English",
        asr=True,
        answer="yes",
        say=None,
        tablet="yes",
        leave_at_goal=0,
        stub_args=(),
        check=None,
        launch=False,
        groot2=False,
    ):
        self.name, self.language, self.asr, self.answer = name, language, asr, answer
        self.launch = launch  # through behaviorController.launch (roslaunch) rather than the bare node
        self.groot2 = groot2  # with ~groot2_port set
        self.say, self.tablet, self.leave_at_goal = say, tablet, leave_at_goal
        self.stub_args, self.check = list(stub_args), check


def run_scenario(sc, core, node, kb_path, kb, workdir):
    d = os.path.join(workdir, sc.name)
    os.makedirs(d, exist_ok=True)
    calls_path = os.path.join(d, "calls.jsonl")
    stub_cmd = [sys.executable, STUB, "--log", calls_path, "--tablet", sc.tablet, "__name:=robot_stub"]
    if sc.say is not None:
        stub_cmd += ["--say", sc.say]
    if sc.leave_at_goal:
        stub_cmd += ["--leave-at-goal", str(sc.leave_at_goal)]
    stub_cmd += sc.stub_args
    stub = start(stub_cmd, core.env, os.path.join(d, "stub.log"))
    nodep = None
    try:
        # The node starts once the stub's services (all but the late ones) are registered.
        wanted = {SAY, MODE, ANIMATE, GESTURE, POSE, GOAL, LANGUAGE, SPEECH, TABLET}
        late = {a.rpartition(":")[0] for i, a in enumerate(sc.stub_args) if i and sc.stub_args[i - 1] == "--late"}
        deadline = time.time() + 20
        while not (wanted - late) <= core.services():
            if time.time() > deadline or stub.poll() is not None:
                raise Failure(
                    "the robot stub did not advertise its services (see {})".format(os.path.join(d, "stub.log"))
                )
            time.sleep(0.1)
        config = os.path.join(d, "kb.ini")
        with open(config, "w") as f:
            f.write(f"knowledgeBase {kb_path}\nverboseMode false\n")
        if sc.launch:
            node_cmd = [
                "roslaunch",
                "btgen_behavior_controller",
                "behaviorController.launch",
                "tick_rate:=50",
                "language:=" + sc.language,
                "asr_enabled:=" + ("true" if sc.asr else "false"),
                "knowledge_base_config:=" + config,
            ]
        else:
            node_cmd = [
                node,
                "__name:=behaviorController",
                "_tick_rate:=50",
                "_language:=" + sc.language,
                "_asr_enabled:=" + ("true" if sc.asr else "false"),
                "_wait_report_period:=1.0",
                "_knowledge_base_config:=" + config,
            ]
        groot2_port = None
        if sc.groot2:
            groot2_port = free_port(pair=True)
            node_cmd += ["_groot2_port:=%d" % groot2_port, "_groot2_address:=127.0.0.1"]
        nodep = start(node_cmd, core.env, os.path.join(d, "node.log"))
        ctx = {"dir": d, "stub": stub, "node": nodep, "calls": calls_path, "core": core}
        if groot2_port is not None:
            check_groot2(ctx, groot2_port)
        if sc.check is not None:
            sc.check(sc, ctx, kb)
        else:
            check_mission(sc, ctx, kb)
    finally:
        if nodep is not None:
            stop(nodep)
        stop(stub)


def expected_for(sc, kb):
    e = Expect(kb, sc.language, sc.asr)
    result = e.mission(sc.answer, sc.leave_at_goal)
    return e.calls, result


def check_mission(sc, ctx, kb, timeout=60):
    """The node runs the mission to its end by itself; exact calls, result, exit status."""
    try:
        status = ctx["node"].wait(timeout)
    except subprocess.TimeoutExpired:
        raise Failure("the node did not finish the mission within %d s" % timeout)
    time.sleep(0.3)  # anything still on its way to the stub
    log = node_log(os.path.join(ctx["dir"], "node.log"))
    calls, result = expected_for(sc, kb)
    check_calls(read_calls(ctx["calls"]), calls)
    ended = message_time(log, r"^behaviorController: mission (SUCCESS|FAILURE) after")
    if ended is None:
        raise Failure("the node did not report the end of the mission")
    got = [m for _, _, m in log if m.startswith("behaviorController: mission ")][0].split()[2]
    if got != result:
        raise Failure(f"mission {got}, expected {result}")
    if sc.launch:  # roslaunch's own status; the node is `required`, so its end ends the launch
        with open(os.path.join(ctx["dir"], "node.log"), encoding="utf-8", errors="replace") as f:
            text = f.read()
            if "process [behaviorController-1] has died" not in text or "process has finished cleanly" not in text:
                raise Failure("roslaunch did not report the node finishing cleanly")
    elif status != (0 if result == "SUCCESS" else 1):
        raise Failure("exit status %d after mission %s" % (status, result))
    late = [c for c in read_calls(ctx["calls"]) if c["t"] > ended]
    if late:
        raise Failure("%d calls after the mission ended, first %s" % (len(late), late[0]))
    ctx["log"] = log
    return log


GROOT2 = {"status": "not tried"}


def check_groot2(ctx, port):
    """With ~groot2_port: Groot2's two ports accept connections while the mission runs, or, in a
    build without btgen's Groot2 publisher, the node says it ignores the port."""
    path = os.path.join(ctx["dir"], "node.log")
    deadline = time.time() + 20
    while time.time() < deadline:
        msgs = [m for _, _, m in node_log(path)]
        if any("Groot2 publisher on ports %d and %d" % (port, port + 1) in m for m in msgs):
            for p in (port, port + 1):
                with socket.create_connection(("127.0.0.1", p), timeout=5):
                    pass
            GROOT2["status"] = "publisher on ports %d and %d" % (port, port + 1)
            return
        if any("~groot2_port %d ignored" % port in m for m in msgs):
            GROOT2["status"] = "not built in (the node ignored ~groot2_port, as it says)"
            return
        if ctx["node"].poll() is not None:
            break
        time.sleep(0.1)
    raise Failure("with ~groot2_port %d the node neither published nor said it ignores the port" % port)


def check_failing_services(sc, ctx, kb):
    log = check_mission(sc, ctx, kb)
    fallbacks = [m for sev, _, m in log if "HandleFallBack:" in m]
    expected = ['SayText "2" failed', "Navigate failed", 'SetAnimateBehavior "enabled" failed']
    for text in expected:
        if not any(text in m for m in fallbacks):
            raise Failure(f"no HandleFallBack report for {text}; reports: {fallbacks}")
    if len(fallbacks) != len(expected):
        raise Failure("%d HandleFallBack reports, expected %d: %s" % (len(fallbacks), len(expected), fallbacks))


def check_missing_service(sc, ctx, kb):
    log = check_mission(sc, ctx, kb)
    # The first reports may also name the topics (their publishers take a moment to connect).
    waits = [m for sev, _, m in log if sev == "WARN" and "waiting for" in m]
    if not waits or waits[-1] != "behaviorController: waiting for service " + TABLET:
        raise Failure(f"the node did not report waiting for {TABLET} alone: {waits}")
    if any("service" in m and TABLET not in m for m in waits) or any(m.count("service ") > 1 for m in waits):
        raise Failure(f"the node reported waiting for another service: {waits}")
    with open(os.path.join(ctx["dir"], "stub.log"), encoding="utf-8") as f:
        m = re.search(rf"advertised {re.escape(TABLET)} at (\d+\.\d+)", f.read())
    if m is None:
        raise Failure(f"the stub did not advertise {TABLET}")
    first = read_calls(ctx["calls"])[0]["t"]
    if first < float(m.group(1)):
        raise Failure(
            "the mission called {} before {} was advertised".format(read_calls(ctx["calls"])[0]["service"], TABLET)
        )
    if message_time(log, r"all 9 services and both topics are available") is None:
        raise Failure("the node did not report that everything is available")


def check_bad_parameter(sc, ctx, kb):
    """A bad parameter: reported, exit status 2, not a single call."""
    try:
        status = ctx["node"].wait(20)
    except subprocess.TimeoutExpired:
        raise Failure("the node did not stop on a bad ~language")
    if status != 2:
        raise Failure("exit status %d for a bad ~language, expected 2" % status)
    log = node_log(os.path.join(ctx["dir"], "node.log"))
    want = f'behaviorController: ~language "{sc.language}": expected English, IsiZulu or Kinyarwanda'
    if not any(sev == "FATAL" and m == want for sev, _, m in log):
        raise Failure("no FATAL report of the bad ~language in the node's log")
    time.sleep(0.3)
    if read_calls(ctx["calls"]):
        raise Failure("the node called the robot despite a bad parameter")


def check_sigint(sc, ctx, kb):
    """SIGINT while a navigation call blocks the worker: the node stops at once, cleanly."""
    deadline = time.time() + 40
    while not any(c["service"] == GOAL for c in read_calls(ctx["calls"])):
        if time.time() > deadline or ctx["node"].poll() is not None:
            raise Failure(f"the node never called {GOAL}")
        time.sleep(0.05)
    time.sleep(0.3)
    n_before = len(read_calls(ctx["calls"]))
    sent = time.time()
    os.killpg(ctx["node"].pid, signal.SIGINT)
    try:
        status = ctx["node"].wait(10)
    except subprocess.TimeoutExpired:
        raise Failure("the node did not stop within 10 s of SIGINT")
    took = time.time() - sent
    if status != 0:
        raise Failure("exit status %d after SIGINT" % status)
    if took > 5:
        raise Failure(f"the node took {took:.1f} s to stop after SIGINT")
    time.sleep(0.5)
    after = read_calls(ctx["calls"])[n_before:]
    if after:
        raise Failure("%d calls after SIGINT, first %s" % (len(after), after[0]))
    log = node_log(os.path.join(ctx["dir"], "node.log"))
    for text in ("interrupted: halting the mission", "behaviorController: shutting down"):
        if message_time(log, re.escape(text)) is None:
            raise Failure(f'no "{text}" in the node\'s log')
    expected, _ = expected_for(sc, kb)
    calls = read_calls(ctx["calls"])
    check_calls(calls, expected[: len(calls)])


SCENARIOS = [
    Scenario("yes", say="yes, I would love to", groot2=True),
    Scenario("no_tablet_isizulu_launch", language="IsiZulu", asr=False, answer="no", tablet="no", launch=True),
    Scenario(
        "failing_services",
        say="yes please",
        stub_args=["--error", SAY + ":3", "--fail", GOAL + ":3", "--fail", ANIMATE + ":1"],
        check=check_failing_services,
    ),
    Scenario("walks_away_kinyarwanda", language="Kinyarwanda", say="yego", answer="yes", leave_at_goal=3),
    Scenario(
        "missing_service",
        answer="no",
        say="no thanks",
        stub_args=["--late", TABLET + ":2.5"],
        check=check_missing_service,
    ),
    Scenario("sigint", say="yes", stub_args=["--slow", GOAL + ":30"], check=check_sigint),
    Scenario("bad_language", language="Klingon", check=check_bad_parameter),
]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--node", required=True, help="the behaviorController executable")
    p.add_argument("--kb", required=True, help="environmentKnowledgeBaseInput.dat")
    p.add_argument("--keep", help="keep the logs in this directory")
    p.add_argument("-k", dest="only", help="run only scenarios whose name contains this")
    args = p.parse_args()

    workdir = args.keep or tempfile.mkdtemp(prefix="btgen_ros1_")
    os.makedirs(workdir, exist_ok=True)
    kb_path = os.path.abspath(args.kb)
    kb = read_kb(kb_path)
    passed = failed = 0
    core = Roscore(workdir)
    try:
        for sc in SCENARIOS:
            if args.only and args.only not in sc.name:
                continue
            t0 = time.time()
            try:
                run_scenario(sc, core, os.path.abspath(args.node), kb_path, kb, workdir)
                passed += 1
                print("PASS %-26s %5.1f s" % (sc.name, time.time() - t0), flush=True)
            except Failure as e:
                failed += 1
                print(
                    "FAIL %-26s %5.1f s: %s (logs: %s)"
                    % (sc.name, time.time() - t0, e, os.path.join(workdir, sc.name)),
                    flush=True,
                )
    finally:
        core.stop()
        if not args.keep and failed == 0:
            shutil.rmtree(workdir, ignore_errors=True)
    print("ros1 e2e: Groot2: {}".format(GROOT2["status"]))
    print("ros1 e2e: %d passed, %d failed" % (passed, failed))
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
