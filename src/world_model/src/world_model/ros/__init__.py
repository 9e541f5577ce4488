"""ROS adapters shared by world_model's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
