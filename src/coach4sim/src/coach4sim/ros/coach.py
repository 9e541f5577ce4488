"""The coach's ROS side: a command sent once, the console, and a robot's world model watched in the terminal
(``coach4sim.console`` parses and draws; this module only talks to the topics and the referee's service)."""

from __future__ import annotations

import threading
import time

import rospy

from coach4sim import conversions as conv
from coach4sim.console import (
    COMMAND_SERVICE,
    STATE_TOPIC,
    CoachArgs,
    CoachUsageError,
    coach_topic,
    describe_sent,
    help_text,
    parse_console_line,
    render_score,
    render_watch,
    worldmodel_topic,
)
from coach4sim.ros.sender import CommandSender
from nubot_common import NubotCommonError
from nubot_common.msg import GameState, WorldModelInfo
from nubot_common.world_description import WORLD_NAMESPACE, WorldDescription, world_from_params


def send_once(args: CoachArgs) -> int:
    mode = args.mode
    if mode is None:
        raise CoachUsageError("send: give a command")  # parse_args gives every send one
    sender = CommandSender(args.team, args.period)
    accepted, text = sender.send(mode)
    if sender.via_referee:
        print(text)
        return 0 if accepted else 1
    print(describe_sent(f"{mode.name} ({mode.value})", coach_topic(args.team), args.period,
                        args.duration), flush=True)
    sender.publish_for(args.duration)
    print(f"sent {text}")
    return 0


def console(args: CoachArgs) -> int:
    sender = CommandSender(args.team, args.period)
    print(help_text())
    if sender.via_referee:
        print(f"commands for {args.team} go through the referee ({COMMAND_SERVICE})")
    else:
        print(describe_sent("each command", coach_topic(args.team), args.period, None))
        threading.Thread(target=sender.publish_for, args=(None,), daemon=True).start()
    while not rospy.is_shutdown():
        try:
            line = input(f"coach {args.team}> ")
        except EOFError:
            break
        entry = parse_console_line(line)
        if entry.kind == "quit":
            break
        if entry.kind == "help":
            print(help_text())
        elif entry.kind == "error":
            print(entry.message)
        elif entry.mode is not None:
            accepted, text = sender.send(entry.mode)
            print(text if accepted else f"not sent: {text}")
    return 0


def watch(args: CoachArgs) -> int:
    try:  # the field of the match; a world model watched without one is drawn on the chapter's
        field = world_from_params(rospy.get_param(WORLD_NAMESPACE, None)).field
    except NubotCommonError:
        field = WorldDescription().field
    latest: dict[str, object] = {}
    rospy.Subscriber(worldmodel_topic(args.robot), WorldModelInfo, lambda m: latest.__setitem__("wm", m),
                     queue_size=1)
    rospy.Subscriber(STATE_TOPIC, GameState, lambda m: latest.__setitem__("state", m), queue_size=1)
    shown = 0
    while not rospy.is_shutdown() and (args.count == 0 or shown < args.count):
        time.sleep(1.0)
        wm, state = latest.get("wm"), latest.get("state")
        if wm is None:
            score = conv.score_view(state) if state is not None else None
            print(f"waiting for {worldmodel_topic(args.robot)}  {render_score(score)}")
        else:
            print(render_watch(conv.watch_view(args.robot, wm, state), field))
        print(flush=True)
        shown += 1
    return 0
