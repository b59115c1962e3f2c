"""Fixtures of the expectation tests."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A spec's folder holding a teacher's check file, a broken one and a text file."""
    (tmp_path / "laps.py").write_text("def lap(record):\n    return True\n", encoding="utf-8")
    (tmp_path / "broken.py").write_text("def lap(:\n", encoding="utf-8")
    (tmp_path / "notes.txt").write_text("def lap(record):\n    return True\n", encoding="utf-8")
    return tmp_path
