"""One robot's world model (pure core; the ROS node lives in ``nodes/``).

Modules: ``params`` (typed configuration), ``ball_fusion`` (ball tracks, least-squares velocity,
source choice, confidence), ``obstacles`` (teammate/opponent labelling), ``game`` (coach commands,
the pass in force) and ``world_model`` (the ``WorldModel`` tying them together); the numbers are fused in the compiled
``_kernels`` (``cpp/``). What it takes
and gives are the shared representations of ``nubot_common`` (``percepts``, ``team_play``,
``world_state``); ``nubot_common.conversions`` turns the messages into them and back.
"""


class WorldModelError(ValueError):
    """Raised for invalid input to the world model (bad parameters, unknown MatchMode, bad AgentID)."""
