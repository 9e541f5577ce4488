"""StampPairs: a camera frame and the truth of its stamp are paired whichever comes first."""

from omni_vision.stamp_pairs import StampPairs


def test_either_order_pairs_once_and_unmatched_items_wait():
    pairs = StampPairs(kept=30)
    assert pairs.first(1.0, "frame 1") is None, "its truth has not come"
    assert pairs.second(1.00001, "truth 1") == "frame 1", "the truth that comes after its frame finds it"
    assert pairs.second(2.0, "truth 2") is None
    assert pairs.first(2.0, "frame 2") == "truth 2", "the frame that comes after its truth finds it"
    assert pairs.first(1.0, "frame 1 again") is None, "a pair is made once"


def test_only_the_newest_are_kept():
    pairs = StampPairs(kept=2)
    for t in (1.0, 2.0, 3.0):
        pairs.first(t, f"frame {t}")
    assert pairs.second(1.0, "truth 1") is None, "the oldest frame was let go"
    assert pairs.second(3.0, "truth 3") == "frame 3.0"
