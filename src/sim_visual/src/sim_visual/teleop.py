"""Keyboard teleoperation of one robot, as a pure key-to-command mapper (no rospy here).

Requires: one key at a time (a one-character string, as read from a terminal in
cbreak mode). Provides: ``KeyTeleop.handle`` returning a ``RobotCommand``: the new
body-frame velocity command (Vx forward and Vy left [m/s], w counter-clockwise
[rad/s], as nubot_common/VelCmd), an optional BallHandle request (enable 1 dribble,
0 release), an optional kick (a ground pass at the pass strength [m/s], or a lob);
None when the key asks to quit. ``HELP`` lists the bindings. Parameters (``TeleopParams``):
linear_step [m/s], angular_step [rad/s], max_linear [m/s, on the norm of (Vx, Vy)],
max_angular [rad/s] and pass_strength [m/s, integer, 1..12].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nubot_common.commands import BodyVelocity, KickCommand, KickKind, RobotCommand

MIN_PASS_STRENGTH = 1  # [m/s]; Shoot.strength is an integer, 0 would not move the ball
MAX_PASS_STRENGTH = 12  # [m/s]; the simulator's kick_max_speed, faster kicks are clamped anyway
PASS_STRENGTH_STEP = 1  # [m/s] per +/- key press
_ZERO_TOLERANCE = 1e-9  # steps like 0.1 do not sum back to exactly 0.0 in binary floating point

HELP = """\
Keyboard teleop (body frame: x forward, y left):
  w / s     forward / back      (Vx +/- linear_step)
  a / d     left / right        (Vy +/- linear_step)
  q / e     turn left / right   (w +/- angular_step, CCW positive)
  space, k  full stop
  h         toggle dribble      (BallHandle enable 1 / 0)
  p         ground pass         (Shoot strength = pass strength, ShootPos -1)
  l         lob shot at goal    (Shoot strength 0, ShootPos 1)
  + / -     pass strength +/- 1 m/s (1..12)
  x, Ctrl-C quit (sends a zero command)
Speeds are clamped to max_linear (norm of Vx, Vy) and max_angular."""

_LINEAR_KEYS = {"w": (1, 0), "s": (-1, 0), "a": (0, 1), "d": (0, -1)}
_ANGULAR_KEYS = {"q": 1, "e": -1}
_STOP_KEYS = frozenset(" k")
_QUIT_KEYS = frozenset("x\x03")
KEYS = frozenset(_LINEAR_KEYS) | frozenset(_ANGULAR_KEYS) | _STOP_KEYS | _QUIT_KEYS | frozenset("hpl+-")


@dataclass(frozen=True)
class TeleopParams:
    linear_step: float = 0.25  # Vx / Vy change per key press [m/s]
    angular_step: float = 0.5  # w change per key press [rad/s]
    max_linear: float = 3.0  # limit on the norm of (Vx, Vy) [m/s]
    max_angular: float = 6.0  # limit on |w| [rad/s]
    pass_strength: int = 5  # initial ground pass speed [m/s]

    def __post_init__(self) -> None:
        for name in ("linear_step", "angular_step", "max_linear", "max_angular"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")
        strength = self.pass_strength
        if isinstance(strength, bool) or not isinstance(strength, int):
            raise ValueError(f"pass_strength must be an integer [m/s], got {strength!r}")
        if not MIN_PASS_STRENGTH <= strength <= MAX_PASS_STRENGTH:
            raise ValueError(f"pass_strength must be in {MIN_PASS_STRENGTH}..{MAX_PASS_STRENGTH} m/s, "
                             f"got {strength}")


def _snap(value: float) -> float:
    return 0.0 if abs(value) < _ZERO_TOLERANCE else value


class KeyTeleop:
    """Hold the current body-frame command and turn key presses into ``RobotCommand``s."""

    def __init__(self, params: TeleopParams):
        self.params = params
        self.vx = 0.0  # [m/s]
        self.vy = 0.0  # [m/s]
        self.w = 0.0  # [rad/s]
        self.pass_strength = params.pass_strength  # [m/s]
        self.dribbling = False  # the dribble mode last requested

    def handle(self, key: str) -> RobotCommand | None:
        """Apply one key; unknown keys leave everything unchanged and request nothing; None: quit."""
        if key in _QUIT_KEYS:
            return None
        prm = self.params
        ball_handle: int | None = None
        kick: KickCommand | None = None
        if key in _LINEAR_KEYS:
            sx, sy = _LINEAR_KEYS[key]
            self._set_linear(self.vx + sx * prm.linear_step, self.vy + sy * prm.linear_step)
        elif key in _ANGULAR_KEYS:
            w = self.w + _ANGULAR_KEYS[key] * prm.angular_step
            self.w = _snap(max(-prm.max_angular, min(prm.max_angular, w)))
        elif key in _STOP_KEYS:
            self.stop()
        elif key == "h":
            self.dribbling = not self.dribbling
            ball_handle = 1 if self.dribbling else 0
        elif key == "p":
            kick = KickCommand(KickKind.GROUND, self.pass_strength)
        elif key == "l":
            kick = KickCommand(KickKind.LOB, 0)
        elif key == "+":
            self.pass_strength = min(MAX_PASS_STRENGTH, self.pass_strength + PASS_STRENGTH_STEP)
        elif key == "-":
            self.pass_strength = max(MIN_PASS_STRENGTH, self.pass_strength - PASS_STRENGTH_STEP)
        return RobotCommand(BodyVelocity(self.vx, self.vy, self.w), self.dribbling, ball_handle, kick)

    def stop(self) -> None:
        """Zero the velocity command (dribble mode and pass strength are kept)."""
        self.vx = self.vy = self.w = 0.0

    def kick_result(self, done: bool) -> None:
        """Record a Shoot answer: the simulator switches dribbling off after a kick it made."""
        if done:
            self.dribbling = False

    def status(self) -> str:
        """Describe the current command in one line, for the terminal."""
        return (f"Vx {self.vx:+.2f} m/s  Vy {self.vy:+.2f} m/s  w {self.w:+.2f} rad/s  "
                f"pass {self.pass_strength} m/s  dribble {'on' if self.dribbling else 'off'}")

    def _set_linear(self, vx: float, vy: float) -> None:
        norm = math.hypot(vx, vy)
        limit = self.params.max_linear
        if norm > limit:
            # Scale the vector rather than each axis, so the direction of travel is kept.
            vx, vy = vx * limit / norm, vy * limit / norm
        self.vx, self.vy = _snap(vx), _snap(vy)
