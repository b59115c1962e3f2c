"""The browser app, built once for the tests that open it in Chromium."""

from __future__ import annotations

from pathlib import Path

import pytest
from browser import chromium

from roboscript.web.build import WebBuildError, build_web_app


@pytest.fixture(scope="session")
def app(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The built app's page (``index.html``); skips without Chromium or the npm packages."""
    if chromium() is None:
        pytest.skip("Chromium is not installed (apt-get install chromium; .ci/run does it)")
    try:
        built = build_web_app(tmp_path_factory.mktemp("web") / "app")
    except WebBuildError as exc:
        pytest.skip(f"the web app cannot be built here: {exc}")
    return built.page
