"""Missions: loading, checking and running state machines.

This package is the only user of ``transitions``; YAML is read by :mod:`roboscript.inputs`.
Both syntaxes build missions through :mod:`roboscript.mission.builder`.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from roboscript.errors import InputError, MissionError

if TYPE_CHECKING:
    from roboscript.mission.spec import MissionSpec
    from roboscript.profiles import RobotProfile

__all__ = ["load_mission", "mission_for_robot"]


def load_mission(
    path: str | Path, profile: RobotProfile | None = None
) -> tuple[MissionSpec, list[InputError]]:
    """Load and check a mission file.

    Args:
        path: A ``.yaml`` mission, or a ``.py`` one (which is imported: it is code).
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
    if suffix == ".py":
        from roboscript.mission.python_loader import load_python_mission

        return load_python_mission(path, profile)
    raise MissionError(
        f"a mission file ends in .yaml or .py (got '{suffix or Path(path).name}')",
        path=str(path),
    )


def mission_for_robot(
    path: str | Path, robot: str | None = None
) -> tuple[Any, Any, list[InputError]]:
    """Load a mission and the robot to run it on, and check that they fit.

    The robot is ``robot`` if given, else the one the mission names, else ``mirto``.

    Returns:
        ``(spec, profile, warnings)``.

    Raises:
        MissionError: The mission is invalid or needs what the robot lacks.
        ProfileError: The robot is unknown.
    """
    from roboscript.mission.builder import MissionProblemsError
    from roboscript.mission.checks import check_capabilities
    from roboscript.profiles import get_profile

    spec, warnings = load_mission(path)
    profile = get_profile(robot or spec.robot or "mirto")
    problems = check_capabilities(spec, profile)
    if problems:
        raise MissionProblemsError(problems)
    return spec, profile, warnings
