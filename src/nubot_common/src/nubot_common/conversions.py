"""Small helpers for message fields shared by every package's conversions module (no rospy)."""

from __future__ import annotations


def char_value(value: int | bytes | str) -> int:
    """The number in a ROS ``char`` field, whether genpy gives it as an int, a byte or a one-letter string."""
    if isinstance(value, bytes | str):
        return ord(value) if value else 0
    return int(value)
