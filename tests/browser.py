"""A headless Chromium driven over the DevTools protocol, for tests of pages in a real browser.

The protocol runs over two pipes (``--remote-debugging-pipe``: Chromium reads commands on its
fd 3 and writes replies on fd 4, each a JSON message ending in a NUL byte), so no WebSocket
client and no debugging port are needed: standard library only.

    with open_browser(tmp_path) as browser:     # skips the test without Chromium
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.x') !== null")
        browser.click("button[data-action=play]")
        assert browser.evaluate("document.title") == "..."

Waits have generous time limits that only stop a broken test; no test asserts on a duration.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import select
import shutil
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S

__all__ = ["Browser", "BrowserError", "chromium", "open_browser"]

FLAGS = (
    "--headless",
    "--no-sandbox",  # tests run as root in CI containers
    "--disable-gpu",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
    "--window-size=1200,1000",
)


class BrowserError(AssertionError):
    """The browser said no (a failed command, a script that threw) or took too long."""


def chromium() -> str | None:
    """The Chromium binary, or ``None`` (``.ci/run`` installs Debian's package)."""
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    return None


class Browser:
    """One headless Chromium with one page.

    Args:
        executable: The Chromium binary.
        profile: An empty folder for the browser's profile.
        timeout_s: Longest wait for one reply (a bound for a hang: a busy machine may make
            Chromium slow, never a broken test pass).
    """

    def __init__(self, executable: str, profile: Path, *, timeout_s: float = HANG_BOUND_S) -> None:
        self.timeout_s = timeout_s
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        # Above 4, so putting one on fd 3 never overwrites the other before it reaches fd 4.
        high_r = fcntl.fcntl(to_browser_r, fcntl.F_DUPFD_CLOEXEC, 10)
        high_w = fcntl.fcntl(from_browser_w, fcntl.F_DUPFD_CLOEXEC, 10)
        os.close(to_browser_r)
        os.close(from_browser_w)

        def pipes_on_3_and_4() -> None:  # in the child, before exec
            os.dup2(high_r, 3)
            os.dup2(high_w, 4)

        # close_fds=False keeps fds 3 and 4; every other descriptor is close-on-exec.
        self._process = subprocess.Popen(
            [
                executable,
                *FLAGS,
                "--remote-debugging-pipe",
                f"--user-data-dir={profile}",
                "about:blank",
            ],
            close_fds=False,
            preexec_fn=pipes_on_3_and_4,  # noqa: PLW1509 - it only moves two pipes
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        os.close(high_r)
        os.close(high_w)
        self._buffer = b""
        self.errors: list[str] = []
        """Uncaught exceptions the page's scripts threw, as Chromium describes them."""
        self.bindings: list[tuple[str, str]] = []
        """``(name, payload)`` of each call the page made to a binding (``add_binding``)."""
        self._next_id = 0
        self._session: str | None = None
        target = self._call("Target.createTarget", {"url": "about:blank"}, session=False)
        attached = self._call(
            "Target.attachToTarget", {"targetId": target["targetId"], "flatten": True}, False
        )
        self._session = attached["sessionId"]
        self._call("Page.enable")
        self._call("Runtime.enable")

    # ------------------------------------------------------------------ the protocol

    def _call(
        self, method: str, params: dict[str, Any] | None = None, session: bool = True
    ) -> dict[str, Any]:
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params or {}}
        if session and self._session is not None:
            message["sessionId"] = self._session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + self.timeout_s
        while True:
            reply = self._read(deadline)
            self._note(reply)
            if reply.get("id") != self._next_id:
                continue  # an event, or a reply to nobody
            if "error" in reply:
                raise BrowserError(f"{method}: {reply['error'].get('message')}")
            result: dict[str, Any] = reply.get("result", {})
            return result

    def _note(self, message: dict[str, Any]) -> None:
        """Keep what an event says that a test may ask for later."""
        method = message.get("method")
        if method == "Runtime.exceptionThrown":
            details = message["params"]["exceptionDetails"]
            self.errors.append(
                details.get("exception", {}).get("description") or details.get("text", "")
            )
        elif method == "Runtime.bindingCalled":
            self.bindings.append((message["params"]["name"], message["params"]["payload"]))

    def _read(self, deadline: float, *, quiet: bool = False) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                if quiet:
                    return {}
                raise BrowserError("Chromium did not answer in time")
            ready, _, _ = select.select([self._from_browser], [], [], left)
            if ready:
                chunk = os.read(self._from_browser, 1 << 16)
                if not chunk:
                    raise BrowserError("Chromium closed the DevTools pipe")
                self._buffer += chunk
        raw, _, self._buffer = self._buffer.partition(b"\0")
        message: dict[str, Any] = json.loads(raw)
        return message

    # --------------------------------------------------------------------- the API

    def open(self, url: str) -> None:
        """Load ``url`` and wait until the page has finished loading."""
        # The page being left is 'complete' already: mark it, and wait for one without the mark.
        self.evaluate("window.rsLeaving = true")
        self._call("Page.navigate", {"url": url})
        self.wait_for("!window.rsLeaving && document.readyState === 'complete'")

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression in the page (promises are awaited).

        Raises:
            BrowserError: The script threw.
        """
        reply = self._call(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
        )
        if "exceptionDetails" in reply:
            details = reply["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"{expression!r} threw: {text}")
        return reply["result"].get("value")

    def add_binding(self, name: str) -> None:
        """Give every page a function ``window[name](text)`` whose calls :meth:`take_bindings`
        returns, in order (the page's way to hand bytes to the test as they happen)."""
        self._call("Runtime.addBinding", {"name": name})

    def take_bindings(self, wait_s: float) -> list[tuple[str, str]]:
        """The binding calls the page made since the last time, waiting up to ``wait_s``
        for events to arrive."""
        deadline = time.monotonic() + wait_s
        while True:
            message = self._read(deadline, quiet=True)
            self._note(message)
            if not message or time.monotonic() > deadline:
                break
        taken, self.bindings = self.bindings, []
        return taken

    def wait_for(self, condition: str, timeout_s: float = HANG_BOUND_S) -> Any:
        """Wait until a JavaScript expression is truthy; return its value.

        Raises:
            BrowserError: Still false after ``timeout_s`` (a limit for broken tests only).
        """
        deadline = time.monotonic() + timeout_s
        while True:
            value = self.evaluate(condition)
            if value:
                return value
            if time.monotonic() > deadline:
                raise BrowserError(f"never true: {condition}")
            time.sleep(0.02)

    def click(self, selector: str, *, x_fraction: float = 0.5) -> None:
        """Click the first element matching ``selector`` with real mouse events.

        Args:
            selector: A CSS selector.
            x_fraction: Where across the element to click, 0 (left edge) to 1 (right edge).
        """
        box = self.evaluate(
            "(() => { const e = document.querySelector(" + json.dumps(selector) + ");"
            " if (!e) return null; e.scrollIntoView({block: 'center'});"
            " const r = e.getBoundingClientRect();"
            " return [r.left, r.top, r.width, r.height]; })()"
        )
        if box is None:
            raise BrowserError(f"nothing matches {selector}")
        x = box[0] + box[2] * min(max(x_fraction, 0.0), 1.0)
        x = min(max(x, box[0] + 1), box[0] + box[2] - 1)
        y = box[1] + box[3] / 2
        for kind in ("mouseMoved", "mousePressed", "mouseReleased"):
            self._call(
                "Input.dispatchMouseEvent",
                {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1},
            )

    def close(self) -> None:
        """End the browser."""
        with contextlib.suppress(BrowserError, OSError):
            self._call("Browser.close", session=False)
        with contextlib.suppress(OSError):
            os.close(self._to_browser)
        try:
            self._process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        os.close(self._from_browser)


@contextlib.contextmanager
def open_browser(folder: Path) -> Iterator[Browser]:
    """A headless Chromium with its profile in ``folder``; skips the test without one."""
    executable = chromium()
    if executable is None:
        pytest.skip("Chromium is not installed (apt-get install chromium; .ci/run does it)")
    profile = folder / "chromium-profile"
    profile.mkdir(exist_ok=True)
    browser = Browser(executable, profile)
    try:
        yield browser
    finally:
        browser.close()
