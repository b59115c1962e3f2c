"""One mission builder: every rule the YAML and the Python syntaxes share.

The two loaders are front ends. The YAML one (:mod:`roboscript.mission.yaml_loader`) reads
values and where they were written from a YAML file; the Python one
(:mod:`roboscript.mission.python_compiler`) reads them from a ``Mission`` class and its
syntax tree. Both hand them to a :class:`MissionBuilder`, which turns them into a
:class:`~roboscript.mission.spec.MissionSpec`: it converts action parameters (every parameter,
with its documented default when omitted, quantities in their base unit as ``float``), works
out what each action needs and whether it ends by itself, checks state names, conditions,
timeouts and final outcomes, and collects every problem, located where it was written. So a
YAML mission and its Python twin build the same spec (``tests/mission/test_builder.py``).
"""

from __future__ import annotations

import copy
import functools
import html
import re
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from roboscript import capabilities as cap
from roboscript.actions import ACTIONS
from roboscript.actions.base import Action, Param, UnderSpecifiedError
from roboscript.actions.composite import Parallel, Repeat
from roboscript.actions.output import parse_color
from roboscript.errors import InputError, MissionError, did_you_mean
from roboscript.inputs.limits import name_too_long
from roboscript.inputs.quantities import (
    DIMENSIONS,
    QuantityError,
    bare_number_warning,
    parse_quantity,
    radians_warning,
)
from roboscript.inputs.source import YAML_1_1_WORDS, Location
from roboscript.mission.checks import check_mission
from roboscript.mission.condition_reads import (
    PY_WAIT,
    YAML_WAIT,
    action_sleeps,
    sleep_warning,
    update_returns,
)
from roboscript.mission.guards import GuardError, compile_guard
from roboscript.mission.limits import a_noun, example, param_problems, shown, time_problem
from roboscript.mission.nested import SubMission
from roboscript.mission.python_source import PythonSource
from roboscript.mission.spec import ActionSpec, MissionSpec, StateSpec, TransitionSpec
from roboscript.mission.student_code import StudentCodeError, shown_path
from roboscript.robot_profile import RobotProfile

__all__ = ["MissionBuilder", "MissionProblemsError", "ParamProblem", "action_params"]

ParamProblem = tuple[str, str, str | None, int | None]
"""A parameter problem: ``(param name, message, hint, offset)``; ``offset`` is the character of
a condition where the problem is, else ``None``; the name is ``""`` for a missing parameter."""


class MissionProblemsError(MissionError):
    """The first error in a mission, carrying every problem found (errors and warnings).

    Attributes:
        problems: All problems, in file order.
    """

    def __init__(self, problems: list[InputError]) -> None:
        self.problems = problems
        first = next(p for p in problems if p.severity == "error")
        super().__init__(
            first.message,
            path=first.path,
            line=first.line,
            col=first.col,
            hint=first.hint,
        )


# ------------------------------------------------------------------------------ parameters


