#!/usr/bin/env python3
"""A stand-in for the CSSR4Africa robot's nodes, for the end-to-end test.

Advertises every service the behaviorController calls and publishes both
topics it reads, with the cssr_system types; records every call with its
request fields, one JSON object a line, in --log. A small world model
decides the answers:

- the visitor arrives --arrive-after seconds after the first scanning mode
  is set, and walks away when set_goal is called for the --leave-at-goal-th
  time;
- /overtAttention/mode is published at 20 Hz: (mode, 2) while the mode finds
  what it looks for (a visitor when scanning, mutual gaze when seeking, the
  visitor when social), otherwise (scanning, 1), (seeking, 3), (social, 3),
  and (disabled, 0);
- 0.3 s after /speechEvent/set_enabled "true", /speechEvent/text carries
  --say (if given);
- /tabletEvent/prompt_and_get_response answers --tablet (yes: success true).

Faults: --fail SERVICE:N (the N-th call reports failure in its response),
--error SERVICE:N (the N-th call raises, so the caller's call() fails),
--late SERVICE:SECONDS (advertised only after that long), --slow
SERVICE:SECONDS (each call takes that long).

Run with Debian's /usr/bin/python3 and the catkin workspace's setup sourced.
"""

import argparse
import json
import threading
import time

import rospy
from cssr_system.msg import overtAttentionMode
from cssr_system.srv import (
    animateBehaviorSetActivation,
    animateBehaviorSetActivationResponse,
    gestureExecutionPerformGesture,
    gestureExecutionPerformGestureResponse,
    overtAttentionSetMode,
    overtAttentionSetModeResponse,
    robotLocalizationSetPose,
    robotLocalizationSetPoseResponse,
    robotNavigationSetGoal,
    robotNavigationSetGoalResponse,
    speechEventSetLanguage,
    speechEventSetLanguageResponse,
    speechEventSetStatus,
    speechEventSetStatusResponse,
    tabletEventPromptAndGetResponse,
    tabletEventPromptAndGetResponseResponse,
    textToSpeechSayText,
    textToSpeechSayTextResponse,
)
from std_msgs.msg import String


def parse_pairs(values, cast):
    out = {}
    for v in values or []:
        name, _, arg = v.rpartition(":")
        out.setdefault(name, []).append(cast(arg))
    return out


