"""omni_vision: the omni-directional camera's vision (chapter 4.1), a pure core and a thin node.

Modules: ``colors`` (the YUV colour lookup table and its calibration),
``lines`` (white line points on radial scan lines), ``objects`` (ball and obstacles), ``localization``
(matching optimisation against the field's distance map, global localization, Kalman tracking with
odometry) and ``pipeline`` (one frame: image in, percepts out). The mirror model, the colour classes and the
image messages are ``nubot_common.mirror``, ``color_class`` and ``images``, shared with the simulator.
"""


class OmniVisionError(ValueError):
    """Bad input to omni_vision (an image, a table file, a parameter): the message says what and why."""
