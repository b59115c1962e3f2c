"""Compile a :class:`~roboscript.mission.python_api.Mission` class into a ``MissionSpec``.

The result is the same data the YAML loader makes, checked by the same rules
(:mod:`roboscript.mission.checks`), so ``run``, ``check`` and ``graph`` treat both syntaxes
alike. Every problem is located where it was written (the positions come from the file's
syntax tree, :mod:`roboscript.mission.python_source`), all problems are collected, and the
first is raised as a :class:`~roboscript.mission.builder.MissionProblemsError` carrying
the rest, exactly as for YAML. This module is a front end: it reads values and where they
were written from the class, and :class:`~roboscript.mission.builder.MissionBuilder` applies
the rules both syntaxes share.

Guard methods are compiled to :class:`MethodGuard` objects. What they read cannot be known
for certain without running them, so the compiler reads their code: every ``self.range``,
``self.bumper``, ``self.line`` and ``self.heading_deg`` (in the method and in the methods it
calls on ``self``) adds the capability it needs, so a mission's fit to a robot is checked
before the robot moves. A mission's ``requires`` adds what the code hides.
"""

from __future__ import annotations

import ast
import contextlib
import copy
import dis
import inspect
import keyword as pykeyword
import math
import operator
import re
import sys
import typing
import weakref
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from types import FunctionType
from typing import Any

from roboscript import capabilities as cap
from roboscript.actions.base import Action
from roboscript.actions.composite import Parallel, Repeat
from roboscript.code_owner import is_student_file
from roboscript.errors import InputError, LinkError, did_you_mean
from roboscript.inputs.quantities import DIMENSIONS, bare_number_warning, parse_quantity
from roboscript.inputs.source import Location
from roboscript.mission.builder import MissionBuilder
from roboscript.mission.checks import FIXED_NODES
from roboscript.mission.condition_reads import (
    PY_WAIT,
    condition_slips,
    endless_waits,
    helper_sleeps,
    sleep_warning,
    sleeps_in,
)
from roboscript.mission.guards import GuardEnv, guard_names
from roboscript.mission.never_true import bounds_of, never_true
from roboscript.mission.python_api import Mission, StateDef
from roboscript.mission.python_source import PythonSource, item, keyword
from roboscript.mission.spec import ActionSpec, MissionSpec, StateSpec, TransitionSpec
from roboscript.mission.student_code import (
    StudentCodeError,
    is_student_class,
    passes_through,
    shown_path,
)

__all__ = ["MethodGuard", "compile_mission", "mission_states", "nested_missions"]

# The capability each value a guard method can read needs: {"range": "range", ...}.
_SENSOR_CAPABILITY: dict[str, str] = {
    name.split(".")[0]: needs for name, needs in guard_names().items() if needs is not None
}
_KEYWORDS = {"done": "on_done", "failed": "on_failed", "timeout": "on_timeout"}


def nested_missions(action: object) -> Iterator[type[Mission]]:
    """The Mission classes a state's action runs as nested machines: the action itself, or
    one inside a ``Repeat`` or ``Parallel`` (``Repeat(Side, times=4)``)."""
    if isinstance(action, type) and issubclass(action, Mission):
        yield action
    elif isinstance(action, Repeat):
        yield from nested_missions(action.action)
    elif isinstance(action, Parallel):
        for child in action.actions:
            yield from nested_missions(child)


def _reading_class(sensor: str) -> type | None:
    """The class of ``self.SENSOR`` of a mission (``RangeReading``), or ``None`` when
    ``SENSOR`` is not one of the Mission's sensor readings."""
    prop = inspect.getattr_static(Mission, sensor, None)
    if not isinstance(prop, property) or prop.fget is None:
        return None
    try:
        reading = typing.get_type_hints(prop.fget).get("return")
    except (NameError, TypeError):
        return None
    if not isinstance(reading, type) or not reading.__name__.endswith("Reading"):
        return None
    return reading


def _reading_names(sensor: str) -> list[str]:
    """What ``self.SENSOR`` of a mission has (``distance_cm``, ...), or ``[]`` when ``SENSOR``
    is not one of the Mission's sensor readings."""
    reading = _reading_class(sensor)
    return [] if reading is None else [name for name in vars(reading) if not name.startswith("_")]


def _as_number(text: str, read: str) -> str:
    """How to write ``text`` (``"20 cm"``) as the number ``read`` (``self.range.distance_cm``)
    is compared with: in the unit its name ends with."""
    unit = read.rsplit(".", 1)[-1].rpartition("_")[2]
    try:
        number = float(text)  # "20": the number itself, in quotes
    except ValueError:
        pass
    else:
        if math.isfinite(number):
            return f"write the number without quotes: {text.strip()}"
    for kind, dimension in DIMENSIONS.items():
        if unit not in dimension.units:
            continue
        try:
            value = parse_quantity(text, kind) / dimension.units[unit]
        except ValueError:
            continue
        return f"compare it with a number in {unit}: {text!r} is {value:g}"
    return f"compare it with a number, in the unit its name ends with, e.g. {read} < 20"


def _reading_property(node: ast.expr) -> tuple[str, property] | None:
    """``self.range.distance_cm`` as written and its property, when ``node`` reads a value
    of a sensor (not a method), else ``None``."""
    if not (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Attribute)):
        return None
    sensor = node.value
    if not (isinstance(sensor.value, ast.Name) and sensor.value.id == "self"):
        return None
    reading = _reading_class(sensor.attr)
    value = inspect.getattr_static(reading, node.attr, None) if reading is not None else None
    return (f"self.{sensor.attr}.{node.attr}", value) if isinstance(value, property) else None


def _reading_value(node: ast.expr) -> str | None:
    """``self.range.distance_cm`` as written, when ``node`` reads a value of a sensor (a
    number, True/False or a name such as a colour's; not a method), else ``None``."""
    found = _reading_property(node)
    return found[0] if found is not None else None


def _used_as_values(node: ast.AST) -> list[ast.expr]:
    """The expressions ``node`` uses as a value to compare, to test or to return: the
    operands of a comparison, of ``and``/``or``/``not``, a test of ``if``/``while`` and what a
    ``return`` gives."""
    if isinstance(node, ast.Compare):
        return [node.left, *node.comparators]
    if isinstance(node, ast.BoolOp):
        return list(node.values)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
        return [node.operand]
    if isinstance(node, ast.If | ast.While | ast.IfExp):
        return [node.test]
    if isinstance(node, ast.Return) and node.value is not None:
        return [node.value]
    return []


def _whole_sensor(node: ast.expr) -> str | None:
    """``range`` when ``node`` is ``self.range``, a sensor itself (not one of its values),
    else ``None``."""
    if (
        isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == "self"
        and _reading_names(node.attr)
    ):
        return node.attr
    return None


def _reading_returns(node: ast.expr) -> tuple[str, object] | None:
    """``self.range.distance_cm`` as written and the type its value has (``float``), when
    ``node`` reads a sensor value whose type is written on it, else ``None``."""
    found = _reading_property(node)
    if found is None or found[1].fget is None:
        return None
    try:
        return found[0], typing.get_type_hints(found[1].fget).get("return")
    except (NameError, TypeError):
        return None


def _reads_number(node: ast.expr) -> str | None:
    """``self.range.distance_cm`` as written, when ``node`` reads a sensor value that is a
    number (not True/False, nor text), else ``None``."""
    found = _reading_returns(node)
    return found[0] if found is not None and found[1] in (float, int) else None


def _reads_text(node: ast.expr) -> bool:
    """``node`` reads a sensor value that is text (``self.color.name``), which may rightly
    be compared with text."""
    found = _reading_returns(node)
    returned = found[1] if found is not None else None
    return returned is str or str in typing.get_args(returned)


def _compared_with_none(node: ast.expr) -> tuple[str, str] | None:
    """``(self.range.distance_cm, "a number")`` when ``node`` asks whether a sensor value that
    is never None is None (``== None``, ``is None``), else ``None``."""
    if not (
        isinstance(node, ast.Compare)
        and len(node.ops) == 1
        and isinstance(node.ops[0], ast.Eq | ast.Is)
    ):
        return None
    left, right = node.left, node.comparators[0]
    if isinstance(left, ast.Constant) and left.value is None:
        left, right = right, left
    if not (isinstance(right, ast.Constant) and right.value is None):
        return None
    found = _reading_returns(left)
    if found is None:
        return None
    if found[1] in (float, int):
        return found[0], "a number"
    return (found[0], "True or False") if found[1] is bool else None


