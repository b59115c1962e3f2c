"""Load a Python mission file: import it, find its one Mission class, compile and check it.

A Python mission is code, run with the permissions of whoever runs it: ``roboscript run``
and ``roboscript check`` import the file. Teachers grading untrusted submissions run each in
a separate process (the grader does).
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Any

from roboscript.actions.base import Action
from roboscript.errors import InputError, MissionError
from roboscript.inputs.source import read_source
from roboscript.mission.python_api import Mission, StateDef
from roboscript.mission.python_compiler import compile_mission, mission_states, nested_missions
from roboscript.mission.python_source import PythonSource
from roboscript.mission.spec import MissionSpec
from roboscript.mission.student_code import import_student_file

__all__ = [
    "PACKAGE_FILE",
    "find_mission_class",
    "is_python_mission",
    "load_python_mission",
    "package_shadow_warning",
]


def find_mission_class(module: Any, path: str) -> type[Mission]:
    """The one mission class a module defines.

    Base classes that another mission class of the file extends do not count, so a file may
    hold a template and the mission built on it; nor do missions that another one runs as a
    nested state (``state(Inner, ...)``, or inside one: ``state(Repeat(Inner, times=4))``), so
    a file may hold a mission and its parts.

    Raises:
        MissionError: The file defines no mission class, or several.
    """
    classes = [
        value
        for value in vars(module).values()
        if isinstance(value, type)
        and issubclass(value, Mission)
        and value is not Mission
        and value.__module__ == module.__name__
    ]
    leaves = [c for c in classes if not any(o is not c and issubclass(o, c) for o in classes)]
    nested = {
        id(inner)
        for c in leaves
        for d in mission_states(c).values()
        for inner in nested_missions(d.action)
    }
    leaves = [c for c in leaves if id(c) not in nested] or leaves
    if not leaves:
        behaviours = sorted(
            str(getattr(value, "name", value.__name__))
            for value in vars(module).values()
            if isinstance(value, type)
            and issubclass(value, Action)
            and value.__module__ == module.__name__
        )
        hint = "write a class that extends Mission: class MyMission(Mission): ..."
        unmarked = [
            value
            for value in vars(module).values()
            if isinstance(value, type)
            and value.__module__ == module.__name__
            and any(isinstance(member, StateDef) for member in vars(value).values())
        ]
        if unmarked:  # class M: with its states, the (Mission) left out
            name = unmarked[0].__name__
            source = PythonSource(module.__file__ or path, path)
            where = source.loc(source.class_def(name))
            raise MissionError(
                f"class {name} has states but does not extend Mission, so it is no mission",
                path=path,
                line=where.line,
                col=where.col,
                hint=f"write class {name}(Mission):, and import Mission from roboscript",
            )
        if behaviours:
            hint = (
                f"it holds behaviours ({', '.join(behaviours)}): list the file under"
                " 'behaviours:' in a YAML mission, or import it in a Python one"
            )
        raise MissionError("this file holds no mission", path=path, line=1, col=1, hint=hint)
    if len(leaves) > 1:
        names = ", ".join(c.__name__ for c in leaves)
        source = PythonSource(module.__file__ or path, path)
        where = source.loc(source.class_def(leaves[1].__name__))
        raise MissionError(
            f"this file holds {len(leaves)} missions ({names}); a mission file holds one",
            path=path,
            line=where.line,
            col=where.col,
            hint="move each mission to a file of its own",
        )
    return leaves[0]


def load_python_mission(
    path: str | Path, profile: Any = None
) -> tuple[MissionSpec, list[InputError]]:
    """Load and check a Python mission file.

    Args:
        path: The ``.py`` file.
        profile: A :class:`~roboscript.profiles.RobotProfile` to check capabilities against,
            or ``None``.

    Returns:
        The mission and its warnings.

    Raises:
        MissionError: The file does not import, or holds no mission or several.
        MissionProblemsError: The mission is invalid (every problem is in ``problems``).
    """
    module = import_student_file(path, kind="mission")
    cls = find_mission_class(module, str(path))
    spec, warnings = compile_mission(cls, profile, path=str(path))
    shadow = package_shadow_warning(path)
    return spec, warnings if shadow is None else [shadow, *warnings]


PACKAGE_FILE = "roboscript.py"
"""A file of this name beside a Python mission is what ``python mission.py`` imports as
``roboscript`` (Python puts the script's folder first on its path): the package is hidden."""


def package_shadow_warning(path: str | Path) -> MissionError | None:
    """A warning if a file beside the Python mission ``path`` (or the mission itself) is named
    like the package, so that ``python`` imports it instead of roboscript; else ``None``.

    roboscript's own commands import the package before the mission, so they are not fooled;
    ``python mission.py`` is, and fails with an ``ImportError`` that names neither cause nor
    cure. The warning says both, on the mission's first line.
    """
    mission = Path(path)
    shadow = mission.parent / PACKAGE_FILE
    if not shadow.is_file():
        return None
    if mission.name == PACKAGE_FILE:
        message = (
            f"this file is named {PACKAGE_FILE}, like the package it imports: `python"
            f" {PACKAGE_FILE}` would import this file instead of roboscript and fail"
        )
        hint = "rename it, for example to my_mission.py"
    else:
        message = (
            f"{PACKAGE_FILE} in this folder hides the roboscript package: `python"
            f" {mission.name}` would import that file instead of roboscript and fail"
        )
        hint = f"rename {PACKAGE_FILE}, for example to my_helpers.py"
    return MissionError(message, path=str(path), line=1, col=1, hint=hint, severity="warning")


def is_python_mission(path: str | Path) -> bool:
    """Whether a ``.py`` file looks like a mission, judged from its text without running it.

    Used when ``roboscript check`` walks a folder, which also holds behaviours and helpers:
    a file counts if it defines a class whose base is named ``Mission`` (or it mentions
    ``Mission`` but does not parse, so the syntax error is reported).
    """
    try:
        text = read_source(path)  # at most 1 MiB, an ordinary UTF-8 file
    except InputError:
        return False
    if "Mission" not in text:
        return False
    try:
        tree = ast.parse(text)
    except (SyntaxError, RecursionError, MemoryError, ValueError):
        return True  # loading it says what is wrong, with its line
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            for base in node.bases:
                name = base.id if isinstance(base, ast.Name) else getattr(base, "attr", "")
                if name == "Mission":
                    return True
    return False
