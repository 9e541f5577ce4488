"""front_vision: the front camera's near-ball vision (chapter 3.2, 4.2), a pure core and thin nodes.

Modules: ``ball`` (colour seeds, region growing, the ball's centre ray and its ground
point), ``pipeline`` (one frame: image in, ``FrontBallResult`` out), ``calibration`` (chessboard views ->
intrinsics and extrinsics, written as the YAML the node loads). The camera's model (pinhole, distortion, mount:
pixel <-> ray <-> ground) and its CameraInfo conversions are ``nubot_common.camera_model`` and ``camera_info``,
which the simulator renders through too.
"""


class FrontVisionError(ValueError):
    """Bad input to front_vision (an image, a camera file, a parameter): the message says what and why."""
