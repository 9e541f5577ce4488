"""Colour classes of the omni camera's image, and the YUV lookup table that assigns them (chapter 4.1).

``ColorClass``: what a pixel shows. The simulator's renderer labels its pixels with these classes
(simulator-labelled images for the table's calibration); omni_vision's lookup table maps a pixel's
YUV value to one of them.

Requires: RGB images (``uint8``, height x width x 3) of the ``MirrorModel``'s size; for calibration,
label images (``ColorClass`` per pixel, UNKNOWN = not labelled).
Provides:

- ``check_image(image, mirror)``: the one entry check of a camera frame (type, size, a camera that
  delivers nothing but black or white), raising ``OmniVisionError`` with the reason.
- ``ColorTable``: 64^3 ``ColorClass`` cells indexed by (Y >> 2, U >> 2, V >> 2), YUV as OpenCV's
  ``COLOR_RGB2YUV``; ``classify`` (YUV pixels -> classes), ``classify_rgb``, ``calibrate`` (majority
  label per cell, then nearest-cell fill within a bounded YUV distance), ``save`` / ``load``.
- ``CalibrationParams``, ``ImageCheckParams`` (frozen, validated).

Table file format (``save``/``load``, version 1): a NumPy ``.npz`` archive (``numpy.savez_compressed``,
no pickles) holding ``format_version`` (int64 scalar, 1), ``table`` (uint8, 64 x 64 x 64, values
ColorClass, index [Y >> 2, U >> 2, V >> 2]) and ``labelled_pixels`` (int64, one count per ColorClass:
the labelled pixels the calibration voted with; zeros for a table not made by ``calibrate``).
"""

from __future__ import annotations

import math
import os
import tempfile
import zipfile
from collections.abc import Iterable
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import cv2
import numpy as np
import numpy.typing as npt
from scipy import ndimage

from nubot_common.color_class import ColorClass
from nubot_common.mirror import MirrorModel
from nubot_common.untrusted import UntrustedInputError, declared_arrays
from omni_vision import OmniVisionError

TABLE_BITS = 6  # bits kept per channel: the table's index is (Y >> 2, U >> 2, V >> 2)
TABLE_SIDE = 1 << TABLE_BITS  # cells per channel (64)
TABLE_SHAPE = (TABLE_SIDE, TABLE_SIDE, TABLE_SIDE)
FORMAT_VERSION = 1
_SHIFT = 8 - TABLE_BITS
_CLASSES = len(ColorClass)
_SPREAD_MASK = (TABLE_SIDE - 1) * (1 | 1 << 8 | 1 << 16)  # 0x3F3F3F: the shifted Y, U, V in one word

ClassArray = npt.NDArray[np.uint8]


@dataclass(frozen=True)
class CalibrationParams:
    min_votes: int = 1  # labelled pixels a cell needs to be calibrated by its own majority
    fill_distance: float = 3.0  # [cells of 4 grey levels] uncalibrated cells this near a calibrated one take its class

    def __post_init__(self) -> None:
        if not (isinstance(self.min_votes, int) and self.min_votes >= 1):
            raise OmniVisionError(f"min_votes must be an integer >= 1, got {self.min_votes!r}")
        if not (math.isfinite(self.fill_distance) and 0.0 <= self.fill_distance <= TABLE_SIDE):
            raise OmniVisionError(f"fill_distance must be in [0, {TABLE_SIDE}] cells, got {self.fill_distance}")


@dataclass(frozen=True)
class ImageCheckParams:
    sample_step: int = 8  # [px] the grid of ring pixels whose brightness the check looks at
    min_mean_level: float = 12.0  # [grey levels] a darker ring: the camera is covered or not exposing
    max_mean_level: float = 245.0  # [grey levels] a brighter ring: the camera is blinded (saturated)

    def __post_init__(self) -> None:
        if not (isinstance(self.sample_step, int) and 1 <= self.sample_step <= 64):
            raise OmniVisionError(f"sample_step must be an integer in [1, 64] px, got {self.sample_step!r}")
        if not 0.0 <= self.min_mean_level < self.max_mean_level <= 255.0:
            raise OmniVisionError("need 0 <= min_mean_level < max_mean_level <= 255, got "
                                  f"{self.min_mean_level}, {self.max_mean_level}")


