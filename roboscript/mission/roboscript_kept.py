"""roboscript's own classes and names, and Python's built-in names, kept as they are made while a
student's file loads.

A mission file that writes ``Drive.update = fast`` or ``roboscript.Drive = MyDrive`` would
change what every mission loaded after it in the same program builds (``roboscript check`` of a
class's folder), and a run at home would differ from the teacher's, where each run has a
program of its own. So a change a file makes to them while it loads is put back and refused,
located at the line that makes it; the same line inside a method (a condition that changes
``Drive`` as the robot runs) is refused before the robot moves. A built-in robot profile is
kept by :class:`roboscript.profiles.BuiltinsKept`. Python's built-in names (``print``,
``open``, ``__import__``) are kept the same way: roboscript's own code calls them too, so a file
that wrote ``builtins.print = None`` would break the very sentence that tells its mistake.
"""

from __future__ import annotations

import ast
import builtins
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from types import ModuleType
from typing import Any

from roboscript.actions.base import Action
from roboscript.code_owner import is_roboscript_module, is_student_class
from roboscript.profiles import BUILTIN_PROFILES, get_profile
from roboscript.robot_profile import RobotProfile

__all__ = ["Change", "RoboscriptKept", "changes_written"]


def _classes() -> Iterator[type]:
    """roboscript's action classes and its Mission class."""
    # here, not at the top: the mission package imports this module (through student_code)
    # before python_api, so a top-level import would go round in a circle
    from roboscript.mission.python_api import Mission

    todo: list[type] = [Action, Mission]
    while todo:
        cls = todo.pop()
        if not is_student_class(cls):
            yield cls
            todo.extend(cls.__subclasses__())


@dataclass(frozen=True)
class Change:
    """One change to roboscript: ``owner`` (``Drive``, ``roboscript``) and the ``name`` set."""

    owner: str
    name: str
    kind: str
    """``module`` (one of roboscript's modules: a name replaced), ``class``, ``robot`` (a
    built-in robot profile) or ``python`` (one of Python's built-in names)."""

    def sentence(self) -> tuple[str, str]:
        """``(message, hint)`` for a student who made this change."""
        if self.kind == "robot":
            return (
                (
                    f"this changes the built-in robot '{self.owner}' ({self.name}), and a"
                    " built-in robot stays as it is built: the simulated robot would not have the"
                    " change"
                ),
                (
                    f"a robot of your own is a profile file beside the mission, e.g."
                    f" my_{self.owner}.yaml holding 'extends: {self.owner}' and '{self.name}: ...';"
                    f' then write robot = "my_{self.owner}.yaml"'
                ),
            )
        if self.kind == "python":
            return (
                (
                    f"this changes Python's own '{self.name}', which roboscript's code uses too,"
                    " so Python's stays as it is"
                ),
                f"give yours a name of its own and use that name, e.g. my_{self.name.strip('_')}",
            )
        if self.kind == "module":
            return (
                (
                    f"this puts something of its own in the place of roboscript's"
                    f" '{self.name}', and roboscript's names stay as roboscript makes them"
                ),
                f"give yours a name of its own and use that name, e.g. My{self.name}",
            )
        return (
            (
                f"this changes roboscript's own {self.owner} ({self.name}), which every mission"
                " shares, so roboscript keeps it as it is"
            ),
            (
                f"make one of your own that extends it: class My{self.owner}({self.owner}): ...,"
                f" and use My{self.owner}(...) in your states"
            ),
        )


