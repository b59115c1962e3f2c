"""Which kind of file a YAML file is: a mission, a simulator world, a robot profile or a test spec.

Each kind has top-level keys no other kind has (``states`` for a mission, ``walls`` for a
world, ``extends`` for a profile, ``test`` for a test spec): the kind with the most of its own
keys wins. A file with none of them, or one that does not parse, is taken as a mission, so
the mission reader says what is wrong with it. ``check``, ``run`` and ``grade`` ask here
first, so a world given where a mission is expected is named as a world, not read as a
mission with five false errors (:class:`NotAMissionError`), with what to do with it in the words of
the front end it was given in: the command line's (:data:`ON_THE_COMMAND_LINE`) unless the front
end says it its own way (:meth:`NotAMissionError.advised`; the browser app has no ``--world``).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal

from roboscript.errors import InputError
from roboscript.inputs.source import YamlMap, load_yaml

__all__ = [
    "KINDS",
    "ON_THE_COMMAND_LINE",
    "OWN_KEYS",
    "FileKind",
    "NotAMissionError",
    "file_kind",
    "kind_of_keys",
    "not_a_mission",
    "not_the_kind_expected",
    "refuse_another_kind",
]

FileKind = Literal["mission", "world", "profile", "test spec"]

KINDS: tuple[FileKind, ...] = ("mission", "world", "profile", "test spec")

OWN_KEYS: dict[FileKind, frozenset[str]] = {
    "mission": frozenset({"mission", "behaviours", "initial", "states", "plot"}),
    "world": frozenset({"start", "walls", "lines", "regions"}),
    "profile": frozenset(
        {
            "extends",
            "gains",
            "ticks_per_rev",
            "wheel_diameter_mm",
            "track_mm",
            "body_radius_mm",
            "max_speed_mm_s",
            "options",
        }
    ),
    "test spec": frozenset({"test", "runs", "max_time", "wall_time_limit", "points", "expect"}),
}
"""Top-level keys only that kind of file has (the readers' other keys are shared:
``description``, ``world``, ``robot``, ``name``). A test checks each reader against this."""

ON_THE_COMMAND_LINE: Mapping[FileKind, str] = {
    "world": "a simulator world: run a mission in it with 'roboscript run MISSION --world {path}'",
    "profile": "a robot profile: run a mission on it with 'roboscript run MISSION --robot {path}'",
    "test spec": (
        "a teacher's test spec: grade missions with 'roboscript grade {path} --mission MISSIONS'"
    ),
}
"""What each kind of file is and how it is used, on the command line (``{path}``: the file)."""


def not_the_kind_expected(kind: FileKind, expected: str) -> str:
    """The sentence for a file of ``kind`` given where ``expected`` belongs (``this is a world
    file, not a mission``), for every reader that tells one kind of file from another."""
    article = "an" if kind[0] in "aeiou" else "a"
    return f"this is {article} {kind} file, not {expected}"


def kind_of_keys(keys: set[str] | frozenset[str]) -> FileKind:
    """The kind of file whose top level has ``keys`` (``mission`` when nothing tells)."""
    counts = {kind: len(keys & own) for kind, own in OWN_KEYS.items()}
    best = max(counts.values())
    if best == 0:
        # 'world: NAME' and a description, nothing else: a world that has no walls yet
        return (
            "world"
            if "world" in keys and len(keys - {"world", "description"}) == 0
            else ("mission")
        )
    leaders = [kind for kind, count in counts.items() if count == best]
    return leaders[0] if len(leaders) == 1 else "mission"


def file_kind(path: str | Path) -> FileKind:
    """The kind of the file at ``path``: a Python file is a mission, a YAML file by its keys.

    Never raises: a file that cannot be read or parsed is a ``mission``, so the mission reader
    reports why.
    """
    if Path(path).suffix.lower() not in (".yaml", ".yml"):
        return "mission"
    try:
        data = load_yaml(path)
    except InputError:
        return "mission"
    if not isinstance(data, YamlMap):
        return "mission"
    return kind_of_keys({str(key) for key in data})


class NotAMissionError(InputError):
    """A world, robot profile or test spec given where a mission is expected.

    Args:
        path: The file, as the user named it.
        kind: What it is.
        uses: What each kind of file is and how it is used, in the front end's words
            (``{path}`` for the file): the command line's by default.

    Attributes:
        kind: What the file is.
    """

    def __init__(
        self, path: str | Path, kind: FileKind, uses: Mapping[FileKind, str] = ON_THE_COMMAND_LINE
    ) -> None:
        self.kind = kind
        self.uses = uses
        super().__init__(
            not_the_kind_expected(kind, "a mission"),
            path=str(path),
            line=1,
            col=1,
            hint=f"it is {uses[kind].format(path=path)}" if kind in uses else None,
        )

    def __reduce__(self) -> tuple[Any, ...]:
        # rebuilt from what it was made of (an error crosses to another process pickled)
        return (type(self), (self.path, self.kind, dict(self.uses)))

    def advised(self, uses: Mapping[FileKind, str]) -> NotAMissionError:
        """The same error, saying how the file is used in a front end's own words."""
        return NotAMissionError(self.path or "", self.kind, uses)


def not_a_mission(path: str | Path, kind: FileKind) -> NotAMissionError:
    """The error for a world, profile or test spec given where a mission is expected."""
    return NotAMissionError(path, kind)


_NAMED: dict[FileKind, str] = {
    "mission": "a mission",
    "world": "a simulator world",
    "profile": "a robot profile",
    "test spec": "a test spec",
}
"""Each kind of file as a sentence names what was expected."""

_RUN_IT = "a mission: run it with 'roboscript run {path}'"


def refuse_another_kind(
    data: YamlMap, path: str | Path, expected: FileKind, error: type[InputError]
) -> None:
    """Raise ``error`` when the YAML ``data`` read from ``path`` where ``expected`` belongs
    (``--robot square.yaml``, ``--world test.yaml``) is, by its own keys, another kind of file,
    saying what it is and how that kind is used; a file with keys of ``expected``, or none
    that tell, is left to ``expected``'s reader to judge."""
    keys = {str(key) for key in data}
    if keys & OWN_KEYS[expected]:
        return
    kind = kind_of_keys(keys)
    if kind == expected or not keys & OWN_KEYS[kind]:
        return
    use = _RUN_IT if kind == "mission" else ON_THE_COMMAND_LINE[kind]
    raise error(
        not_the_kind_expected(kind, _NAMED[expected]),
        path=str(path),
        line=1,
        col=1,
        hint=f"it is {use.format(path=path)}",
    )
