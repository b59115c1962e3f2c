"""Shared fixtures, and Hypothesis set for any machine."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# Hypothesis times each example (200 ms) and the generation of its data by default: wall-clock
# limits that fail correct code on a machine whose every core is busy. The suite must pass
# there, so neither is checked; a stuck example is still bounded by pytest's timeout.
settings.register_profile(
    "any-machine", deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("any-machine")


@pytest.fixture
def write_mission(tmp_path: Path) -> Callable[..., Path]:
    """Write a mission file and return its path."""

    def write(text: str, name: str = "mission.yaml") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """The student works in ``tmp_path``, so messages name files as they typed them."""
    monkeypatch.chdir(tmp_path)
    before = set(sys.modules)
    yield tmp_path
    # files beside a mission (sizes.py, ...) are imported by name: forget them, so the next
    # test's file of the same name is imported afresh
    for name in set(sys.modules) - before:
        del sys.modules[name]
