"""The tools around a match (pure Python; no rospy here, see ``ros`` for the tools that drive a ROS graph).

Modules: ``processes`` (start and stop roscore, roslaunch and rosrun processes in groups of their own,
for the runners and the tests), ``match_analysis`` (statistics of a match from plain records),
``match_plots`` (heat map and trajectories), ``match_report`` (the report from a match bag alone,
with ``rosbags``), ``workspace`` (where the workspace's files are). Each script in the workspace's
``scripts/`` only calls one of these.
"""
