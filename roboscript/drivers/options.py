"""Reading a robot family's profile options (standard library only).

Drivers and simulated devices both read their options, so this module may not pull in the
transport or the host driver base.
"""

from __future__ import annotations

import dataclasses
import difflib
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

from roboscript.errors import ProfileError

__all__ = ["read_options"]


_Options = TypeVar("_Options")


def read_options(
    cls: type[_Options],
    options: Mapping[str, Any],
    *,
    profile: str,
    family: str,
    read: Callable[[str, object, str], Any],
) -> _Options:
    """Build a driver's options dataclass from a profile's ``options`` mapping.

    Args:
        cls: The options dataclass; its fields are the option names.
        options: Option name -> value, as written in the profile.
        profile: The profile's name, for messages.
        family: The robot family, for messages (``"SPIKE"``).
        read: Checks and converts one value: ``read(name, value, profile)``.

    Raises:
        ProfileError: An unknown option (with a "did you mean") or a bad value.
    """
    known = {f.name for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
    values: dict[str, Any] = {}
    for name, value in options.items():
        if name not in known:
            close = difflib.get_close_matches(name, sorted(known), n=1)
            raise ProfileError(
                f"{profile}: unknown {family} option '{name}'",
                hint=f"did you mean '{close[0]}'?" if close else None,
            )
        values[name] = read(name, value, profile)
    return cls(**values)
