"""The ODE soccer simulator (pure core; the ROS node lives in ``nodes/``).

Modules: ``params`` (typed configuration), ``world`` (ODE physics layer),
``rules`` (the model plugin's rules: clamping, dribbling, kicking),
``sensing`` (noisy omni-vision frames), ``simulator`` (the step loop tying them
together), ``rejections`` (throttled reports of refused inputs), ``demo`` (the
single-robot behaviour) and ``teleop`` (key bindings).
"""


class SimVisualError(ValueError):
    """Raised for invalid input to the simulator (bad command, unknown model, bad parameters)."""
