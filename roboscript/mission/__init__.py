"""Missions: loading, checking and running state machines.

This package is the only user of ``transitions``; YAML is read by :mod:`roboscript.inputs`.
Both syntaxes build missions through :mod:`roboscript.mission.builder`.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from roboscript.errors import InputError, MissionError, nearby_file, wrong_ending

if TYPE_CHECKING:
    from roboscript.mission.spec import MissionSpec
    from roboscript.profiles import RobotProfile

__all__ = ["fit_to_robot", "load_mission", "mission_for_robot"]


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
        # this package loads with every mission module: YAML only for a YAML mission
        from roboscript.mission.yaml_loader import load_yaml_mission

        return load_yaml_mission(path, profile)
    if suffix == ".py":
        # the Python loader (and its compiler) only for a .py mission
        from roboscript.mission.python_loader import load_python_mission

        return load_python_mission(path, profile)
    raise MissionError(
        f"a mission file ends in .yaml or .py (got '{suffix or Path(path).name}')",
        path=str(path),
        hint=wrong_ending(path) or nearby_file(path),
    )


def mission_for_robot(
    path: str | Path, robot: str | None = None
) -> tuple[Any, Any, list[InputError]]:
    """Load a mission and the robot to run it on, and check that they fit.

    The robot is ``robot`` if given, else the one the mission names (a built-in robot, or a
    profile file beside the mission), else ``mirto``. The world the mission names is checked
    too, and the speeds it asks for against the robot's (warnings).

    Returns:
        ``(spec, profile, warnings)``; a world file the mission names is in ``spec.world``
        as a resolved path.

    Raises:
        MissionError: The mission is invalid, names an unknown robot or world, or needs
            what the robot lacks (every problem is in ``problems``).
        ProfileError: ``robot`` is unknown, or a profile file is invalid.
        InputError: ``path`` is a world, robot profile or test spec, named as what it is
            rather than read as a mission.
    """
    # reading a file's keys loads YAML, only when a mission is loaded from a file
    from roboscript.inputs.kinds import file_kind, not_a_mission

    kind = file_kind(path)
    if kind != "mission":
        raise not_a_mission(path, kind)
    spec, warnings = load_mission(path)
    return fit_to_robot(spec, warnings, robot)


def fit_to_robot(
    spec: MissionSpec, warnings: list[InputError], robot: str | None = None
) -> tuple[Any, Any, list[InputError]]:
    """The second half of :func:`mission_for_robot`, for a mission already loaded (a Python
    mission class run from Python): choose the robot and check that the two fit."""
    # checking against a robot loads the builder, only when a mission is fitted to one
    from roboscript.mission.builder import MissionProblemsError
    from roboscript.mission.checks import check_capabilities
    from roboscript.mission.limits import profile_problems
    from roboscript.mission.references import mission_robot, with_world_checked

    spec, problems = with_world_checked(spec)

    def in_order(found: list[InputError]) -> list[InputError]:
        return sorted(found, key=lambda p: (p.path != spec.path, p.line or 0, p.col or 0))

    try:
        profile = mission_robot(spec, robot)
    except MissionError as exc:
        raise MissionProblemsError(in_order([*problems, exc, *warnings])) from None
    problems += check_capabilities(spec, profile)
    problems += profile_problems(spec, profile)
    if any(p.severity == "error" for p in problems):
        raise MissionProblemsError(in_order([*problems, *warnings]))
    return spec, profile, in_order([*warnings, *problems])
