"""A real browser (headless Chromium) on a page of another web site tries to command a viewer on this machine: from
another origin, and by DNS rebinding (the site's name resolving to 127.0.0.1, Chromium's host resolver rules playing
the site's DNS): the viewer refuses, and no command reaches the match."""

from __future__ import annotations

import asyncio
import http.server
import threading

import pytest

from coach4sim.viewer_server import ViewerServer
from nubot_tools.bench.hostile import RecordingBackend
from nubot_tools.browser import Page

pytestmark = pytest.mark.integration

ATTACK = """<!doctype html><title>waiting</title><script>
const ws = new WebSocket("ws://127.0.0.1:%d/ws");
ws.onopen = () => { ws.send(JSON.stringify({type: "command", command: "STOPROBOT", team: "nubot"}));
                    document.title = "open"; };
ws.onerror = () => { if (document.title !== "open") document.title = "refused"; };
</script>"""


def _serving(backend: RecordingBackend) -> tuple[ViewerServer, asyncio.AbstractEventLoop, threading.Thread]:
    server = ViewerServer(backend, port=0, log=lambda text: None)
    loop = asyncio.new_event_loop()
    urls: list[str] = []
    viewer = threading.Thread(target=lambda: loop.run_until_complete(server.run(ready=urls.append)), daemon=True)
    viewer.start()
    while not urls:
        threading.Event().wait(0.01)
    return server, loop, viewer


REBIND = """const ws = new WebSocket("ws://evil.test:%d/ws");
ws.onopen = () => { ws.send(JSON.stringify({type: "command", command: "STOPROBOT", team: "nubot"}));
                    document.title = "open"; };
ws.onerror = () => { if (document.title !== "open") document.title = "refused"; };"""


def test_a_page_of_another_site_cannot_command_the_viewer_from_its_origin_or_by_dns_rebinding():
    backend = RecordingBackend()
    server, loop, viewer = _serving(backend)
    page = ATTACK % server.port

    class Attacker(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 - http.server's name
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.end_headers()
            self.wfile.write(page.encode())

        def log_message(self, *_args: object) -> None:
            pass

    site = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Attacker)
    threading.Thread(target=site.serve_forever, daemon=True).start()
    rules = ("--host-resolver-rules=MAP evil.test 127.0.0.1",)  # the site's DNS, rebound to this machine
    try:
        with Page(f"http://127.0.0.1:{site.server_address[1]}/", flags=rules) as browser:
            browser.wait_for(lambda: browser.driver.title in ("refused", "open"), 20.0, "the page's attempt")
            threading.Event().wait(0.5)  # a command sent on an open socket would have arrived by now
            assert browser.driver.title == "refused" and backend.commands == [], "another origin"
            browser.driver.get(f"http://evil.test:{server.port}/")
            assert "viewer" not in browser.driver.title.lower() and "403" in browser.driver.page_source
            browser.run(REBIND % server.port)
            browser.wait_for(lambda: browser.driver.title in ("refused", "open"), 20.0, "the rebound page's attempt")
            threading.Event().wait(0.5)
            assert browser.driver.title == "refused" and backend.commands == [], "a rebound name"
    finally:
        site.shutdown()
        loop.call_soon_threadsafe(server.stop)
        viewer.join(timeout=10)