def _always_returns(body: list[ast.stmt]) -> bool:
    """True if running ``body`` always ends in a ``return`` or a ``raise`` (as far as plain
    ``if``/``else``, ``with`` and ``try`` show; a loop is taken to end, except
    ``while True``)."""
    if not body:
        return False
    last = body[-1]
    if isinstance(last, ast.Return | ast.Raise):
        return True
    if isinstance(last, ast.If):
        return _always_returns(last.body) and _always_returns(last.orelse)
    if isinstance(last, ast.With | ast.AsyncWith):
        return _always_returns(last.body)
    if isinstance(last, ast.Try):
        ends = [last.body + last.orelse, *(h.body for h in last.handlers)]
        return _always_returns(last.finalbody) or all(_always_returns(b) for b in ends)
    if isinstance(last, ast.While):
        return isinstance(last.test, ast.Constant) and last.test.value is True
    if isinstance(last, ast.Match):
        return any(
            isinstance(case.pattern, ast.MatchAs) and case.pattern.pattern is None
            for case in last.cases
        ) and all(_always_returns(case.body) for case in last.cases)
    # an earlier statement may return at every turn: any return in the body counts then
    return any(isinstance(statement, ast.Return | ast.Raise) for statement in body[:-1])


def _names_state(node: ast.expr) -> bool:
    """True for ``state`` (or ``roboscript.state``)."""
    return (isinstance(node, ast.Name) and node.id == "state") or (
        isinstance(node, ast.Attribute) and node.attr == "state"
    )


def _calls_state(node: ast.expr) -> bool:
    """True for ``state(...)`` (or ``roboscript.state(...)``)."""
    return isinstance(node, ast.Call) and _names_state(node.func)


def mission_states(cls: type[Mission]) -> dict[str, StateDef]:
    """The states of a mission class by name, in the order written (base classes first)."""
    found: dict[str, StateDef] = {}
    for klass in reversed(cls.__mro__):
        for name, value in vars(klass).items():
            if isinstance(value, StateDef):
                found[name] = value
            elif name in found:
                del found[name]  # a subclass replaced the state with something else
    return found


# --------------------------------------------------------------------------- guard methods


class _Instances:
    """One object of the mission class per run (per runner), made at the first guard."""

    def __init__(self, cls: type[Mission], state_names: frozenset[str]) -> None:
        self._cls = cls
        self._state_names = state_names
        self._by_env: weakref.WeakKeyDictionary[Any, Mission] = weakref.WeakKeyDictionary()
        self._last: tuple[Any, Mission] | None = None  # for runners that cannot be weak keys

    def get(self, env: GuardEnv) -> Mission:
        if self._last is not None and self._last[0] is env:
            return self._last[1]
        try:
            mission = self._by_env.get(env)
        except TypeError:
            mission = None
        if mission is None:
            try:
                mission = self._cls()
            except (LinkError, StudentCodeError):
                raise
            except BaseException as exc:  # exit() ends the run, not the program
                if passes_through(exc):
                    raise
                raise StudentCodeError(f"mission class {self._cls.__name__}", exc) from exc
            mission._bind(env, self._state_names)
            with contextlib.suppress(TypeError):  # unhashable runners use the last slot
                self._by_env[env] = mission
        self._last = (env, mission)
        return mission


@dataclass(frozen=True)
class MethodGuard:
    """A condition written in Python: a guard method of the mission, or a function.

    Attributes:
        source: The method's name, for diagrams and messages.
        capabilities: Capability names it reads (found in its code, plus ``requires``).
        states: State names it passes to ``visits``, as far as its code shows.
        where: ``file:line`` of its ``def``, for messages.
    """

    source: str
    _read: Callable[[Mission], object] = field(repr=False, compare=False)
    _instances: _Instances = field(repr=False, compare=False)
    capabilities: frozenset[str] = frozenset()
    states: frozenset[str] = frozenset()
    where: str | None = None

    def __call__(self, env: GuardEnv) -> bool:
        """Run the condition now.

        Raises:
            StudentCodeError: It raised, or returned None (a missing ``return``).
        """
        mission = self._instances.get(env)
        try:
            value = self._read(mission)
        except (LinkError, StudentCodeError):
            raise
        except BaseException as exc:  # exit() ends the run, not the program
            if passes_through(exc):
                raise
            raise StudentCodeError(f"condition '{self.source}'", exc) from exc
        if value is None:
            raise StudentCodeError(
                f"condition '{self.source}'",
                problem="returned None instead of True or False (is 'return' missing?)",
                where=self.where,
            )
        if inspect.isgenerator(value):
            raise StudentCodeError(
                f"condition '{self.source}'",
                problem="returned a generator (it uses yield) instead of True or False",
                where=self.where,
            )
        if isinstance(value, str):
            raise StudentCodeError(
                f"condition '{self.source}'",
                problem=f"returned the text {value[:40]!r} instead of True or False",
                where=self.where,
            )
        if isinstance(value, float | list | tuple | dict | set):
            # a distance (true unless 0) or a list (true unless empty): never what was meant
            what = (
                f"the number {value:g}" if isinstance(value, float) else f"a {type(value).__name__}"
            )
            raise StudentCodeError(
                f"condition '{self.source}'",
                problem=f"returned {what} instead of True or False",
                fix="return a comparison, e.g. return self.range.distance_cm < 20",
                where=self.where,
            )
        return bool(value)


@dataclass
class _Scan:
    """What a guard's code reads, found without running it."""

    capabilities: set[str] = field(default_factory=set)
    states: dict[str, ast.Constant] = field(default_factory=dict)
    returns_value: bool = False
    returns_text: ast.Constant | None = None  # the first ``return "..."``
    # the first ``return self.range.distance_cm``: a number, which holds unless it is 0
    returns_number: tuple[ast.expr, str] | None = None
    # ``self.range.distnce``: (the node, the sensor, the names it has), in the method's file
    misread: list[tuple[ast.Attribute, str, list[str]]] = field(default_factory=list)
    yields: ast.expr | None = None  # the first ``yield``: the method makes a generator
    falls_off: ast.stmt | None = None  # the last statement, when the code can run past it
    # ``Rotate(...)`` made in the method: (the call, the action's class name)
    actions: list[tuple[ast.Call, str]] = field(default_factory=list)
    # ``self.bumper.any()``: a sensor's value called as a function (the call, as written)
    called_values: list[tuple[ast.Call, str]] = field(default_factory=list)
    # ``self.range.distance_cm < "20 cm"``: a sensor's value compared with text
    text_compared: list[tuple[ast.Constant, str]] = field(default_factory=list)
    # ``self.visits(side)``: a state named without quotes
    unquoted_states: list[ast.Name] = field(default_factory=list)
    # ``self.range < 20``, ``return self.bumper``: a sensor itself used as its value
    whole_sensors: list[tuple[ast.Attribute, str]] = field(default_factory=list)


def _walk_own(node: ast.AST) -> Iterator[ast.AST]:
    """Every node of a function's body, not entering nested functions or classes."""
    todo = list(ast.iter_child_nodes(node))
    while todo:
        child = todo.pop()
        yield child
        if not isinstance(
            child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda | ast.ClassDef
        ):
            todo.extend(ast.iter_child_nodes(child))


# ------------------------------------------------------------------------------- compiling


