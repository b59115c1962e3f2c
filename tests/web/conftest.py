"""The browser app, built once for the tests that open it in Chromium."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from browser import Browser
from web_app import LONG_S, build_or_skip, open_offline


@pytest.fixture(scope="session")
def app(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The built app's page (``index.html``); skips without Chromium or the npm packages."""
    return build_or_skip(tmp_path_factory.mktemp("web") / "app").page


@pytest.fixture(scope="module")
def page(app: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Browser]:
    """The built app open offline in headless Chromium, ready (a module's tests share it; a
    module that needs the page otherwise defines its own)."""
    browser = open_offline(app, tmp_path_factory.mktemp("profile"))
    try:
        browser.wait_for("document.body.dataset.ready === '1'", LONG_S)
        yield browser
    finally:
        browser.close()
