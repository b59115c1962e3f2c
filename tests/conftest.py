"""Shared fixtures."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest


@pytest.fixture
def write_mission(tmp_path: Path) -> Callable[..., Path]:
    """Write a mission file and return its path."""

    def write(text: str, name: str = "mission.yaml") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write
