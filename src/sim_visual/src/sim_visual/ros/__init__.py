"""ROS adapters of sim_visual's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
