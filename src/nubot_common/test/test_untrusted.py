"""A peer's JSON: one object, or one UntrustedInputError naming why not; never another exception."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from nubot_common import NubotCommonError
from nubot_common.untrusted import UntrustedInputError, json_object, nesting_depth


def test_an_object_decodes_and_brackets_inside_strings_do_not_count_as_nesting():
    text = '{"a": "[[[[{{{{\\"]]]]", "b": [1, [2, {"c": 3}]]}'
    assert nesting_depth(text) == 4  # the object, two lists, the inner object
    assert json_object(text.encode(), max_depth=4) == {"a": '[[[[{{{{"]]]]', "b": [1, [2, {"c": 3}]]}
    with pytest.raises(UntrustedInputError, match="nested 4 deep, more than 3"):
        json_object(text, max_depth=3)


@pytest.mark.parametrize(("raw", "error"), [
    (b"\xff{}", "not UTF-8"),
    (b'{"a": ', "malformed JSON"),
    (b"[1, 2]", "JSON list, not an object"),
    (b"[" * 100_000 + b"]" * 100_000, "nested 100000 deep"),
    (b'{"a": ' + b"1" * 5000 + b"}", "cannot be decoded"),
    (b'{"a": NaN}', "NaN is not a JSON number"),
    (b'{"a": -Infinity}', "-Infinity is not a JSON number"),
], ids=["not_utf8", "truncated", "list", "deep", "huge_integer", "nan", "infinity"])
def test_anything_else_is_one_clear_error(raw, error):
    with pytest.raises(UntrustedInputError, match=error) as caught:
        json_object(raw)
    assert isinstance(caught.value, NubotCommonError)


@given(st.binary(max_size=400) | st.text(max_size=400) | st.integers(1, 5000).map(lambda n: "[" * n + "]" * n)
       | st.integers(1, 9000).map(lambda n: '{"a": ' + "7" * n + "}"))
def test_property_any_input_is_an_object_or_one_clear_error(raw):
    try:
        assert isinstance(json_object(raw), dict)
    except UntrustedInputError:
        pass
