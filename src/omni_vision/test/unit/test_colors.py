"""The colour table (calibration, lookup, file) and the frame's entry check."""

import io
import zipfile

import cv2
import numpy as np
import pytest

from nubot_common.color_class import ColorClass
from nubot_common.mirror import MirrorModel
from omni_vision import OmniVisionError
from omni_vision.colors import TABLE_SHAPE, CalibrationParams, ColorTable, ImageCheckParams, check_image

from .scenes import calibrated_table, render, training_scenes

MIRROR = MirrorModel()


def _cell(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    """The table cell of an RGB colour."""
    y, u, v = cv2.cvtColor(np.array([[rgb]], np.uint8), cv2.COLOR_RGB2YUV)[0, 0]
    return int(y) >> 2, int(u) >> 2, int(v) >> 2


def _patch(rgb: tuple[int, int, int], label: ColorClass, count: int) -> tuple[np.ndarray, np.ndarray]:
    """An image of ``count`` pixels of one colour, all labelled ``label``."""
    return np.full((1, count, 3), rgb, np.uint8), np.full((1, count), label, np.uint8)


def test_a_calibrated_table_classifies_held_out_pixels_of_every_class():
    """Calibrated on 8 varied field scenes, the table classifies >= 98 % of each class's labelled pixels of 3 other
    scenes (other poses, lighting, noise) correctly."""
    table = calibrated_table(MIRROR)
    correct = np.zeros(len(ColorClass))
    total = np.zeros(len(ColorClass))
    for scene in training_scenes(3, seed=2):
        image, labels = render(MIRROR, scene)
        predicted = table.classify_rgb(image)
        for cls in ColorClass:
            mine = labels == cls
            total[cls] += mine.sum()
            correct[cls] += (predicted[mine] == cls).sum()
    for cls in (ColorClass.GREEN, ColorClass.WHITE, ColorClass.BALL, ColorClass.BLACK):
        assert total[cls] > 200, f"too few {cls.name} pixels to judge"
        assert correct[cls] / total[cls] >= 0.98, f"{cls.name}: {correct[cls] / total[cls]:.3f}"


def test_a_cell_takes_the_majority_of_its_labels_and_unknown_labels_do_not_vote():
    """Three GREEN votes beat one WHITE vote in a cell; a hundred UNKNOWN labels do not outvote one BALL label."""
    table = ColorTable.calibrate([_patch((40, 140, 55), ColorClass.GREEN, 3),
                                  _patch((40, 140, 55), ColorClass.WHITE, 1),
                                  _patch((245, 105, 20), ColorClass.UNKNOWN, 100),
                                  _patch((245, 105, 20), ColorClass.BALL, 1)])
    assert table.table[_cell((40, 140, 55))] == ColorClass.GREEN
    assert table.table[_cell((245, 105, 20))] == ColorClass.BALL
    assert table.labelled_pixels.tolist() == [0, 3, 1, 1, 0]


def test_uncalibrated_cells_take_the_nearest_class_only_within_the_fill_distance():
    """Cells 2 cells from a calibrated one take its class (fill distance 3); cells 10 away stay UNKNOWN."""
    table = ColorTable.calibrate([_patch((128, 128, 128), ColorClass.WHITE, 5)], CalibrationParams(fill_distance=3.0))
    y, u, v = _cell((128, 128, 128))
    assert table.table[y + 2, u, v] == ColorClass.WHITE
    assert table.table[y, u - 1, v + 1] == ColorClass.WHITE
    assert table.table[y + 10, u, v] == ColorClass.UNKNOWN
    assert (table.table != ColorClass.UNKNOWN).sum() == pytest.approx(4 / 3 * np.pi * 27, rel=0.3)


def test_classify_looks_up_the_cell_of_y_u_v_divided_by_4():
    """classify gives table[Y >> 2, U >> 2, V >> 2] for every pixel, any shape; classify_rgb converts RGB as
    OpenCV's COLOR_RGB2YUV first."""
    rng = np.random.default_rng(3)
    table = ColorTable(rng.integers(0, len(ColorClass), TABLE_SHAPE, dtype=np.uint8))
    yuv = rng.integers(0, 256, (7, 11, 3), dtype=np.uint8)
    expected = table.table[yuv[..., 0] >> 2, yuv[..., 1] >> 2, yuv[..., 2] >> 2]
    assert np.array_equal(table.classify(yuv), expected)
    assert np.array_equal(table.classify(yuv[2, 3]), expected[2, 3])
    rgb = rng.integers(0, 256, (5, 9, 3), dtype=np.uint8)
    assert np.array_equal(table.classify_rgb(rgb), table.classify(cv2.cvtColor(rgb, cv2.COLOR_RGB2YUV)))


@pytest.mark.parametrize("pixels, message", [
    (np.zeros((4, 3), np.float32), "uint8"),
    (np.zeros((4, 2), np.uint8), r"\(\.\.\., 3\)"),
])
def test_classify_refuses_pixels_that_are_not_uint8_triples(pixels, message):
    """Float pixels or pixels without three channels are refused, saying what is expected."""
    with pytest.raises(OmniVisionError, match=message):
        ColorTable.empty().classify(pixels)


def test_calibration_refuses_a_label_image_of_another_size():
    """A sample whose labels do not match its image is refused naming the sample."""
    with pytest.raises(OmniVisionError, match="sample 1: the labels must be integers of shape"):
        ColorTable.calibrate([_patch((1, 2, 3), ColorClass.GREEN, 4), (np.zeros((2, 2, 3), np.uint8),
                                                                        np.zeros((3, 2), np.uint8))])


def test_a_saved_table_loads_back_identical(tmp_path):
    """save then load gives the same cells and counts, and classifies the same."""
    table = calibrated_table(MIRROR)
    path = tmp_path / "omni.colors"
    table.save(path)
    again = ColorTable.load(path)
    assert again == table
    assert np.array_equal(again.table, table.table)
    assert np.array_equal(again.labelled_pixels, table.labelled_pixels)
    image, _ = render(MIRROR, training_scenes(1, seed=5)[0])
    assert np.array_equal(again.classify_rgb(image), table.classify_rgb(image))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["omni.colors"]  # no temporary file left


def _write(path, **arrays):
    with open(path, "wb") as stream:
        np.savez(stream, **arrays)


def _write_truncated(path):
    ColorTable.empty().save(path)
    path.write_bytes(path.read_bytes()[:300])


def _write_array(path, array):
    with open(path, "wb") as stream:
        np.save(stream, array)


def _write_huge_declaration(path):
    """A small file whose table declares 2 GiB (its data cut short): once read whole before its shape was checked."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "|u1", "fortran_order": False, "shape": (2048, 1024, 1024)})
    with zipfile.ZipFile(path, "w") as archive:
        for name, array in _good(table=None).items():
            with archive.open(f"{name}.npy", "w") as member:
                np.save(member, array)
        archive.writestr("table.npy", header.getvalue() + bytes(1 << 20))


def _good(**changes):
    arrays = {"format_version": np.int64(1), "table": np.zeros(TABLE_SHAPE, np.uint8),
              "labelled_pixels": np.zeros(len(ColorClass), np.int64)}
    arrays.update(changes)
    return {k: v for k, v in arrays.items() if v is not None}


@pytest.mark.parametrize("make, message", [
    (lambda p: p.write_bytes(b""), "the file is empty"),
    (lambda p: None, "cannot read it"),
    (lambda p: p.write_text("not a table"), "truncated or not a colour table archive"),
    (_write_truncated, "truncated"),
    (lambda p: _write_array(p, np.zeros(4)), "found a single array"),
    (lambda p: _write(p, **_good(table=None)), r"missing \['table'\]"),
    (lambda p: _write(p, **_good(format_version=np.int64(2))), "format_version 2 is not the supported 1"),
    (lambda p: _write(p, **_good(table=np.zeros((64, 64, 32), np.uint8))), r"shape \(64, 64, 64\), got \(64, 64, 32\)"),
    (lambda p: _write(p, **_good(table=np.zeros(TABLE_SHAPE, np.int32))), "must be uint8"),
    (lambda p: _write(p, **_good(table=np.full(TABLE_SHAPE, 9, np.uint8))), "ColorClass values 0-4, found 9"),
    (lambda p: _write(p, **_good(labelled_pixels=np.array([-1, 0, 0, 0, 0]))), "non-negative"),
    (_write_huge_declaration, r"table must have shape \(64, 64, 64\), got \(2048, 1024, 1024\) of \|u1 declared"),
])
def test_loading_a_bad_table_file_names_the_file_and_the_problem(tmp_path, make, message):
    """An empty, missing, foreign, truncated, wrong-shaped, wrong-typed or out-of-range file is refused with an
    OmniVisionError that names the file and says what is wrong."""
    path = tmp_path / "bad.colors"
    make(path)
    with pytest.raises(OmniVisionError, match=message) as raised:
        ColorTable.load(path)
    assert str(path) in str(raised.value)


@pytest.mark.parametrize("image, message", [
    (np.zeros((480, 640, 3), np.uint8) + 100, r"480 x 480 px \(shape \(480, 480, 3\)\), got shape \(480, 640, 3\)"),
    (np.zeros((480, 480), np.uint8) + 100, r"got shape \(480, 480\)"),
    (np.zeros((480, 480, 4), np.uint8) + 100, r"got shape \(480, 480, 4\)"),
    (np.zeros((480, 480, 3), np.float32) + 0.5, "must be uint8, got float32"),
    ([[1, 2, 3]], "must be a numpy array, got list"),
    (np.zeros((480, 480, 3), np.uint8), "the image is black"),
    (np.full((480, 480, 3), 255, np.uint8), "the image is saturated"),
])
def test_check_image_refuses_frames_the_vision_cannot_use(image, message):
    """A wrong size, grey or RGBA frame, a float frame, a list, a black or a saturated frame: OmniVisionError with
    the reason."""
    with pytest.raises(OmniVisionError, match=message):
        check_image(image, MIRROR)


def test_check_image_returns_a_contiguous_copy():
    """A usable frame comes back C-contiguous and equal, and independent of the caller's buffer."""
    image, _ = render(MIRROR, training_scenes(1, seed=4)[0])
    bgr_view = image[..., ::-1]
    checked = check_image(bgr_view, MIRROR)
    assert checked.flags.c_contiguous and np.array_equal(checked, bgr_view)
    image[:] = 0
    assert checked.any()


@pytest.mark.parametrize("kwargs, message", [
    ({"min_votes": 0}, "min_votes"),
    ({"fill_distance": -1.0}, "fill_distance"),
    ({"fill_distance": float("nan")}, "fill_distance"),
])
def test_bad_calibration_parameters_are_refused(kwargs, message):
    """Parameters out of range are refused naming the parameter."""
    with pytest.raises(OmniVisionError, match=message):
        CalibrationParams(**kwargs)


def test_bad_image_check_parameters_are_refused():
    """Black and saturated levels that cross are refused."""
    with pytest.raises(OmniVisionError, match="min_mean_level < max_mean_level"):
        ImageCheckParams(min_mean_level=200.0, max_mean_level=100.0)
