"""A ROS 1 bag of a lockstep match: the topics ``rosbag record -a`` keeps of a ROS match, without ROS.

Requires: the engine's listener calls (sim time [s], world frame [m]), the catkin-generated message
classes (genpy, no rospy) and ``rosbags`` (the ``rosbag1.Writer``). Every message is built by the
nodes' own converters (``nubot_common.conversions``, ``sim_visual.conversions``,
``coach4sim.conversions``), so a bag of a lockstep match and one of a ROS match carry the same bytes.
Provides: ``BagRecorder`` (a ``MatchListener``) writing

- ``/clock`` (rosgraph_msgs/Clock) and ``/sim_visual/model_states`` (nubot_common/ModelStates, stamped)
  at the model-state rate (100 Hz);
- ``/sim_visual/goal`` (GoalEvent), ``/sim_visual/kick`` (KickEvent), ``/sim_visual/ball_touch``
  (BallTouch), ``/sim_visual/ball_holder`` (BallHolder) as they happen;
- ``/sim_visual/world_description`` (WorldDescription, latched) once, at the start;
- ``/referee/state`` (GameState), ``/referee/foul`` (RefereeCall) and ``/<team>/receive_from_coach``
  (CoachInfo);
- with ``robots=True`` also per robot ``/<robot>/omnivision/OmniVisionInfo`` (30 Hz),
  ``/<robot>/worldmodel/worldmodelinfo`` (WorldModelInfo), ``/<robot>/nubotcontrol/strategy``
  (StrategyInfo) and ``/<robot>/nubotcontrol/velcmd`` (VelCmd) at the control rate (33 Hz).

Bag times are sim time [ns] (a lockstep match has no wall time), at least 1 ns (``rosbag play`` drops
messages at time 0, such as the world description); each topic's are non-decreasing, as ``rosbag``'s
index merge needs. The bag is written to ``<path>.active`` and renamed to ``path``
by ``close()``: a match that never closes its recorder leaves no bag under the final name.
Parameters: ``path`` (the bag; neither it nor its ``.active`` may exist), ``robots`` (record the
robots' own topics too; default True).
"""

from __future__ import annotations

import io
import os
import struct
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Protocol

from rosbags.interfaces import Connection
from rosbags.rosbag1 import Writer, WriterError

from coach4sim.conversions import game_state_msg, referee_call_msg
from coach4sim.fouls import RefereeCall
from coach4sim.game import GameStateData
from nubot_common import conversions as shared
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import RobotView
from nubot_common.world_description import WorldDescription
from nubot_control.agent import AgentStep
from nubot_match import NubotMatchError
from nubot_match.record import MatchListener, ModelStates
from sim_visual import conversions as sim_conv
from sim_visual.simulator import BallKicked, BallTouched, GoalScored, HolderChanged, SimEvent

ACTIVE_SUFFIX = ".active"  # as rosbag record names the bag it is still writing
CLOCK_TOPIC = "/clock"
STATES_TOPIC = "/sim_visual/model_states"
WORLD_TOPIC = "/sim_visual/world_description"
GOAL_TOPIC, KICK_TOPIC, TOUCH_TOPIC = "/sim_visual/goal", "/sim_visual/kick", "/sim_visual/ball_touch"
HOLDER_TOPIC = "/sim_visual/ball_holder"
STATE_TOPIC, CALL_TOPIC = "/referee/state", "/referee/foul"
_NS = 1_000_000_000  # nanoseconds per second
TIME_MIN_NS = 1  # ros::TIME_MIN: rosbag's C++ storage (rosbag play) drops every message at bag time 0


class Message(Protocol):
    """A genpy message: what the recorder needs of one."""

    _type: str
    _full_text: str
    _md5sum: str

    def serialize(self, buff: io.BytesIO) -> None: ...


@dataclass(frozen=True)
class RawClock:
    """rosgraph_msgs/Clock serialised by hand, for a Python without Debian's python3-rosgraph-msgs."""

    _type = "rosgraph_msgs/Clock"
    _full_text = "time clock\n"
    _md5sum = "a9c97c1d230cfc112e270351a944ee47"
    t: float  # sim time [s]

    def serialize(self, buff: io.BytesIO) -> None:
        stamp = shared.stamp(self.t)
        buff.write(struct.pack("<II", stamp.secs, stamp.nsecs))


try:
    from rosgraph_msgs.msg import Clock as _Clock
except ImportError:  # pragma: no cover - Debian's python3-rosgraph-msgs is there wherever ROS is
    _Clock = None


def clock_msg(t: float) -> Message:
    """A /clock message at sim time ``t`` [s]."""
    if _Clock is None:
        return RawClock(t)
    return _Clock(clock=shared.stamp(t))


def active_path(path: Path) -> Path:
    """Where the bag of ``path`` is written until it is closed."""
    return path.with_name(path.name + ACTIVE_SUFFIX)


