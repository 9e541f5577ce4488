"""ROS adapters shared by nubot_control's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
