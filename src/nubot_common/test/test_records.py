"""fast_init: a frozen dataclass made through it is the record its own __init__ makes, in about half the time."""

import dataclasses
import pickle
from dataclasses import dataclass, field

import pytest

from nubot_common.records import fast_init


def _record(name: str) -> type:
    """The same frozen dataclass each call: defaults, factories and a keyword-only field."""

    @dataclass(frozen=True)
    class Record:
        a: int
        b: float = 2.0
        c: tuple[int, ...] = field(default_factory=tuple)
        d: list[int] = field(default_factory=list)
        e: str = field(default="e", kw_only=True)

    Record.__name__ = Record.__qualname__ = name
    return Record


Plain = _record("Plain")
Fast = fast_init(_record("Fast"))


@fast_init
@dataclass(frozen=True)
class Checked:
    x: float

    def __post_init__(self) -> None:
        if self.x < 0:
            raise ValueError(f"x must be >= 0, got {self.x}")


def _fields(record):
    return dataclasses.asdict(record)


@pytest.mark.parametrize("args, kwargs", [((1,), {}), ((1, 3.0), {}), ((1,), {"c": (4,), "e": "f"}),
                                          ((), {"a": 5, "d": [1], "b": -1.0})])
def test_the_same_record_from_the_same_arguments(args, kwargs):
    fast, plain = Fast(*args, **kwargs), Plain(*args, **kwargs)
    assert _fields(fast) == _fields(plain)
    assert repr(fast) == repr(plain).replace("Plain", "Fast")
    assert fast == Fast(*args, **kwargs)
    assert dataclasses.replace(fast, a=9) == Fast(9, *args[1:], **{k: v for k, v in kwargs.items() if k != "a"})
    assert pickle.loads(pickle.dumps(fast)) == fast


def test_a_default_factory_makes_a_new_value_each_time_and_a_given_one_is_kept():
    one, two = Fast(1), Fast(2)
    assert one.d == [] and one.d is not two.d
    given = [3]
    assert Fast(1, d=given).d is given


def test_the_record_stays_frozen_and_its_signature_refuses_what_the_dataclass_refuses():
    record = Fast(1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        record.a = 2  # type: ignore[misc]
    for args, kwargs in [((), {}), ((1, 2.0, (), [], "e"), {}), ((1,), {"z": 1}), ((1,), {"a": 1})]:
        with pytest.raises(TypeError) as fast_error:
            Fast(*args, **kwargs)
        with pytest.raises(TypeError) as plain_error:
            Plain(*args, **kwargs)
        assert str(fast_error.value).split("() ", 1)[1] == str(plain_error.value).split("() ", 1)[1]


def test_post_init_still_checks():
    assert Checked(1.0).x == 1.0 and hash(Checked(1.0)) == hash(Checked(1.0))
    with pytest.raises(ValueError, match="x must be >= 0, got -1"):
        Checked(-1.0)


def test_only_a_frozen_dataclass_is_taken():
    with pytest.raises(TypeError, match="needs a @dataclass\\(frozen=True\\)"):
        fast_init(dataclass(type("Loose", (), {"__annotations__": {"a": int}})))

