"""The coach and the automatic referee of a simulated match (pure core; the ROS nodes live in ``nodes/``).

Modules: ``params`` (typed configuration), ``game`` (score, halves, clock and the
commands in force: ``GameController``), ``referee`` (the MSL rules applied to
snapshots of the simulated world: ``AutomaticReferee``), ``console`` (the coach
CLI's argument parsing, prompt and text rendering), ``refbox`` (the MSL RefBox protocol: commands to
MatchModes, our worldstate, its validator), ``refbox_server`` (a practice RefBox) and ``conversions``
(messages to and from the core types; imports generated messages but no rospy).
"""

from nubot_common import NubotCommonError


class CoachError(NubotCommonError):
    """Raised for invalid input to the coach or referee (unknown team or command, bad parameters)."""
