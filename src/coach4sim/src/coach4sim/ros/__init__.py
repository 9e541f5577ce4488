"""ROS adapters shared by coach4sim's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
