"""ROS adapters of nubot_comm's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
