"""The team link node's ROS side: a ``TeamLink`` (LCM) between the robot's or the coach's topics and the team's
multicast group, with ``OwnState`` and ``DropReport`` (``nubot_comm.reports``) deciding what to send and log."""

from __future__ import annotations

import time

import rospy

from nubot_comm import NubotCommError
from nubot_comm import conversions as conv
from nubot_comm.link import TeamLink
from nubot_comm.params import TeamLinkParams
from nubot_comm.reports import DropReport, OwnState
from nubot_comm.signing import load_key
from nubot_common.msg import (
    CoachInfo,
    StrategyInfo,
    TeamLinkStatus,
    TeamMessage,
    TeamMessages,
    simulation_strategy,
)
from nubot_common.node_io import publisher, timer


class TeamLinkNode:
    def __init__(self, params: TeamLinkParams):
        """Raises ``NubotCommError`` when the link cannot be opened."""
        self.params, team = params, params.team_name
        key = load_key(params.key_file) if params.key_file else None
        self.link = TeamLink.open(params.lcm_url, team, params.link_agent, team_size=params.team_size,
                                  max_age=params.max_age, max_clock_skew=params.max_clock_skew, key=key)
        self.own: OwnState[TeamMessage, StrategyInfo] = OwnState(params.max_age)
        self.drops = DropReport(self.link.stats(), params.log_period)
        self.status_pub = publisher("~status", TeamLinkStatus)
        if params.coach:
            rospy.Subscriber("receive_from_coach", CoachInfo, self.on_coach_command, queue_size=10)
            what = f"the coach of team {team}, from {rospy.resolve_name('receive_from_coach')}"
        else:
            robot = params.robot
            rospy.Subscriber(f"/{robot}/worldmodel/teammessage", TeamMessage,
                             lambda msg: self.own.message(rospy.get_time(), msg), queue_size=1)
            rospy.Subscriber(f"/{robot}/nubotcontrol/strategy", StrategyInfo,
                             lambda msg: self.own.strategy(rospy.get_time(), msg), queue_size=1)
            self.team_pub = publisher(f"/{team}/simulation_interface/teammates", TeamMessages)
            self.strategy_pub = publisher(f"/{team}/simulation_interface/strategy", simulation_strategy)
            self.coach_pub = publisher(f"/{team}/receive_from_coach", CoachInfo)
            self.timer = timer(1.0 / params.rate, self.on_timer)
            what = f"{robot} (AgentID {params.agent}) of team {team}"
        self.status_timer = timer(params.status_period, self.on_status)
        self.link.start()
        rospy.on_shutdown(self.link.close)
        rospy.loginfo("team_link: %s on %s (channels %s, %s), %s", what, params.lcm_url, self.link.team_channel,
                      self.link.coach_channel, f"signed with {params.key_file}" if key else "unsigned (no key_file)")

    def on_coach_command(self, msg: CoachInfo) -> None:
        try:
            self.link.send_coach(conv.coach_packet(msg))
        except NubotCommError as exc:
            rospy.logwarn_throttle(5.0, "team_link: coach command %s", exc)

    def on_timer(self, _event: object) -> None:
        own = self.own.fresh(rospy.get_time())
        if own is not None:
            try:
                self.link.send_team(conv.team_packet(*own))
            except NubotCommError as exc:
                rospy.logwarn_throttle(5.0, "team_link: own packet %s", exc)
        packets = self.link.teammates()
        out = TeamMessages(messages=[conv.team_message(p) for p in packets])
        out.header.stamp = rospy.Time.now()
        self.team_pub.publish(out)
        self.strategy_pub.publish(simulation_strategy(strategy_msgs=[conv.strategy_info(p) for p in packets]))
        coach = self.link.take_coach()
        if coach is not None:
            self.coach_pub.publish(conv.coach_info(coach))

    def on_status(self, _event: object) -> None:
        stats = self.link.stats()
        status = TeamLinkStatus(team=self.link.team, agent_id=self.link.agent_id, sent=stats.sent, heard=stats.heard,
                                accepted=stats.accepted, echoes=stats.echoes, dropped=stats.total_dropped,
                                drop_reasons=[r.value for r in stats.dropped],
                                drop_counts=list(stats.dropped.values()),
                                members_heard=[p.agent_id for p in self.link.teammates()])
        status.header.stamp = rospy.Time.now()
        self.status_pub.publish(status)
        line = self.drops.due(stats, time.monotonic())
        if line is not None:
            text, fault = line
            (rospy.logwarn if fault else rospy.loginfo)(text)