class _Compiler:
    def __init__(
        self,
        cls: type[Mission],
        path: str | None,
        *,
        sources: dict[str, PythonSource] | None = None,
        nested: dict[type[Mission], MissionSpec | None] | None = None,
    ) -> None:
        self.cls = cls
        self.file = _file_of(cls)
        self.shown = path or shown_path(self.file)
        # Shared with nested compilers and the builder: each file is parsed once, and a Mission
        # class nested in several states is compiled, checked and warned about once (None: it
        # had errors).
        self._sources: dict[str, PythonSource] = {} if sources is None else sources
        self.build = MissionBuilder(self.shown, self._sources)
        self._nested: dict[type[Mission], MissionSpec | None] = {} if nested is None else nested
        self.source = self.source_of(self.file)
        self.states = mission_states(cls)
        first_line = next(
            (s.where[1] for s in self.states.values() if s.where and s.where[0] == self.file),
            None,
        )
        self.class_node = self.source.class_def(cls.__name__, first_line)
        self.names = frozenset(self.states)
        self.instances = _Instances(cls, self.names)
        self.method_guards: dict[str, MethodGuard] = {}
        self.missing_states: set[str] = set()
        """Names of class attributes taken for states and told once: ``end = "success"``."""
        self.declared: frozenset[str] = frozenset()  # the class's `requires`
        self._slipped: set[tuple[str, str]] = set()  # (where, message) said by slips()

    def source_of(self, filename: str) -> PythonSource:
        if filename not in self._sources:
            same = self.file == filename
            self._sources[filename] = PythonSource(
                filename, self.shown if same else shown_path(filename)
            )
        return self._sources[filename]

    @property
    def problems(self) -> list[InputError]:
        return self.build.problems

    def problem(
        self, message: str, where: Location, hint: str | None = None, severity: str = "error"
    ) -> None:
        self.build.problem(message, where, hint, severity)

    @property
    def class_loc(self) -> Location:
        return self.source.loc(self.class_node)

    def attribute_loc(self, name: str) -> Location:
        found = self.source.assignment(self.class_node, name)
        return self.source.loc(found[1]) if found else self.class_loc

    # ----------------------------------------------------------------------------- top

    def compile(self) -> MissionSpec | None:
        cls = self.cls
        if self.miswritten_states():
            return None
        if not self.states:
            inside = self.states_in_methods()
            self.problem(
                f"mission {cls.__name__} has no states",
                self.source.loc(inside) if inside is not None else self.class_loc,
                "write each state in the class body, not in a method: go = state(...)"
                if inside is not None
                else "add one, e.g. go = state(Drive(distance_mm=300), initial=True,"
                " on_done='end')",
            )
            return None
        self.declared = self.requires()
        self.made_without_values()
        self.states_written_twice()
        states: dict[str, StateSpec] = {}
        for state_name, definition in self.states.items():
            built = self.state(state_name, definition)
            if built is not None:
                states[state_name] = built
        initial = self.initial()
        hints: dict[str, str | None] = {}
        for key in ("robot", "world"):
            example = "mirto" if key == "robot" else "square-room"
            hints[key] = self.build.names_a(
                key, getattr(cls, key, None), self.attribute_loc(key), f'{key} = "{example}"'
            )
        name: Any = getattr(cls, "name", None)
        if name is not None and not isinstance(name, str):
            self.problem("'name' is the mission's name, as text", self.attribute_loc("name"))
            name = None
        return self.build.mission(
            name=name or _kebab(cls.__name__),
            initial=initial or next(iter(self.states)),
            states=states,
            description=_description(cls),
            where=self.class_loc,
            robot=hints["robot"],
            world=hints["world"],
            robot_where=self.attribute_loc("robot"),
            world_where=self.attribute_loc("world"),
        )

    def made_without_values(self) -> None:
        """Say so of an ``__init__`` that needs values: roboscript makes the mission with
        none, so it would fail when the first condition runs."""
        init = inspect.getattr_static(self.cls, "__init__", None)
        if not inspect.isfunction(init):
            return
        needed = [
            p.name
            for p in list(inspect.signature(init).parameters.values())[1:]
            if p.default is p.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
        ]
        if needed:
            self.problem(
                f"{self.cls.__name__}.__init__ needs {', '.join(needed)}, and roboscript makes"
                " the mission with nothing to give it",
                self.def_of(init)[0],
                f"give it a default, def __init__(self, {needed[0]}=...), or set it in the class:"
                f" {needed[0]} = ...",
            )

    def states_in_methods(self) -> ast.AST | None:
        """The first ``self.NAME = state(...)`` in a method of the class, if any."""
        for statement in self.class_node.body if self.class_node is not None else []:
            if not isinstance(statement, ast.FunctionDef):
                continue
            for node in ast.walk(statement):
                if isinstance(node, ast.Assign) and _calls_state(node.value):
                    return node
        return None

    def miswritten_states(self) -> bool:
        """Say so of each state that a later ``def`` of the same name in the class replaces
        (Python keeps the last of the two: the state is gone), of ``NAME = state`` without
        its call, of ``NAME = state(...),`` (a comma at its end: a tuple, not a state) and of
        ``NAME = Drive(...)`` (an action without its state); True if there was one."""
        written: dict[str, ast.stmt] = {}
        found = False
        # the names the class body reads, found in one walk of it for all its statements
        body = self.class_node if self.class_node is not None else ast.Module([], [])
        used = frozenset(
            node.id
            for node in ast.walk(body)
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)
        )
        for statement in self.class_node.body if self.class_node is not None else []:
            if isinstance(statement, ast.Assign) and self.not_a_state(statement, used):
                found = True
            elif isinstance(statement, ast.Assign) and _calls_state(statement.value):
                for target in statement.targets:
                    if isinstance(target, ast.Name):
                        written[target.id] = statement
            elif isinstance(statement, ast.Assign) and _names_state(statement.value):
                found = True
                name = ", ".join(ast.unparse(t) for t in statement.targets)
                self.problem(
                    f"'{name} = state' names the state function without calling it",
                    self.source.loc(statement.value),
                    f'call it: {name} = state(...), e.g. {name} = state(final="success")',
                )
            elif isinstance(statement, ast.FunctionDef) and statement.name in written:
                name = statement.name
                found = True
                self.problem(
                    f"'{name}' is a state (line {written[name].lineno}) and a method: this def"
                    " replaces the state, so the mission has no state called"
                    f" '{name}'",
                    self.source.loc(statement),
                    "give the method another name; a state's action goes inside state(...),"
                    f" e.g. {name} = state(Drive(distance_mm=500), ...)",
                )
        return found

    def not_a_state(self, statement: ast.Assign, used: frozenset[str]) -> bool:
        """Say so of ``NAME = state(...),`` and ``NAME = Drive(...)``, which Python takes
        as a tuple and an action, and the mission silently lacks; True if it is one.
        ``used``: the names the class body reads (an action one of them names is kept for
        states to run)."""
        name = ", ".join(ast.unparse(t) for t in statement.targets)
        value = statement.value
        if isinstance(value, ast.Tuple) and len(value.elts) == 1 and _calls_state(value.elts[0]):
            self.problem(
                f"'{name} = state(...),' is not a state: the comma at its end makes a tuple",
                self.source.loc(value),
                "remove the comma after state(...)",
            )
            return True
        held = [vars(self.cls).get(t.id) for t in statement.targets if isinstance(t, ast.Name)]
        named = {t.id for t in statement.targets if isinstance(t, ast.Name)}
        # an action kept to be run by states (turn = Rotate(...); a = state(turn)) is fine
        if (
            isinstance(value, ast.Call)
            and any(isinstance(h, Action) for h in held)
            and not (named & used)
        ):
            self.problem(
                f"'{name}' is an action, not a state: a state runs it",
                self.source.loc(value),
                f"write {name} = state({ast.unparse(value)}, ...)",
            )
            return True
        return False

    def requires(self) -> frozenset[str]:
        raw = getattr(self.cls, "requires", ())
        if isinstance(raw, str):
            raw = (raw,)
        names: set[str] = set()
        for entry in raw if isinstance(raw, tuple | list | set | frozenset) else [raw]:
            if isinstance(entry, str) and entry in cap.CAPABILITY_NAMES:
                names.add(entry)
            else:
                self.problem(
                    f"requires: unknown capability {entry!r}",
                    self.attribute_loc("requires"),
                    did_you_mean(str(entry), cap.CAPABILITY_NAMES)
                    or f"capabilities: {', '.join(cap.CAPABILITY_NAMES)}",
                )
        return frozenset(names)

    def states_written_twice(self) -> None:
        """Refuse a state written twice in the class body: Python keeps the second and drops
        the first without a word, as YAML would not (``'go' is given twice``)."""
        if self.class_node is None:
            return
        lines: dict[str, list[ast.expr]] = {}
        for statement in self.class_node.body:
            if isinstance(statement, ast.Assign):
                for target in statement.targets:
                    if isinstance(target, ast.Name) and target.id in self.states:
                        lines.setdefault(target.id, []).append(target)
        for name, targets in lines.items():
            for again in targets[1:]:
                self.problem(
                    f"'{name}' is given twice (first on line {targets[0].lineno}), and Python"
                    " keeps only the second",
                    self.source.loc(again),
                    "keep one of the two, or give one of them another name",
                )
        defs: dict[str, list[ast.FunctionDef | ast.AsyncFunctionDef]] = {}
        for statement in self.class_node.body:
            # @x.setter and the like define a name again on purpose
            if (
                isinstance(statement, ast.FunctionDef | ast.AsyncFunctionDef)
                and not statement.decorator_list
            ):
                defs.setdefault(statement.name, []).append(statement)
        for name, written in defs.items():
            for twice in written[1:]:  # two `def near`: the first is never used
                self.problem(
                    f"method '{name}' is written twice (first on line {written[0].lineno}), and"
                    " Python keeps only the second",
                    self.source.loc(twice),
                    "keep one of the two, or give one of them another name",
                )

    def initial(self) -> str | None:
        marked = [name for name, s in self.states.items() if s.initial is True]
        for name, definition in self.states.items():
            if definition.initial not in (True, False):
                given = definition.initial
                meant = isinstance(given, str) and given.strip().lower() in ("true", "false")
                self.problem(
                    f"state '{name}': initial is True or False, got {given!r}",
                    self.keyword_loc(name, "initial"),
                    f"write initial={given.strip().capitalize()}, without quotes"
                    if meant and isinstance(given, str)
                    else None,
                )
        if not marked:
            if all(s.initial is False for s in self.states.values()):  # else said above
                first = next(iter(self.states))
                self.problem(
                    f"mission {self.cls.__name__} has no initial state",
                    self.class_loc,
                    f"mark the first state, e.g. {first} = state(..., initial=True)",
                )
            return None
        for extra in marked[1:]:
            self.problem(
                f"states '{marked[0]}' and '{extra}' are both initial; a mission starts in one",
                self.keyword_loc(extra, "initial"),
            )
        return marked[0]

    # -------------------------------------------------------------------------- states

    def call_of(self, name: str) -> tuple[ast.expr | None, ast.expr | None]:
        found = self.source.assignment(self.class_node, name)
        if found is None:
            return None, None
        return found

    def state_loc(self, name: str) -> Location:
        target, _ = self.call_of(name)
        if target is not None:
            return self.source.loc(target)
        where = self.states[name].where
        if where is not None:
            return Location(self.source_of(where[0]).shown, where[1])
        return self.class_loc

    def keyword_loc(self, name: str, key: str) -> Location:
        _, call = self.call_of(name)
        node = keyword(call, key)
        return self.source.loc(node) if node is not None else self.state_loc(name)

    def state(self, name: str, definition: StateDef) -> StateSpec | None:
        where = self.state_loc(name)
        if name.startswith("_") or hasattr(Mission, name):
            self.problem(
                f"a state cannot be called '{name}': Mission uses that name",
                where,
                "choose another name",
            )
            return None
        if len(definition.names) > 1:
            self.problem(
                f"one state(...) is assigned to {' and '.join(definition.names)}",
                where,
                "write a separate state(...) for each",
            )
        _, call = self.call_of(name)
        action = self.action(name, definition.action, self.action_node(call))
        during: list[ActionSpec] = []
        extras = definition.during
        if isinstance(extras, Action):
            extras = [extras]
        during_node = keyword(call, "during")
        for index, extra in enumerate(extras or ()):
            built = self.action(name, extra, item(during_node, index, len(extras or ())))
            if built is not None:
                during.append(built)
        on: dict[str, tuple[TransitionSpec, ...]] = {}
        for outcome, route in definition.routes.items():
            if route is not None:
                node = keyword(call, _KEYWORDS[outcome])
                on[outcome] = self.choices(name, route, node, need_condition=False)
        when: tuple[TransitionSpec, ...] = ()
        if definition.when is not None:
            when = self.choices(name, definition.when, keyword(call, "when"), need_condition=True)
        return self.build.state(
            name,
            action=action,
            during=tuple(during),
            on=on,
            when=when,
            timeout_s=self.build.timeout(
                name, "timeout_s", definition.timeout_s, self.keyword_loc(name, "timeout_s")
            ),
            final=self.build.final(name, definition.final, self.keyword_loc(name, "final")),
            description=definition.description,
            where=where,
        )

    @staticmethod
    def action_node(call: ast.expr | None) -> ast.expr | None:
        if isinstance(call, ast.Call) and call.args:
            return call.args[0]
        return keyword(call, "action")

    def action(self, name: str, action: object, node: ast.expr | None) -> ActionSpec | None:
        if action is None:
            return None
        where = self.source.loc(node) if node is not None else self.state_loc(name)
        if isinstance(action, type) and issubclass(action, Mission):
            return self.nested(name, action, where)
        if isinstance(action, type) and issubclass(action, Action):
            self.problem(
                f"state '{name}': {action.__name__} is a kind of action; call it to make one",
                where,
                f"write {action.written()[1]}",
            )
            return None
        if isinstance(action, Repeat | Parallel):
            return self.composite(name, action, node, where)
        if isinstance(action, list | tuple) and len(action) == 1:
            self.problem(
                f"state '{name}' is given its action in a list, and a state runs one action",
                where,
                "take away the [ ] around it: state("
                + (
                    ast.unparse(node.elts[0])
                    if isinstance(node, ast.List | ast.Tuple) and len(node.elts) == 1
                    else "Drive(distance_mm=300)"
                )
                + ", ...)",
            )
            return None
        if isinstance(action, list | tuple):
            self.problem(
                f"state '{name}' is given {len(action)} actions in a list, and a state runs one",
                where,
                "to do them one after another, give each its own state and go on with"
                ' on_done="NEXT"; to do them at the same time, write state(Parallel([...]), ...)',
            )
            return None
        if not isinstance(action, Action):
            shown = repr(action) if " at 0x" not in repr(action) else type(action).__name__
            self.problem(
                f"state '{name}' does {shown}, which is not an action",
                where,
                "use an action such as Drive(distance_mm=300)",
            )
            return None
        kind = type(action)
        action_name = getattr(kind, "name", None)
        if not isinstance(action_name, str):
            self.problem(
                f"action class {kind.__name__} has no name",
                where,
                f'give it the word a mission uses for it: name = "{kind.__name__.lower()}"',
            )
            return None
        template = self.conditions_in(action, node, where)
        if template is None:
            return None
        try:
            copy.deepcopy(template)
        except Exception as exc:  # noqa: BLE001 - a student's action may hold anything
            self.problem(
                f"state '{name}': {action_name} cannot be copied for each visit ({exc})", where
            )
            return None
        # The values the object holds, by their mission names; the builder converts them
        # (quantities to float, omitted parameters to their defaults) as it does YAML's.
        values = {
            p.name: getattr(template, p.kwarg) for p in kind.params if hasattr(template, p.kwarg)
        }
        kwargs_of = {p.name: p.kwarg for p in kind.params}

        def param_where(param: str, message: str, offset: int | None) -> Location:
            # A value out of range is shown at its keyword (Drive(distance_mm=1e400)).
            found = keyword(node, kwargs_of.get(param, param)) if param else None
            return self.source.loc(found) if found is not None else where

        self.unnamed_numbers(kind, node)
        self.numbers_as_text(kind, node)
        return self.build.action(
            kind,
            values,
            where,
            self.names,
            param_where=param_where,
            # Each entry runs a fresh copy, so nothing carries over from an earlier visit.
            instance=template,
            name=action_name,
        )

    def unnamed_numbers(self, kind: type[Action], node: ast.expr | None) -> None:
        """Warn of a number given without its keyword (``Drive(30)``), where the keyword's
        unit is unlikely to be the one meant (30 mm, for 30 cm): the unit is in the keyword,
        and without it nothing shows which unit the number is in."""
        if not isinstance(node, ast.Call) or not node.args:
            return
        try:
            keywords = list(inspect.signature(kind).parameters)[: len(node.args)]
        except (TypeError, ValueError):
            return
        params = {p.kwarg: p for p in kind.params}
        for arg, kwarg in zip(node.args, keywords, strict=False):
            param = params.get(kwarg)
            value = arg.value if isinstance(arg, ast.Constant) else None
            if param is None or isinstance(value, bool) or not isinstance(value, int | float):
                continue
            note = bare_number_warning(value, param.kind)
            if note is None or note[1] is None:
                continue
            meant = note[1].removeprefix("or did you mean ").rstrip("?")
            unit = DIMENSIONS[param.kind].base_unit
            self.problem(
                f"{value}, given to {kind.__name__} without its name, is taken as {kwarg}={value},"
                f" {value} {unit}",
                self.source.loc(arg),
                f'name it: {kwarg}={value}; for {meant}, write {kwarg}="{meant}"',
                "warning",
            )

    def numbers_as_text(self, kind: type[Action], node: ast.expr | None) -> None:
        """Warn of a number written in quotes (``Drive(distance_mm="30")``): it is read in
        the keyword's unit, as YAML reads ``distance: "30"``, and said so, since quotes make
        text and a number in Python is written without them (a number with its unit in
        quotes, ``distance_mm="30 cm"``, is read as written and needs no warning)."""
        if not isinstance(node, ast.Call):
            return
        try:
            positional = list(inspect.signature(kind).parameters)[: len(node.args)]
        except (TypeError, ValueError):
            positional = []
        given = [*zip(node.args, positional, strict=False)]
        given += [(k.value, k.arg) for k in node.keywords if k.arg is not None]
        params = {p.kwarg: p for p in kind.params}
        for value, kwarg in given:
            param = params.get(kwarg)
            text = value.value if isinstance(value, ast.Constant) else None
            if param is None or param.kind not in DIMENSIONS or not isinstance(text, str):
                continue
            try:
                number = float(text)
            except ValueError:
                continue  # a unit, or text the builder refuses at its keyword
            if not math.isfinite(number) or "_" in text:
                continue
            written = text.strip()
            unit = "" if param.kind == "count" else f" {DIMENSIONS[param.kind].base_unit}"
            self.problem(
                f'{kwarg}="{text}" is a number in quotes, which makes it text: taken as'
                f" {written}{unit}",
                self.source.loc(value),
                f"write the number without quotes: {kwarg}={written}",
                "warning",
            )

    def composite(
        self, name: str, action: Repeat | Parallel, node: ast.expr | None, where: Location
    ) -> ActionSpec | None:
        """A ``Repeat`` or ``Parallel`` that runs another Mission class: built from its
        children, as YAML's ``repeat:`` and ``parallel:`` are, so the inner mission is
        compiled and checked like any nested one."""
        if isinstance(action, Repeat):
            given = self.action_node(node) or keyword(node, "factory")
            child = self.action(name, action.action, given)
            return None if child is None else self.build.repeat(action.times, child, where)
        written = self.action_node(node) or keyword(node, "factories")
        children = [
            self.action(name, child, item(written, i, len(action.actions)))
            for i, child in enumerate(action.actions)
        ]
        built = [child for child in children if child is not None]
        if len(built) < len(children):
            return None
        return self.build.parallel(action.mode, built, where)

    def nested(self, name: str, cls: type[Mission], where: Location) -> ActionSpec | None:
        """A state whose action is another Mission class: its machine runs nested."""
        if cls is self.cls:
            self.problem(
                f"state '{name}' nests its own mission", where, "nest another Mission class"
            )
            return None
        if cls not in self._nested:
            inner = _Compiler(cls, None, sources=self._sources, nested=self._nested)
            self._nested[cls] = self.build.check_inner(inner.compile(), inner.build)
        spec = self._nested[cls]
        if spec is None:
            return None
        return self.build.machine(spec, name, where)

    def conditions_in(self, action: Action, node: ast.expr | None, where: Location) -> Any:
        """The action with its condition parameters (``until=``, ...) compiled, or ``None``.

        Python missions write them as in transitions: a guard method's name or an
        expression, e.g. ``WaitUntil(condition="range.distance_cm < 20", timeout_s=5)``.
        """
        template: Any = action
        for param in type(action).params:
            raw = getattr(action, param.kwarg, None)
            written = isinstance(raw, str) or (callable(raw) and not hasattr(raw, "capabilities"))
            if param.kind != "guard" or not written:
                continue  # not a condition, or one compiled already
            guard = self.condition(raw, keyword(node, param.kwarg), where)
            if guard is None:
                return None
            if template is action:
                template = copy.copy(action)
            setattr(template, param.kwarg, guard)
        return template

    # --------------------------------------------------------------------- transitions

    def choices(
        self, name: str, route: object, node: ast.expr | None, *, need_condition: bool
    ) -> tuple[TransitionSpec, ...]:
        if need_condition and isinstance(route, dict) and route:
            pairs = ", ".join(f"({condition!r}, {target!r})" for condition, target in route.items())
            self.problem(  # when={"near": "end"}: a dict, as YAML's mapping would be
                f"state '{name}': when is a list of (condition, state) pairs, not a dict",
                self.source.loc(node) if node is not None else self.state_loc(name),
                f"write when=[{pairs}]",
            )
            return ()
        items = route if isinstance(route, list) else [route]
        if need_condition and isinstance(route, list) and self._pair_without_brackets(route):
            self.problem(  # when=["near", "end"]: the pair's own brackets left out
                f"state '{name}': each 'when' entry is (condition, state), in its own brackets",
                self.source.loc(node) if node is not None else self.state_loc(name),
                f'write when=[("{route[0]}", "{route[1]}")]',
            )
            return ()
        found = []
        for index, entry in enumerate(items):
            entry_node = item(node, index, len(items)) if isinstance(route, list) else node
            transition = self.choice(name, entry, entry_node, need_condition=need_condition)
            if transition is not None:
                found.append(transition)
        return tuple(found)

    def _pair_without_brackets(self, route: list[object]) -> bool:
        """Whether ``route`` is a condition method's name and a state's, written as the
        list itself rather than a pair in it."""
        if len(route) != 2 or not all(isinstance(part, str) for part in route):
            return False
        condition, target = (str(part) for part in route)
        return inspect.isfunction(inspect.getattr_static(self.cls, condition, None)) and not (
            inspect.isfunction(inspect.getattr_static(self.cls, target, None))
        )

    def choice(
        self, name: str, entry: object, node: ast.expr | None, *, need_condition: bool
    ) -> TransitionSpec | None:
        where = self.source.loc(node) if node is not None else self.state_loc(name)
        if isinstance(entry, tuple):
            if len(entry) != 2:
                self.problem(
                    "a conditional choice is (condition, state), e.g. ('bumper_hit', 'stuck')",
                    where,
                )
                return None
            condition, target_raw = entry
            target = self.target(target_raw, item(node, 1, 2), where)
            guard = self.condition(condition, item(node, 0, 2), where)
            if guard is None or target is None:
                return None
            return self.build.transition(target, guard, guard.source, where)
        if need_condition:
            self.problem(
                f"state '{name}': each 'when' entry is (condition, state)",
                where,
                f"e.g. when=[('bumper_hit', {entry!r})]" if isinstance(entry, str) else None,
            )
            return None
        target = self.target(entry, node, where)
        return self.build.transition(target, where=where) if target is not None else None

    def target(self, value: object, node: ast.expr | None, fallback: Location) -> str | None:
        where = self.source.loc(node) if node is not None else fallback
        if isinstance(value, StateDef):
            for name, definition in self.states.items():
                if definition is value:
                    return name
            self.problem(f"{value!r} is not a state of {self.cls.__name__}", where)
            return None
        if (
            isinstance(value, str)
            and value not in self.names
            and inspect.isfunction(inspect.getattr_static(self.cls, value, None))
        ):
            self.problem(
                f"'{value}' is a condition method, not a state",
                where,
                "a choice made by a condition is a tuple of the condition and the state it goes"
                f" to: ('{value}', 'STATE')",
            )
            return None
        held = inspect.getattr_static(self.cls, value, None) if isinstance(value, str) else None
        if isinstance(value, str) and value not in self.names and isinstance(held, str | Action):
            if value in self.missing_states:
                return None  # told once, where the first transition names it
            self.missing_states.add(value)
            made = (
                f'state(final="{held}")'
                if held in ("success", "failure")
                else f"state({held.written_call()}, ...)"
                if isinstance(held, Action)
                else "state(...)"
            )
            self.problem(
                f"'{value}' is {'an action' if isinstance(held, Action) else 'text'} in the"
                " class, not a state",
                where,
                f"make it a state: {value} = {made}",
            )
            return None
        return self.build.target(value, self.names, where)

    # ---------------------------------------------------------------------- conditions

    def condition(self, raw: object, node: ast.expr | None, fallback: Location) -> Any:
        where = self.source.loc(node) if node is not None else fallback
        if callable(raw) and not isinstance(raw, str | StateDef):
            method = getattr(raw, "__name__", "")
            if inspect.isfunction(getattr(self.cls, method, None)) and _owned(
                self.cls, method, raw
            ):
                return self.method_guard(method, where)
            return self.function_guard(raw, where)
        if not isinstance(raw, str):
            self.problem(
                f"a condition is a method's name or an expression as text, got {raw!r}", where
            )
            return None
        text = raw.strip()
        if text.isidentifier() and not pykeyword.iskeyword(text) and text not in ("true", "false"):
            return self.method_guard(text, where)
        return self.build.expression(
            text, self.names, lambda offset: _shift(where, node, raw, offset)
        )

    def method_guard(self, name: str, where: Location) -> MethodGuard | None:
        if name in self.method_guards:
            return self.method_guards[name]
        value = inspect.getattr_static(self.cls, name, None)
        if isinstance(value, property) and inspect.isfunction(value.fget):
            self.problem(
                f"condition '{name}' is a property, and a condition is a plain method",
                self.def_of(value.fget)[0],
                f"take away the @property above def {name}(self)",
            )
            return None
        if isinstance(value, StateDef):
            self.problem(
                f"'{name}' is a state, not a condition",
                where,
                "a condition names a method that returns True or False; "
                "for several choices, use a list: [(condition, state), state]",
            )
            return None
        if inspect.isfunction(value) and value is not inspect.getattr_static(Mission, name, value):
            # Its own method: "has no method 'visits' (did you mean 'visits'?)" would puzzle.
            self.problem(
                f"a condition method cannot be called '{name}': Mission uses that name",
                self.def_of(value)[0],
                "choose another name",
            )
            return None
        if self.not_a_plain_method(name, value, where):
            return None
        if not inspect.isfunction(value) or hasattr(Mission, name):
            methods = _methods(self.cls)
            outside = vars(sys.modules.get(self.cls.__module__, object())).get(name)
            self.problem(
                f"{self.cls.__name__} has no method '{name}'",
                where,
                did_you_mean(name, methods)
                or (
                    f"'{name}' is written outside the class: indent its def under class"
                    f" {self.cls.__name__}: to make it a method"
                    if inspect.isfunction(outside) and value is None
                    else f"define it: def {name}(self) -> bool: ... (return True or False)"
                ),
            )
            return None
        signature = inspect.signature(value)
        extra = [p for p in list(signature.parameters.values())[1:] if p.default is p.empty]
        def_loc, _ = self.def_of(value)
        if not signature.parameters or extra:
            self.problem(
                f"condition method '{name}' must take only self", def_loc, f"def {name}(self):"
            )
            return None
        scan = self.scan(value)
        for state_name, constant in scan.states.items():
            if state_name not in self.names:
                self.problem(
                    f"visits('{state_name}'): there is no state '{state_name}'",
                    self.source_of(value.__code__.co_filename).loc(constant),
                    did_you_mean(state_name, self.names),
                )
        for node, sensor, names in scan.misread:
            self.problem(
                f"self.{sensor} has no '{node.attr}' (it has {', '.join(names)})",
                self.source_of(value.__code__.co_filename).loc(node),
                did_you_mean(node.attr, names),
            )
        where_in = self.source_of(value.__code__.co_filename).loc
        if scan.yields is not None:
            self.problem(
                f"condition method '{name}' uses yield, so it returns a generator, which"
                " counts as true at once",
                where_in(scan.yields),
                "write return, not yield: a condition returns True or False; an action runs"
                " in a state of its own",
            )
        for call, action in scan.actions:
            self.problem(
                f"{action}(...) in condition method '{name}' is made and thrown away: a"
                " condition cannot run an action",
                where_in(call),
                f"run it in a state of its own, e.g. turn = state({action}(...), ...), and go"
                f" there when the condition holds: when=[('{name}', 'turn')]",
            )
        for used, sensor in scan.whole_sensors:
            names = _reading_names(sensor)
            shown = next((n for n in names if n in ("any", "distance_cm")), names[0])
            self.problem(
                f"self.{sensor} is the {sensor} sensor, not one of its values, so it is never"
                " a number nor True or False",
                where_in(used),
                f"read one of its values, e.g. self.{sensor}.{shown}"
                + (f" (it has {', '.join(names)})" if len(names) > 1 else ""),
            )
        for call, read in scan.called_values:
            self.problem(
                f"{read} is a value, not a function: it is read without ()",
                where_in(call),
                f"write {read}",
            )
        for text, read in scan.text_compared:
            self.problem(
                f"{read} is compared with the text {text.value!r}, and a sensor's value is a"
                " number (or True/False)",
                where_in(text),
                _as_number(str(text.value), read),
            )
        for never, message, hint, severity in self.never_true(value):
            self.problem(message, where_in(never), hint, severity)
        for unquoted in scan.unquoted_states:
            self.problem(
                f"visits({unquoted.id}) names the state '{unquoted.id}' without quotes",
                where_in(unquoted),
                f"write self.visits('{unquoted.id}')",
            )
        self.slips(value, set())
        if scan.returns_text is not None:
            self.problem(
                f"condition method '{name}' returns the text {scan.returns_text.value!r},"
                " and any text but '' counts as true",
                self.source_of(value.__code__.co_filename).loc(scan.returns_text),
                "return True or False, e.g. return self.range.distance_cm < 20",
            )
        if scan.returns_number is not None:
            number, read = scan.returns_number
            self.problem(
                f"condition method '{name}' returns {read}, a number, and any number but 0"
                " counts as true",
                self.source_of(value.__code__.co_filename).loc(number),
                f"return a comparison, e.g. return {read} < 20",
            )
        fixed = _fixed_result(value)
        if (
            fixed is not None
            and scan.returns_value
            and scan.returns_text is None
            and scan.returns_number is None
        ):
            self.problem(
                f"condition method '{name}' reads nothing but fixed values, so what it returns"
                f" never changes{_always(fixed[0])}",
                def_loc,
                "compare a sensor's value, e.g. return self.range.distance_cm < 20",
                "warning",
            )
        elif scan.returns_value:
            for test in _fixed_tests(value, self.def_of(value)[1]):
                self.problem(
                    f"'if {ast.unparse(test)}:' tests nothing but fixed values, so it never"
                    f" changes{_always(_truth(test))}",
                    where_in(test),
                    "test a sensor's value, e.g. if self.range.distance_cm < 20:",
                    "warning",
                )
        if not scan.returns_value and scan.yields is None:
            self.problem(
                f"condition method '{name}' never returns a value, so it never holds",
                def_loc,
                "return True or False, e.g. return self.bumper.any",
                "warning",
            )
        elif scan.falls_off is not None and scan.yields is None:
            self.problem(
                f"condition method '{name}' can end without returning, and then gives None:"
                " the run stops with a failure the first time it does",
                self.source_of(value.__code__.co_filename).loc(scan.falls_off),
                "end it with return False, or return the comparison itself:"
                " return self.range.distance_cm < 20",
                "warning",
            )
        guard = MethodGuard(
            source=name,
            _read=lambda mission: getattr(mission, name)(),
            _instances=self.instances,
            capabilities=frozenset(scan.capabilities) | self.declared,
            states=frozenset(scan.states),
            where=f"{def_loc.path}:{def_loc.line}" if def_loc.line else None,
        )
        self.method_guards[name] = guard
        return guard

    def never_true(self, func: Callable[..., object]) -> list[tuple[ast.AST, str, str | None, str]]:
        """Comparisons in condition method ``func`` that no reading can make true
        (``self.range.distance_cm < 0``, ``x < 20 and x > 30``, ``self.bumper.any == None``),
        as ``(where, message, fix, severity)``: an error when the method returns it, as a
        YAML condition is refused; a warning elsewhere in the method."""
        _, node = self.def_of(func)
        if not isinstance(node, ast.FunctionDef):
            return []
        returned = {id(child.value) for child in _walk_own(node) if isinstance(child, ast.Return)}
        within_and = {
            id(part)
            for child in _walk_own(node)
            if isinstance(child, ast.BoolOp) and isinstance(child.op, ast.And)
            for part in child.values
        }
        found: list[tuple[ast.AST, str, str | None, str]] = []
        for child in _walk_own(node):
            if isinstance(child, ast.BoolOp) and isinstance(child.op, ast.And):
                parts = list(child.values)
            elif isinstance(child, ast.Compare) and id(child) not in within_and:
                parts = [child]
            else:
                continue
            severity = "error" if id(child) in returned else "warning"
            written = ast.unparse(child)
            never = never_true(bounds_of(parts, _reading_value))
            if never is not None:
                found.append(
                    (
                        never.node,
                        f"'{written}' can never be true: {never.why}",
                        never.hint(written, len(parts)),
                        severity,
                    )
                )
            for part in parts:
                none = _compared_with_none(part)
                if none is not None:
                    read, kind = none
                    why = f"{read} is {kind}, never None"
                    found.append(
                        (
                            part,
                            f"'{ast.unparse(part)}' can never be true: {why}",
                            (
                                f"compare it with a number, e.g. {read} < 20"
                                if kind == "a number"
                                else f"use it as it is: {read} (or not {read})"
                            ),
                            severity,
                        )
                    )
        return sorted(
            found, key=lambda f: (getattr(f[0], "lineno", 0), getattr(f[0], "col_offset", 0))
        )

    def slips(self, func: Callable[..., object], seen: set[str]) -> None:
        """Say what condition code ``func``, and each method of the mission it calls, reads
        that is not there (``self.bumpr``, ``bumper`` without ``self.``), once each."""
        _, node = self.def_of(func)
        name = getattr(func, "__name__", "")
        if not isinstance(func, FunctionType) or not isinstance(node, ast.FunctionDef):
            return
        if name in seen:
            return
        seen.add(name)
        trees = [
            self.source_of(_file_of(klass)).tree
            for klass in self.cls.__mro__
            if klass not in (Mission, object) and is_student_class(klass)
        ]
        source = self.source_of(func.__code__.co_filename)
        for where, message, hint in condition_slips(self.cls, node, func, trees, _reading_names):
            loc = source.loc(where)
            if (str(loc), message) not in self._slipped:
                self._slipped.add((str(loc), message))
                self.problem(message, loc, hint)
        for loop, read, meant in endless_waits(node, _reading_names):
            self.problem(
                f"this loop waits for {read} to change, but what a condition reads stays as it"
                " is while the condition runs (the next reading comes at the next tick), so the"
                " loop never ends",
                source.loc(loop),
                f"return at once, e.g. return {meant}: roboscript asks the condition again at"
                " every tick",
            )
        for call in sleeps_in(node, func.__globals__):
            message, hint = sleep_warning(call, f"{name}()", PY_WAIT)
            self.problem(message, source.loc(call), hint, "warning")
        for helper, call in helper_sleeps(node, func.__globals__, self.source_of):
            message, hint = sleep_warning(call, f"{name}()", PY_WAIT, helper)
            at = self.source_of(helper.__code__.co_filename).loc(call)
            if (str(at), message) not in self._slipped:  # a helper two conditions call
                self._slipped.add((str(at), message))
                self.problem(message, at, hint, "warning")
        for child in ast.walk(node):
            if (
                isinstance(child, ast.Attribute)
                and isinstance(child.value, ast.Name)
                and child.value.id == "self"
                and not hasattr(Mission, child.attr)
            ):
                helper = inspect.getattr_static(self.cls, child.attr, None)
                if inspect.isfunction(helper):
                    self.slips(helper, seen)

    def function_sleeps(self, func: Callable[..., object], label: str) -> None:
        """Warn of each ``time.sleep`` a condition given as a function or a lambda reaches:
        in its own body, in the functions of the student's own it calls, and in the mission's
        methods a lambda calls on the mission (``lambda m: m.look()``)."""
        if not isinstance(func, FunctionType) or not is_student_file(func.__code__.co_filename):
            return
        _, node = self.def_of(func)
        runs = f"{label}()" if label != "lambda" else "the condition lambda"
        reached: list[tuple[ast.Call, FunctionType | None, str]] = []
        if isinstance(node, ast.FunctionDef):
            reached += [(call, None, runs) for call in sleeps_in(node, func.__globals__)]
            reached += [
                (c, f, runs) for f, c in helper_sleeps(node, func.__globals__, self.source_of)
            ]
        for name in func.__code__.co_names if label == "lambda" else ():
            method = inspect.getattr_static(self.cls, name, None)
            if not isinstance(method, FunctionType) or not is_student_file(
                method.__code__.co_filename
            ):
                continue
            _, method_node = self.def_of(method)
            if isinstance(method_node, ast.FunctionDef):
                called = f"{name}()"
                namespace = method.__globals__
                reached += [(c, method, runs) for c in sleeps_in(method_node, namespace)]
                reached += [
                    (c, f, called) for f, c in helper_sleeps(method_node, namespace, self.source_of)
                ]
        for call, helper, caller in reached:
            message, hint = sleep_warning(call, caller, PY_WAIT, helper)
            at = self.source_of((helper or func).__code__.co_filename).loc(call)
            if (str(at), message) not in self._slipped:
                self._slipped.add((str(at), message))
                self.problem(message, at, hint, "warning")

    def function_guard(self, func: Callable[..., object], where: Location) -> MethodGuard | None:
        label = getattr(func, "__name__", "condition")
        label = "lambda" if label == "<lambda>" else label
        try:
            inspect.signature(func).bind(None)
        except TypeError:
            self.problem(
                f"the condition {label} is called with the mission, and does not take it",
                where,
                "write the condition as a method, def near(self) -> bool: ..., and name it in"
                " quotes: when=[('near', 'STATE')]",
            )
            return None
        except ValueError:
            pass  # a built-in whose signature Python does not know: it is called as written
        self.function_sleeps(func, label)
        fixed = _fixed_result(func)
        if fixed is not None:
            self.problem(
                f"the condition {label} reads nothing but fixed values, so it never"
                f" changes{_always(fixed[0])}",
                where,
                "compare a sensor's value, e.g. lambda m: m.range.distance_cm < 20",
                "warning",
            )
        return MethodGuard(
            source=label,
            _read=func,
            _instances=self.instances,
            capabilities=self.declared,
            where=f"{where.path}:{where.line}" if where.line else None,
        )

    def not_a_plain_method(self, name: str, value: object, where: Location) -> bool:
        """Report a condition ``name`` that the class holds as something other than a plain
        method (a ``@staticmethod``, a ``@classmethod``, a method wrapped by another
        decorator, or a value such as ``near = True``); True if it did."""
        if isinstance(value, staticmethod | classmethod):
            kind = type(value).__name__
            self.problem(
                f"condition '{name}' is a @{kind}, and a condition is a plain method that"
                " reads the robot through self",
                self.def_of(value.__func__)[0],
                f"take away the @{kind} above it and write def {name}(self) -> bool:",
            )
            return True
        if inspect.iscoroutinefunction(value) or inspect.isasyncgenfunction(value):
            self.problem(
                f"condition '{name}' is written 'async def', so calling it only makes a"
                " coroutine, which counts as true at once",
                self.def_of(value)[0],
                f"write def {name}(self) -> bool:, without async",
            )
            return True
        wrapped = getattr(value, "__wrapped__", None)
        if not inspect.isfunction(value) and inspect.isfunction(wrapped):
            self.problem(
                f"condition '{name}' has a decorator that makes it something other than a"
                " method, and a condition is a plain method",
                self.def_of(wrapped)[0],
                f"take away the line starting with @ above def {name}(self)",
            )
            return True
        if value is None or callable(value) or hasattr(Mission, name):
            return False
        shown = (
            "text"
            if isinstance(value, str)
            else repr(value)
            if isinstance(value, bool | int | float)
            else f"a {type(value).__name__}"
        )
        self.problem(
            f"'{name}' is {shown}, set once when the class is made, so it cannot be a"
            " condition, which is asked again at every tick",
            where,
            f"define it as a method: def {name}(self) -> bool: return ... (True or False)",
        )
        return True

    def def_of(self, func: Callable[..., object]) -> tuple[Location, ast.AST | None]:
        code = getattr(func, "__code__", None)
        if code is None:
            return self.class_loc, None
        source = self.source_of(code.co_filename)
        node = source.function_def(code.co_name, code.co_firstlineno)
        return source.loc(node, code.co_firstlineno), node

    def scan(self, func: Callable[..., object], seen: set[str] | None = None) -> _Scan:
        """What a guard method reads, following the methods it calls on ``self``."""
        seen = seen if seen is not None else set()
        result = _Scan()
        _, node = self.def_of(func)
        if node is None:
            result.returns_value = True  # cannot tell; do not warn
            return result
        seen.add(getattr(func, "__name__", ""))
        if isinstance(node, ast.FunctionDef) and node.body and not _always_returns(node.body):
            result.falls_off = node.body[-1]
        namespace = getattr(func, "__globals__", {})
        for child in _walk_own(node):
            if isinstance(child, ast.Yield | ast.YieldFrom) and result.yields is None:
                result.yields = child
            if isinstance(child, ast.Call) and isinstance(child.func, ast.Name):
                made = namespace.get(child.func.id)
                if isinstance(made, type) and issubclass(made, Action):
                    result.actions.append((child, child.func.id))
            if isinstance(child, ast.Return) and child.value is not None:
                result.returns_value = True
                value = child.value
                if isinstance(value, ast.Constant) and isinstance(value.value, str):
                    first = result.returns_text
                    if first is None or value.lineno < first.lineno:
                        result.returns_text = value
                read = _reads_number(value)
                if read is not None and (
                    result.returns_number is None or value.lineno < result.returns_number[0].lineno
                ):
                    result.returns_number = (value, read)
            if not isinstance(child, ast.Attribute):
                continue
            sensor = child.value
            if (
                isinstance(sensor, ast.Attribute)
                and isinstance(sensor.value, ast.Name)
                and sensor.value.id == "self"
            ):
                names = _reading_names(sensor.attr)
                if names and child.attr not in names:
                    result.misread.append((child, sensor.attr, names))
            if not (isinstance(child.value, ast.Name) and child.value.id == "self"):
                continue
            if child.attr in _SENSOR_CAPABILITY:
                result.capabilities.add(_SENSOR_CAPABILITY[child.attr])
            helper = inspect.getattr_static(self.cls, child.attr, None)
            if (
                inspect.isfunction(helper)
                and child.attr not in seen
                and not hasattr(Mission, child.attr)
            ):
                inner = self.scan(helper, seen)
                result.capabilities |= inner.capabilities
                result.states.update(inner.states)
        # A name the method sets or takes (for go in ("go",): ...) holds its own value.
        own_names = {
            child.id
            for child in _walk_own(node)
            if isinstance(child, ast.Name) and isinstance(child.ctx, ast.Store)
        }
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            own_names.update(arg.arg for arg in ast.walk(node.args) if isinstance(arg, ast.arg))
        for child in _walk_own(node):
            for used in _used_as_values(child):
                whole = _whole_sensor(used) if isinstance(used, ast.Attribute) else None
                if isinstance(used, ast.Attribute) and whole is not None:
                    result.whole_sensors.append((used, whole))
            if isinstance(child, ast.Call) and (read := _reading_value(child.func)) is not None:
                result.called_values.append((child, read))
            if isinstance(child, ast.Compare):
                operands = [child.left, *child.comparators]
                numeric = [o for o in operands if not _reads_text(o)]
                read = next(filter(None, map(_reading_value, numeric)), None)
                text = [
                    o for o in operands if isinstance(o, ast.Constant) and isinstance(o.value, str)
                ]
                if read is not None and text:
                    result.text_compared.append((text[0], read))
            if (
                isinstance(child, ast.Call)
                and isinstance(child.func, ast.Attribute)
                and child.func.attr == "visits"
                and isinstance(child.func.value, ast.Name)
                and child.func.value.id == "self"
                and child.args
            ):
                given = child.args[0]
                if isinstance(given, ast.Constant) and isinstance(given.value, str):
                    result.states[given.value] = given
                elif (
                    isinstance(given, ast.Name)
                    and given.id in self.names
                    and given.id not in own_names
                ):
                    result.unquoted_states.append(given)
        return result