@lru_cache(maxsize=8)
def _ring_samples(mirror: MirrorModel, step: int) -> npt.NDArray[np.intp]:
    """Flat indices of a grid of pixels (every ``step`` px) inside the usable ring."""
    v, u = np.mgrid[0:mirror.height:step, 0:mirror.width:step]
    r = np.hypot(u - mirror.centre_u, v - mirror.centre_v)
    keep = (r >= mirror.r_min) & (r <= mirror.r_max)
    return (v[keep] * mirror.width + u[keep]).astype(np.intp)


def check_image(image: object, mirror: MirrorModel, params: ImageCheckParams | None = None) -> np.ndarray:
    """A C-contiguous copy of ``image`` if it is a usable RGB frame for ``mirror``; else raise ``OmniVisionError``
    saying why."""
    params = params if params is not None else ImageCheckParams()
    if not isinstance(image, np.ndarray):
        raise OmniVisionError(f"the image must be a numpy array, got {type(image).__name__}")
    expected = (mirror.height, mirror.width, 3)
    if image.shape != expected:
        raise OmniVisionError(f"the image must be RGB of {mirror.width} x {mirror.height} px (shape {expected}), "
                              f"got shape {image.shape}")
    if image.dtype != np.uint8:
        raise OmniVisionError(f"the image must be uint8, got {image.dtype}")
    # A copy: the caller may reuse its buffer while the frame's detections are made, and one sequential read
    # brings the frame into the cache before the scans' scattered reads (4x faster than without, measured).
    frame = np.array(image, order="C", copy=True)
    samples = frame.reshape(-1, 3)[_ring_samples(mirror, params.sample_step)].astype(np.float32)
    level = float(samples.mean()) if samples.size else 0.0
    if level < params.min_mean_level:
        raise OmniVisionError(f"the image is black (mean level {level:.1f} in the usable ring, below "
                              f"{params.min_mean_level}): camera covered or not exposing")
    if level > params.max_mean_level:
        raise OmniVisionError(f"the image is saturated (mean level {level:.1f} in the usable ring, above "
                              f"{params.max_mean_level}): camera blinded")
    return frame


def _check_table(table: np.ndarray, where: str) -> None:
    if table.shape != TABLE_SHAPE:
        raise OmniVisionError(f"{where}: the table must have shape {TABLE_SHAPE}, got {table.shape}")
    if table.dtype != np.uint8:
        raise OmniVisionError(f"{where}: the table must be uint8, got {table.dtype}")
    if table.size and int(table.max()) >= _CLASSES:
        raise OmniVisionError(f"{where}: table values must be ColorClass values 0-{_CLASSES - 1}, "
                              f"found {int(table.max())}")


