"""Files a mission names: where they may be, and what a mistake in naming one reads like.

A mission names other files (a robot profile, a world, inner missions, behaviours) by paths
relative to its own folder. Each must lie in that folder or below it and be a regular file that
exists when the mission is checked: a mission copied to another machine, or handed in for
grading, takes its folder with it, and a path out of it (``../../usr/lib/python3/this.py``)
would read, or for behaviours import, whatever happens to be there.
"""

from __future__ import annotations

from pathlib import Path

from roboscript.errors import did_you_mean

__all__ = ["FileReferenceError", "beside_mission", "nearby_files"]


class FileReferenceError(ValueError):
    """A file a mission names cannot be used.

    Attributes:
        hint: What to write instead, or ``None``.
    """

    def __init__(self, message: str, hint: str | None = None) -> None:
        super().__init__(message)
        self.hint = hint


def nearby_files(folder: Path, suffixes: tuple[str, ...]) -> list[str]:
    """Files ending in ``suffixes`` in ``folder`` and the folders just below it, as paths
    relative to ``folder`` (for a "did you mean")."""
    found: list[str] = []
    for pattern in ("*", "*/*"):
        for path in sorted(folder.glob(pattern)):
            if path.suffix.lower() in suffixes and path.is_file():
                found.append(path.relative_to(folder).as_posix())
    return found


def beside_mission(mission_path: str, written: str, what: str, suffixes: tuple[str, ...]) -> Path:
    """The file ``written`` names, checked to be a regular file beside the mission.

    Args:
        mission_path: The mission file; ``written`` is relative to its folder.
        written: The path as the mission wrote it.
        what: What the file is, for messages (``behaviour file``, ``world file``).
        suffixes: The endings such a file has (``(".py",)``), lowercase, for the "did you
            mean" over the files nearby.

    Returns:
        The file's resolved path.

    Raises:
        FileReferenceError: The path leaves the mission's folder, or names no regular file.
    """
    folder = Path(mission_path).parent.resolve()
    path = (folder / written).resolve()
    if not path.is_relative_to(folder):
        raise FileReferenceError(
            f"the {what} '{written}' is outside the mission's folder",
            f"put it in the folder of the mission ({folder.name or folder}) or below, "
            "and name it from there",
        )
    if path.exists() and not path.is_file():
        raise FileReferenceError(f"the {what} '{written}' is not a regular file")
    if not path.is_file():
        nearby = nearby_files(folder, suffixes)
        raise FileReferenceError(
            f"there is no {what} '{written}' beside the mission",
            did_you_mean(written, nearby) if nearby else None,
        )
    return path