def action_params(
    cls: type[Action],
    values: Mapping[str, Any],
    state_names: frozenset[str] | None = None,
    *,
    written: bool = True,
) -> tuple[dict[str, Any], list[ParamProblem]]:
    """Convert an action's parameters to its keyword arguments, every parameter included.

    Args:
        cls: The action class.
        values: Parameter values by mission name (``distance``); a quantity may carry a unit,
            a bare number is in the parameter's base unit (mm, mm/s, s, deg, deg/s, Hz).
        state_names: The mission's states, for conditions that read ``visits.STATE``.
        written: True when ``values`` are what the student wrote (a missing required
            parameter is a problem); False when they were read from an action object, which
            its constructor checked.

    Returns:
        The keyword arguments in the order the action declares its parameters (an omitted
        parameter takes its documented default), and the problems.
    """
    problems: list[ParamProblem] = []
    params = {p.name: p for p in cls.params}
    for name in values:
        if name not in params:
            key, colon, value = str(name).partition(":")
            if colon and key.strip() in params:  # YAML reads "distance:50 cm" as one word
                spaced = f"put a space after the ':': {key.strip()}: {value.strip()}"
                problems.append((name, f"'{cls.name}' has no parameter '{name}'", spaced, None))
                continue
            hint = (
                cls.guessed_params.get(str(name).lower())
                or did_you_mean(name, params)
                or (f"'{cls.name}' takes {', '.join(params)}" if params else None)
            )
            problems.append((name, f"'{cls.name}' has no parameter '{name}'", hint, None))
    kwargs: dict[str, Any] = {}
    # A parameter written under another name (rotate: {degrees: 90}) is told once, as that
    # name: "needs 'angle'" beside it would be a second sentence for one slip.
    misnamed = any(name not in params for name in values)
    for param in cls.params:
        if param.name not in values:
            if not param.required:
                kwargs[param.kwarg] = param.default
            elif misnamed:
                continue
            elif written:
                missing = cls.under_specified([param.name])
                if missing is not None:  # a behaviour may answer None
                    problems.append(("", missing.message, f"write {missing.yaml}", None))
                else:
                    problems.append(("", f"'{cls.name}' needs '{param.name}'", None, None))
            continue
        try:
            kwargs[param.kwarg] = _convert(param, values[param.name], state_names)
        except GuardError as exc:
            problems.append((param.name, f"{cls.name} {param.name}: {exc}", exc.hint, exc.offset))
        except ValueError as exc:
            problems.append((param.name, f"{cls.name} {param.name}: {exc}", None, None))
    return kwargs, problems


_NOT_FINITE = re.compile(r"^\s*[-+]?(inf|infinity|nan)\b", re.IGNORECASE)


_HTML_ENTITY = re.compile(r"&(?:lt|gt|amp);")

_PLACEHOLDERS = frozenset({"NEXT", "STATE", "NAME", "TARGET", "NEXT_STATE", "STATE_NAME"})
"""Words the documentation's examples write where a state's name goes."""


def _convert(param: Param, value: Any, state_names: frozenset[str] | None = None) -> Any:
    if value is None and not param.required:
        return param.default
    if value is Ellipsis:  # Drive(...), as an example writes what is left to the reader
        raise ValueError(
            f"'...' stands for the value an example leaves to you: write {param.python_example}"
        )
    if param.kind == "count":
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"expected a whole number, got {value!r}")
        return value
    if param.kind in DIMENSIONS:
        try:
            return parse_quantity(value, param.kind)
        except QuantityError as exc:
            if isinstance(value, str) and _NOT_FINITE.match(value):
                noun = a_noun(DIMENSIONS[param.kind].name)
                raise ValueError(
                    f"{value.strip()!r} is not a number the robot can use; write {noun} "
                    f"such as {example(param.kind)}"
                ) from None
            raise ValueError(str(exc)) from None
        except OverflowError:  # an int beyond any float (a 5000-digit number)
            noun = a_noun(DIMENSIONS[param.kind].name)
            raise ValueError(f"{shown(value)} is far too large for {noun}") from None
    if param.kind == "choice":
        if value not in param.choices:
            raise ValueError(f"expected one of {', '.join(param.choices)}, got {value!r}")
        return value
    if param.kind == "guard":
        if callable(value):
            return value  # compiled already (a Python mission's method or expression)
        if isinstance(value, bool):
            value = "true" if value else "false"
        if not isinstance(value, str):
            raise ValueError(
                f'expected a condition such as "range.distance_cm < 20", got {value!r}'
            )
        return compile_guard(value, state_names, truth=True)
    if param.kind == "color":
        return parse_color(value)
    if param.kind == "text":
        if not isinstance(value, str | int | float):
            raise ValueError(f"expected text, got {value!r}")
        return str(value)
    return value