class RoboscriptKept:
    """roboscript's classes and module names as they are when made; :meth:`changed` finds
    (and puts back) a change made since."""

    def __init__(self) -> None:
        self._classes = [(cls, dict(vars(cls))) for cls in _classes()]
        # Only the public names: roboscript's private state (a signal noted while the file
        # loads, a cache) changes as it works.
        self._modules = [
            (module, {k: v for k, v in vars(module).items() if not k.startswith("_")})
            for name, module in list(sys.modules.items())
            if is_roboscript_module(name) and isinstance(module, ModuleType)
        ]
        # Every built-in name but ``_`` (the interpreter's last value, gettext's translator).
        self._python = {k: v for k, v in vars(builtins).items() if k != "_"}

    def changed(self) -> list[Change]:
        """Each attribute changed, added, or taken away since this was made; each is put back
        as it was. A submodule added to a module is left (importing it adds it)."""
        found: list[Change] = []
        for cls, kept in self._classes:
            now = dict(vars(cls))
            for name in sorted(set(now) | set(kept)):
                if name in kept and now.get(name, _GONE) is kept[name]:
                    continue
                if name.startswith("_abc_"):
                    continue  # abc's own caches of what is a subclass
                found.append(Change(cls.__name__, name, "class"))
                if name in kept:
                    type.__setattr__(cls, name, kept[name])
                else:
                    type.__delattr__(cls, name)
        for module, kept_names in self._modules:
            names = vars(module)
            added = [
                name
                for name, value in names.items()
                if not (name.startswith("_") or name in kept_names or isinstance(value, ModuleType))
            ]
            for name in added:
                # A name roboscript makes when first asked (its lazy names) set by the student
                # first: theirs would be taken for roboscript's.
                found.append(Change(module.__name__, name, "module"))
                del names[name]
            for name, value in kept_names.items():
                if names.get(name, _GONE) is not value:
                    found.append(Change(module.__name__, name, "module"))
                    names[name] = value
        found.extend(self._python_changed())
        return found

    def _python_changed(self) -> list[Change]:
        names = vars(builtins)
        found: list[Change] = []
        for name in sorted(set(names) | set(self._python)):
            if name == "_" or names.get(name, _GONE) is self._python.get(name, _GONE):
                continue
            found.append(Change("builtins", name, "python"))
            if name in self._python:
                names[name] = self._python[name]
            else:
                del names[name]
        return found


_GONE = object()


def changes_written(module: ModuleType, tree: ast.Module | None) -> list[tuple[ast.AST, Change]]:
    """Each line of a student's file (``tree``, run as ``module``) that sets or deletes an
    attribute of roboscript's classes or modules, or an item of one (``Drive.update = ...``,
    ``roboscript.Drive = ...``, ``setattr(Drive, "update", ...)``), in file order; methods
    included, so a change written to run later is found before it runs."""
    if tree is None:
        return []
    found: list[tuple[ast.AST, Change]] = []
    for node in ast.walk(tree):
        for owner_node, name in _targets(node):
            change = _change(owner_node, name, vars(module))
            if change is not None:
                found.append((node, change))
    found.sort(key=lambda item: (getattr(item[0], "lineno", 0), getattr(item[0], "col_offset", 0)))
    return found


def _targets(node: ast.AST) -> Iterator[tuple[ast.expr, str]]:
    """``(owner expression, attribute name)`` for each attribute ``node`` sets or deletes."""
    targets: list[ast.expr] = []
    if isinstance(node, ast.Assign | ast.Delete):
        targets = list(node.targets)
    elif isinstance(node, ast.AugAssign | ast.AnnAssign):
        targets = [node.target]
    elif (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id in ("setattr", "delattr")
        and len(node.args) >= 2
        and isinstance(node.args[1], ast.Constant)
        and isinstance(node.args[1].value, str)
    ):
        yield node.args[0], node.args[1].value
    for target in targets:
        for part in ast.walk(target) if isinstance(target, ast.Tuple | ast.List) else [target]:
            if (
                isinstance(part, ast.Subscript)
                and isinstance(part.value, ast.Name)
                and isinstance(part.slice, ast.Constant)
                and isinstance(part.slice.value, str)
            ):
                yield part.value, part.slice.value  # __builtins__["len"] = ...
                continue
            if isinstance(part, ast.Subscript) and isinstance(part.value, ast.Attribute):
                part = part.value  # Drive.params[0] = ...: changes what Drive holds
            if isinstance(part, ast.Attribute):
                yield part.value, part.attr


def _change(owner: ast.expr, name: str, names: dict[str, Any]) -> Change | None:
    value = _resolved(owner, names)
    if (value is builtins or value is vars(builtins)) and name != "_":
        return Change("builtins", name, "python")
    if isinstance(value, ModuleType) and is_roboscript_module(value.__name__):
        return Change(value.__name__, name, "module")
    if isinstance(value, type) and not is_student_class(value):
        return Change(value.__name__, name, "class")
    if isinstance(value, RobotProfile) and BUILTIN_PROFILES.get(value.name) is value:
        return Change(value.name, name, "robot")
    return None


def _resolved(node: ast.expr, names: dict[str, Any]) -> object:
    """The object a name or a dotted name of the student's module stands for, or ``None``."""
    if isinstance(node, ast.Name):
        return names.get(node.id)
    if (
        isinstance(node, ast.Call)
        and _resolved(node.func, names) is get_profile
        and len(node.args) == 1
        and isinstance(node.args[0], ast.Constant)
        and isinstance(node.args[0].value, str)
    ):
        return BUILTIN_PROFILES.get(node.args[0].value)  # get_profile("mirto").gains[...]
    if isinstance(node, ast.Attribute):
        outer = _resolved(node.value, names)
        if isinstance(outer, ModuleType | type):
            return getattr(outer, node.attr, None)
    return None
