"""The firmware tier: skipped, with one reason line, where it cannot run."""

from __future__ import annotations

import pytest
from firmware.avr import missing_prerequisite


@pytest.fixture(autouse=True)
def _firmware_toolchain() -> None:
    reason = missing_prerequisite()
    if reason is not None:
        pytest.skip(f"firmware tier: {reason}")
