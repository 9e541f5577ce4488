"""front_vision: the front camera's near-ball vision (chapter 3.2, 4.2), a pure core and thin nodes.

Modules: ``camera_model`` (the calibrated pinhole camera: intrinsics, distortion and its mount on the robot;
pixel <-> ray <-> ground), ``ball`` (colour seeds, region growing, the ball's centre ray and its ground
point), ``pipeline`` (one frame: image in, ``FrontBallResult`` out), ``calibration`` (chessboard views ->
intrinsics and extrinsics, written as the YAML the node loads) and ``conversions`` (image checks, the
``FrontBallInfo`` message).
"""


class FrontVisionError(ValueError):
    """Bad input to front_vision (an image, a camera file, a parameter): the message says what and why."""
