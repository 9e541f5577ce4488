"""The referee node's ROS side: ``RefereeDesk`` (``coach4sim.referee_desk``) behind the coach's topics, the command
service and, in auto mode, the simulator's reports and services. It only adapts."""

from __future__ import annotations

import threading
import time

import rospy
from std_srvs.srv import Trigger

from coach4sim import conversions as conv
from coach4sim.params import RefereeNodeParams
from coach4sim.referee_desk import RefereeDesk, decision_line
from nubot_common import NubotCommonError
from nubot_common import conversions as shared
from nubot_common.msg import BallHolder, BallTouch, CoachInfo, GameState, GoalEvent, KickEvent, ModelStates, RefereeCall
from nubot_common.node_io import publisher
from nubot_common.srv import CoachCommand, CoachCommandResponse, SetModelState


class RefereeNode:
    def __init__(self, params: RefereeNodeParams):
        self.params = p = params
        self.desk = desk = RefereeDesk(p)
        self.wake = threading.Event()
        self.coach_pubs = {t.prefix: publisher(f"/{t.prefix}/receive_from_coach", CoachInfo) for t in p.teams}
        self.state_pub = publisher("/referee/state", GameState, latch=True)
        self.call_pub = publisher("/referee/foul", RefereeCall, queue_size=20)
        rospy.Service("/referee/command", CoachCommand, self.on_command)
        if p.auto:
            ns = p.sim_namespace
            rospy.Subscriber(f"{ns}/model_states", ModelStates, self.on_model_states, queue_size=1)
            rospy.Subscriber(f"{ns}/goal", GoalEvent, lambda m: desk.seen_goal(int(m.side), m.last_touch),
                             queue_size=10)
            rospy.Subscriber(f"{ns}/ball_touch", BallTouch, lambda m: desk.seen_touch(m.robot), queue_size=50)
            rospy.Subscriber(f"{ns}/kick", KickEvent, lambda m: desk.seen_kick(m.robot), queue_size=50)
            rospy.Subscriber(f"{ns}/ball_holder", BallHolder, lambda m: desk.seen_holder(m.robot), queue_size=50)
            self.set_model_state = rospy.ServiceProxy(f"{ns}/set_model_state", SetModelState)
            self.switch_ends = rospy.ServiceProxy(f"{ns}/switch_ends", Trigger)
        rospy.loginfo("referee: field %s, teams %s, %s, %d half(s) of %.0f s", p.world.name, ", ".join(
            f"{t.prefix} (attacks {'+x' if t.attack > 0 else '-x'})" for t in p.teams),
            "automatic" if p.auto else "manual commands only", p.halves, p.half_duration)

    def on_model_states(self, msg: ModelStates) -> None:
        ball, robots = conv.world_from_model_states(msg, self.params.world.ball_name)
        # The states' own sim time: the first states can arrive before this node's first /clock message, when
        # rospy's time is still 0 (a kickoff set up at 0 s ended at the next states, with no setup time).
        self.desk.seen_world(shared.seconds(msg.header.stamp) or rospy.get_time(), ball, robots)

    def on_command(self, req: CoachCommand._request_class) -> CoachCommandResponse:
        try:
            text = self.desk.command(req.team, req.command, rospy.get_time())
        except NubotCommonError as exc:
            rospy.logwarn("referee: command %r for team %r refused: %s", req.command, req.team, exc)
            return CoachCommandResponse(False, f"refused: {exc}")
        rospy.loginfo("referee: %s", text)
        self.wake.set()
        return CoachCommandResponse(True, text)

    def judge(self) -> None:
        decision = self.desk.judge()
        if decision is None:
            return
        for call in decision.calls:
            self.call_pub.publish(conv.referee_call_msg(call))
        if decision.switch_ends:
            failure = self.call(self.switch_ends)
            if failure:
                self.desk.keep_ends()
                rospy.logerr("referee: the simulator could not switch ends (%s); the teams keep their ends", failure)
        if decision.ball is not None:
            state = conv.ball_placement(self.params.world.ball_name, *decision.ball, self.params.ball_radius)
            failure = self.call(self.set_model_state, state)
            if failure:
                rospy.logwarn("referee: could not place the ball: %s", failure)
        rospy.loginfo(decision_line(decision))

    @staticmethod
    def call(service: rospy.ServiceProxy, *args: object) -> str:
        """Call the simulator's ``service``; why it failed, or empty."""
        try:
            response = service(*args)
        except (rospy.ServiceException, rospy.ROSException) as exc:
            return str(exc)
        if response.success:
            return ""
        return getattr(response, "message", "") or getattr(response, "status_message", "") or "refused"

    def run(self) -> None:
        next_tick = time.monotonic()
        while not rospy.is_shutdown():
            if self.params.auto:
                self.judge()
            now = rospy.get_time()
            modes, state = self.desk.modes(now)
            for team, mode, previous in modes:
                self.coach_pubs[team].publish(shared.coach_info_msg(mode, previous, now))
            wall = time.monotonic()
            if self.desk.state_due(state, wall):
                self.state_pub.publish(conv.game_state_msg(state, rospy.get_time()))
            next_tick = max(next_tick + self.params.republish_period, wall)
            self.wake.wait(max(0.0, next_tick - time.monotonic()))
            self.wake.clear()