def _file_of(cls: type) -> str:
    """The file a class was written in, as its code objects name it."""
    try:
        return inspect.getsourcefile(cls) or inspect.getfile(cls)
    except (TypeError, OSError):
        return f"<{cls.__module__}>"


def _owned(cls: type, name: str, func: object) -> bool:
    """True if ``func`` is the function the mission class defines as ``name``."""
    return any(vars(klass).get(name) is func for klass in cls.__mro__)


def _methods(cls: type[Mission]) -> list[str]:
    return sorted(
        name
        for klass in cls.__mro__
        if klass not in (Mission, object)
        for name, value in vars(klass).items()
        if inspect.isfunction(value) and not name.startswith("_")
    )


def _shift(where: Location, node: ast.expr | None, raw: str, offset: int) -> Location:
    """The position of character ``offset`` of a condition written as a one-line string."""
    if where.col is None or not isinstance(node, ast.Constant) or node.end_lineno != node.lineno:
        return where
    leading = len(raw) - len(raw.lstrip())
    return Location(where.path, where.line, where.col + 1 + leading + offset)


def _kebab(name: str) -> str:
    """``BumpAndTurn`` -> ``bump-and-turn``."""
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "-", name).lower()


def _description(cls: type) -> str:
    """The class docstring, with each paragraph's lines joined (as YAML's ``>`` does)."""
    doc = cls.__dict__.get("__doc__")
    if not isinstance(doc, str):
        return ""
    paragraphs = inspect.cleandoc(doc).split("\n\n")
    return "\n\n".join(" ".join(p.split()) for p in paragraphs).strip()


