"""The browser app built once and opened as a student opens it: from file://, network off.

For the page's tests in headless Chromium; a test without Chromium, or where the app cannot be
built (no npm, no cached packages), is skipped with the reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest
from browser import Browser, chromium

from roboscript.web.build import BuiltApp, WebBuildError, build_web_app

__all__ = ["FLOOD", "LONG_S", "build_or_skip", "open_offline"]

FLOOD = """from roboscript import Mission, Wait, state

for n in range(2500):
    print("again", n)


class Flood(Mission):
    wait = state(Wait(0.2), initial=True, on_done="done")
    done = state(final="success")
"""
"""A mission that prints 2500 lines while it loads: more than a run's record keeps."""
LONG_S = 900.0  # Python in WebAssembly on a saturated machine takes its time; never a limit


def build_or_skip(folder: Path, specs: Sequence[str | Path] = ()) -> BuiltApp:
    """The app built into ``folder`` (with ``specs`` to practise against)."""
    if chromium() is None:
        pytest.skip("Chromium is not installed (apt-get install chromium; .ci/run does it)")
    try:
        return build_web_app(folder, specs=specs)
    except WebBuildError as exc:
        pytest.skip(f"the web app cannot be built here: {exc}")


def open_offline(page: Path, profile: Path, *, before: str = "", agent: str = "") -> Browser:
    """``page`` in a fresh headless Chromium with the network off, once its body exists.

    Args:
        page: The app's ``index.html``.
        profile: An empty folder for the browser's profile.
        before: A script run before the page's own (a stand-in for another browser).
        agent: Another browser's user agent.
    """
    browser = Browser(chromium() or "", profile, timeout_s=LONG_S)
    browser._call("Network.enable")
    browser._call(
        "Network.emulateNetworkConditions",
        {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1},
    )
    if agent:
        browser._call("Emulation.setUserAgentOverride", {"userAgent": agent})
    if before:
        browser._call("Page.addScriptToEvaluateOnNewDocument", {"source": before})
    browser._call("Page.navigate", {"url": page.as_uri()})
    browser.wait_for("document.body !== null", LONG_S)
    return browser
