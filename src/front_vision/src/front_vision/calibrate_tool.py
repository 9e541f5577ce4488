"""``rosrun front_vision calibrate``: the front camera's offline calibration, written as the YAML front_vision loads.

The images: ``--images DIR`` (pictures of the board held in front of the camera, any of png/jpg/bmp) and
``--ground-image FILE`` once per ``--ground`` placement (the board lying flat at that place). The simulated
camera is calibrated from views it renders itself by ``rosrun nubot_tools calibrate_front_camera``
(``nubot_tools.front_calibration``), which shares this tool's arguments and output.

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
from nubot_common.camera_model import camera_yaml

_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp")


def board_arg(text: str) -> Chessboard:
    try:
        columns, rows, square = text.split(",")
        return Chessboard(int(columns), int(rows), float(square))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"a board is columns,rows,square_m (e.g. 9,6,0.03): {exc}") from None


def placement_arg(text: str) -> GroundPlacement:
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


def add_board_arguments(p: argparse.ArgumentParser, ground_help: str) -> None:
    """The boards, the ground placements and the output file: the arguments every source of views takes."""
    p.add_argument("--ground", type=placement_arg, action="append", default=[], help=ground_help)
    p.add_argument("--board", type=board_arg, default=Chessboard(), help="columns,rows,square_m (default 9,6,0.03)")
    p.add_argument("--ground-board", type=board_arg, default=Chessboard(7, 4, 0.10),
                   help="columns,rows,square_m of the board on the ground (default 7,4,0.10)")
    p.add_argument("--out", type=Path, required=True, help="the camera YAML to write")


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="calibrate", description=__doc__.splitlines()[0])
    p.add_argument("--images", type=Path, required=True,
                   help="folder of the board's pictures held in front of the camera")
    p.add_argument("--ground-image", type=Path, action="append", default=[],
                   help="a picture of the ground board at the matching --ground placement")
    add_board_arguments(p, "x,y,yaw_deg of a ground board (one per --ground-image)")
    return p


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        placements = list(args.ground)
        files = sorted(f for f in args.images.iterdir() if f.suffix.lower() in _IMAGE_SUFFIXES)
        if not files:
            raise FrontVisionError(f"{args.images}: no images ({', '.join(_IMAGE_SUFFIXES)})")
        if len(args.ground_image) != len(placements) or not placements:
            raise FrontVisionError("give one --ground-image per --ground placement (at least one)")
        views = [_read(f) for f in files]
        ground = [_read(f) for f in args.ground_image]
    except (ValueError, OSError) as exc:  # FrontVisionError and NubotCommonError are ValueErrors
        print(f"calibrate: {exc}", file=sys.stderr)
        return 2
    source = f"pictures in {args.images} ({len(files)}) and {', '.join(map(str, args.ground_image))}"
    return calibrate_and_write(views, ground, placements, args, source, "rosrun front_vision calibrate")


def calibrate_and_write(views: list[np.ndarray], ground: list[np.ndarray], placements: list[GroundPlacement],
                        args: argparse.Namespace, source: str, command: str) -> int:
    """Calibrate from the views (``args.board``) and the ground views (``args.ground_board`` at ``placements``),
    write the camera YAML with a header saying how it was made to ``args.out`` and print it; 0, or 2 with the
    reason on stderr when the calibration fails."""
    try:
        camera, report = calibrate(views, args.board, ground, placements, args.ground_board)
    except (ValueError, OSError) as exc:
        print(f"{command.split()[-1]}: {exc}", file=sys.stderr)
        return 2
    b, g = args.board, args.ground_board
    header = "\n".join([
        f"Front camera calibration, {datetime.date.today().isoformat()}: {command}",
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
