"""Shared fixtures: a real browser (Debian's chromium driven by Playwright) for the pages the
verifier writes. Skipped, with the reason, where Playwright or chromium is missing."""

from __future__ import annotations

import os
import shutil
import signal
from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import settings

settings.register_profile("repeatable", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))
"""The property-based tests draw the same examples on every run (a CI run passes or fails
alike on every machine); ``HYPOTHESIS_PROFILE=explore`` draws new ones each run."""


@pytest.fixture(autouse=True)
def _the_watchdog_is_left_idle() -> Iterator[None]:
    """Every test leaves the watchdog as it found it: no user-code count, no armed deadline,
    no memory watch. One left behind would ring in the next test's (or pytest's own) code, far
    from its cause; here the test that left it fails, and the next one starts clean."""
    from gather_verify import watchdog

    yield
    left = (watchdog._inside, len(watchdog._ARMED), len(watchdog._WATCHING))
    if left != (0, 0, 0):
        watchdog._inside = 0
        watchdog._ARMED.clear()
        watchdog._WATCHING.clear()
        signal.setitimer(signal.ITIMER_REAL, 0)
        pytest.fail(f"the watchdog was left busy (user-code depth, deadlines, memory watches):"
                    f" {left}")


CHROMIUM = ("chromium", "chromium-browser", "google-chrome")


def _executable() -> str | None:
    given = os.environ.get("GATHER_VERIFY_CHROMIUM")
    if given:
        return given
    for name in CHROMIUM:
        found = shutil.which(name)
        if found:
            return found
    return None


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """A headless chromium (the system's: nothing is downloaded)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("no browser test: Playwright is not installed (pip install -e '.[browser]')")
    path = _executable()
    if path is None:
        pytest.skip("no browser test: no chromium on PATH (apt-get install chromium, or set "
                    "GATHER_VERIFY_CHROMIUM)")
    with sync_playwright() as p:
        try:
            browser = p.chromium.launch(executable_path=path,
                                        args=["--disable-gpu", "--no-sandbox"])
        except Exception as error:  # a browser that does not start is a missing browser
            pytest.skip(f"no browser test: chromium at {path} did not start: "
                        f"{str(error).splitlines()[0]}")
        yield browser
        browser.close()


class Page:
    """A browser page that records console errors, page errors and every request that
    leaves the local files (the pages must load nothing from the network)."""

    def __init__(self, browser: Any) -> None:
        self.page = browser.new_page(viewport={"width": 1200, "height": 900})
        self.errors: list[str] = []
        self.remote: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("request", lambda r: None if r.url.startswith(("file:", "data:", "about:"))
                     else self.remote.append(r.url))


@pytest.fixture
def web(browser: Any) -> Iterator[Page]:
    p = Page(browser)
    yield p
    p.page.close()
