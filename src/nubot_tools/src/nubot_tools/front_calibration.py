"""``rosrun nubot_tools calibrate_front_camera``: the simulated front camera calibrated from views it renders itself
(its renderer, its true camera and noise), by front_vision's calibration, as a real camera is from its pictures
(``rosrun front_vision calibrate``: the same arguments and camera YAML). A tool above both the simulator and
front_vision: the robot's vision needs no simulator.

Requires: the simulated camera's ``FrontCameraParams``, a ``Chessboard`` for the intrinsics and one for the ground,
the ground placements and a seed. Provides ``board_views`` (the board held at random poses in front of the camera,
every corner in view: tilted up to ``max_tilt_deg``, 0.4 - 0.9 m away, spread over the image) and ``ground_views``
(the board lying at each placement), both rendered by ``FrontCameraRenderer.render_board`` on an empty field (the
robot at the centre spot facing +x, the ball far behind it) with the camera's noise; and ``main``, the command.
Exit status 2 on a bad argument or a failed calibration, with the reason.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np
import yaml

from front_vision.calibrate_tool import add_board_arguments, calibrate_and_write
from front_vision.calibration import Chessboard, GroundPlacement
from nubot_common.params import from_mapping
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import OmniCameraParams
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.front_camera_params import FrontCameraParams
from sim_visual.world import BallState, RobotState

_ROBOT = RobotState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
_BALL = BallState(-3.0, 0.0, 0.11, 0.0, 0.0, 0.0)  # behind the robot: not in view
_MARGIN = 6.0  # [px] every corner at least this far inside the image
_TRIES = 200  # poses tried per view


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    r, _ = cv2.Rodrigues(np.asarray(axis, np.float64) * angle)
    return r


def board_views(params: FrontCameraParams, board: Chessboard, count: int, seed: int,
                max_tilt_deg: float = 35.0) -> list[np.ndarray]:
    """``count`` images of ``board`` held at random poses (seeded) in front of the simulated camera."""
    renderer = FrontCameraRenderer(WorldDescription(), params, OmniCameraParams())
    cam = params.camera
    rng = np.random.default_rng(seed)
    texture = board.texture()
    sx, sy = board.size
    views: list[np.ndarray] = []
    for _ in range(count):
        for _ in range(_TRIES):
            # In the camera frame: the board faces the lens, tilted about x and y, turned about the optical axis.
            tilt = math.radians(max_tilt_deg)
            r_cb = (_rotation(np.array([0.0, 0.0, 1.0]), rng.uniform(-0.4, 0.4))
                    @ _rotation(np.array([1.0, 0.0, 0.0]), rng.uniform(-tilt, tilt))
                    @ _rotation(np.array([0.0, 1.0, 0.0]), rng.uniform(-tilt, tilt)))
            target = np.array([rng.uniform(-0.35, 0.35), rng.uniform(-0.25, 0.25), 1.0])
            centre = target / np.linalg.norm(target) * rng.uniform(0.4, 0.9)
            origin_cam = centre - r_cb @ np.array([sx / 2.0, sy / 2.0, 0.0])
            rotation = cam.rotation @ r_cb
            position = cam.origin + cam.rotation @ origin_cam
            corners = board.object_points() @ rotation.T + position
            uv, ahead = cam.project(corners)
            inside = (uv[:, 0] >= _MARGIN) & (uv[:, 0] <= cam.width - 1 - _MARGIN) & (uv[:, 1] >= _MARGIN) \
                & (uv[:, 1] <= cam.height - 1 - _MARGIN)
            if ahead.all() and inside.all():
                views.append(renderer.render_board(_ROBOT, _BALL, [], 0.0, rng, texture, (sx, sy), rotation, position))
                break
    return views


def ground_views(params: FrontCameraParams, board: Chessboard, placements: Sequence[GroundPlacement],
                 seed: int) -> list[np.ndarray]:
    """One image of ``board`` lying at each of ``placements`` (a millimetre above the carpet)."""
    renderer = FrontCameraRenderer(WorldDescription(), params, OmniCameraParams())
    rng = np.random.default_rng(seed)
    texture = board.texture()
    return [renderer.render_board(_ROBOT, _BALL, [], 0.0, rng, texture, board.size, p.rotation(),
                                  p.origin(board) + np.array([0.0, 0.0, 0.001])) for p in placements]


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="calibrate_front_camera", description=__doc__.splitlines()[0])
    p.add_argument("--views", type=int, default=30, help="views of the held board (default 30)")
    p.add_argument("--seed", type=int, default=0, help="seed of the views' poses and noise")
    p.add_argument("--sim-config", type=Path, help="simulator YAML whose sim/sensors/front_camera is the camera "
                   "(default: the simulator's defaults)")
    add_board_arguments(p, "x,y,yaw_deg of a ground board (default 0.95,0,-90 and 1.25,0,-90)")
    return p


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        params = camera_params(args.sim_config)
        placements = list(args.ground) or [GroundPlacement(0.95, 0.0, -90.0), GroundPlacement(1.25, 0.0, -90.0)]
        views = board_views(params, args.board, args.views, args.seed)
        ground = ground_views(params, args.ground_board, placements, args.seed + 1)
    except (ValueError, OSError) as exc:  # the packages' errors are ValueErrors
        print(f"calibrate_front_camera: {exc}", file=sys.stderr)
        return 2
    source = f"rendered by the simulated front camera (seed {args.seed}): {args.views} views of the held board"
    return calibrate_and_write(views, ground, placements, args, source, "rosrun nubot_tools calibrate_front_camera")


def camera_params(path: Path | None) -> FrontCameraParams:
    """The simulated front camera of the simulator YAML at ``path`` (sim/sensors/front_camera), or the default."""
    if path is None:
        return FrontCameraParams()
    data = yaml.safe_load(path.read_text()) or {}
    section = data.get("sim", {}).get("sensors", {}).get("front_camera", {})
    return from_mapping(FrontCameraParams, section, f"{path}: sim/sensors/front_camera")