def _holding(instance: Action, cls: type[Action], kwargs: Mapping[str, Any]) -> Action:
    """``instance``, or a copy of it holding each quantity as the float the spec has.

    A Python mission writes ``Drive(distance_mm=500)`` or, as in YAML,
    ``Drive(distance_mm="50 cm")``; YAML writes ``distance: 50 cm``: all three run 500.0, read
    by the one rule (:func:`~roboscript.inputs.quantities.parse_quantity`) at ``check``.
    """
    changed = {
        p.kwarg: kwargs[p.kwarg]
        for p in cls.params
        if p.kind in DIMENSIONS
        and p.kwarg in kwargs
        and _as_written(getattr(instance, p.kwarg, None), kwargs[p.kwarg])
    }
    if not changed:
        return instance
    template = copy.copy(instance)
    try:
        for kwarg, value in changed.items():
            setattr(template, kwarg, value)
    except (AttributeError, TypeError):  # a behaviour's read-only attribute: keep it
        return instance
    return template


def _as_written(held: object, converted: object) -> bool:
    """True if an action holds a quantity as a student wrote it, not as it runs: text
    (``"50 cm"``), or a whole number the constructor kept as given."""
    return isinstance(held, str) or (type(held) is int and held == converted)


_MOVING = {cap.DRIVE_BASE: "wheels", cap.WALKER: "legs"}
"""Capabilities one action at a time moves, and what they move, for messages."""


def _moves(action: ActionSpec) -> set[str]:
    """What a built-in action (or a repeat or parallel of them) moves: ``{"wheels"}`` for
    drive; nothing for a student's behaviour, which may only read what it requires."""
    if action.children:
        return set().union(*(_moves(child) for child in action.children))
    if action.action_class is None or not _is_built_in(action.action_class):
        return set()
    return {what for needed, what in _MOVING.items() if needed in action.action_class.requires}


def _guard_capabilities(kwargs: Mapping[str, Any]) -> frozenset[str]:
    found: set[str] = set()
    for value in kwargs.values():
        found |= set(getattr(value, "capabilities", ()))
    return frozenset(found)


# --------------------------------------------------------------------------------- builder


def _is_built_in(cls: type[Action]) -> bool:
    """True for roboscript's own actions and those made from them (``class Cruise(Drive)``),
    whose values are bounded as the built-in's are."""
    return any(issubclass(cls, known) for known in ACTIONS.values())


