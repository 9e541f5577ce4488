"""Input from outside (a peer's JSON: the RefBox, a browser page; a file from elsewhere): taken whole or refused
with one error, never another exception, and never a size it declares read before it is checked.

Requires: numpy. Provides: ``json_object(raw, max_depth)`` -> the decoded JSON object, or
``UntrustedInputError`` (a ``NubotCommonError``) naming what is wrong: not UTF-8, malformed, nested deeper than
``max_depth`` (checked before decoding: a message nested 40,000 deep would exhaust the decoder's recursion), a
number too long to convert (an integer of over 4,300 digits, Python's limit), ``NaN`` or ``Infinity`` (not JSON),
or a JSON value that is not an object; and ``declared_arrays(path)``, what a ``.npz`` file's arrays declare they are,
read before any is loaded.
"""

from __future__ import annotations

import json
import os
import zipfile
from typing import Any

import numpy as np

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


def declared_arrays(path: str | os.PathLike[str]) -> dict[str, tuple[tuple[int, ...], np.dtype[Any]]]:
    """Each array of a ``.npz`` archive with the shape and type its header declares, read without loading any
    array: a 2 MB file may declare a 2 GB array, to be refused before it is read. Raises ``UntrustedInputError``
    for a file that is no such archive."""
    arrays: dict[str, tuple[tuple[int, ...], np.dtype[Any]]] = {}
    npy: Any = np.lib.format  # (untyped in numpy's stubs)
    try:
        with zipfile.ZipFile(path) as archive:
            for member in archive.namelist():
                if not member.endswith(".npy"):
                    continue
                with archive.open(member) as stream:
                    major, _minor = npy.read_magic(stream)
                    read = npy.read_array_header_1_0 if major == 1 else npy.read_array_header_2_0
                    shape, _fortran, dtype = read(stream)
                arrays[member.removesuffix(".npy")] = (tuple(shape), dtype)
    except Exception as exc:  # a damaged archive or header: zip's, zlib's, tokenize's errors and more
        raise UntrustedInputError(f"not an array archive (.npz): {exc or type(exc).__name__}") from None
    return arrays
