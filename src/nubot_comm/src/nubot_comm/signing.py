"""The team's shared key: every datagram of the link signed, and only signed ones taken, when a key is set.

Plain LCM multicast lets anyone on the team's network speak for a robot or the coach. With a key, each datagram
carries an HMAC-SHA256 tag (Python's ``hmac``) of its channel and its bytes, appended after the LCM message;
a receiver with the key drops a datagram without a valid tag (``DropReason.SIGNATURE``) before decoding it.
Replays of signed datagrams are what the link's ordering refuses (a sequence number heard before, a session
older than the one heard, a stamp beyond ``max_clock_skew``).

Provides: ``TAG_BYTES``, ``sign(key, channel, data)``, ``verify(key, channel, datagram)`` -> the message bytes or
None, and ``load_key(path)``: a key file's bytes (at least ``MIN_KEY_BYTES``, a trailing newline stripped),
refusing a missing, short or other-readable file with ``NubotCommError``. Make one with
``head -c 32 /dev/urandom | base64 > team.key && chmod 600 team.key`` and copy it to every robot and the coach.
"""

from __future__ import annotations

import hashlib
import hmac
import os
import stat
from pathlib import Path

from nubot_comm import NubotCommError

TAG_BYTES = 32  # HMAC-SHA256
MIN_KEY_BYTES = 16


def _tag(key: bytes, channel: str, data: bytes) -> bytes:
    return hmac.new(key, channel.encode() + b"\0" + data, hashlib.sha256).digest()


def sign(key: bytes, channel: str, data: bytes) -> bytes:
    """``data`` for ``channel`` with its tag appended."""
    return data + _tag(key, channel, data)


def verify(key: bytes, channel: str, datagram: bytes) -> bytes | None:
    """The message of a datagram whose tag is the key's for ``channel``, else None."""
    if len(datagram) <= TAG_BYTES:
        return None
    data, tag = datagram[:-TAG_BYTES], datagram[-TAG_BYTES:]
    return data if hmac.compare_digest(tag, _tag(key, channel, data)) else None


def load_key(path: str | os.PathLike[str]) -> bytes:
    """The team key in file ``path``."""
    where = Path(path)
    try:
        mode = where.stat().st_mode
        key = where.read_bytes().rstrip(b"\r\n")
    except OSError as exc:
        raise NubotCommError(f"team key {where}: cannot read it ({exc.strerror or exc})") from None
    if mode & (stat.S_IRWXG | stat.S_IRWXO):
        raise NubotCommError(f"team key {where}: others may read it (mode {stat.S_IMODE(mode):o}); chmod 600 it")
    if len(key) < MIN_KEY_BYTES:
        raise NubotCommError(f"team key {where}: {len(key)} bytes, at least {MIN_KEY_BYTES} (head -c 32 "
                             "/dev/urandom | base64 makes one)")
    return key
