"""``rosrun front_vision calibrate``: the front camera's offline calibration, written as the YAML front_vision loads.

Two sources of images:

- ``--simulate``: the simulated camera renders them itself (sim_visual's ``FrontCameraRenderer`` with its true
  camera from ``--sim-config``, default the simulator's defaults): ``--views`` poses of the board held in front
  of it and the ground board lying at each ``--ground`` placement;
- ``--images DIR`` (pictures of the board held in front of a real camera, any of png/jpg/bmp) and
  ``--ground-image FILE`` once per ``--ground`` placement (the board lying flat at that place).

A placement is ``x,y,yaw_deg``: the board's centre [m] in the robot's body frame and the direction [deg] of its
columns (-90: to the robot's right, as the camera sees it upright). Boards: ``--board`` and ``--ground-board``,
``columns,rows,square_m`` (inner corners; columns + rows odd). The result (intrinsics, distortion, mount) and a
header saying how it was made go to ``--out``; the report is printed. Exit status 2 on a bad argument or a
failed calibration, with the reason.
"""

from __future__ import annotations

import argparse
import datetime
import sys
from pathlib import Path

import cv2
import numpy as np

from front_vision import FrontVisionError
from front_vision.calibration import Chessboard, GroundPlacement, calibrate
from front_vision.camera_model import camera_yaml

_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp")


def _board(text: str) -> Chessboard:
    try:
        columns, rows, square = text.split(",")
        return Chessboard(int(columns), int(rows), float(square))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"a board is columns,rows,square_m (e.g. 9,6,0.03): {exc}") from None


def _placement(text: str) -> GroundPlacement:
    try:
        x, y, yaw = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"a placement is x,y,yaw_deg (e.g. 0.95,0,-90), got {text!r}") from None
    return GroundPlacement(x, y, yaw)


def _read(path: Path) -> np.ndarray:
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if image is None:
        raise FrontVisionError(f"{path}: not an image OpenCV can read")
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="calibrate", description=__doc__.splitlines()[0])
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument("--simulate", action="store_true", help="render the images with the simulated camera")
    source.add_argument("--images", type=Path, help="folder of the board's pictures held in front of the camera")
    p.add_argument("--ground-image", type=Path, action="append", default=[],
                   help="a picture of the ground board at the matching --ground placement (real camera)")
    p.add_argument("--ground", type=_placement, action="append", default=[],
                   help="x,y,yaw_deg of a ground board (default with --simulate: 0.95,0,-90 and 1.25,0,-90)")
    p.add_argument("--board", type=_board, default=Chessboard(), help="columns,rows,square_m (default 9,6,0.03)")
    p.add_argument("--ground-board", type=_board, default=Chessboard(7, 4, 0.10),
                   help="columns,rows,square_m of the board on the ground (default 7,4,0.10)")
    p.add_argument("--views", type=int, default=30, help="simulated views of the held board (default 30)")
    p.add_argument("--seed", type=int, default=0, help="seed of the simulated views' poses and noise")
    p.add_argument("--sim-config", type=Path, help="simulator YAML whose sim/sensors/front_camera is the camera")
    p.add_argument("--out", type=Path, required=True, help="the camera YAML to write")
    return p


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        placements = list(args.ground)
        if args.simulate:
            from front_vision import simulated_views as sim

            params = _sim_params(args.sim_config)
            placements = placements or [GroundPlacement(0.95, 0.0, -90.0), GroundPlacement(1.25, 0.0, -90.0)]
            views = sim.board_views(params, args.board, args.views, args.seed)
            ground = sim.ground_views(params, args.ground_board, placements, args.seed + 1)
            source = (f"rendered by the simulated front camera (sim_visual, seed {args.seed}): {args.views} views of "
                      "the held board")
        else:
            files = sorted(f for f in args.images.iterdir() if f.suffix.lower() in _IMAGE_SUFFIXES)
            if not files:
                raise FrontVisionError(f"{args.images}: no images ({', '.join(_IMAGE_SUFFIXES)})")
            if len(args.ground_image) != len(placements) or not placements:
                raise FrontVisionError("give one --ground-image per --ground placement (at least one)")
            views = [_read(f) for f in files]
            ground = [_read(f) for f in args.ground_image]
            source = f"pictures in {args.images} ({len(files)}) and {', '.join(map(str, args.ground_image))}"
        camera, report = calibrate(views, args.board, ground, placements, args.ground_board)
    except (ValueError, OSError) as exc:  # FrontVisionError and NubotCommonError are ValueErrors
        print(f"calibrate: {exc}", file=sys.stderr)
        return 2
    b, g = args.board, args.ground_board
    header = "\n".join([
        f"Front camera calibration, {datetime.date.today().isoformat()}: rosrun front_vision calibrate",
        f"Images: {source}.",
        f"Intrinsics: cv2.calibrateCamera (k3 fixed at 0, no tangential distortion) on {report.views} views of a "
        f"{b.columns} x {b.rows} board of {b.square * 100:g} cm squares; RMS reprojection "
        f"{report.intrinsics_rms:.3f} px.",
        f"Mount: cv2.solvePnP on a {g.columns} x {g.rows} board of {g.square * 100:g} cm squares lying at "
        + "; ".join(f"({p.x:g}, {p.y:g}) m, {p.yaw_deg:g} deg" for p in placements)
        + f" (body frame); RMS reprojection {report.mount_rms:.3f} px."])
    args.out.write_text(camera_yaml(camera, header))
    print(header)
    print(f"written to {args.out}")
    return 0


def _sim_params(path: Path | None):  # noqa: ANN202 (sim_visual's FrontCameraParams)
    import yaml

    from nubot_common.params import from_mapping
    from sim_visual.front_camera_params import FrontCameraParams

    if path is None:
        return FrontCameraParams()
    data = yaml.safe_load(path.read_text()) or {}
    section = data.get("sim", {}).get("sensors", {}).get("front_camera", {})
    return from_mapping(FrontCameraParams, section, f"{path}: sim/sensors/front_camera")