def compile_mission(
    cls: type[Mission], profile: Any = None, *, path: str | Path | None = None
) -> tuple[MissionSpec, list[InputError]]:
    """Compile and check a Python mission class.

    Args:
        cls: A subclass of :class:`~roboscript.mission.python_api.Mission`.
        profile: A robot profile to check capabilities against, or ``None``.
        path: How messages name the mission's file (default: where the class was written).

    Returns:
        The mission and its warnings.

    Raises:
        MissionProblemsError: The first error, with every problem in ``problems``.
    """
    compiler = _Compiler(cls, str(path) if path is not None else None)
    return compiler.build.finish(compiler.compile(), profile, own_file_first=True)


_FIXED_OPS = frozenset(
    {
        "RESUME",
        "NOP",
        "CACHE",
        "EXTENDED_ARG",
        "LOAD_CONST",
        "RETURN_VALUE",
        "RETURN_CONST",
        "COMPARE_OP",
        "IS_OP",
        "CONTAINS_OP",
        "UNARY_NOT",
        "UNARY_NEGATIVE",
        "UNARY_INVERT",
        "TO_BOOL",
        "BINARY_OP",
        "COPY",
        "SWAP",
        "POP_TOP",
        "JUMP_FORWARD",
        "JUMP_IF_FALSE_OR_POP",
        "JUMP_IF_TRUE_OR_POP",
        "POP_JUMP_IF_FALSE",
        "POP_JUMP_IF_TRUE",
        "POP_JUMP_FORWARD_IF_FALSE",
        "POP_JUMP_FORWARD_IF_TRUE",
        "POP_JUMP_IF_NONE",
        "POP_JUMP_IF_NOT_NONE",
        "POP_JUMP_FORWARD_IF_NONE",
        "POP_JUMP_FORWARD_IF_NOT_NONE",
    }
)
"""What a function that reads nothing but fixed values is compiled to: constants, operators
and jumps (no name, attribute or call is read)."""