class Robot:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.log = open(args.log, "a", encoding="utf-8")
        self.counts = {}
        self.fail = parse_pairs(args.fail, int)
        self.error = parse_pairs(args.error, int)
        self.slow = {k: v[0] for k, v in parse_pairs(args.slow, float).items()}
        self.mode = "disabled"
        self.arrives_at = None  # time the visitor arrives
        self.present = False
        self.goals = 0
        self.speech_enabled = False
        self.mode_pub = rospy.Publisher("/overtAttention/mode", overtAttentionMode, queue_size=10)
        self.text_pub = rospy.Publisher("/speechEvent/text", String, queue_size=10)

    # ---- recording and faults ----------------------------------------------------------
    def record(self, service, req):
        with self.lock:
            n = self.counts.get(service, 0) + 1
            self.counts[service] = n
            fields = {f: getattr(req, f) for f in req.__slots__}
            self.log.write(json.dumps({"t": time.time(), "service": service, "request": fields}) + "\n")
            self.log.flush()
        if service in self.slow:
            time.sleep(self.slow[service])
        if n in self.error.get(service, []):
            raise rospy.ServiceException("robot_stub: injected error in call %d of %s" % (n, service))
        return n not in self.fail.get(service, [])

    # ---- services ------------------------------------------------------------------------
    def animate(self, req):
        ok = self.record("/animateBehaviour/setActivation", req)
        return animateBehaviorSetActivationResponse("1" if ok else "0")

    def gesture(self, req):
        return gestureExecutionPerformGestureResponse(1 if self.record("/gestureExecution/perform_gesture", req) else 0)

    def set_mode(self, req):
        ok = self.record("/overtAttention/set_mode", req)
        with self.lock:
            if ok:
                self.mode = req.state
            if ok and req.state == "scanning" and self.arrives_at is None:
                self.arrives_at = time.time() + self.args.arrive_after
        return overtAttentionSetModeResponse(1 if ok else 0)

    def set_pose(self, req):
        return robotLocalizationSetPoseResponse(self.record("/robotLocalization/set_pose", req))

    def set_goal(self, req):
        ok = self.record("/robotNavigation/set_goal", req)
        with self.lock:
            self.goals += 1
            if self.args.leave_at_goal and self.goals >= self.args.leave_at_goal:
                self.present = False
                self.arrives_at = float("inf")
        return robotNavigationSetGoalResponse(1 if ok else 0)

    def set_language(self, req):
        return speechEventSetLanguageResponse(1 if self.record("/speechEvent/set_language", req) else 0)

    def set_enabled(self, req):
        ok = self.record("/speechEvent/set_enabled", req)
        with self.lock:
            self.speech_enabled = ok and req.status == "true"
        if self.speech_enabled and self.args.say is not None:
            threading.Timer(0.3, self.say_answer).start()
        return speechEventSetStatusResponse(1 if ok else 0)

    def tablet(self, req):
        ok = self.record("/tabletEvent/prompt_and_get_response", req)
        return tabletEventPromptAndGetResponseResponse(ok and self.args.tablet == "yes")

    def say_text(self, req):
        return textToSpeechSayTextResponse(self.record("/textToSpeech/say_text", req))

    # ---- topics --------------------------------------------------------------------------
    def say_answer(self):
        with self.lock:
            enabled = self.speech_enabled
        if enabled and not rospy.is_shutdown():
            self.text_pub.publish(String(self.args.say))

    def publish_mode(self, _event):
        with self.lock:
            if self.arrives_at is not None and time.time() >= self.arrives_at:
                self.present = True
            mode, present = self.mode, self.present
        value = {"scanning": 2 if present else 1, "seeking": 2 if present else 3, "social": 2 if present else 3}.get(
            mode, 0
        )
        self.mode_pub.publish(overtAttentionMode(mode, value))


SERVICES = {
    "/animateBehaviour/setActivation": (animateBehaviorSetActivation, "animate"),
    "/gestureExecution/perform_gesture": (gestureExecutionPerformGesture, "gesture"),
    "/overtAttention/set_mode": (overtAttentionSetMode, "set_mode"),
    "/robotLocalization/set_pose": (robotLocalizationSetPose, "set_pose"),
    "/robotNavigation/set_goal": (robotNavigationSetGoal, "set_goal"),
    "/speechEvent/set_language": (speechEventSetLanguage, "set_language"),
    "/speechEvent/set_enabled": (speechEventSetStatus, "set_enabled"),
    "/tabletEvent/prompt_and_get_response": (tabletEventPromptAndGetResponse, "tablet"),
    "/textToSpeech/say_text": (textToSpeechSayText, "say_text"),
}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--log", required=True)
    p.add_argument("--arrive-after", type=float, default=0.5)
    p.add_argument("--leave-at-goal", type=int, default=0)
    p.add_argument("--say", default=None)
    p.add_argument("--tablet", choices=("yes", "no"), default="yes")
    p.add_argument("--fail", action="append")
    p.add_argument("--error", action="append")
    p.add_argument("--late", action="append")
    p.add_argument("--slow", action="append")
    args = p.parse_args(rospy.myargv()[1:])

    rospy.init_node("robot_stub")
    robot = Robot(args)
    late = {k: v[0] for k, v in parse_pairs(args.late, float).items()}
    for name, (srv_type, method) in SERVICES.items():
        if name not in late:
            rospy.Service(name, srv_type, getattr(robot, method))
    rospy.Timer(rospy.Duration(0.05), robot.publish_mode)
    start = time.time()
    for name, delay in sorted(late.items(), key=lambda kv: kv[1]):
        rospy.sleep(max(0.0, start + delay - time.time()))
        srv_type, method = SERVICES[name]
        rospy.Service(name, srv_type, getattr(robot, method))
        print(f"robot_stub: advertised {name} at {time.time():.6f}", flush=True)
    print("robot_stub: ready", flush=True)
    rospy.spin()


if __name__ == "__main__":
    main()
