"""A team's configuration and what the spawner derives from it (no rospy).

Provides: ``TeamConfig`` (frozen, validated; read from ``config/teams/<team>.yaml``), the
robots' world-frame start poses, and ``team_launch_xml`` (the roslaunch file that starts
the team's relay and every robot's nodes under its prefix). Start poses are written in the
team's own frame (own goal at -x), so both teams' files look alike; ``attack`` (1 or -1)
says which world goal the team attacks.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from xml.sax.saxutils import quoteattr

from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.naming import RobotName, RobotSelection, check_team_prefix
from nubot_common.policy import PolicyNet
from nubot_common.team_frame import TeamFrame
from nubot_control.plugins import resolve_spec, strategy_class
from nubot_control.policy_player import playable


@dataclass(frozen=True)
class TeamConfig:
    name: str  # display name, e.g. NuBot
    prefix: str  # robot name prefix and team namespace, e.g. nubot
    attack: int  # 1 attacks the goal at +x (world), -1 the goal at -x
    goalie: int  # AgentID of the goalie
    robots: tuple[Pose2D, ...]  # start poses, team frame [m], [rad]
    control_config: str = ""  # extra nubot_control YAML for this team (e.g. your own strategy's parameters)
    strategy: str = ""  # your own strategy class, "package.module:Class" or "file.py:Class" (nubot_control.plugins)
    policy: str = ""  # a trained policy file (.npz, make train) that the robots policy_robots play in open play
    policy_robots: tuple[int, ...] = ()  # AgentIDs of the robots playing ``policy``

    def __post_init__(self) -> None:
        try:
            check_team_prefix(self.prefix)
            TeamFrame(self.attack)
        except NubotCommonError as exc:
            raise ValueError(str(exc)) from None
        if not 1 <= len(self.robots) <= 5:
            raise ValueError(f"a team has 1 to 5 robots, got {len(self.robots)}")
        if not 1 <= self.goalie <= len(self.robots):
            raise ValueError(f"goalie must be one of the robots 1..{len(self.robots)}, got {self.goalie}")
        if bool(self.policy) != bool(self.policy_robots):
            raise ValueError("a policy needs the robots that play it (policy_robots: [2]), and policy_robots a policy")
        for agent in self.policy_robots:
            if not 1 <= agent <= len(self.robots):
                raise ValueError(f"policy_robots: {agent} is not one of the robots 1..{len(self.robots)}")

    def resolved(self, base: str | Path) -> TeamConfig:
        """This team with its strategy's file and its policy file made absolute against ``base`` (the YAML's
        folder), each checked to load: ``NubotControlError`` or ``PolicyError`` saying why not."""
        strategy = resolve_spec(self.strategy, base)
        if strategy:
            strategy_class(strategy)
        policy = ""
        if self.policy:
            path = Path(self.policy).expanduser()
            policy = str((path if path.is_absolute() else Path(base) / path).resolve())
            playable(PolicyNet.load(policy))
        return replace(self, strategy=strategy, policy=policy)

    def policy_of(self, agent_id: int) -> str:
        """The policy file robot ``agent_id`` plays ("" none)."""
        return self.policy if agent_id in self.policy_robots else ""

    def robot_names(self) -> list[str]:
        return [str(RobotName(self.prefix, k)) for k in range(1, len(self.robots) + 1)]

    def world_poses(self) -> list[tuple[str, float, float, float]]:
        """(name, x, y, yaw) of every robot in the world frame."""
        frame = TeamFrame(self.attack)
        poses = []
        for name, p in zip(self.robot_names(), self.robots):
            pose = frame.pose_to_world(p)
            poses.append((name, pose.x, pose.y, pose.theta))
        return poses

    def check_field(self, field: FieldGeometry) -> None:
        """Raise ``ValueError`` naming the first robot whose start pose is off ``field`` (lines plus border)."""
        for name, p in zip(self.robot_names(), self.robots):
            if not field.is_inside(p.x, p.y, field.border):
                raise ValueError(f"{name} starts at ({p.x:g}, {p.y:g}), off the {field.length:g} x {field.width:g} m "
                                 "field")


def team_launch_xml(team: TeamConfig, tracker: str = "", vision: RobotSelection | None = None,
                    processes: str = "one") -> str:
    """A roslaunch file starting the team's relay and each robot's world model and nubot_control (with
    ``tracker``, the motion layer's tracker, if given; else the configured one), in one node per robot or in
    two (``processes``: robot.launch's), and omni_vision for the robots in ``vision`` (the simulator gives them
    camera images instead of their percepts)."""
    if processes not in ("one", "two"):
        raise NubotCommonError(f"processes per robot: one or two, not {processes!r}")
    vision = vision if vision is not None else RobotSelection()
    lines = ["<launch>",
             f"  <!-- team {team.name}: generated by the spawner -->",
             f"  <node pkg=\"sim_visual\" type=\"sim_interface\" name=\"sim_interface\" ns={quoteattr(team.prefix)}"
             " clear_params=\"true\" output=\"log\">",
             f"    <param name=\"team\" value={quoteattr(team.prefix)}/>",
             f"    <param name=\"team_size\" value=\"{len(team.robots)}\"/>",
             "  </node>"]
    for agent, name in enumerate(team.robot_names(), 1):
        lines += ["  <include file=\"$(find nubot_control)/launch/robot.launch\">",
                  f"    <arg name=\"robot\" value={quoteattr(name)}/>",
                  f"    <arg name=\"goalie_id\" value=\"{team.goalie}\"/>",
                  f"    <arg name=\"goalie\" value=\"{'true' if agent == team.goalie else 'false'}\"/>",
                  f"    <arg name=\"config\" value={quoteattr(team.control_config)}/>",
                  f"    <arg name=\"tracker\" value={quoteattr(tracker)}/>",
                  f"    <arg name=\"strategy\" value={quoteattr(team.strategy)}/>",
                  f"    <arg name=\"policy\" value={quoteattr(team.policy_of(agent))}/>",
                  f"    <arg name=\"perception\" value=\"{'vision' if name in vision else 'truth'}\"/>",
                  f"    <arg name=\"processes\" value=\"{processes}\"/>",
                  "  </include>"]
    lines.append("</launch>")
    return "\n".join(lines) + "\n"
