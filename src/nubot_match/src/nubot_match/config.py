"""A lockstep match's configuration, read from the same YAML files the launch files load.

Requires: two team YAMLs (``nubot_control/config/teams/*.yaml``: prefix, attack, goalie, start poses,
optional ``control_config``, ``strategy`` and ``policy`` with ``policy_robots``; relative paths are taken from
the YAML's folder; a team can meet a variant of itself: ``opponents`` gives the second another prefix and end), a field
(``18x12``, ``22x14`` or a world description YAML), the tracker (``mpc``, ``baseline`` or "" for the
configured one), the half length [s of game time] and number of halves.
Provides: ``MatchConfig`` (frozen: the world, both teams with the ``ControlParams`` their nubot_control
nodes would get, the simulator's ``SimNodeParams`` from ``sim_visual.yaml``, ``WorldModelParams`` from
``world_model.yaml``, the referee's ``RefereeParams`` from ``referee.yaml``, the team relay's
``SimInterfaceParams``) and ``match_config(...)`` that builds one. Every error names the file and the
value (``NubotMatchError``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import yaml

from coach4sim.params import RefereeParams
from nubot_common import NubotCommonError
from nubot_common.packages import package_path, shipped_teams
from nubot_common.params import from_mapping
from nubot_common.world_description import WorldDescription, load_world
from nubot_control import NubotControlError
from nubot_control.params import TRACKERS, ControlParams
from nubot_control.team_config import TeamConfig
from nubot_match import NubotMatchError
from sim_visual.params import SimInterfaceParams, SimNodeParams
from world_model.params import WorldModelParams

TEAMS = shipped_teams()
CONFIG = {
    "sim": package_path("sim_visual") / "config" / "sim_visual.yaml",
    "world_model": package_path("world_model") / "config" / "world_model.yaml",
    "control": package_path("nubot_control") / "config" / "nubot_control.yaml",
    "referee": package_path("coach4sim") / "config" / "referee.yaml",
}
REFEREE_NODE_KEYS = ("teams", "auto", "republish_period", "state_period", "sim_namespace")  # the node's, not the rules'


@dataclass(frozen=True)
class TeamSetup:
    """One team as the spawner starts it: its configuration and what each robot's nubot_control gets."""

    config: TeamConfig
    control: ControlParams
    source: str = ""  # the team YAML it came from

    def control_of(self, agent_id: int) -> ControlParams:
        """What robot ``agent_id``'s nubot_control gets: the team's parameters and its policy file, if any."""
        policy = self.config.policy_of(agent_id)
        return replace(self.control, policy=policy) if policy else self.control


@dataclass(frozen=True)
class MatchConfig:
    world: WorldDescription
    teams: tuple[TeamSetup, ...]  # the first kicks off the first half
    sim: SimNodeParams  # physics, robot plugin, sensor noise, vision and model-state rates
    world_model: WorldModelParams
    referee: RefereeParams  # the rules, the half length [s] and the number of halves
    relay_max_age: float = 1.0  # teammates' packets older than this are not relayed [s] (sim_interface)
    referee_period: float = 0.03  # the referee judges and republishes CoachInfo this often [s]
    world_model_rate: float = 30.0  # [Hz]; the lockstep agent fuses at each control cycle, this is for the record

    def __post_init__(self) -> None:
        if len(self.teams) != 2:
            raise NubotMatchError(f"a match has two teams, got {len(self.teams)}")
        a, b = (t.config for t in self.teams)
        if a.prefix == b.prefix:
            raise NubotMatchError(f"both teams use the prefix {a.prefix!r}: give one of them another prefix")
        if a.attack == b.attack:
            raise NubotMatchError(f"both teams attack the goal at {'+x' if a.attack > 0 else '-x'}: one must have "
                                  "attack: -1")

    @property
    def robot_names(self) -> list[str]:
        return [n for t in self.teams for n in t.config.robot_names()]

    @property
    def half_duration(self) -> float:
        return self.referee.half_duration

    @property
    def halves(self) -> int:
        return self.referee.halves

    def with_seed(self, seed: int) -> MatchConfig:
        if seed < 0:
            raise NubotMatchError(f"seed must not be negative, got {seed}")
        return replace(self, sim=replace(self.sim, sim=replace(self.sim.sim, seed=int(seed))))

    def swapped(self) -> MatchConfig:
        """The same match with the other team kicking off and each team at the other end."""
        teams = tuple(replace(t, config=replace(t.config, attack=-t.config.attack)) for t in reversed(self.teams))
        return replace(self, teams=teams)


