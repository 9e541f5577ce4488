"""One robot's world model (pure core; the ROS node lives in ``nodes/``).

Modules: ``params`` (typed configuration), ``state`` (the plain data it takes and
gives: reports, observations, the ``WorldState`` snapshot), ``ball_fusion`` (ball
tracks, least-squares velocity, source choice, confidence), ``obstacles``
(teammate/opponent labelling), ``game`` (coach commands, pass commands) and
``world_model`` (the ``WorldModel`` agent tying them together). ``conversions``
turns ROS messages into these types and back (the only module that knows both).
"""


class WorldModelError(ValueError):
    """Raised for invalid input to the world model (bad parameters, unknown MatchMode, bad AgentID)."""
