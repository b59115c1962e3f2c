"""The robot and the world a mission names, found before the robot moves.

``robot:`` names a built-in robot or a profile file beside the mission; ``world:`` a built-in
simulator world or a world file beside it. A name that is neither is reported at the line that
wrote it, with a "did you mean" over the built-in ones and the files nearby, so a typo fails
``roboscript check`` instead of a run.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path, PurePath
from typing import Any

from roboscript.errors import InputError, MissionError, did_you_mean
from roboscript.inputs.kinds import FileKind, file_kind
from roboscript.inputs.source import Location
from roboscript.mission.files import FileReferenceError, beside_mission, nearby_files
from roboscript.mission.spec import MissionSpec
from roboscript.profiles import BUILTIN_PROFILES, get_profile

__all__ = ["mission_robot", "with_world_checked"]

_YAML = (".yaml", ".yml")


def _is_path(name: str) -> bool:
    """True if ``name`` is written as a file (``robot.yaml``, ``robots/mine``) not a name."""
    return PurePath(name).suffix.lower() in _YAML or "/" in name or "\\" in name


def _error(message: str, where: Location | None, hint: str | None = None) -> MissionError:
    where = where or Location("<mission>")
    return MissionError(message, path=where.path, line=where.line, col=where.col, hint=hint)


def _close(name: str, spec: MissionSpec, builtin: list[str], kind: FileKind) -> str | None:
    """A "did you mean" over the built-in names and the YAML files of ``kind`` beside the
    mission (a mission beside it is no world to suggest)."""
    folder = Path(spec.path).parent
    files = [f for f in nearby_files(folder, _YAML) if file_kind(folder / f) == kind]
    written = re.sub(r"[\s_]+", "-", name.strip().lower()).removeprefix("lego-")
    # "SPIKE Prime", "LEGO spike_prime", "PLEN2": a robot's name as its maker writes it
    return did_you_mean(name, [*builtin, *files]) or did_you_mean(written, builtin)


def mission_robot(spec: MissionSpec, robot: str | None = None) -> Any:
    """The robot profile a mission runs on.

    Args:
        spec: The mission.
        robot: The command line's ``--robot`` (a name, or a file relative to the current
            folder), which overrides the mission's own ``robot:``; ``None`` to use that
            (and ``mirto`` if the mission names none).

    Returns:
        The :class:`~roboscript.profiles.RobotProfile`.

    Raises:
        MissionError: The mission's ``robot:`` names no built-in robot, or a profile file
            that is not beside the mission (located at the ``robot:`` value).
        ProfileError: ``--robot`` is unknown, or the profile file is invalid (located in it).
    """
    if robot is not None or spec.robot is None:
        return get_profile(robot or "mirto")
    name, where = spec.robot, spec.robot_location
    if _is_path(name):
        try:
            path = beside_mission(spec.path, name, "robot profile file", _YAML)
        except FileReferenceError as exc:
            raise _error(str(exc), where, exc.hint) from None
        return get_profile(str(path))
    if name in BUILTIN_PROFILES:
        return BUILTIN_PROFILES[name]
    try:
        return get_profile(name)  # registered in this process (a simulated profile file)
    except InputError:
        pass
    builtin = list(BUILTIN_PROFILES)
    raise _error(
        f"there is no robot called '{name}' (built-in robots: {', '.join(builtin)})",
        where,
        _close(name, spec, builtin, "profile")
        or "or name a profile file beside the mission, e.g. robot: my-robot.yaml",
    )


def with_world_checked(spec: MissionSpec) -> tuple[MissionSpec, list[InputError]]:
    """Check the world a mission names, and name a world file by its resolved path.

    Returns:
        The mission (its ``world`` a resolved path when it names a file beside the mission,
        so a run from another folder finds it), and the problems: an unknown world name or a
        world file that is missing or outside the mission's folder, at the ``world:`` value.
    """
    # the simulator's worlds load only for a mission that names one
    from roboscript.sim.world import builtin_worlds

    name = spec.world
    if name is None:
        return spec, []
    builtin = builtin_worlds()
    if name in builtin:
        return spec, []
    where = spec.world_location
    if _is_path(name):
        try:
            path = beside_mission(spec.path, name, "world file", _YAML)
        except FileReferenceError as exc:
            return spec, [_error(str(exc), where, exc.hint)]
        return dataclasses.replace(spec, world=str(path)), []
    return spec, [
        _error(
            f"there is no world called '{name}' (built-in worlds: {', '.join(builtin)})",
            where,
            _close(name, spec, builtin, "world")
            or "or name a world file beside the mission, e.g. world: my-room.yaml",
        )
    ]
