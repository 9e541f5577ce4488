"""nubot_hwcontrol: the real robot's hardware controller (chapter 4.4).

Pure cores (the omni wheel layouts, which the simulator drives with too, are ``nubot_common.kinematics``):
``odometry`` (encoder counts to body velocity, stuck
detection), ``ball_handling`` (the arms' PD control and holding detection), ``shooting`` (lever and pulse,
calibration table and its fit), ``backend`` (the ``HardwareBackend`` interface and its selection),
``sim_drive`` (a simulated drive behind that interface), ``ethercat`` (Elmo drives and I/O over pysoem) and
``controller`` (one 50 Hz cycle of it all). The node ``nubot_hwcontrol_node`` only adapts them to ROS.
"""


class HardwareError(ValueError):
    """Invalid hardware parameters or commands, or a hardware interface that cannot be used."""