def _fixed_result(func: object) -> tuple[bool | None] | None:
    """``(what it always gives,)`` if ``func``, a condition, reads nothing but fixed values
    (``lambda m: 1 < 2``, ``return True``, ``if 5: return True``), its value ``None`` when it
    is not worked out (arithmetic, which a huge power would make slow); else ``None``."""
    code = getattr(func, "__code__", None)
    if code is None:
        return None
    ops = {instruction.opname for instruction in dis.get_instructions(code)}
    if not ops <= _FIXED_OPS:
        return None
    if "BINARY_OP" in ops:
        return (None,)
    try:
        return (bool(func(*([None] * code.co_argcount))),)  # type: ignore[operator]
    except Exception:  # noqa: BLE001  # 1 < "a": said when it runs, as any other
        return (None,)


def _always(holds: bool | None) -> str:
    """``: it is always true`` (or false), for a condition that never changes."""
    if holds is None:
        return ""
    return ": it is always true" if holds else ": it is always false, so it never holds"


def _fixed_tests(func: object, node: ast.AST | None) -> list[ast.expr]:
    """The tests of the ``if``s (and ``x if TEST else y``) in condition method ``func`` made
    only of fixed values (``if 5:``, ``if True:``)."""
    if not isinstance(node, ast.FunctionDef):
        return []
    return [
        child.test
        for child in _walk_own(node)
        if isinstance(child, ast.If | ast.IfExp)
        and all(isinstance(part, FIXED_NODES) for part in ast.walk(child.test))
        and not any(isinstance(part, ast.BinOp) for part in ast.walk(child.test))
    ]


