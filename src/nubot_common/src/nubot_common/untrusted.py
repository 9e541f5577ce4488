"""JSON from a peer (the RefBox, a browser page): decoded whole or refused with one error, never another exception.

Requires: nothing but the standard library. Provides: ``json_object(raw, max_depth)`` -> the decoded JSON object, or
``UntrustedInputError`` (a ``NubotCommonError``) naming what is wrong: not UTF-8, malformed, nested deeper than
``max_depth`` (checked before decoding: a message nested 40,000 deep would exhaust the decoder's recursion), a
number too long to convert (an integer of over 4,300 digits, Python's limit), ``NaN`` or ``Infinity`` (not JSON),
or a JSON value that is not an object.
"""

from __future__ import annotations

import json
from typing import Any

from nubot_common import NubotCommonError

MAX_DEPTH = 32  # nesting of arrays and objects a peer's message may have (the RefBox's and the page's need 3)
EXCERPT = 80  # characters of a bad message quoted in its error


class UntrustedInputError(NubotCommonError):
    """A peer's message that cannot be taken."""


def _refuse_constant(name: str) -> Any:
    raise UntrustedInputError(f"{name} is not a JSON number")


def nesting_depth(text: str) -> int:
    """The deepest nesting of arrays and objects in ``text``, brackets inside strings aside."""
    if text.count("[") + text.count("{") <= 1:
        return text.count("[") + text.count("{")
    depth = deepest = 0
    in_string = escaped = False
    for char in text:
        if in_string:
            if escaped:
                escaped = False
            elif char == "\\":
                escaped = True
            elif char == '"':
                in_string = False
        elif char == '"':
            in_string = True
        elif char in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "]}":
            depth -= 1
    return deepest


def excerpt(text: str) -> str:
    return repr(text[:EXCERPT] + ("..." if len(text) > EXCERPT else ""))


def json_object(raw: bytes | str, max_depth: int = MAX_DEPTH) -> dict[str, Any]:
    """Decode ``raw`` as one JSON object; raise ``UntrustedInputError`` for anything else."""
    if isinstance(raw, bytes):
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise UntrustedInputError(f"message is not UTF-8 ({exc.reason} at byte {exc.start})") from None
    else:
        text = raw
    depth = nesting_depth(text)
    if depth > max_depth:
        raise UntrustedInputError(f"JSON nested {depth} deep, more than {max_depth}: {excerpt(text)}")
    try:
        message = json.loads(text, parse_constant=_refuse_constant)
    except json.JSONDecodeError as exc:
        raise UntrustedInputError(f"malformed JSON ({exc.msg} at character {exc.pos}): {excerpt(text)}") from None
    except (ValueError, RecursionError) as exc:  # a number of over 4,300 digits; nesting the scan missed
        raise UntrustedInputError(f"JSON that cannot be decoded ({str(exc)[:80]}): {excerpt(text)}") from None
    if not isinstance(message, dict):
        raise UntrustedInputError(f"JSON {type(message).__name__}, not an object: {excerpt(text)}")
    return message
