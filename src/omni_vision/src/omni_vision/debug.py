"""The omni vision's debug image (like the chapter's Fig. 10b): what one frame saw, drawn over the frame.

Requires: the RGB frame, its ``VisionFrame`` and the ``OmniVision`` that made it (rays, table, mirror).
Provides: ``draw_debug_image`` -> an RGB image of the frame's size: each scan-line sample painted in its
colour class (green carpet, white, orange ball, blue for black), the white line points (red dots), the
ball (a yellow circle) and the obstacles (magenta crosses at their positions), the usable ring, and a
text line with the pose [m, deg], the localization state, the matching error and the frame's time [ms].
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from nubot_common.color_class import ColorClass
from omni_vision.pipeline import OmniVision, VisionFrame

_CLASS_RGB = {ColorClass.GREEN: (0, 160, 0), ColorClass.WHITE: (255, 255, 255), ColorClass.BALL: (255, 140, 0),
              ColorClass.BLACK: (40, 90, 255)}
_POINT_RGB = (255, 0, 0)
_BALL_RGB = (255, 255, 0)
_OBSTACLE_RGB = (255, 0, 255)
_RING_RGB = (120, 120, 120)


def draw_debug_image(image: np.ndarray, frame: VisionFrame, vision: OmniVision) -> np.ndarray:
    """The frame with the segmentation on the scan lines, the line points, the ball, obstacles and the pose."""
    out = (np.asarray(image, dtype=np.uint8) // 2).copy()  # darkened, so the drawings stand out
    rays, mirror = vision.scanner.rays, vision.mirror
    for cls, rgb in _CLASS_RGB.items():
        mask = frame.classes == cls
        out[rays.v[mask], rays.u[mask]] = rgb
    centre = (int(round(mirror.centre_u)), int(round(mirror.centre_v)))
    for radius in (mirror.r_min, mirror.r_max):
        cv2.circle(out, centre, int(round(radius)), _RING_RGB, 1, cv2.LINE_AA)
    for u, v in frame.lines.pixels:
        cv2.circle(out, (int(round(u)), int(round(v))), 2, _POINT_RGB, -1)
    if frame.ball is not None:
        u, v = mirror.body_to_pixel(frame.ball.x, frame.ball.y)
        cv2.circle(out, (int(round(float(u))), int(round(float(v)))), 8, _BALL_RGB, 2, cv2.LINE_AA)
    for obstacle in frame.obstacles:
        u, v = mirror.body_to_pixel(obstacle.x, obstacle.y)
        cv2.drawMarker(out, (int(round(float(u))), int(round(float(v)))), _OBSTACLE_RGB, cv2.MARKER_CROSS, 12, 2)
    pose, est = frame.view.robot.pose, frame.estimate
    text = (f"({pose.x:+.2f}, {pose.y:+.2f}) {math.degrees(pose.theta):+.0f} deg {est.state.value} "
            f"err {est.matching_error:.2f} {1000 * frame.timings['total']:.1f} ms")
    cv2.putText(out, text, (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (255, 255, 255), 1, cv2.LINE_AA)
    return out
