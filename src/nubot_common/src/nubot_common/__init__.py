"""Shared pure-Python library of the NuBot workspace (no rospy here).

Provides: ``field`` (MSL field geometry), ``match_mode`` (the coach's game
commands), ``geometry`` (2-D poses and frames), ``params`` (typed parameter
loading), ``reconfigure`` (dynamic_reconfigure descriptions built at run time), ``packages`` (where a ROS
package is, by ROS's own lookup), ``processes`` (roscore, roslaunch and rosrun processes in groups of their own,
for the runners and the tests) and ``launch_checks`` (what a launch file gives its nodes, for the tests).
What the simulator and the robot's own software share about the robot's hardware lives here too, below both:
``mirror`` (the omni camera's mirror), ``color_class`` (what a pixel shows), ``images`` (sensor_msgs/Image <->
arrays), ``camera_model`` and ``camera_info`` (the front camera), ``kinect_mount`` and ``clouds`` (the goalie's
RGB-D cameras) and ``kinematics`` (the omni wheels).
The generated ``msg`` and ``srv`` modules live beside these after catkin_make.
"""


class NubotCommonError(ValueError):
    """Raised for invalid input to the shared library (bad parameters, unknown enum values)."""