class BagRecorder(MatchListener):
    """Write a lockstep match as a ROS 1 bag; ``close()`` (idempotent) finishes it under its final name."""

    def __init__(self, path: str | Path, robots: bool = True):
        self.path = Path(path)
        self.robots = robots
        self.active = active_path(self.path)
        for existing in (self.path, self.active):
            if existing.exists() or existing.is_symlink():
                raise NubotMatchError(f"bag {existing} exists already: remove it or choose another name")
        self._writer: Writer | None = Writer(self.active)
        try:
            self._writer.open()
        except (OSError, WriterError) as exc:
            self._writer = None
            raise NubotMatchError(f"cannot write the bag {self.active}: {exc}") from None
        self._connections: dict[str, tuple[Connection, list[int]]] = {}  # topic -> (connection, [last time ns])
        self._buffer = io.BytesIO()
        self._now = 0.0  # latest sim time of a timed call [s]: when an untimed percept was published
        self._started = False
        self.messages = 0  # written so far
        self.closed = False

    # --- the listener ------------------------------------------------------------------------------------
    def start(self, world: WorldDescription, t: float) -> None:
        if self._started:
            raise NubotMatchError(f"bag {self.path} holds one match: make a new BagRecorder for each reset")
        self._started = True
        self.write(WORLD_TOPIC, shared.world_description_msg(world, t), t, latching=True)

    def clock(self, t: float) -> None:
        self.write(CLOCK_TOPIC, clock_msg(t), t)

    def model_states(self, t: float, states: ModelStates) -> None:
        self.write(STATES_TOPIC, sim_conv.model_states_msg(states, t), t)

    def sim_event(self, event: SimEvent) -> None:
        if isinstance(event, GoalScored):
            self.write(GOAL_TOPIC, sim_conv.goal_event_msg(event), event.time)
        elif isinstance(event, BallKicked):
            self.write(KICK_TOPIC, sim_conv.kick_event_msg(event), event.time)
        elif isinstance(event, BallTouched):
            self.write(TOUCH_TOPIC, sim_conv.ball_touch_msg(event), event.time)
        elif isinstance(event, HolderChanged):
            self.write(HOLDER_TOPIC, sim_conv.ball_holder_msg(event), event.time)

    def game_state(self, t: float, state: GameStateData) -> None:
        self.write(STATE_TOPIC, game_state_msg(state, t), t)

    def coach(self, t: float, team: str, mode: MatchMode, previous: MatchMode) -> None:
        self.write(f"/{team}/receive_from_coach", shared.coach_info_msg(int(mode), int(previous), t), t)

    def referee_call(self, call: RefereeCall) -> None:
        self.write(CALL_TOPIC, referee_call_msg(call), call.time)

    def vision(self, robot: str, view: RobotView) -> None:
        if self.robots:
            self.write(f"/{robot}/omnivision/OmniVisionInfo", shared.omni_vision_msg(view), max(view.stamp, self._now))

    def robot_step(self, t: float, robot: str, step: AgentStep) -> None:
        if not self.robots:
            return
        self.write(f"/{robot}/worldmodel/worldmodelinfo", shared.world_model_info_msg(step.world), t)
        self.write(f"/{robot}/nubotcontrol/strategy", shared.strategy_info_msg(step.report), t)
        self.write(f"/{robot}/nubotcontrol/velcmd", shared.velcmd_msg(step.command.velocity), t)

    def close(self) -> None:
        """Write the bag's index and give it its final name; again: nothing."""
        writer, self._writer = self._writer, None
        if writer is None:
            return
        self.closed = True
        writer.close()
        os.replace(self.active, self.path)

    # --- writing -----------------------------------------------------------------------------------------
    def write(self, topic: str, msg: Message, t: float, latching: bool = False) -> None:
        """Serialise ``msg`` and write it on ``topic`` at bag time ``t`` [s] (sim time)."""
        if self._writer is None:
            raise NubotMatchError(f"bag {self.path} is closed: nothing more can be written to it")
        entry = self._connections.get(topic)
        if entry is None:
            entry = self._connect(topic, msg, latching)
        connection, last = entry
        # rosbag merges each topic's index as sorted: a time never goes back on one topic
        ns = max(round(t * _NS), last[0], TIME_MIN_NS)
        last[0] = ns
        self._now = max(self._now, t)
        buffer = self._buffer
        buffer.seek(0)
        buffer.truncate()
        msg.serialize(buffer)
        self._writer.write(connection, ns, buffer.getvalue())
        self.messages += 1

    def _connect(self, topic: str, msg: Message, latching: bool) -> tuple[Connection, list[int]]:
        assert self._writer is not None
        package, name = msg._type.split("/")
        connection = self._writer.add_connection(topic, f"{package}/msg/{name}", msgdef=msg._full_text,
                                                 md5sum=msg._md5sum, latching=1 if latching else None)
        entry = self._connections[topic] = (connection, [0])
        return entry

    def __enter__(self) -> BagRecorder:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


__all__ = ["ACTIVE_SUFFIX", "TIME_MIN_NS", "BagRecorder", "RawClock", "active_path", "clock_msg"]
