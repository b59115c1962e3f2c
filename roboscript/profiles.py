"""Robot profiles: what a robot is, which protocol it speaks and what it can do.

Built-in profiles live with their protocol (``drivers/<protocol>/profiles.py``) and are found
through the protocol units; a profile file (YAML) starts from a built-in one and changes what
differs::

    extends: mirto
    name: mirto-classroom-3
    track_mm: 165
    gains:
      wheel_speed: [0.004, 0.02, 0.0]
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from copy import deepcopy
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

from roboscript.drivers import units
from roboscript.errors import InputError, ProfileError, did_you_mean
from roboscript.robot_profile import RobotProfile

__all__ = [
    "BUILTIN_PROFILES",
    "PROFILE_FILE_KEYS",
    "BuiltinsKept",
    "RobotProfile",
    "get_profile",
    "register_profile",
]


class _BuiltinProfiles(Mapping[str, RobotProfile]):
    """Name -> profile, read from the protocol units (each unit's ``profiles.py``)."""

    def _all(self) -> dict[str, RobotProfile]:
        return {profile.name: profile for unit in units() for profile in unit.profiles}

    def __getitem__(self, name: str) -> RobotProfile:
        return self._all()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._all())

    def __len__(self) -> int:
        return len(self._all())


BUILTIN_PROFILES: Mapping[str, RobotProfile] = _BuiltinProfiles()
"""The built-in profiles by name, from every protocol unit (derived: a new protocol's folder
adds its robots here)."""


_REGISTERED: dict[str, RobotProfile] = {}


def register_profile(profile: RobotProfile) -> None:
    """Make a profile (from a file, say) findable by name in this process.

    ``sim://NAME`` URLs carry only a name; registering lets a profile file's robot be
    simulated in-process.
    """
    if profile.name not in BUILTIN_PROFILES:
        _REGISTERED[profile.name] = profile


def get_profile(name_or_path: str) -> RobotProfile:
    """Return a built-in or registered profile by name, or load a profile file.

    Raises:
        ProfileError: Unknown name, or an invalid profile file (with ``file:line:col``).
    """
    if name_or_path in BUILTIN_PROFILES:
        return BUILTIN_PROFILES[name_or_path]
    if name_or_path in _REGISTERED:
        return _REGISTERED[name_or_path]
    path = Path(name_or_path)
    if path.exists():
        return _load_profile_file(path)
    if name_or_path.endswith((".yaml", ".yml")):
        # "mirto.yaml" for the built-in mirto: a name written as a file's
        raise ProfileError(
            f"there is no robot profile file {name_or_path}",
            hint=f"did you mean the built-in robot '{path.stem}', named without '{path.suffix}'?"
            if path.stem in BUILTIN_PROFILES
            else did_you_mean(path.stem, BUILTIN_PROFILES),
        )
    raise ProfileError(
        f"no robot called '{name_or_path}' (built-in: {', '.join(BUILTIN_PROFILES)})",
        hint=did_you_mean(name_or_path, BUILTIN_PROFILES),
    )


_NUMBER_FIELDS = {
    f.name: f.type
    for f in fields(RobotProfile)
    if f.name in {"wheel_diameter_mm", "track_mm", "body_radius_mm", "max_speed_mm_s"}
}


PROFILE_FILE_KEYS = ("description", "gains", "ticks_per_rev", *_NUMBER_FIELDS, "options")
"""What a profile file may change of the built-in robot it extends (besides its name)."""


class BuiltinsKept:
    """The built-in profiles as they are when made, to find (and undo) a change made to them
    since: a student's file that changes a field of ``get_profile("mirto")`` (its ``gains``
    dict, say) would change the robot the mission's side runs with, but not the simulated
    board, which is made from the built-in's name alone (and, when grading, in another
    process), so a built-in profile is kept as it is built."""

    def __init__(self) -> None:
        self._kept = [
            (profile, deepcopy(vars(profile))) for unit in units() for profile in unit.profiles
        ]

    def changed(self) -> list[tuple[str, str]]:
        """``(profile name, field)`` for each field changed since this was made, in the
        profile's field order; each changed profile is put back as it was."""
        found = []
        for profile, kept in self._kept:
            now = vars(profile)
            if now == kept:
                continue
            found += [
                (kept["name"], f.name) for f in fields(profile) if now.get(f.name) != kept[f.name]
            ]
            now.clear()
            now.update(deepcopy(kept))
        return found


def _load_profile_file(path: Path) -> RobotProfile:
    # YAML loads only for a profile file, so codecs and drivers import profiles without it
    from roboscript.inputs.fields import FieldReader
    from roboscript.inputs.kinds import refuse_another_kind
    from roboscript.inputs.source import YamlMap, load_yaml

    data = load_yaml(path, error=ProfileError)
    reader = FieldReader(str(path), ProfileError)

    def fail(message: str, key: str | None = None) -> InputError:
        mark = data.key_mark(key) if isinstance(data, YamlMap) and key else None
        return reader.fail(message, mark)

    if not isinstance(data, YamlMap):
        raise fail("a profile file must be a mapping with 'extends:' and the values to change")
    refuse_another_kind(data, path, "profile", ProfileError)  # --robot square.yaml
    base_name = data.get("extends")
    if not isinstance(base_name, str) or base_name not in BUILTIN_PROFILES:
        raise fail(
            f"'extends' must name a built-in robot ({', '.join(BUILTIN_PROFILES)})", "extends"
        )
    changes: dict[str, Any] = {"name": str(data.get("name", path.stem))}
    reader.allowed(data, ("extends", "name", *PROFILE_FILE_KEYS), "a profile")
    for key, value in data.items():
        if key in _NUMBER_FIELDS or key == "ticks_per_rev":
            if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
                raise fail(f"'{key}' must be a positive number", key)
            changes[key] = int(value) if key == "ticks_per_rev" else float(value)
        elif key == "description":
            changes[key] = str(value)
        elif key == "gains":
            changes[key] = _read_gains(value, fail)
        elif key == "options":
            if not isinstance(value, dict):
                raise fail("'options' maps option names to values", key)
            # Values are checked by the protocol's driver, which knows what they mean.
            changes[key] = {**BUILTIN_PROFILES[base_name].options, **value}
    return replace(BUILTIN_PROFILES[base_name], **changes)


def _read_gains(value: Any, fail: Any) -> dict[str, tuple[float, float, float]]:
    if not isinstance(value, dict):
        raise fail("'gains' maps a loop name to [kp, ki, kd]", "gains")
    gains = {}
    for loop, triple in value.items():
        if (
            not isinstance(triple, list)
            or len(triple) != 3
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in triple)
        ):
            raise fail(f"gains for '{loop}' must be [kp, ki, kd]", "gains")
        gains[str(loop)] = (float(triple[0]), float(triple[1]), float(triple[2]))
    return gains