class MissionBuilder:
    """Builds one mission's spec from values and where they were written, collecting problems.

    Args:
        path: The mission file, as messages name it.
        sources: Python files parsed already, by the name Python knows them (a code
            object's ``co_filename``), shared with whoever else reads them (the Python
            mission compiler): each file is parsed once, however many classes it holds.
    """

    def __init__(self, path: str, sources: dict[str, PythonSource] | None = None) -> None:
        self.path = path
        self.problems: list[InputError] = []
        self._sleeps_told: set[type[Action]] = set()  # a class used in many states: once
        self._sources: dict[str, PythonSource] = {} if sources is None else sources

    def problem(
        self, message: str, where: Location | None, hint: str | None = None, severity: str = "error"
    ) -> None:
        """Record a problem at ``where`` (the mission file when ``None``)."""
        where = where or Location(self.path)
        self.problems.append(
            MissionError(
                message,
                path=where.path,
                line=where.line,
                col=where.col,
                hint=hint,
                severity=severity,
            )
        )

    @property
    def failed(self) -> bool:
        """True once an error (not a warning) was recorded."""
        return any(p.severity == "error" for p in self.problems)

    # ----------------------------------------------------------------------------- actions

    def action(
        self,
        cls: type[Action],
        values: Mapping[str, Any],
        where: Location,
        state_names: frozenset[str],
        *,
        param_where: Callable[[str, str, int | None], Location] | None = None,
        instance: Action | None = None,
        make: Callable[[], Any] | None = None,
        name: str | None = None,
    ) -> ActionSpec | None:
        """An action's spec from its parameters.

        Args:
            cls: The action class.
            values: Parameter values by mission name, as written (YAML) or as read from
                ``instance`` (Python).
            where: Where the action was written.
            state_names: The mission's states.
            param_where: ``(param name, message, offset) -> Location`` of a parameter's
                problem (default: ``where``).
            instance: The action object, when the mission made one (Python): a template,
                of which each state entry runs a fresh copy, holding the converted values.
                Without one the builder makes one from the converted parameters to check them.
            make: Builds a fresh action for each state entry (default: ``cls(**kwargs)``,
                or a copy of ``instance``).
            name: The action's name in messages (default: ``cls.name``).
        """
        label = name or cls.name
        misdefined = None if _is_built_in(cls) else cls.misdefined()
        if misdefined is not None:  # def update(ctx): would raise at every tick
            self.problem(misdefined[0], where, misdefined[1])
            return None
        if cls not in self._sleeps_told:  # a subclass of a built-in (Cruise(Drive)) too
            self._sleeps_told.add(cls)
            self.tell_sleeps(cls)
        kwargs, problems = action_params(cls, values, state_names, written=instance is None)
        refused = False
        if not problems:
            for param_name, message, range_hint in param_problems(
                label, cls.params, kwargs, built_in=_is_built_in(cls)
            ):
                problems.append((param_name, message, range_hint, None))
            try:
                conflicts = cls.conflicts(kwargs)
            except Exception as exc:  # noqa: BLE001 - a student's behaviour may raise anything
                conflicts = []
                self.problem(StudentCodeError(f"behaviour '{label}'", exc).reason(None), where)
                refused = True
            problems.extend((name_, message, hint, None) for name_, message, hint in conflicts)
        for param_name, message, hint, offset in problems:
            at = param_where(param_name, message, offset) if param_where else where
            self.problem(message, at, hint)
        for param in cls.params:
            # written in a file, a bare number's unit may not be the one meant; and degrees
            # that look like radians (1.57) were most likely radians
            note = None
            if instance is None:
                note = bare_number_warning(values.get(param.name), param.kind)
            if note is None and param.kind == "angle":
                keyword = param.kwarg if instance is not None else None
                note = radians_warning(kwargs.get(param.kwarg), keyword)
            if note is not None:
                at = param_where(param.name, "", None) if param_where else where
                self.problem(f"{label} {param.name}: {note[0]}", at, note[1], "warning")
        if problems or refused:
            return None
        param_locations = {
            p.name: param_where(p.name, "", None) if param_where else where
            for p in cls.params
            if p.name in values
        }
        if instance is not None:
            template = _holding(instance, cls, kwargs)
            make = make or functools.partial(copy.deepcopy, template)
        else:
            try:
                instance = cls(**kwargs)
            except UnderSpecifiedError as exc:  # its own sentence names the action
                self.problem(exc.message, where, f"write {exc.yaml}")
                return None
            except ValueError as exc:
                self.problem(f"{label}: {exc}", where)
                return None
            except Exception as exc:  # noqa: BLE001 - a student's behaviour may raise anything
                self.problem(StudentCodeError(f"behaviour '{label}'", exc).reason(None), where)
                return None
        frozen = dict(kwargs)
        return ActionSpec(
            name=label,
            kwargs=frozen,
            factory=make or (lambda: cls(**frozen)),
            requires=frozenset(cls.requires)
            | frozenset(getattr(instance, "child_requires", frozenset()))
            | _guard_capabilities(frozen),
            location=where,
            bounded=not cls.bounded_by
            or any(frozen.get(p.kwarg) is not None for p in cls.params if p.name in cls.bounded_by),
            param_locations=param_locations,
            action_class=cls,
        )

    def source_of(self, filename: str) -> PythonSource:
        """The Python file ``filename`` (a code object's ``co_filename``), parsed the first
        time it is asked for; named as the mission when it is the mission file."""
        if filename not in self._sources:
            same = Path(filename).resolve() == Path(self.path).resolve()
            shown = self.path if same else shown_path(filename)
            self._sources[filename] = PythonSource(filename, shown)
        return self._sources[filename]

    def tell_sleeps(self, cls: type[Action]) -> None:
        """Warn about each ``time.sleep`` in a student's action class (its ``update`` is run
        every tick, and holds up the robot while it sleeps), and about each ``return`` of its
        ``update`` that gives no Result (``return True``), at its line."""
        example = PY_WAIT if self.path.endswith(".py") else YAML_WAIT
        for function, call, helper in action_sleeps(cls, self.source_of):
            runs = f"{cls.__name__}.{function.__name__}()"
            message, hint = sleep_warning(call, runs, example, helper)
            where = self.source_of((helper or function).__code__.co_filename).loc(call)
            self.problem(message, where, hint, "warning")
        for function, returned, what, fix in update_returns(cls, self.source_of):
            self.problem(
                f"{cls.__name__}.update() returns {what}, and roboscript reads what update()"
                " returns as how the action is going: a Result, or None while it runs",
                self.source_of(function.__code__.co_filename).loc(returned),
                fix,
                "warning",  # the run ends in failure, with its sentence, if it is reached
            )

    def parallel(self, mode: str, children: list[ActionSpec], where: Location) -> ActionSpec:
        """``parallel``: run ``children`` together, ``all`` or ``any`` of them to finish."""
        movers: dict[str, list[str]] = {}
        for child in children:
            for part in _moves(child):
                movers.setdefault(part, []).append(child.name)
        for part, names in movers.items():
            if len(names) > 1:  # drive and rotate at once: each sets the wheels every tick
                self.problem(
                    f"'{names[0]}' and '{names[1]}' both move the {part}, and a parallel runs"
                    " its actions at the same time, so each would undo what the other does",
                    where,
                    "one after another, each in a state of its own; a parallel is for one move"
                    " with actions that do not move the robot, such as play_tone or set_led",
                )
        factories = [child.factory for child in children]
        return ActionSpec(
            name="parallel",
            kwargs={"mode": mode, "actions": tuple(c.name for c in children)},
            factory=lambda: Parallel(factories, mode),
            requires=frozenset().union(*(c.requires for c in children)),
            location=where,
            bounded=all(c.bounded for c in children)
            if mode == "all"
            else any(c.bounded for c in children),
            children=tuple(children),
        )

    def repeat(self, times: Any, child: ActionSpec, where: Location) -> ActionSpec | None:
        """``repeat``: run ``child`` ``times`` times in a row."""
        wrong = Repeat.times_problem(times)
        if wrong is not None:  # a Python mission's Repeat refused it when made
            self.problem(wrong.message, where, f"write {wrong.yaml}")
            return None
        make = child.factory
        return ActionSpec(
            name="repeat",
            kwargs={"times": times, "action": child.name},
            factory=lambda: Repeat(make, times),
            requires=child.requires,
            location=where,
            bounded=child.bounded,
            children=(child,),
        )

    def machine(self, spec: MissionSpec, label: str, where: Location) -> ActionSpec:
        """A state whose action is a whole inner machine (nested states, another mission)."""
        return ActionSpec(
            name="states",
            kwargs={"mission": spec.name, "states": tuple(spec.states)},
            factory=lambda: SubMission(spec, label),
            requires=spec.requires(),
            location=where,
            inner=spec,
        )

    # ------------------------------------------------------------------------- transitions

    def target(self, value: Any, names: frozenset[str], where: Location) -> str | None:
        """``value`` as the name of one of the mission's states."""
        if not isinstance(value, str):
            self.problem(f"expected a state name, got {value!r}", where)
            return None
        if not self.short_name(value, where, "state name"):
            return None
        if value not in names:
            self.problem(
                f"there is no state '{value}'",
                where,
                did_you_mean(value, names)
                or (
                    f"{value} stands for a state of yours in the examples: write the name of"
                    f" one of them ({', '.join(sorted(names))})"
                    if value in _PLACEHOLDERS
                    else None
                ),
            )
            return None
        return value

    def expression(
        self,
        text: Any,
        names: frozenset[str],
        at: Callable[[int], Location],
        *,
        truth: bool = True,
    ) -> Any:
        """A condition written as an expression, compiled; ``at(offset)`` locates a mistake
        (``truth=False``: a value to record, which may be a number)."""
        if isinstance(text, bool):
            text = "true" if text else "false"
        if not isinstance(text, str):
            self.problem('a condition is text, e.g. if: "range.distance_cm < 20"', at(0))
            return None
        entity = _HTML_ENTITY.search(text)
        if entity is not None:  # &lt; copied from a web page's source
            sign = html.unescape(entity.group())
            self.problem(
                f"'{entity.group()}' is how a web page's source writes '{sign}'",
                at(entity.start()),
                f"write {html.unescape(text)}",
            )
            return None
        try:
            return compile_guard(text, names, truth=truth)
        except GuardError as exc:
            self.problem(str(exc), at(exc.offset), exc.hint)
            return None

    @staticmethod
    def transition(
        target: str, guard: Any = None, guard_text: str | None = None, where: Location | None = None
    ) -> TransitionSpec:
        """A way out of a state (unconditional when ``guard`` is ``None``)."""
        return TransitionSpec(target, guard, guard_text, where)

    # ------------------------------------------------------------------------------ states

    def timeout(
        self, state: str, field: str, seconds: Any, where: Location, written: Any = None
    ) -> float | None:
        """A state's time bound: a positive number of seconds.

        Args:
            state: The state's name.
            field: The bound's name in the syntax (``timeout``, ``timeout_s``).
            seconds: The bound in seconds (``None``: no bound).
            where: Where it was written.
            written: As written, for the message (default: ``seconds``).
        """
        if seconds is None:
            return None
        if isinstance(seconds, bool) or not isinstance(seconds, int | float) or seconds <= 0:
            as_written = seconds if written is None else written
            self.problem(
                f"state '{state}': {field} is a positive number of seconds, got {as_written!r}",
                where,
                "write timeout_s=10" if field.endswith("_s") else f"write `{field}: 10 s`",
            )
            return None
        found: tuple[str, str | None] | None
        try:
            found = time_problem(f"state '{state}': {field}", float(seconds))
        except OverflowError:  # an int beyond any float
            found = (f"state '{state}': {field}: {shown(seconds)} is too large", None)
        if found is not None:
            self.problem(found[0], where, found[1])
            return None
        return float(seconds)

    def final(self, state: str, value: Any, where: Location) -> str | None:
        """A final state's outcome: ``success`` (or ``True``) or ``failure``; else ``None``."""
        if value is True or value == "success":
            return "success"
        if value == "failure":
            return "failure"
        if value not in (None, False):
            meant = YAML_1_1_WORDS.get(value.lower()) if isinstance(value, str) else None
            self.problem(
                f"state '{state}': final is 'success' or 'failure', got {value!r}",
                where,
                f"'{value}' is a word here, not true: write final: success"
                if meant is True
                else f"'{value}' is a word here, not false: a state that does not end the"
                " mission has no 'final', so take it away; final: failure ends it in failure"
                if meant is False
                else did_you_mean(value, ("success", "failure"))
                if isinstance(value, str)
                else None,
            )
        return None

    def state(
        self,
        name: str,
        *,
        action: ActionSpec | None = None,
        during: tuple[ActionSpec, ...] = (),
        on: Mapping[str, tuple[TransitionSpec, ...]] | None = None,
        when: tuple[TransitionSpec, ...] = (),
        timeout_s: float | None = None,
        final: str | None = None,
        description: Any = None,
        where: Location | None = None,
    ) -> StateSpec:
        """One state (its parts built and checked by the methods above)."""
        self.short_name(name, where, "state name")
        return StateSpec(
            name=name,
            action=action,
            during=during,
            on=dict(on or {}),
            when=when,
            timeout_s=timeout_s,
            final=final,
            description=_text(description),
            location=where,
        )

    # ----------------------------------------------------------------------------- mission

    def short_name(self, name: str, where: Location | None, kind: str) -> bool:
        """Whether a state's or the mission's name is short enough to show in a message, a
        report or a replay; a longer one is a problem (a Python mission can make a state of
        any name, ``locals()["s" * 10**7] = state(...)``)."""
        too_long = name_too_long(name, kind)
        if too_long:
            self.problem(too_long, where)
        return too_long is None

    def names_a(self, key: str, value: Any, where: Location, example: str) -> str | None:
        """``robot`` or ``world``: the name of one, or ``None`` (the default)."""
        if value is not None and not isinstance(value, str):
            if key == "robot" and isinstance(value, RobotProfile):  # robot = get_profile(...)
                given = value.name
                self.problem(
                    "'robot' is given a robot profile, and a mission names its robot",
                    where,
                    f'write robot = "{given}"; a robot of your own is a profile file beside'
                    ' the mission, named the same way: robot = "my_robot.yaml"',
                )
                return None
            self.problem(f"'{key}' names a {key}, e.g. {example}", where)
            return None
        return value

    def initial(self, value: Any, names: frozenset[str], where: Location) -> str | None:
        """The first state: one of the states."""
        if not isinstance(value, str) or value not in names:
            self.problem(
                f"the initial state '{value}' is not one of the states",
                where,
                did_you_mean(str(value), names) or f"the states: {', '.join(sorted(names))}",
            )
            return None
        return value

    def mission(
        self,
        *,
        name: Any,
        initial: str,
        states: Mapping[str, StateSpec],
        description: Any = None,
        where: Location | None = None,
        robot: str | None = None,
        world: str | None = None,
        robot_where: Location | None = None,
        world_where: Location | None = None,
        plots: tuple[tuple[str, Any], ...] = (),
    ) -> MissionSpec:
        """The whole mission (``robot_where``, ``world_where``: where those were written;
        ``plots``: the condition values to record, compiled by :meth:`expression`)."""
        self.short_name(str(name), where, "mission name")
        return MissionSpec(
            name=str(name),
            initial=initial,
            states=dict(states),
            description=_text(description),
            path=self.path,
            location=where,
            robot=robot,
            world=world,
            robot_location=robot_where if robot is not None else None,
            world_location=world_where if world is not None else None,
            plots=plots,
        )

    def finish(
        self, spec: MissionSpec | None, profile: Any = None, *, own_file_first: bool = False
    ) -> tuple[MissionSpec, list[InputError]]:
        """Check the built mission (:func:`~roboscript.mission.checks.check_mission`) and
        return it with its warnings.

        Args:
            spec: The built mission, or ``None`` if it could not be built.
            profile: A robot profile to check capabilities against, or ``None``.
            own_file_first: List problems in the mission's own file before those in other
                files (a Python mission's imported classes); else all in line order (a YAML
                mission's behaviour and included files, as ``roboscript check`` has shown them).

        Raises:
            MissionProblemsError: The first error, with every problem in ``problems``.
        """
        if spec is not None and not self.failed:
            self.problems.extend(check_mission(spec, profile))
        if spec is None or self.failed:
            self.problems.sort(
                key=lambda p: (own_file_first and p.path != self.path, p.line or 0, p.col or 0)
            )
            raise MissionProblemsError(self.problems)
        return spec, [p for p in self.problems if p.severity != "error"]

    def check_inner(self, spec: MissionSpec | None, inner: MissionBuilder) -> MissionSpec | None:
        """Take an inner machine's problems (checking it if it built), and the spec if sound."""
        if spec is not None and not inner.failed:
            inner.problems.extend(check_mission(spec))
        self.problems.extend(inner.problems)
        return None if spec is None or inner.failed else spec


def _text(value: Any) -> str:
    """Free text (a description) as both syntaxes give it: surrounding blank space removed
    (YAML's folded ``>`` ends it with a newline, a docstring does not)."""
    return "" if value is None else str(value).strip()
