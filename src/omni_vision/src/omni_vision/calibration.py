"""Offline colour calibration: a lookup table from labelled camera images (``rosrun omni_vision calibrate_colors``).

Requires: labelled images, either a folder of ``<name>.png`` camera frames each with a ``<name>_labels.png``
(one ``ColorClass`` value per pixel, 0 = not labelled), or a bag holding ``.../camera/image_raw`` and
``.../camera/labels`` (``sensor_msgs/Image``, paired by stamp; the simulator publishes labels with its
``~camera_labels`` parameter, ``rosrun sim_visual render_camera_frames`` writes such a folder). Labels
can also come from a person: paint each class in an image editor over a copy of a real frame.
Provides: ``read_samples`` (the (RGB image, labels) pairs of a folder or bag), ``calibrate_file`` (the
table, written where asked, with a summary) and ``main`` (the command line).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from nubot_common import NubotCommonError
from nubot_common.color_class import ColorClass
from nubot_common.images import image_to_array
from omni_vision import OmniVisionError
from omni_vision.colors import CalibrationParams, ColorTable

IMAGE_TOPIC_END = "/camera/image_raw"
LABELS_TOPIC_END = "/camera/labels"


def _folder_samples(folder: Path) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    images = sorted(p for p in folder.glob("*.png") if not p.stem.endswith("_labels"))
    pairs = [(p, p.with_name(f"{p.stem}_labels.png")) for p in images]
    pairs = [(image, labels) for image, labels in pairs if labels.is_file()]
    if not pairs:
        raise OmniVisionError(f"{folder}: no <name>.png with a <name>_labels.png beside it")
    for image_path, labels_path in pairs:
        bgr = cv2.imread(str(image_path), cv2.IMREAD_COLOR)
        labels = cv2.imread(str(labels_path), cv2.IMREAD_UNCHANGED)
        if bgr is None or labels is None:
            raise OmniVisionError(f"{image_path}: cannot read it or its labels as PNG images")
        if labels.ndim != 2:
            raise OmniVisionError(f"{labels_path}: labels must be a one-channel image of ColorClass values")
        yield cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), labels


def _labels_array(msg) -> np.ndarray:  # noqa: ANN001 (a sensor_msgs/Image, mono8)
    if msg.encoding != "mono8":
        raise OmniVisionError(f"labels must be mono8 images, got {msg.encoding!r}")
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    data = np.frombuffer(bytes(msg.data), dtype=np.uint8)
    if data.size < h * step:
        raise OmniVisionError(f"labels of {w} x {h} px need {h * step} B, got {data.size}")
    return data[:h * step].reshape(h, step)[:, :w].copy()


def _bag_samples(bag: Path) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    from rosbags.highlevel import AnyReader

    with AnyReader([bag]) as reader:
        wanted = [c for c in reader.connections if c.topic.endswith((IMAGE_TOPIC_END, LABELS_TOPIC_END))]
        if not any(c.topic.endswith(LABELS_TOPIC_END) for c in wanted):
            raise OmniVisionError(f"{bag}: no .../camera/labels topic (record the simulator with camera_labels "
                                  "true, or label a folder of images)")
        pending: dict[tuple[str, int], tuple[np.ndarray | None, np.ndarray | None]] = {}
        for connection, _, raw in reader.messages(connections=wanted):
            msg: Any = reader.deserialize(raw, connection.msgtype)
            robot = connection.topic.rsplit("/camera/", 1)[0]
            key = (robot, msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
            image, labels = pending.get(key, (None, None))
            if connection.topic.endswith(IMAGE_TOPIC_END):
                image = image_to_array(msg)
            else:
                labels = _labels_array(msg)
            if image is not None and labels is not None:
                pending.pop(key, None)
                yield image, labels
            else:
                pending[key] = (image, labels)


def read_samples(source: Path) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The (RGB image, labels) pairs of a folder or a bag (see the module docstring)."""
    if source.is_dir():
        return _folder_samples(source)
    if source.is_file() and source.suffix == ".bag":
        return _bag_samples(source)
    raise OmniVisionError(f"{source}: give a folder of labelled PNG images or a .bag file")


def calibrate_file(source: Path, out: Path, params: CalibrationParams | None = None) -> tuple[ColorTable, int]:
    """Calibrate a table from ``source``, write it to ``out``; return it and the number of images used."""
    count = 0

    def counted() -> Iterator[tuple[np.ndarray, np.ndarray]]:
        nonlocal count
        for sample in read_samples(source):
            count += 1
            yield sample

    table = ColorTable.calibrate(counted(), params)
    if count == 0:
        raise OmniVisionError(f"{source}: no labelled image pairs")
    out.parent.mkdir(parents=True, exist_ok=True)
    table.save(out)
    return table, count


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="calibrate_colors", description=__doc__.splitlines()[0])
    parser.add_argument("source", type=Path, help="a folder of <name>.png + <name>_labels.png, or a .bag")
    parser.add_argument("--out", type=Path, default=Path("colors.npz"), help="the table file to write")
    parser.add_argument("--fill-distance", type=float, default=CalibrationParams().fill_distance,
                        help="uncalibrated YUV cells this near [cells of 4 levels] a calibrated one take its class")
    args = parser.parse_args(argv)
    try:
        table, count = calibrate_file(args.source, args.out, CalibrationParams(fill_distance=args.fill_distance))
    except (NubotCommonError, OmniVisionError) as exc:  # a bad image or table
        print(f"calibrate_colors: {exc}", file=sys.stderr)
        return 2
    cells = np.bincount(table.table.ravel(), minlength=len(ColorClass))
    pixels = ", ".join(f"{c.name.lower()} {int(table.labelled_pixels[c])}" for c in ColorClass if c)
    classes = ", ".join(f"{c.name.lower()} {int(cells[c])}" for c in ColorClass)
    print(f"calibrate_colors: {count} images ({pixels} labelled pixels); table cells: {classes}; wrote {args.out}")
    return 0
