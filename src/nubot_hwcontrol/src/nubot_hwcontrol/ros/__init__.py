"""ROS adapters of nubot_hwcontrol's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
