"""Robot control (pure core; the ROS node lives in ``nodes/``).

Modules: ``team_state`` (the plain world snapshot the strategy reads), ``roles``
(role enum), ``role_allocation`` (hybrid distributed role allocation with hysteresis),
``set_plays`` (formations for every MatchMode, MSL distance rules), ``behaviours``
(chase, dribble, shoot, pass, catch, mark, defend, goalie), ``motion`` (go-to with
limits and obstacle avoidance) and ``strategy`` (one control cycle: world in, commands out).
"""


class NubotControlError(ValueError):
    """Raised for invalid input to the control core (bad parameters, unknown roles)."""
