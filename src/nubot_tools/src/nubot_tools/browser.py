"""A headless Chromium (Debian's ``chromium`` and ``chromium-driver``, driven by selenium) that opens the match
viewer's page: for the tests, the benchmarks and the screenshots in ``docs/``.

Provides: ``Page(url)`` (a context manager): ``stats()`` (the page's own counters: frames, frames per second,
frames in which a robot moved, commands sent, replies), ``frame()`` (the last frame the page drew), ``click``,
``select``, ``slide`` (move the replay slider as a user does), ``wait_for`` and ``screenshot``.
Chromium starts with a fresh profile and without its background connections (this machine has no internet).
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.support.ui import Select

from nubot_common.processes import wait_until

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage")


class Page:
    def __init__(self, url: str, width: int = 1500, height: int = 860, flags: tuple[str, ...] = ()):
        self._profile = tempfile.TemporaryDirectory(prefix="viewer-chromium-")
        options = webdriver.ChromeOptions()
        options.binary_location = CHROMIUM
        for flag in (*FLAGS, *flags, f"--window-size={width},{height}", f"--user-data-dir={self._profile.name}"):
            options.add_argument(flag)
        self.driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
        self.driver.get(url)

    def __enter__(self) -> Page:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        try:
            self.driver.quit()
        finally:
            self._profile.cleanup()

    def run(self, script: str, *args: Any) -> Any:
        return self.driver.execute_script(script, *args)

    def stats(self) -> dict[str, Any]:
        return self.run("return window.viewerStats ? JSON.parse(JSON.stringify(window.viewerStats)) : null;")

    def frame(self) -> dict[str, Any] | None:
        return self.run("return window.viewerFrame ? window.viewerFrame() : null;")

    def text(self, element_id: str) -> str:
        return self.driver.find_element("id", element_id).text

    def click(self, css: str) -> None:
        self.driver.find_element("css selector", css).click()

    def select(self, element_id: str, value: str) -> None:
        Select(self.driver.find_element("id", element_id)).select_by_value(value)

    def slide(self, element_id: str, value: float) -> None:
        """Move a range input to ``value`` and let go, as a user's drag ends."""
        self.run("const s = document.getElementById(arguments[0]); s.value = arguments[1];"
                 "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change'));", element_id, value)

    def wait_for(self, predicate: Callable[[], Any], timeout: float, what: str, poll: float = 0.1) -> Any:
        """``nubot_common.processes.wait_until``, its timeout telling the page's counters and console too."""
        try:
            return wait_until(predicate, timeout, what, poll)
        except AssertionError as exc:
            raise AssertionError(f"{exc}; page stats {self.stats()}, "
                                 f"console {self.driver.get_log('browser')[-5:]}") from None

    def screenshot(self, path: Path) -> Path:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.driver.save_screenshot(str(path))
        return path
