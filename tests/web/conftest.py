"""The browser app, built once for the tests that open it in Chromium."""

from __future__ import annotations

from pathlib import Path

import pytest
from web_app import build_or_skip


@pytest.fixture(scope="session")
def app(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The built app's page (``index.html``); skips without Chromium or the npm packages."""
    return build_or_skip(tmp_path_factory.mktemp("web") / "app").page
