"""Missions: loading, checking and running state machines.

This package is the only user of ``yaml`` and ``transitions``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from roboscript.errors import InputError, MissionError

__all__ = ["load_mission"]


def load_mission(path: str | Path, profile: Any = None) -> tuple[Any, list[InputError]]:
    """Load and check a mission file.

    Args:
        path: A ``.yaml`` mission.
        profile: A robot profile to check capabilities against, or ``None``.

    Returns:
        The :class:`~roboscript.mission.spec.MissionSpec` and its warnings.

    Raises:
        MissionError: The file is invalid (every problem is in ``problems``).
    """
    suffix = Path(path).suffix.lower()
    if suffix in (".yaml", ".yml"):
        from roboscript.mission.yaml_loader import load_yaml_mission

        return load_yaml_mission(path, profile)
    raise MissionError(
        f"a mission file ends in .yaml (got '{suffix or Path(path).name}')", path=str(path)
    )
