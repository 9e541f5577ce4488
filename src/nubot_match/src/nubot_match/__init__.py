"""Matches without ROS (pure Python; no rospy anywhere in this package).

Modules: ``config`` (a match's configuration from the same YAMLs the launch files load),
``engine`` (``LockstepMatch``: simulator, sensing, one ``RobotAgent`` per robot, the team links and the
automatic referee stepped together at the rates of a ROS match), ``record`` (what a match leaves:
the ``MatchLog`` the report's statistics read), ``bag`` (a ROS 1 bag of a lockstep match, written
with rosbags), ``evaluate`` (many seeded matches on every core or a dask cluster, with confidence
intervals) and ``envs`` (Gymnasium and PettingZoo environments).
"""


class NubotMatchError(ValueError):
    """Raised for a match that cannot be set up or run as asked (bad team file, strategy, option)."""
