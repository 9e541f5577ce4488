"""make match with the viewer's port taken (another match still holding it, say): the match goes on without the
live page, and the runner says why, in the viewer's own words (it once said only "Event loop is closed")."""

from __future__ import annotations

import socket

import pytest

from nubot_tools.ros.match_runner import start_viewer

pytestmark = pytest.mark.integration


def test_a_taken_port_is_reported_as_the_viewers_reason(ros_master, capsys):
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        viewer = start_viewer(ros_master, holder.getsockname()[1], timeout=20.0)
        try:
            said = capsys.readouterr().out
            assert "no live page: the viewer cannot listen on 127.0.0.1" in said and "Address already in use" in said
            assert "Event loop is closed" not in viewer.log_text()
        finally:
            viewer.stop()
