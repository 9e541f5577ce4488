"""The team key's file: read when it is private and long enough, refused with the reason otherwise."""

import os

import pytest

from nubot_comm import NubotCommError
from nubot_comm.signing import load_key, sign, verify


def test_a_private_key_file_is_read_without_its_newline(tmp_path):
    path = tmp_path / "team.key"
    path.write_bytes(b"c2VjcmV0IHNlY3JldCBzZWNyZXQgc2VjcmV0IQ==\n")
    os.chmod(path, 0o600)
    key = load_key(path)
    assert key == b"c2VjcmV0IHNlY3JldCBzZWNyZXQgc2VjcmV0IQ=="
    assert verify(key, "NUBOT_TEAM_nubot", sign(key, "NUBOT_TEAM_nubot", b"message")) == b"message"
    assert verify(key, "NUBOT_COACH_nubot", sign(key, "NUBOT_TEAM_nubot", b"message")) is None


@pytest.mark.parametrize(("content", "mode", "message"), [
    (None, 0o600, "cannot read it"),
    (b"short\n", 0o600, "5 bytes, at least 16"),
    (b"a long enough secret of the team\n", 0o644, "others may read it"),
])
def test_a_bad_key_file_is_refused_with_the_reason(tmp_path, content, mode, message):
    path = tmp_path / "team.key"
    if content is not None:
        path.write_bytes(content)
        os.chmod(path, mode)
    with pytest.raises(NubotCommError, match=message):
        load_key(path)
