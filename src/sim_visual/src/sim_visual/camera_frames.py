"""Simulator-labelled omni camera frames for the colour calibration (``rosrun sim_visual render_camera_frames``).

Requires: a world (``--field``), the simulator's sensor parameters (defaults, or a simulator YAML's
``sim/sensors``), a seed. Provides: ``random_scenes`` (robot poses, other robots and the ball drawn from
one seeded generator, over the whole field and its border, the ball sometimes in the air) and ``main``,
which writes ``frame_NNNN.png`` (the camera image) and ``frame_NNNN_labels.png`` (each pixel's
``ColorClass``) into a folder for ``rosrun omni_vision calibrate_colors <folder>``.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Iterator
from pathlib import Path

import cv2
import numpy as np

from nubot_common import NubotCommonError
from nubot_common.world_description import WorldDescription, load_world
from sim_visual.sensors import RobotSensors, SensorParams
from sim_visual.world import BallState, RobotState

OTHER_ROBOTS = 9  # a 5 vs 5 match: every frame shows up to nine others


def random_scenes(world: WorldDescription, frames: int, rng: np.random.Generator
                  ) -> Iterator[tuple[float, RobotState, BallState, list[RobotState]]]:
    """``frames`` scenes (time [s], the viewer, the ball, the others), all inside the lines plus the border."""
    f = world.field
    hx, hy = f.half_length + f.border * 0.8, f.half_width + f.border * 0.8

    def robot() -> RobotState:
        return RobotState(rng.uniform(-hx, hx), rng.uniform(-hy, hy), rng.uniform(-math.pi, math.pi), 0.0, 0.0, 0.0)

    for k in range(frames):
        me = robot()
        others = [robot() for _ in range(int(rng.integers(0, OTHER_ROBOTS + 1)))]
        # the ball near the viewer half the time, so its colour is seen large and small
        near = rng.uniform() < 0.5
        bx = me.x + rng.uniform(-3.0, 3.0) if near else rng.uniform(-hx, hx)
        by = me.y + rng.uniform(-3.0, 3.0) if near else rng.uniform(-hy, hy)
        # a ball near a viewer at the wall would land beyond it: keep it inside, like the robots
        bx, by = float(np.clip(bx, -hx, hx)), float(np.clip(by, -hy, hy))
        bz = world.ball.radius + (rng.uniform(0.0, 0.6) if rng.uniform() < 0.2 else 0.0)
        yield 2.0 * k, me, BallState(bx, by, bz, 0.0, 0.0, 0.0), others


def write_frames(out: Path, world: WorldDescription, frames: int, seed: int,
                 params: SensorParams | None = None) -> int:
    """Render ``frames`` labelled frames into ``out``; return how many were written."""
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    sensors = RobotSensors(world, params if params is not None else SensorParams(), seed)
    for k, (t, me, ball, others) in enumerate(random_scenes(world, frames, rng)):
        frame = sensors.camera(t, me, ball, others, labels=True)
        assert frame.labels is not None
        cv2.imwrite(str(out / f"frame_{k:04d}.png"), cv2.cvtColor(frame.image, cv2.COLOR_RGB2BGR))
        cv2.imwrite(str(out / f"frame_{k:04d}_labels.png"), frame.labels)
    return frames


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="render_camera_frames", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="folder for frame_NNNN.png and their labels")
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--field", default="18x12", help="18x12, 22x14 or a world YAML")
    args = parser.parse_args(argv)
    if args.frames < 1:
        parser.error(f"--frames must be at least 1, got {args.frames}")
    try:
        world = load_world(args.field)
    except (NubotCommonError, ValueError) as exc:
        print(f"render_camera_frames: {exc}", file=sys.stderr)
        return 2
    count = write_frames(args.out, world, args.frames, args.seed)
    print(f"render_camera_frames: {count} labelled frames in {args.out}")
    return 0