def _read(path: Path) -> dict[str, Any]:
    try:
        with open(path, encoding="utf-8") as handle:
            data = yaml.safe_load(handle)
    except OSError as exc:
        raise NubotMatchError(f"cannot read {path}: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise NubotMatchError(f"{path} is not valid YAML: {exc}") from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise NubotMatchError(f"{path}: expected a mapping of parameters, got {data!r}")
    return data


def merged(base: Mapping[str, Any], extra: Mapping[str, Any]) -> dict[str, Any]:
    """``extra`` loaded over ``base`` as ``rosparam load`` does: nested mappings merge key by key."""
    out = dict(base)
    for key, value in extra.items():
        out[key] = merged(out[key], value) if isinstance(value, Mapping) and isinstance(out.get(key), Mapping) \
            else value
    return out


def load_team(path: str | Path, world: WorldDescription, tracker: str = "") -> TeamSetup:
    """A team YAML and the ``ControlParams`` its robots get (nubot_control.yaml, the team's control_config,
    its goalie, ``tracker``, its strategy); raise ``NubotMatchError`` naming the file and the problem."""
    path = Path(path)
    try:
        team = from_mapping(TeamConfig, _read(path), path.name)
        team.check_field(world.field)
    except (NubotCommonError, ValueError) as exc:
        raise NubotMatchError(f"team {path}: {exc}") from None
    control = _read(CONFIG["control"])
    if team.control_config:
        extra = Path(team.control_config).expanduser()
        control = merged(control, _read(extra if extra.is_absolute() else path.parent / extra))
    control = merged(control, {"play": {"goalie_id": team.goalie}})
    if tracker:
        if tracker not in TRACKERS:
            raise NubotMatchError(f"tracker must be one of {', '.join(TRACKERS)}, got {tracker!r}")
        control = merged(control, {"motion": {"tracker": tracker}})
    try:
        team = team.resolved(path.parent)
        if team.strategy:
            control["strategy"] = team.strategy
        params = from_mapping(ControlParams, control, f"{path.name} control")
    except (NubotCommonError, NubotControlError, ValueError) as exc:
        raise NubotMatchError(f"team {path}: {exc}") from None
    return TeamSetup(team, params, str(path))


def opponents(home: TeamSetup, away: TeamSetup) -> tuple[TeamSetup, TeamSetup]:
    """The two teams made able to meet: AWAY takes another prefix if both use one (a team against a variant
    of itself) and the other end if both attack the same goal (start poses are in the team's own frame)."""
    a, b = home.config, away.config
    if b.prefix == a.prefix:
        b = replace(b, prefix="rival" if a.prefix != "rival" else "nubot")
    if b.attack == a.attack:
        b = replace(b, attack=-a.attack)
    return home, replace(away, config=b)


def _only(cls: type, data: Mapping[str, Any]) -> dict[str, Any]:
    names = {f.name for f in dataclasses.fields(cls)}
    return {k: v for k, v in data.items() if k in names}


def match_config(home: str | Path = TEAMS / "nubot.yaml", away: str | Path = TEAMS / "rival.yaml",
                 field: str | Path = "18x12", tracker: str = "", half_seconds: float = 300.0, halves: int = 2,
                 seed: int = 0) -> MatchConfig:
    """The configuration of a lockstep match between the teams of the YAMLs ``home`` and ``away``."""
    if not half_seconds > 0.0 or half_seconds > 4 * 3600:
        raise NubotMatchError(f"half length must lie in (0, 14400] s, got {half_seconds}")
    if not 1 <= halves <= 10:
        raise NubotMatchError(f"halves must lie in 1..10, got {halves}")
    try:
        world = load_world(field)
    except (OSError, NubotCommonError, ValueError) as exc:
        raise NubotMatchError(f"field {field}: {exc}") from None
    teams = opponents(load_team(home, world, tracker), load_team(away, world, tracker))
    sim_yaml = _read(CONFIG["sim"])
    wm_yaml = _read(CONFIG["world_model"])
    ref_yaml = _read(CONFIG["referee"])
    try:
        sim = from_mapping(SimNodeParams, merged(sim_yaml, {"sim": {"seed": int(seed)}}), "sim_visual.yaml")
        sim = replace(sim, sim=replace(sim.sim, world=world))
        world_model = from_mapping(WorldModelParams, _only(WorldModelParams, wm_yaml), "world_model.yaml")
        rules = {k: v for k, v in ref_yaml.items() if k not in REFEREE_NODE_KEYS}
        referee = from_mapping(RefereeParams, {**rules, "half_duration": half_seconds, "halves": halves},
                               "referee.yaml")
        referee = replace(referee, world=world)
        relay = SimInterfaceParams()
    except (NubotCommonError, ValueError) as exc:
        raise NubotMatchError(str(exc)) from None
    return MatchConfig(world, teams, sim, world_model, referee, relay_max_age=relay.max_age,
                       referee_period=float(ref_yaml.get("republish_period", 0.03)),
                       world_model_rate=float(wm_yaml.get("rate", 30.0)))
