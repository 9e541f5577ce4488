"""Typed configuration of a robot's control (read once from ``config/nubot_control.yaml``).

All values SI: metres, seconds, m/s, rad/s. The field and the robot's size are not here: they come
from the match's world description (``nubot_common.world_description``), the same for every node.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field as dc_field

from nubot_common.params import require_non_negative, require_positive

TRACKERS = ("mpc", "baseline")


@dataclass(frozen=True)
class MotionParams:
    tracker: str = "mpc"  # "mpc": B-spline path + Laguerre MPC; "baseline": sub-target go-to
    max_speed: float = 3.0  # [m/s]
    max_accel: float = 3.0  # [m/s^2]
    max_lateral_accel: float = 2.0  # on curves: speed <= sqrt(a / curvature) [m/s^2], below max_accel
    max_rot_speed: float = 4.0  # [rad/s]
    max_rot_accel: float = 8.0  # [rad/s^2]
    dribble_speed: float = 1.5  # while holding the ball, forwards [m/s]
    dribble_back_speed: float = 0.5  # ... backwards [m/s]
    dribble_side_speed: float = 0.5  # ... sideways [m/s]
    dribble_rot_speed: float = 2.5  # ... turning [rad/s]
    dribble_accel: float = 1.5  # while holding the ball [m/s^2]
    replan_tolerance: float = 0.3  # replan from the reference while this close to it, else from the robot [m]
    # A plan is kept (not replanned) while it still holds: its acceleration within the robot's limit, the robot
    # within keep_plan_deviation of its reference, every waypoint within keep_plan_goal_shift +
    # keep_plan_goal_share * (robot to waypoint) of where it was when planned, the same speed and acceleration
    # limits, no obstacle inside the clearance of what remains of the path, the plan younger than
    # keep_plan_time. keep_plan_time 0 replans every cycle.
    keep_plan_deviation: float = 0.1  # [m]
    keep_plan_goal_shift: float = 0.05  # [m]
    keep_plan_goal_share: float = 0.1  # [m per m of distance still to go]
    keep_plan_time: float = 0.5  # [s]
    # The plan uses this share of the speed and acceleration limits: below 1 it leaves the MPC room to catch up with
    # its reference, at the price of pace (0.92 reached a ball 5 m away 0.2 s after the baseline tracker did)
    plan_share: float = 1.0
    planning_range: float = 8.0  # obstacles farther than this are left out of the plan [m]
    position_gain: float = 2.5  # [1/s], velocity per metre of error near the target
    heading_gain: float = 4.0  # [1/s]
    clearance: float = 0.25  # kept free between two robots' hulls [m]
    # The contact guard (``motion.keep_clear``), after either tracker: the speed towards another robot in the way is at
    # most what lets this robot stop ``contact_margin`` short of its hull, braking at ``contact_brake`` after
    # ``contact_latency`` (two robots in each other's way brake together: at most half the base's braking). 0 turns
    # it off. The margin covers what the robot does not know of the gap: each robot's self-localization (2 cm
    # in the simulator, two robots' together about 3 cm), another robot's tracked or reported position, and a
    # command that reaches the base some 10-30 ms late over ROS (at 0.08 m the ROS matches had 4 times the
    # lockstep matches' contacts; at 0.15 m defenders stood off so far that 31 % of shots scored). A velocity whose
    # line keeps ``clearance`` from a robot is left alone.
    contact_margin: float = 0.12  # [m] between the hulls
    contact_brake: float = 2.0  # [m/s^2], at most half the base's braking
    contact_latency: float = 0.1  # [s] from seeing the other robot to braking: the percepts' age, a control cycle and
    # the drive's response

    def __post_init__(self) -> None:
        require_positive(self, "max_speed", "max_accel", "max_lateral_accel", "max_rot_speed", "max_rot_accel",
                         "dribble_speed", "dribble_back_speed", "dribble_side_speed", "dribble_rot_speed",
                         "dribble_accel", "replan_tolerance", "planning_range", "position_gain",
                         "heading_gain")
        require_non_negative(self, "clearance", "keep_plan_deviation", "keep_plan_goal_shift", "keep_plan_goal_share",
                             "keep_plan_time", "contact_margin", "contact_latency")
        require_positive(self, "contact_brake")
        if not 0.0 < self.plan_share <= 1.0:
            raise ValueError(f"plan_share must lie in (0, 1], got {self.plan_share}")
        if self.tracker not in TRACKERS:
            raise ValueError(f"tracker must be one of {', '.join(TRACKERS)}, got {self.tracker!r}")


@dataclass(frozen=True)
class PlayParams:
    set_play_distance: float = 3.0  # opponents keep this far from the ball at our set pieces [m] (MSL)
    drop_ball_distance: float = 1.0  # everyone keeps this far until the drop ball is started [m]
    set_play_timeout: float = 7.0  # after STARTROBOT of an opponent set play, play on after this [s]
    grab_distance: float = 0.45  # ask for the ball when this close, centre to centre [m]
    shot_threshold: float = 0.1  # shoot when the shot's chance to score (``chances``) is at least this and beats
    # the best pass [1]: a shot seldom costs more than the ball, and a team that waits for a sure chance shoots only
    # from close in (0.45: 55 % of shots scored, 2.9 shots a team and half; MSL teams shoot far more, score less)
    last_chance: float = 0.1  # ... or at least this when the ball must go (carried to carry_limit, no pass) [1]
    shot_range: float = 9.0  # no shot from farther than this from the goal's centre [m]
    lob_range: float = 7.0  # no lob from farther than this (the kicker's lob does not reach) [m]
    shot_speed: int = 10  # ground shot [m/s]
    pass_speed_per_metre: float = 0.9  # ground pass speed = clamp(k * distance, 3, 8) [m/s per m]
    pass_margin: float = 0.15  # pass when the ball beats every opponent by this all along its line [s]
    kick_spread: float = 2.0  # what the team reckons a kick scatters, aim included (one standard deviation) [deg]
    aim_tolerance: float = 0.08  # pass when facing the receiver this well [rad]
    shot_aim_tolerance: float = 0.03  # shoot when facing the aim point this well [rad]
    role_hysteresis: float = 0.6  # a challenger must reach the ball this much sooner [s]
    min_role_time: float = 1.0  # keep a role at least this long unless the holder drops out [s]
    search_distance: float = 1.5  # with the ball lost, the active robot stops this short of where it was seen [m]
    search_turn: float = 0.6  # ... and then turns on the spot, aiming this far ahead of its heading [rad]
    press_distance: float = 0.9  # an opponent playing the ball is pressed from this far, on its way to our goal [m]
    block_range: float = 9.0  # with the ball this near our goal's centre the PASSIVE robot blocks a shot's lane [m]
    block_distance: float = 1.6  # ... this far from the ball, towards the part of the goal the goalie leaves open [m]
    carry_limit: float = 2.4  # the rules allow 3 m with the ball from where it was caught: pass, shoot or let go by
    # this distance [m]
    hold_limit: float = 4.0  # a robot that has held the ball this long lets it go as at carry_limit (a pressed
    # carrier turning on the spot carries it nowhere, and would hold it for ever) [s]
    area_time: float = 7.0  # the rules allow 10 s in a penalty area: leave it after this long [s]
    goalie_line: float = 0.4  # the goalie guards the goal this far ahead of its goal line, on the bisector of the
    # angle the goal makes at the ball (``behaviours.goalie_spot``) [m]
    lob_line: float = -0.2  # ... and meets a lob coming down into the goal this far ahead of the line (behind it:
    # a lob aimed under the bar is lower there, and comes down on the goalie's body, not over it) [m]
    goalie_shot_speed: float = 2.0  # a ball at least this fast whose line crosses the goal mouth (half a metre
    # either side) is a shot the goalie steps into (straight, no plan); a slower one (a dribble, a pass across)
    # leaves it at its spot [m/s]
    goalie_id: int = 1
    team_size: int = 5

    def __post_init__(self) -> None:
        require_positive(self, "search_distance", "search_turn", "carry_limit", "hold_limit", "area_time",
                         "shot_range", "lob_range", "press_distance", "block_range", "block_distance",
                         "goalie_shot_speed",
                         "kick_spread", "shot_aim_tolerance")
        for name in ("shot_threshold", "last_chance"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must lie in [0, 1], got {getattr(self, name)}")
        if not -0.3 <= self.lob_line <= self.goalie_line <= 2.0:
            raise ValueError(f"need -0.3 <= lob_line <= goalie_line <= 2.0 [m], got {self.lob_line}, "
                             f"{self.goalie_line}")
        if not 1 <= self.goalie_id <= self.team_size:
            raise ValueError(f"goalie_id must lie in 1..team_size, got {self.goalie_id}")


@dataclass(frozen=True)
class ControlParams:
    motion: MotionParams = dc_field(default_factory=MotionParams)
    play: PlayParams = dc_field(default_factory=PlayParams)
    rate: float = 33.0  # control cycles per second [Hz] (chapter 4.4)
    world_model_timeout: float = 0.5  # a world model older than this is stale: the robot stops [s, sim time]
    strategy: str = ""  # "" the built-in Strategy; else "package.module:Class" or "/abs/file.py:Class" (plugins)
    policy: str = ""  # "" none; else a trained policy file (.npz) this robot plays in open play (policy_player)

    def __post_init__(self) -> None:
        require_positive(self, "rate", "world_model_timeout")
