"""The action of one learning robot, shared by the Gymnasium and the PettingZoo environments.

Requires: the simulator's ``PluginParams`` (``max_linear_speed`` [m/s], ``max_angular_speed`` [rad/s],
``kick_max_speed`` [m/s]). Provides: ``action_space(plugin)``, a ``Box`` float32 of shape (5,):

=====  =========  ======================  ==================================================================
index  name       bounds                  meaning
=====  =========  ======================  ==================================================================
0      vx         [-v_max, v_max] m/s     forward velocity, body frame (x along the kicker)
1      vy         [-v_max, v_max] m/s     leftward velocity, body frame; the simulator scales (vx, vy) down
                                          to a speed of at most v_max (5 m/s)
2      w          [-w_max, w_max] rad/s   counter-clockwise turn rate (12 rad/s)
3      dribble    [0, 1]                  > 0.5: ball handler on (takes a ball in front, keeps a held one);
                                          otherwise off (a held ball is let go)
4      kick       [0, 1]                  > 0.5: kick a held ball along the heading (ground pass) at
                                          round(kick * kick_max_speed) m/s, i.e. 6 to 12 m/s; the ball
                                          handler is left as it is in that cycle. Without the ball: nothing
=====  =========  ======================  ==================================================================

and ``to_command(action, space, plugin, who)``, the ``RobotCommand`` of one control cycle. An action of
another shape, with a non-finite entry or outside the bounds raises ``NubotMatchError`` naming the robot
and the entry (wrap the env in ``gymnasium.wrappers.ClipAction`` for a policy that overshoots).
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from nubot_common.commands import RobotCommand
from nubot_common.policy import ACTION_NAMES, TRIGGER, command_from_action
from nubot_match import NubotMatchError
from sim_visual.params import PluginParams

__all__ = ["ACTION_NAMES", "TRIGGER", "action_space", "check_action", "to_command"]
_TOLERANCE = 1e-5  # float32 rounding of the bounds


def action_space(plugin: PluginParams) -> spaces.Box:
    v, w = plugin.max_linear_speed, plugin.max_angular_speed
    return spaces.Box(low=np.array([-v, -v, -w, 0.0, 0.0], dtype=np.float32),
                      high=np.array([v, v, w, 1.0, 1.0], dtype=np.float32), dtype=np.float32)


def check_action(action: object, space: spaces.Box, who: str) -> np.ndarray:
    """``action`` as float64 after checking its shape, finiteness and bounds; raise ``NubotMatchError``."""
    try:
        a = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError):
        raise NubotMatchError(f"{who}'s action must be numbers [{', '.join(ACTION_NAMES)}], got {action!r}") from None
    if a.shape != space.shape:
        raise NubotMatchError(f"{who}'s action must have shape {space.shape} [{', '.join(ACTION_NAMES)}], "
                              f"got shape {a.shape}")
    for k, name in enumerate(ACTION_NAMES):
        low, high = float(space.low[k]), float(space.high[k])
        if not np.isfinite(a[k]) or not low - _TOLERANCE <= a[k] <= high + _TOLERANCE:
            raise NubotMatchError(f"{who}'s action {name}={a[k]:g} is outside [{low:g}, {high:g}]")
    return a


def to_command(action: object, space: spaces.Box, plugin: PluginParams, who: str) -> RobotCommand:
    """The commands of one control cycle for ``action`` (see the table above)."""
    return command_from_action(check_action(action, space, who), plugin.kick_max_speed)
