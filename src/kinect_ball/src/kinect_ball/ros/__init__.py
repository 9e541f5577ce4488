"""ROS adapters of kinect_ball's nodes (rospy lives here and in ``nodes/``, never in the cores)."""
