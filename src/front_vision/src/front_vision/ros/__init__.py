"""ROS adapters of front_vision's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
