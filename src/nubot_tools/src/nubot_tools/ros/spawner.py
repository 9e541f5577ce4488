"""Spawn one team into the running simulator and start its robots' software under their prefixes.

The chapter's "bash script": it reads the match's world description from /world and refuses
start poses off its field, then for each robot of the team configuration it calls
/sim_visual/spawn_model (model name = prefix + AgentID, the same name prefixes every topic
and service of that robot), then runs one roslaunch with the team's relay (sim_interface)
and each robot's world model and nubot_control (one node, or two with ``--processes two``). It
keeps running until interrupted, then stops the team's nodes and (unless --keep-models) deletes its models.

    python scripts/spawn_team.py src/nubot_control/config/teams/nubot.yaml
"""

from __future__ import annotations

import argparse
import math
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import rospy
from geometry_msgs.msg import Pose

from nubot_common import NubotCommonError
from nubot_common.geometry import yaw_to_quaternion
from nubot_common.naming import RobotSelection, parse_agent_ids
from nubot_common.params import load_yaml
from nubot_common.processes import ending_with_this_process
from nubot_common.srv import DeleteModel, SpawnModel
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from nubot_control.team_config import TeamConfig, team_launch_xml


def spawn_models(team: TeamConfig) -> None:
    rospy.wait_for_service("/sim_visual/spawn_model", timeout=60.0)
    spawn = rospy.ServiceProxy("/sim_visual/spawn_model", SpawnModel)
    for name, x, y, yaw in team.world_poses():
        pose = Pose()
        pose.position.x, pose.position.y = x, y
        _, _, pose.orientation.z, pose.orientation.w = yaw_to_quaternion(yaw)
        result = spawn(name, pose, team.attack)
        if not result.success:
            raise RuntimeError(f"could not spawn {name}: {result.status_message}")
        print(f"[spawn] {name} at ({x:.1f}, {y:.1f}) facing {math.degrees(yaw):.0f} deg", flush=True)


def delete_models(team: TeamConfig) -> None:
    try:
        delete = rospy.ServiceProxy("/sim_visual/delete_model", DeleteModel)
        for name in team.robot_names():
            delete(name)
    except (rospy.ServiceException, rospy.ROSException) as exc:
        print(f"[spawn] could not delete the models: {exc}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("team_config", type=Path, help="team YAML (see src/nubot_control/config/teams/)")
    parser.add_argument("--keep-models", action="store_true", help="leave the models in the world on exit")
    parser.add_argument("--tracker", choices=("mpc", "baseline"), default="",
                        help="the motion layer's tracker for every robot (default: as configured)")
    parser.add_argument("--vision", default="",
                        help="robots that see through the simulated omni camera (omni_vision): all or nubot1,nubot2")
    parser.add_argument("--policy", default="", help="a trained policy file (make train) for --policy-robots, "
                        "instead of the team's")
    parser.add_argument("--policy-robots", default="2", help="AgentIDs playing --policy, e.g. 2 or 2,3 (default 2)")
    parser.add_argument("--processes", choices=("one", "two"), default="one",
                        help="each robot's world model and nubot_control in one node (/ROBOT/robot) or in two "
                             "(/ROBOT/world_model, /ROBOT/nubot_control); default one")
    args = parser.parse_args(argv)
    try:
        vision = RobotSelection.parse(args.vision)
        team = load_yaml(TeamConfig, args.team_config)
        if args.policy:
            team = replace(team, policy=str(Path(args.policy).resolve()),
                           policy_robots=parse_agent_ids(args.policy_robots))
        team = team.resolved(args.team_config.parent)  # refuse a strategy or policy the robots could not load
    except (OSError, NubotCommonError, ValueError) as exc:
        print(f"spawn_team: {exc}", file=sys.stderr)
        return 2

    # No rospy node: the spawner only reads a parameter and calls services, which need none, and a node would
    # take every /clock message of the match (each costs an idle rospy node about 0.2 ms of CPU).
    try:
        world = world_from_params(rospy.get_param(WORLD_NAMESPACE, None))
        team.check_field(world.field)
    except (NubotCommonError, ValueError) as exc:
        print(f"spawn_team: {exc}", file=sys.stderr)
        return 2
    spawn_models(team)
    with tempfile.TemporaryDirectory(prefix=f"team_{team.prefix}_") as folder:  # gone with the team
        launch_file = Path(folder) / "team.launch"
        launch_file.write_text(team_launch_xml(team, args.tracker, vision, args.processes))
        child = subprocess.Popen(["roslaunch", "--skip-log-check", str(launch_file)], start_new_session=True,
                                 preexec_fn=ending_with_this_process())
        print(f"[spawn] team {team.name}: {len(team.robots)} robots' nodes started (pid {child.pid})", flush=True)
        _supervise(child)
    if not args.keep_models:
        delete_models(team)
    return 0


def _supervise(child: subprocess.Popen) -> None:
    """Wait for the team's roslaunch to end, or for SIGINT or SIGTERM, then end it (SIGINT, SIGKILL after 15 s)."""
    stopping = False

    def stop(*_args: object) -> None:
        nonlocal stopping
        stopping = True

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    while not stopping and child.poll() is None:
        time.sleep(0.2)
    if child.poll() is None:
        child.send_signal(signal.SIGINT)
        try:
            child.wait(timeout=15)
        except subprocess.TimeoutExpired:
            child.kill()


if __name__ == "__main__":
    sys.exit(main())
