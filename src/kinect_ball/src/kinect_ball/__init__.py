"""kinect_ball: the goalie's two RGB-D cameras (chapter 3.2, 4.2), a pure core and a thin node.

Modules: ``detection`` (orange candidates, clusters, the RANSAC sphere fit of the
known ball radius), ``flight`` (the 3-D track, the parabola fitted to the current flight, its touchdown) and
``pipeline`` (both cameras' clouds and the robot's pose in, one ``Ball3dPercept`` out). Where each camera sits
(``nubot_common.kinect_mount``) and the clouds' messages (``nubot_common.clouds``) are shared with the simulator.
"""


class KinectBallError(ValueError):
    """Bad input to kinect_ball (a point cloud, a parameter): the message says what and why."""