class ColorTable:
    """The YUV -> ColorClass lookup table (read-only)."""

    __hash__ = None  # type: ignore[assignment]  # equal tables compare equal; the class is not a dict key

    def __init__(self, table: np.ndarray, labelled_pixels: np.ndarray | None = None) -> None:
        table = np.asarray(table)
        _check_table(table, "ColorTable")
        counts = np.zeros(_CLASSES, np.int64) if labelled_pixels is None else np.asarray(labelled_pixels)
        if counts.shape != (_CLASSES,) or counts.dtype.kind not in "iu" or (counts.size and counts.min() < 0):
            raise OmniVisionError(f"labelled_pixels must be {_CLASSES} non-negative integers, got {counts!r}")
        self._table = np.array(table, dtype=np.uint8)
        self._table.flags.writeable = False
        self._counts = counts.astype(np.int64)
        self._counts.flags.writeable = False
        # Classification indexes a table spread over 8-bit fields (Y | U << 8 | V << 16 of the shifted values),
        # so a pixel's index is one 32-bit word of its (padded) YUV bytes: 4 MB instead of 256 kB, 3x faster.
        quantised = np.arange(TABLE_SIDE)
        qy, qu, qv = np.meshgrid(quantised, quantised, quantised, indexing="ij")
        spread = np.zeros(_SPREAD_MASK + 1, np.uint8)
        spread[(qy | (qu << 8) | (qv << 16)).ravel()] = self._table.ravel()
        self._spread = spread

    @property
    def table(self) -> ClassArray:
        """The cells (64 x 64 x 64 uint8 ColorClass values, index [Y >> 2, U >> 2, V >> 2]), read-only."""
        return self._table

    @property
    def labelled_pixels(self) -> npt.NDArray[np.int64]:
        """Labelled pixels per ColorClass that calibrated the table (zeros if not calibrated), read-only."""
        return self._counts

    @classmethod
    def empty(cls) -> ColorTable:
        """A table that knows nothing (every cell UNKNOWN)."""
        return cls(np.zeros(TABLE_SHAPE, np.uint8))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ColorTable):
            return NotImplemented
        return bool(np.array_equal(self._table, other._table) and np.array_equal(self._counts, other._counts))

    def classify(self, yuv: np.ndarray) -> ClassArray:
        """ColorClass (uint8) of each YUV pixel of ``yuv`` (uint8, shape (..., 3)); shape (...)."""
        yuv = np.asarray(yuv)
        if yuv.dtype != np.uint8 or yuv.ndim < 1 or yuv.shape[-1] != 3:
            raise OmniVisionError(f"classify needs uint8 YUV pixels of shape (..., 3), got {yuv.dtype} {yuv.shape}")
        if yuv.size == 0:
            return np.zeros(yuv.shape[:-1], np.uint8)
        row = np.ascontiguousarray(yuv).reshape(1, -1, 3)  # one image row: OpenCV pays per row
        # each pixel as one little-endian word Y | U << 8 | V << 16 | A << 24; >> 2 and the mask keep the top
        # six bits of Y, U and V in their bytes
        words = cv2.cvtColor(row, cv2.COLOR_RGB2RGBA).view(np.uint32).ravel()
        words >>= _SHIFT
        words &= np.uint32(_SPREAD_MASK)
        return np.take(self._spread, words).reshape(yuv.shape[:-1])

    def classify_rgb(self, rgb: np.ndarray) -> ClassArray:
        """ColorClass (uint8) of each RGB pixel of ``rgb`` (uint8, shape (..., 3)); shape (...)."""
        rgb = np.asarray(rgb)
        if rgb.dtype != np.uint8 or rgb.ndim < 1 or rgb.shape[-1] != 3:
            raise OmniVisionError(f"classify_rgb needs uint8 RGB pixels of shape (..., 3), got {rgb.dtype} "
                                  f"{rgb.shape}")
        if rgb.size == 0:
            return np.zeros(rgb.shape[:-1], np.uint8)
        yuv = cv2.cvtColor(np.ascontiguousarray(rgb).reshape(1, -1, 3), cv2.COLOR_RGB2YUV)
        return self.classify(yuv).reshape(rgb.shape[:-1])

    # --- calibration ---------------------------------------------------------------------------------
    @classmethod
    def calibrate(cls, samples: Iterable[tuple[np.ndarray, np.ndarray]],
                  params: CalibrationParams | None = None) -> ColorTable:
        """The table from ``samples``, (RGB image, label image) pairs: each cell takes the majority label of
        its labelled pixels (UNKNOWN labels ignored); a cell without enough votes takes the class of the
        nearest calibrated cell within ``params.fill_distance`` cells, else stays UNKNOWN."""
        params = params if params is not None else CalibrationParams()
        cells = TABLE_SIDE ** 3
        votes = np.zeros(cells * _CLASSES, np.int64)
        for n, sample in enumerate(samples):
            if not (isinstance(sample, tuple) and len(sample) == 2):
                raise OmniVisionError(f"calibration sample {n}: expected an (image, labels) pair")
            rgb, labels = np.asarray(sample[0]), np.asarray(sample[1])
            if rgb.dtype != np.uint8 or rgb.ndim != 3 or rgb.shape[2] != 3:
                raise OmniVisionError(f"calibration sample {n}: the image must be uint8 RGB (H x W x 3), "
                                      f"got {rgb.dtype} {rgb.shape}")
            if labels.shape != rgb.shape[:2] or labels.dtype.kind not in "iu":
                raise OmniVisionError(f"calibration sample {n}: the labels must be integers of shape "
                                      f"{rgb.shape[:2]}, got {labels.dtype} {labels.shape}")
            labels = labels.astype(np.int64).ravel()
            if labels.size and (labels.min() < 0 or labels.max() >= _CLASSES):
                raise OmniVisionError(f"calibration sample {n}: labels must be ColorClass values 0-{_CLASSES - 1}")
            yuv = cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2YUV).reshape(-1, 3) >> _SHIFT
            index = (yuv[:, 0].astype(np.int64) << (2 * TABLE_BITS)) | (yuv[:, 1].astype(np.int64) << TABLE_BITS) \
                | yuv[:, 2]
            labelled = labels != ColorClass.UNKNOWN
            votes += np.bincount(index[labelled] * _CLASSES + labels[labelled], minlength=cells * _CLASSES)
        per_cell = votes.reshape(cells, _CLASSES)
        counts = per_cell.sum(axis=0)
        calibrated = per_cell.sum(axis=1) >= params.min_votes
        table = np.zeros(cells, np.uint8)
        # argmax over the known classes only (column 0, UNKNOWN, never votes); ties go to the lower class
        table[calibrated] = 1 + np.argmax(per_cell[calibrated, 1:], axis=1)
        table = table.reshape(TABLE_SHAPE)
        calibrated = calibrated.reshape(TABLE_SHAPE)
        if calibrated.any() and params.fill_distance > 0.0:
            distance, nearest = ndimage.distance_transform_edt(~calibrated, return_indices=True)
            fill = ~calibrated & (distance <= params.fill_distance)
            table[fill] = table[nearest[0][fill], nearest[1][fill], nearest[2][fill]]
        return cls(table, counts)

    # --- file ------------------------------------------------------------------------------------------
    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the table to ``path`` (format in the module docstring), atomically (a temporary file renamed)."""
        target = Path(path)
        handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
        try:
            with os.fdopen(handle, "wb") as stream:
                np.savez_compressed(stream, format_version=np.int64(FORMAT_VERSION), table=self._table,
                                    labelled_pixels=self._counts)
            os.replace(temporary, target)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> ColorTable:
        """Read a table written by ``save``; raise ``OmniVisionError`` naming the file and the problem."""
        where = f"colour table {os.fspath(path)}"
        try:
            size = Path(path).stat().st_size
        except OSError as error:
            raise OmniVisionError(f"{where}: cannot read it ({error.strerror or error})") from error
        if size == 0:
            raise OmniVisionError(f"{where}: the file is empty")
        try:  # what the arrays declare, before any is read: a small file may declare a huge array
            declared = declared_arrays(path) if zipfile.is_zipfile(path) else {}
        except UntrustedInputError as error:
            raise OmniVisionError(f"{where}: truncated or not a colour table archive (.npz): {error}") from error
        for name, shape in {"table": TABLE_SHAPE, "labelled_pixels": (_CLASSES,), "format_version": ()}.items():
            if name not in declared:
                continue
            found, dtype = declared[name]
            if found != shape or dtype.itemsize > 8:
                raise OmniVisionError(f"{where}: {name} must have shape {shape}, got {found} of {dtype.str} "
                                      "declared; not read")
        try:
            archive = np.load(path, allow_pickle=False)
            if not isinstance(archive, np.lib.npyio.NpzFile):
                raise OmniVisionError(f"{where}: not a colour table archive (.npz), found a single array")
            with archive:
                missing = {"format_version", "table", "labelled_pixels"} - set(archive.files)
                if missing:
                    raise OmniVisionError(f"{where}: not a colour table archive, missing {sorted(missing)}")
                version = archive["format_version"]
                if version.shape != () or version.dtype.kind not in "iu" or int(version) != FORMAT_VERSION:
                    raise OmniVisionError(f"{where}: format_version {version.tolist()!r} is not the supported "
                                          f"{FORMAT_VERSION}")
                table, counts = archive["table"], archive["labelled_pixels"]
        except OmniVisionError:
            raise
        except Exception as error:  # a damaged file: zip's, zlib's, numpy's header parser's errors and more
            raise OmniVisionError(f"{where}: truncated or not a colour table archive (.npz): {error}") from error
        try:
            return cls(table, counts)
        except OmniVisionError as error:
            raise OmniVisionError(f"{where}: {str(error).removeprefix('ColorTable: ')}") from error