_COMPARED: dict[type[ast.cmpop], Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq,
    ast.NotEq: operator.ne,
    ast.Lt: operator.lt,
    ast.LtE: operator.le,
    ast.Gt: operator.gt,
    ast.GtE: operator.ge,
    ast.Is: operator.is_,
    ast.IsNot: operator.is_not,
    ast.In: lambda a, b: a in b,
    ast.NotIn: lambda a, b: a not in b,
}
_UNARY: dict[type[ast.unaryop], Callable[[Any], Any]] = {
    ast.Not: operator.not_,
    ast.USub: operator.neg,
    ast.UAdd: operator.pos,
    ast.Invert: operator.invert,
}


def _fixed_value(node: ast.expr) -> Any:
    """What ``node``, made of constants, comparisons, ``and``/``or``/``not`` (no arithmetic),
    gives, as Python would."""
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_fixed_value(node.operand))
    if isinstance(node, ast.BoolOp):
        value: Any = None
        for part in node.values:
            value = _fixed_value(part)
            if bool(value) != isinstance(node.op, ast.And):  # and stops at false, or at true
                break
        return value
    if isinstance(node, ast.Compare):
        left = _fixed_value(node.left)
        for op, right_node in zip(node.ops, node.comparators, strict=True):
            right = _fixed_value(right_node)
            if not _COMPARED[type(op)](left, right):
                return False
            left = right
        return True
    raise ValueError(ast.dump(node))


def _truth(test: ast.expr) -> bool | None:
    """What a test made of fixed values gives, or ``None`` when it cannot be worked out
    (``1 < "a"``, said when it runs)."""
    try:
        return bool(_fixed_value(test))
    except (TypeError, ValueError, KeyError):
        return None
