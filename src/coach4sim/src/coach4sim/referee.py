"""The automatic referee: the MSL rules applied to snapshots of the simulated world.

Requires: ``RefereeParams`` (field geometry [m], times [s], the fouls' numbers), a ``GameController``
and, each update, a ``WorldSnapshot`` (sim time [s], ball centre and robot positions in the world
frame [m], the last robot to touch the ball, the robot holding it, and the goals, kicks and touches
seen since the previous snapshot).
Provides: ``AutomaticReferee.update(snapshot)`` -> ``RefereeDecision | None``: the commands now in
force for each team (in its own view, OUR_/OPP_ mirrored), where to place the ball (world frame [m],
at rest), the decision in words and the calls made (``fouls.RefereeCall``). The referee applies each
decision to the game itself (score, commands, half, last event).

Rules (MSL, simplified where noted; docs/rules.md): kickoff for the first team at the start; goal ->
score and kickoff for the conceding team, unless it does not count (``fouls.GoalCheck``: straight
from the scoring team's own set piece or from a dropped ball, or from a shot in its own half:
kick-off for the other team or a goal kick); a foul (``fouls.FoulWatch``: carrying, charging,
pushing, illegal defence or attack) -> a free kick for the other team, a penalty kick for pushing in
the own penalty area; a set piece not taken in ``set_piece_time`` -> a call, and the opponents may
play; ball wholly over a side line -> throw-in for the team that did not touch it last; over a goal
line outside the goal -> goal kick (attacker touched last) or corner kick (defender touched last);
no known last toucher -> dropped ball; a contested ball that does not move -> dropped ball; a
restart nobody plays for ``restart_timeout`` -> dropped ball; the end of a half (at the latest
``half_limit_factor`` half lengths of sim time after its kickoff) -> STOPROBOT, then the next half's
kickoff for the other team after a break, the teams having changed ends at the end of the half
(``switch_ends``: the decision asks the simulator to turn the field round). Each restart is the
set-piece command with the ball placed, then STARTROBOT after ``setup_time``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from enum import Enum

from coach4sim.fouls import FoulWatch, GoalCheck, RefereeCall, restart_spot
from coach4sim.game import GameController, half_name
from coach4sim.params import RefereeParams
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.naming import team_of
from nubot_common.records import fast_init


@dataclass(frozen=True)
class GoalSeen:
    """A goal event from the simulator: the goal at +x (side 1) or -x (-1), and who touched the ball last."""

    side: int
    last_touch: str = ""


@fast_init
@dataclass(frozen=True)
class WorldSnapshot:
    """What the referee sees at one moment (world frame, SI units)."""

    time: float  # sim time [s]
    ball: tuple[float, float, float]  # ball centre [m]
    robots: Mapping[str, tuple[float, float]] = field(default_factory=dict)  # robot positions by model name [m]
    last_touch: str = ""  # model name of the robot that touched the ball last ("" unknown)
    goals: tuple[GoalSeen, ...] = ()  # goals since the previous snapshot
    kicks: tuple[str, ...] = ()  # robots that kicked the ball since the previous snapshot
    touches: tuple[str, ...] = ()  # robots that became the last to touch it since the previous snapshot
    holder: str = ""  # the robot whose ball handler holds the ball ("" none)


class RefereeInputs:
    """What happened to the ball since the referee last looked, as the simulator reports it (the referee node from
    its topics, the lockstep engine from its events): goals, kicks and touches, who touched the ball last and who
    holds it. ``snapshot`` hands them to the referee with the positions of the moment and starts afresh."""

    def __init__(self) -> None:
        self.goals: list[GoalSeen] = []
        self.kicks: list[str] = []
        self.touches: list[str] = []
        self.last_touch = ""
        self.holder = ""

    def goal(self, side: int, last_touch: str) -> None:
        self.goals.append(GoalSeen(side, last_touch))

    def kick(self, robot: str) -> None:
        self.kicks.append(robot)
        self.last_touch = robot

    def touch(self, robot: str) -> None:
        self.touches.append(robot)
        self.last_touch = robot

    def snapshot(self, time: float, ball: tuple[float, float, float],
                 robots: Mapping[str, tuple[float, float]]) -> WorldSnapshot:
        out = WorldSnapshot(time, ball, robots, self.last_touch, tuple(self.goals), tuple(self.kicks),
                            tuple(self.touches), self.holder)
        self.goals, self.kicks, self.touches = [], [], []
        return out


@dataclass(frozen=True)
class RefereeDecision:
    commands: tuple[tuple[str, MatchMode], ...]  # (team, command in that team's view), every team
    ball: tuple[float, float] | None  # place the ball here, at rest (world frame [m]); None leaves it
    event: str  # the decision in words
    switch_ends: bool = False  # the teams have changed ends: every robot now attacks the other goal
    calls: tuple[RefereeCall, ...] = ()  # fouls and other calls made (their restart filled in)


class Phase(Enum):
    WAITING = "waiting for the match to start"
    SETUP = "teams set up for a restart"
    PLAY = "ball in play"
    STOPPED = "stopped by hand"
    HALF_TIME = "half-time break"
    FINISHED = "match over"


def _sign(value: float) -> int:
    return 1 if value >= 0.0 else -1


def _goal_name(side: int) -> str:
    return "+x" if side > 0 else "-x"


class AutomaticReferee:
    def __init__(self, params: RefereeParams, game: GameController):
        self.params, self.game = params, game
        self.phase = Phase.WAITING
        self._start_at = 0.0  # SETUP: STARTROBOT at this sim time [s]
        self._resume_at = 0.0  # HALF_TIME: next half's kickoff at this sim time [s]
        self._restart_side: int | None = None  # the side attacked by the team taking the restart
        self._restart_name = ""  # e.g. "throw-in"
        self._pending = False  # PLAY: the restart has not been taken yet
        self._deadline = 0.0  # ... and must be by this sim time [s]
        self._ball_ref: tuple[float, float] | None = None  # where the ball was when play resumed
        self._spot: tuple[float, float] | None = None  # SETUP: where the ball was placed for the restart
        self._replaced: tuple[float, float, float] | None = None  # PLAY: (x, y, until) a re-placement to see
        self._stuck_since: tuple[float, float, float] | None = None  # (x, y, t) of a contested, still ball
        self._between_halves = True  # before the match or in a half-time break (also when stopped there)
        self._last_ball: tuple[float, float] | None = None  # where the ball was at the latest update
        self._slow_called = False  # PLAY: the set piece was not taken in time (called once)
        self._set_piece_deadline = 0.0  # PLAY: the restart team must have played the ball by then [s]
        self._half_began = 0.0  # sim time the half began [s]
        self.fouls = FoulWatch(params)
        self.goal_check = GoalCheck()

    # --- the rules ----------------------------------------------------------------------------
    def update(self, snap: WorldSnapshot) -> RefereeDecision | None:
        """Apply the rules to ``snap``; return the decision taken, if any."""
        self.game.tick(snap.time)
        self._last_ball = (snap.ball[0], snap.ball[1])
        if self.phase is Phase.WAITING:
            return self._start_half(1, snap.time)
        if self.phase is Phase.HALF_TIME and snap.time >= self._resume_at:
            return self._start_half(self.game.half + 1, snap.time)
        if self.phase is Phase.SETUP and snap.time >= self._start_at:
            return self._start_play(snap.time)
        if self.phase is Phase.PLAY:
            return self._judge(snap)
        return None

    def _judge(self, snap: WorldSnapshot) -> RefereeDecision | None:
        p, f = self.params, self.params.field
        x, y, z = snap.ball
        for robot in (*snap.touches, *snap.kicks):
            self.goal_check.touched(robot, snap.robots.get(robot))
        if self._replaced is not None:  # the ball was just put back: judge it once the simulator shows it there
            rx, ry, until = self._replaced
            if math.hypot(x - rx, y - ry) > p.in_play_distance / 2.0 and snap.time < until:
                return None
            self._replaced = None
        goal_side = snap.goals[0].side if snap.goals else self._goal_by_geometry(x, y, z)
        goal_text = ""
        if goal_side is not None:
            toucher = snap.goals[0].last_touch if snap.goals and snap.goals[0].last_touch else snap.last_touch
            team = self.game.team_attacking(goal_side)
            own_goal = bool(team and toucher and self.game.team_of_robot(toucher) not in (None, team))
            reason, rule = self.goal_check.disallowed(team, goal_side, own_goal) if team else ("", "")
            if reason:
                return self._disallow(snap, team or "", goal_side, toucher, reason, rule)
            scorer = self.game.goal(goal_side)
            goal_text = (f"goal for {scorer or 'the absent opponents'} in the goal at {_goal_name(goal_side)} "
                         f"(last touch {toucher or 'nobody'}), score {self.game.score_text()}")
        if self.game.game_time >= p.half_duration or snap.time - self._half_began >= p.half_limit_factor * \
                p.half_duration + p.half_time_break:
            return self._end_half(snap.time, goal_text)
        if goal_side is not None:
            return self._restart(snap.time, -goal_side, MatchMode.OUR_KICKOFF, (0.0, 0.0), f"{goal_text}: ")
        over_side = abs(y) - (f.half_width + p.ball_radius)
        over_goal = abs(x) - (f.half_length + p.ball_radius)
        if over_side > 0.0 and over_side >= over_goal:
            return self._ball_out_over_side_line(snap)
        if over_goal > 0.0:
            return self._ball_out_over_goal_line(snap)
        if p.fouls:
            call = self.fouls.update(snap.time, (x, y), snap.robots, snap.holder, (*snap.touches, *snap.kicks),
                                     [t.spec for t in self.game.teams])
            if call is not None:
                return self._foul(snap.time, call)
        if self._ball_ref is None:
            self._ball_ref = (x, y)
        if self._pending:
            return self._check_restart_taken(snap)
        return self._check_stuck(snap)

    def _disallow(self, snap: WorldSnapshot, team: str, side: int, toucher: str, reason: str,
                  rule: str) -> RefereeDecision:
        """A goal that does not count: a kick-off for the other team after one straight from the kick-off
        (RC-8.4.1), else a goal kick for the defenders."""
        f, p = self.params.field, self.params
        robot = next((r for r in reversed(self.goal_check.touchers) if team_of(r) == team), toucher)
        call = RefereeCall("goal_disallowed", team, robot, (snap.ball[0], snap.ball[1]), rule, reason,
                           time=snap.time)
        if rule == "RC-8.4.1":
            decision = self._restart(snap.time, -side, MatchMode.OUR_KICKOFF, (0.0, 0.0),
                                     f"no goal ({rule}): {reason}: ")
        else:
            spot = (side * (f.half_length - f.goal_area_length - p.goal_kick_distance),
                    (1 if snap.ball[1] >= 0.0 else -1) * f.goal_area_width / 2.0)
            decision = self._restart(snap.time, -side, MatchMode.OUR_GOALKICK, spot, f"no goal ({rule}): {reason}: ")
        return replace(decision, calls=(replace(call, restart=decision.event.rsplit(": ", 1)[-1]),))

    def _foul(self, now: float, call: RefereeCall) -> RefereeDecision:
        """A free kick for the other team where the foul happened (from the nearest restart point out of a penalty
        area); a penalty kick for pushing or charging in the offender's own penalty area (RC-12.2)."""
        p = self.params
        other = next((t.spec for t in self.game.teams if t.spec.prefix != call.team), None)
        words = f"{call.kind.replace('_', ' ')} by {call.robot or call.team} ({call.rule}): {call.text}"
        if other is None:  # a match of one team: play goes on from a dropped ball
            decision = self._drop_ball(now, call.position, f"{words}: ")
        elif call.penalty:
            mark = other.attack * (p.field.half_length - p.field.penalty_mark_distance)
            decision = self._restart(now, other.attack, MatchMode.OUR_PENALTY, (mark, 0.0), f"{words}: ")
        else:
            bx, by = self._last_ball or call.position
            spot = restart_spot(bx, by, p.field, p.restart_margin)
            decision = self._restart(now, other.attack, MatchMode.OUR_FREEKICK, spot, f"{words}: ")
        return replace(decision, calls=(replace(call, time=now, restart=decision.event.rsplit(": ", 1)[-1]),))

    def _goal_by_geometry(self, x: float, y: float, z: float) -> int | None:
        """A goal the simulator's event has not reported yet: the ball lies in a goal, by the simulator's own test
        (``FieldGeometry.goal_holding``), so the two agree on every state the referee sees."""
        return self.params.field.goal_holding(x, y, z, self.params.ball_radius) or None

    def _ball_out_over_side_line(self, snap: WorldSnapshot) -> RefereeDecision:
        p, f = self.params, self.params.field
        x, y, _ = snap.ball
        where = f"ball out over the side line at x={x:+.2f} y={y:+.2f} (last touch {snap.last_touch or 'nobody'})"
        toucher_side = self._attack_of(snap.last_touch)
        if toucher_side is None:
            return self._drop_ball(snap.time, (x, y), f"{where}, no team to blame: ")
        limit = f.half_length - p.restart_margin
        spot = (min(max(x, -limit), limit), _sign(y) * (f.half_width - p.throw_in_inset))
        return self._restart(snap.time, -toucher_side, MatchMode.OUR_THROWIN, spot, f"{where}: ")

    def _ball_out_over_goal_line(self, snap: WorldSnapshot) -> RefereeDecision:
        p, f = self.params, self.params.field
        x, y, _ = snap.ball
        side, lateral = _sign(x), _sign(y)
        where = (f"ball out over the goal line at {_goal_name(side)}, y={y:+.2f} "
                 f"(last touch {snap.last_touch or 'nobody'})")
        toucher_side = self._attack_of(snap.last_touch)
        if toucher_side is None:
            return self._drop_ball(snap.time, (x, y), f"{where}, no team to blame: ")
        if toucher_side == side:  # an attacker played it out: goal kick for the defenders
            spot = (side * (f.half_length - f.goal_area_length - p.goal_kick_distance),
                    lateral * f.goal_area_width / 2.0)
            return self._restart(snap.time, -side, MatchMode.OUR_GOALKICK, spot, f"{where}: ")
        spot = (side * (f.half_length - p.corner_inset), lateral * (f.half_width - p.corner_inset))
        return self._restart(snap.time, side, MatchMode.OUR_CORNERKICK, spot, f"{where}: ")

    def _check_restart_taken(self, snap: WorldSnapshot) -> RefereeDecision | None:
        p = self.params
        team = self.game.team_attacking(self._restart_side) if self._restart_side is not None else None
        played = any(team is not None and self.game.team_of_robot(r) == team for r in (*snap.kicks, *snap.touches))
        ref = self._ball_ref or (snap.ball[0], snap.ball[1])
        moved = math.hypot(snap.ball[0] - ref[0], snap.ball[1] - ref[1]) > p.in_play_distance
        if played or moved or (self._slow_called and (snap.kicks or snap.touches)):
            self._pending = False
            self._stuck_since = None
            return None
        if snap.time >= self._deadline:
            return self._drop_ball(snap.time, snap.ball[:2],
                                   f"nobody played the {self._restart_name} within {p.restart_timeout:.0f} s: ")
        if not self._slow_called and team is not None and snap.time >= self._set_piece_deadline:
            self._slow_called = True  # the opponents may go for the ball now (RC-13); play goes on
            text = f"{team} did not take the {self._restart_name} within {p.set_piece_time:g} s: the opponents may play"
            call = RefereeCall("slow_restart", team, "", (snap.ball[0], snap.ball[1]), "RC-13.1", text,
                               time=snap.time)
            return replace(self._decide(None, text), calls=(call,))
        return None

    def _check_stuck(self, snap: WorldSnapshot) -> RefereeDecision | None:
        p = self.params
        x, y, _ = snap.ball
        teams_near = {self.game.team_of_robot(name) for name, (rx, ry) in snap.robots.items()
                      if math.hypot(rx - x, ry - y) <= p.stuck_radius}
        contested = len(self.game.teams) == 2 and set(self.game.team_names) <= teams_near
        if not contested:
            self._stuck_since = None
            return None
        if self._stuck_since is None or math.hypot(x - self._stuck_since[0], y - self._stuck_since[1]) > \
                p.stuck_distance:
            self._stuck_since = (x, y, snap.time)
            return None
        if snap.time - self._stuck_since[2] >= p.stuck_time:
            return self._drop_ball(snap.time, (x, y), f"ball stuck between the teams at ({x:+.2f}, {y:+.2f}) for "
                                                      f"{p.stuck_time:.0f} s: ")
        return None

    # --- the sequences --------------------------------------------------------------------------
    def _start_half(self, half: int, now: float) -> RefereeDecision:
        self.game.start_half(half)
        self._half_began = now
        self._between_halves = False
        first = self.game.teams[0].spec.attack  # the first team kicks off the odd halves, wherever it plays
        side = first if half % 2 else -first
        return self._restart(now, side, MatchMode.OUR_KICKOFF, (0.0, 0.0), f"the {half_name(half)} begins: ")

    def _restart(self, now: float, side: int, mode: MatchMode, spot: tuple[float, float],
                 reason: str) -> RefereeDecision:
        """Give the set piece ``mode`` to the team attacking ``side`` and place the ball at ``spot``."""
        self.game.award(side, mode)
        self._enter_setup(now, side, _restart_name(mode), spot)
        team = self.game.team_attacking(side) or "the absent opponents"
        return self._decide((spot[0], spot[1]), f"{reason}{_restart_name(mode)} for {team}")

    def _drop_ball(self, now: float, at: tuple[float, float], reason: str) -> RefereeDecision:
        f, m = self.params.field, self.params.restart_margin
        spot = (min(max(at[0], -(f.half_length - m)), f.half_length - m),
                min(max(at[1], -(f.half_width - m)), f.half_width - m))
        self.game.send_all(MatchMode.DROPBALL)
        self._enter_setup(now, None, "dropped ball", spot)
        return self._decide(spot, f"{reason}dropped ball")

    def _enter_setup(self, now: float, side: int | None, name: str,
                     spot: tuple[float, float] | None = None) -> None:
        self.phase = Phase.SETUP
        self._start_at = now + self.params.setup_time
        self._restart_side, self._restart_name = side, name
        self._pending = False
        self._ball_ref = self._stuck_since = None
        self._spot = spot
        self._replaced = None

    def _start_play(self, now: float) -> RefereeDecision:
        """STARTROBOT; a ball pushed off its spot during the setup goes back there first."""
        self.game.send_all(MatchMode.STARTROBOT)
        self.phase = Phase.PLAY
        self._pending = self._restart_side is not None
        self._deadline = now + self.params.restart_timeout
        self._set_piece_deadline = now + self.params.set_piece_time
        self._slow_called = False
        self.fouls.reset()
        taker = self.game.team_attacking(self._restart_side) if self._restart_side is not None else None
        known = self._restart_name if self._restart_name != "command by hand" else ""
        self.goal_check.started(known, taker or "")
        self._ball_ref, self._stuck_since = self._last_ball, None
        spot, self._spot = self._spot, None
        text = f"STARTROBOT: play on after the {self._restart_name}"
        if spot is not None and self._last_ball is not None and \
                math.dist(spot, self._last_ball) > self.params.in_play_distance / 2.0:
            x, y = self._last_ball
            self._ball_ref = spot
            self._replaced = (spot[0], spot[1], now + 1.0)
            return self._decide(spot, f"{text} (the ball, moved to ({x:+.2f}, {y:+.2f}) during the setup, "
                                      "goes back to its spot)")
        return self._decide(None, text)

    def _end_half(self, now: float, goal_text: str) -> RefereeDecision:
        self.game.send_all(MatchMode.STOPROBOT)
        prefix = f"{goal_text}; " if goal_text else ""
        switch = False
        if self.game.half < self.params.halves:
            self.phase = Phase.HALF_TIME
            self._between_halves = True
            self._resume_at = now + self.params.half_time_break
            text = f"{prefix}end of the {half_name(self.game.half)} ({self.game.score_text()})"
            if self.params.switch_ends:
                self.game.switch_ends()
                switch = True
                text += "; the teams change ends"
        else:
            self.phase = Phase.FINISHED
            text = f"{prefix}end of the match ({self.game.score_text()})"
        return self._decide(None, text, switch)

    def _decide(self, ball: tuple[float, float] | None, event: str, switch_ends: bool = False) -> RefereeDecision:
        self.game.last_event = event
        commands = tuple((t.spec.prefix, t.mode) for t in self.game.teams)
        return RefereeDecision(commands, ball, event, switch_ends)

    # --- manual commands -------------------------------------------------------------------------
    def manual_command(self, team: str, mode: MatchMode | int | str, now: float) -> str:
        """Apply a command given by hand (raises, changing nothing, if it is invalid); return it in words.

        A set piece or a dropped ball is followed by STARTROBOT after ``setup_time``; STARTROBOT
        puts the ball in play; STOPROBOT (or PARKINGROBOT, TEST) holds the automatic referee until
        the next manual restart. After the match, commands only reach the teams.
        """
        status = self.game.status(team)  # validate both before changing anything
        parsed = parse_match_mode(mode)
        self.game.tick(now)
        text = f"by hand: {self.game.command(team, parsed)}"
        self.game.last_event = text
        if self.phase is Phase.FINISHED:
            return text
        if self._between_halves and (parsed == MatchMode.STARTROBOT or parsed.is_set_play):
            self.game.start_half(self.game.half + 1)
            self._half_began = now
            self._between_halves = False
        if parsed == MatchMode.STARTROBOT:
            if self.phase is not Phase.SETUP:
                self._restart_side, self._restart_name = None, "command by hand"
            self._spot = None  # by hand, the ball stays where it is
            self._start_play(now)
            self.game.last_event = text
        elif parsed.is_set_play:
            side = None
            if parsed != MatchMode.DROPBALL:
                side = status.spec.attack if parsed.is_ours else -status.spec.attack
            self._enter_setup(now, side, _restart_name(parsed))
        else:
            self.phase = Phase.STOPPED
        return text

    @property
    def restart_pending(self) -> bool:
        """Play is on but the team awarded the restart has not played the ball yet."""
        return self.phase is Phase.PLAY and self._pending

    @property
    def attack_sides(self) -> dict[str, int]:
        return {t.spec.prefix: t.spec.attack for t in self.game.teams}

    def _attack_of(self, robot: str) -> int | None:
        team = self.game.team_of_robot(robot) if robot else None
        return self.attack_sides[team] if team is not None else None


def _restart_name(mode: MatchMode) -> str:
    """The restart in words, e.g. ``OUR_THROWIN`` -> ``throw-in`` (OPP_ names the same restart)."""
    return mode.restart.value if mode.restart is not None else mode.name
