"""The firmware tier: skipped, with one reason line, where it cannot run."""

from __future__ import annotations

import pytest
from firmware.avr import missing_prerequisite


# session scope: checked before any module's own fixtures, which build and run firmware
@pytest.fixture(autouse=True, scope="session")
def _firmware_toolchain() -> None:
    reason = missing_prerequisite()
    if reason is not None:
        pytest.skip(f"firmware tier: {reason}")
