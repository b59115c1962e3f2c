"""Behaviours students write in Python and use by name from YAML missions.

A behaviour is a subclass of :class:`~roboscript.actions.base.Action` in a ``.py`` file of its
own. A YAML mission lists its files (paths relative to the mission file) and then uses each
behaviour by its ``name``, like a built-in action::

    behaviours: [behaviours/zigzag.py]
    states:
      weave:
        do: {zigzag: {leg: 20 cm, legs: 4}}

The file is imported (it is code, run with the permissions of whoever runs the mission), and
each behaviour class is checked before the robot moves: it has a ``name`` that no built-in
action has, an ``update(ctx)``, parameters of known kinds that its ``__init__`` accepts, and
``requires`` naming real capabilities. Problems are reported at the behaviour's line.
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from roboscript import capabilities as cap
from roboscript.actions import ACTIONS, Action, Param
from roboscript.errors import InputError, MissionError, did_you_mean
from roboscript.inputs.quantities import DIMENSIONS
from roboscript.inputs.source import Location
from roboscript.mission.files import FileReferenceError, beside_mission
from roboscript.mission.python_source import PythonSource
from roboscript.mission.student_code import import_student_file

__all__ = ["behaviours_from_yaml", "load_behaviour_file"]

_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


def _kinds() -> set[str]:
    """Parameter kinds a mission can convert: quantities, and those built-in actions use."""
    return {*DIMENSIONS, "text", "choice", *(p.kind for a in ACTIONS.values() for p in a.params)}


def _error(message: str, where: Location, hint: str | None = None) -> MissionError:
    return MissionError(message, path=where.path, line=where.line, col=where.col, hint=hint)


def load_behaviour_file(
    path: str | Path, taken: Mapping[str, Any] | None = None
) -> tuple[dict[str, type[Action]], list[InputError]]:
    """Import a behaviour file and check the behaviours it defines.

    Args:
        path: The ``.py`` file, as messages should name it.
        taken: Behaviour names already loaded from other files (name -> file), which this
            file must not reuse.

    Returns:
        The file's behaviours by name, and the problems found (located in the file).
    """
    shown = str(path)
    try:
        module = import_student_file(path, kind="behaviour")
    except MissionError as exc:
        return {}, [exc]
    classes = [
        value
        for value in vars(module).values()
        if isinstance(value, type)
        and issubclass(value, Action)
        and value.__module__ == module.__name__
    ]
    source = PythonSource(module.__file__ or shown, shown)
    # A class another one of the file extends is a helper base, unless it has its own name.
    behaviours = [
        c
        for c in classes
        if "name" in vars(c) or not any(o is not c and issubclass(o, c) for o in classes)
    ]
    if not behaviours:
        return {}, [
            _error(
                "this file holds no behaviour",
                Location(shown, 1, 1),
                "write a class that extends Action, with name = '...' and update(self, ctx)",
            )
        ]
    found: dict[str, type[Action]] = {}
    problems: list[InputError] = []
    for cls in behaviours:
        where = source.loc(source.class_def(cls.__name__))
        name = _check(cls, where, problems, taken or {}, found)
        if name is not None:
            found[name] = cls
    return found, problems


def _check(
    cls: type[Action],
    where: Location,
    problems: list[InputError],
    taken: Mapping[str, Any],
    found: Mapping[str, Any],
) -> str | None:
    """Check one behaviour class; its name if it can be used."""
    name = vars(cls).get("name", getattr(cls, "name", None))
    label = cls.__name__
    if not isinstance(name, str) or not _NAME.match(name):
        problems.append(
            _error(
                f"behaviour {label} needs a name, a lowercase word"
                + (f" (got {name!r})" if name is not None else ""),
                where,
                f"add name = '{_snake(label)}' to the class",
            )
        )
        return None
    if name in ACTIONS:
        problems.append(
            _error(
                f"behaviour {label} is called '{name}', like the built-in action",
                where,
                "give it a name of its own",
            )
        )
        return None
    if name in taken or name in found:
        problems.append(
            _error(
                f"two behaviours are called '{name}'",
                where,
                f"the other is in {taken[name]}" if name in taken else "rename one",
            )
        )
        return None
    ok = True
    if inspect.isabstract(cls):
        problems.append(
            _error(
                f"behaviour '{name}' has no update(self, ctx) method",
                where,
                "update() returns None while running, else Result.done() or Result.failed(...)",
            )
        )
        ok = False
    params = getattr(cls, "params", ())
    if not isinstance(params, tuple | list) or not all(isinstance(p, Param) for p in params):
        problems.append(
            _error(
                f"behaviour '{name}': params is a tuple of Param(...)",
                where,
                "e.g. params = (Param('speed', 'speed_mm_s', 'speed', 'how fast', 150.0),)",
            )
        )
        return None
    kinds = _kinds()
    accepted = _keywords(cls)
    for param in params:
        if param.kind not in kinds:
            problems.append(
                _error(
                    f"behaviour '{name}' parameter '{param.name}': unknown kind '{param.kind}'",
                    where,
                    did_you_mean(param.kind, kinds) or f"kinds: {', '.join(sorted(kinds))}",
                )
            )
            ok = False
        if accepted is not None and param.kwarg not in accepted:
            problems.append(
                _error(
                    f"behaviour '{name}' parameter '{param.name}' is passed as "
                    f"{param.kwarg}=..., which its __init__ does not take",
                    where,
                    did_you_mean(param.kwarg, accepted),
                )
            )
            ok = False
    requires: Any = getattr(cls, "requires", frozenset())
    if isinstance(requires, str):
        requires = {requires}
    unknown = sorted(str(r) for r in requires if r not in cap.CAPABILITY_NAMES)
    for entry in unknown:
        problems.append(
            _error(
                f"behaviour '{name}' requires '{entry}', which is not a capability",
                where,
                did_you_mean(entry, cap.CAPABILITY_NAMES)
                or f"capabilities: {', '.join(cap.CAPABILITY_NAMES)}",
            )
        )
        ok = False
    if ok:
        # Missions and checks treat these as a frozenset and a tuple; students may write
        # a list or a set.
        cls.requires = frozenset(requires)
        cls.params = tuple(params)
    return name if ok else None


def _keywords(cls: type) -> set[str] | None:
    """The keywords ``cls(...)`` accepts, or ``None`` when it takes any (``**kwargs``)."""
    try:
        signature = inspect.signature(cls)
    except (TypeError, ValueError):
        return None
    if any(p.kind is p.VAR_KEYWORD for p in signature.parameters.values()):
        return None
    return {
        name
        for name, p in signature.parameters.items()
        if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
    }


def _snake(name: str) -> str:
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", name).lower()


def behaviours_from_yaml(
    raw: Any, mark: tuple[int, int], mission_path: str
) -> tuple[dict[str, type[Action]], list[InputError], frozenset[str]]:
    """Load the files a YAML mission's ``behaviours:`` lists.

    Args:
        raw: The value of ``behaviours:`` (a list of paths, or one path).
        mark: Where the value starts, ``(line, col)``.
        mission_path: The mission file; paths are relative to its folder.

    Returns:
        Every behaviour by name; the problems (in the mission or in the behaviour files); and
        the names of behaviours whose file has errors, so the mission does not also call
        them unknown.
    """
    items = raw if isinstance(raw, list) else [raw]
    marks = getattr(raw, "item_marks", None) or [mark] * len(items)
    found: dict[str, type[Action]] = {}
    origin: dict[str, str] = {}
    problems: list[InputError] = []
    broken: set[str] = set()
    for entry, (line, col) in zip(items, marks, strict=True):
        here = Location(mission_path, line, col)
        if not isinstance(entry, str) or not entry.endswith(".py"):
            problems.append(
                _error(
                    f"behaviours lists .py files, got {entry!r}",
                    here,
                    "e.g. behaviours: [my_behaviours.py]",
                )
            )
            continue
        try:
            # Checked before the import: a path out of the mission's folder could import
            # anything on the machine (the standard library's this.py prints on import).
            beside_mission(mission_path, entry, "behaviour file", (".py",))
        except FileReferenceError as exc:
            problems.append(_error(str(exc), here, exc.hint))
            continue
        path = Path(mission_path).parent / entry  # as the student wrote it, for messages
        loaded, file_problems = load_behaviour_file(path, origin)
        problems.extend(file_problems)
        for name, cls in loaded.items():
            found[name] = cls
            origin[name] = str(path)
        if any(p.severity == "error" for p in file_problems):
            broken |= _written_names(path) - set(found)
    return found, problems, frozenset(broken)


def _written_names(path: Path) -> set[str]:
    """Behaviour names a file seems to define (``name = "..."``), read as text.

    Read as text, because the file may not even parse.
    """
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return set()
    return set(re.findall(r"^\s+name\s*(?::[^=]*)?=\s*[\"'](\w+)[\"']", text, re.MULTILINE))
