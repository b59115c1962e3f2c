"""Actions: non-blocking behaviours with a start / update / stop lifecycle.

An action is started when its state is entered, updated once per tick, and stopped when its
state is left (finished or interrupted). :meth:`Action.update` never blocks: it looks at the
capabilities, sets actuators, and returns ``None`` while running or a :class:`Result` when it
has ended. Every action ends with one of three outcomes:

* ``done``: it did what it was asked;
* ``failed``: it could not, with a reason (``stalled``, ``bumped``, ``lost wall``,
  ``lost line``, ``not supported``);
* ``timeout``: its own time bound passed (state timeouts are the runner's).

Actions see only capabilities (:mod:`roboscript.capabilities`), never drivers or transports.
"""

from __future__ import annotations

import abc
import dataclasses
import difflib
import enum
import functools
import inspect
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Literal, cast, get_args

from roboscript import capabilities as cap
from roboscript.code_owner import is_student_class, raised_by_roboscript
from roboscript.errors import CapabilityError
from roboscript.inputs.quantities import DIMENSIONS, parse_quantity

__all__ = [
    "ACTION_OUTCOMES",
    "FROM_INIT",
    "PARAM_EXAMPLES",
    "PARAM_KINDS",
    "REQUIRED",
    "Action",
    "ActionContext",
    "Outcome",
    "OutcomeName",
    "Param",
    "ParamKind",
    "Result",
    "UnderSpecifiedError",
    "UpdateReturnError",
    "params_of",
]


class Outcome(str, enum.Enum):
    """How an action ended."""

    DONE = "done"
    FAILED = "failed"
    TIMEOUT = "timeout"


OutcomeName = Literal["done", "failed", "timeout"]
"""An :class:`Outcome` as missions write it (the keys of a state's ``on``)."""

ACTION_OUTCOMES: tuple[OutcomeName, ...] = get_args(OutcomeName)

ParamKind = Literal[
    "distance",
    "speed",
    "time",
    "angle",
    "turn_rate",
    "frequency",
    "percent",
    "count",
    "text",
    "choice",
    "guard",
    "color",
]
"""What a :class:`Param` takes: a quantity dimension (``distance`` ... ``count``, read with a
unit), or ``text``, ``choice`` (one of its words), ``guard`` (a condition) or ``color``."""

PARAM_KINDS: tuple[ParamKind, ...] = get_args(ParamKind)

PARAM_EXAMPLES: dict[str, str] = {
    "distance": "50 cm",
    "speed": "15 cm/s",
    "time": "2 s",
    "angle": "90 deg",
    "turn_rate": "90 deg/s",
    "frequency": "880 Hz",
    "percent": "50 %",
    "count": "4",
    "text": "hello",
    "guard": "range.distance_cm < 20",
    "color": "red",
}
"""A value of each :data:`ParamKind` as a YAML mission writes it, for the examples messages
give (a :class:`Param` may name a better one for itself)."""


@dataclass(frozen=True)
class Result:
    """An action's ending: its outcome and, unless done, why."""

    outcome: Outcome
    reason: str | None = None

    @classmethod
    def done(cls) -> Result:
        """The action did what it was asked."""
        return cls(Outcome.DONE)

    @classmethod
    def failed(cls, reason: str) -> Result:
        """The action could not finish, because of ``reason``."""
        return cls(Outcome.FAILED, reason)

    @classmethod
    def timeout(cls, reason: str = "took too long") -> Result:
        """The action's own time bound passed."""
        return cls(Outcome.TIMEOUT, reason)


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()
"""Marks a parameter with no default."""


class _FromInit:
    def __repr__(self) -> str:
        return "FROM_INIT"


FROM_INIT: Any = _FromInit()
"""Marks a parameter whose default is the one its action's ``__init__`` gives its keyword, so
the value is written once (the class fills it in when it is defined)."""


@dataclass(frozen=True)
class Param:
    """One parameter of an action, as missions write it.

    Attributes:
        name: The name in YAML (``distance``).
        kwarg: The Python keyword, with its unit (``distance_mm``).
        kind: A quantity dimension (``distance``, ``speed``, ``time``, ``angle``,
            ``turn_rate``, ``frequency``, ``percent``, ``count``), or ``text``, ``choice``,
            ``guard`` or ``color``.
        doc: One line for the reference and for error messages.
        default: The value when omitted, or :data:`REQUIRED`.
        choices: Allowed words for a ``choice``.
        example: A value as a YAML mission writes it, for messages (``"20 cm"``); empty for
            the kind's own (:data:`PARAM_EXAMPLES`, or a ``choice``'s first word).
    """

    name: str
    kwarg: str
    kind: ParamKind
    doc: str
    default: Any = REQUIRED
    choices: tuple[str, ...] = ()
    example: str = ""

    @property
    def required(self) -> bool:
        """True if the parameter has no default."""
        return self.default is REQUIRED

    @property
    def yaml_example(self) -> str:
        """The parameter with a value, as a YAML mission writes it (``distance: 50 cm``)."""
        return f"{self.name}: {self.example_value}"

    @property
    def python_example(self) -> str:
        """The parameter with a value, as a Python mission writes it (``distance_mm=500``):
        a quantity as a number in the keyword's unit, words in quotes."""
        value = self.example_value
        if self.kind in DIMENSIONS:
            try:
                return f"{self.kwarg}={parse_quantity(value, self.kind):g}"
            except ValueError:  # a count's example, or a student's Param with an odd one
                pass
        return f'{self.kwarg}="{value}"'

    def in_its_unit(self, keyword: str, value: object) -> str | None:
        """This parameter written for ``keyword=value`` given in another unit
        (``distance_mm=500, which is 50 cm`` for ``distance_cm=50``; ``distance_mm=..., in
        mm`` when ``value`` is not a number), or ``None`` when ``keyword`` is not this
        parameter in a unit of its kind."""
        dimension = DIMENSIONS.get(self.kind)
        stem = f"{self.name}_"
        if dimension is None or not (keyword.startswith(stem) and self.kwarg.startswith(stem)):
            return None
        unit = keyword.removeprefix(stem).replace("_", "/")
        if unit not in dimension.units or keyword == self.kwarg:
            return None
        if isinstance(value, bool) or not isinstance(value, int | float):
            return f"{self.kwarg}=..., in {dimension.base_unit}"
        converted = parse_quantity(value, self.kind, default_unit=unit)
        return f"{self.kwarg}={converted:g}, which is {value:g} {unit}"

    @property
    def example_value(self) -> str:
        """A value as a YAML mission writes it (``"20 cm"``), for messages."""
        if self.example:
            return self.example
        if self.kind == "choice" and self.choices:
            return self.choices[0]
        return PARAM_EXAMPLES.get(self.kind, "...")


class UnderSpecifiedError(ValueError):
    """An action made without a parameter it needs, or with a value it cannot use where it
    needs one (no steps, no actions), told with an example to copy in the student's own
    language: a YAML mission's ``write`` hint, or a Python one's.

    ``str()`` of it is the Python message with the Python example, as a traceback shows it.

    Attributes:
        message: What is missing, as a YAML mission names it
            (``"drive needs a distance or a duration"``).
        yaml: How a YAML mission writes it (``"`distance: 50 cm` or `duration: 2 s`"``).
        python: How a Python mission writes it (``"Drive(distance_mm=500) or ..."``).
        python_message: What is missing, as a Python mission names it (its keywords), when
            that differs from ``message``.
    """

    def __init__(
        self, message: str, *, yaml: str, python: str, python_message: str | None = None
    ) -> None:
        self.message = message
        self.yaml = yaml
        self.python = python
        self.python_message = python_message or message
        super().__init__(f"{self.python_message} (write {python})")


class ActionContext:
    """What an action may use: the robot's capabilities and the scheduler's time.

    Attributes:
        capabilities: Capability objects by name.
        now_s: Scheduler time, seconds.
        dt_s: Seconds since the previous tick (> 0).
        robot_name: For messages.
        gains: Host PID gains ``(kp, ki, kd)`` by loop name, from the robot profile.
        env: What conditions read (the mission runner), or ``None`` outside a mission.
    """

    def __init__(
        self,
        capabilities: Mapping[str, object],
        robot_name: str = "the robot",
        *,
        gains: Mapping[str, tuple[float, float, float]] | None = None,
        env: Any = None,
    ) -> None:
        self.capabilities = capabilities
        self.robot_name = robot_name
        self.gains = dict(gains or {})
        self.env = env
        self.now_s = 0.0
        self.dt_s = 0.0

    def gain(self, loop: str, default: tuple[float, float, float]) -> tuple[float, float, float]:
        """The robot profile's gains for ``loop``, or ``default``."""
        return self.gains.get(loop, default)

    def holds(self, condition: Any) -> bool:
        """Evaluate a compiled condition (a guard) now; False outside a mission."""
        if condition is None or self.env is None:
            return False
        return bool(condition(self.env))

    def has_passed(self, start_s: float, duration_s: float) -> bool:
        """True once ``duration_s`` seconds have passed since ``start_s``.

        A tick's time is a sum of periods, so 1.1 s at 0.1 s ticks may read 1.0999999999;
        a nanosecond of slack ends the action on the tick the student expects.
        """
        return self.now_s - start_s >= duration_s - 1e-9

    def has(self, name: str) -> bool:
        """True if the robot has capability ``name``."""
        return name in self.capabilities

    def get(self, name: str) -> Any:
        """The capability ``name``.

        Raises:
            CapabilityError: The robot does not have it.
        """
        try:
            return self.capabilities[name]
        except KeyError:
            raise CapabilityError(
                f"{self.robot_name} has no {name} ({cap.CAPABILITY_NAMES.get(name, name)})",
                missing=(name,),
            ) from None

    @property
    def drive_base(self) -> cap.DriveBase:
        """The wheels."""
        return cast(cap.DriveBase, self.get(cap.DRIVE_BASE))

    @property
    def speaker(self) -> cap.Speaker:
        """The tone generator."""
        return cast(cap.Speaker, self.get(cap.SPEAKER))


class Action(abc.ABC):
    """Base class of every action (built-in or student-written).

    Subclasses set :attr:`name`, :attr:`params` and :attr:`requires`, take their parameters
    as keyword arguments named with units, and implement :meth:`update`. What is true of an
    action lives here, on its class (how it can fail, whether it can time out, which of its
    parameters are speeds and turn rates), so the load-time checks read the class and a
    subclass inherits every one of them. A parameter's default is written once, in
    ``__init__``: a :class:`Param` whose default is :data:`FROM_INIT` takes it from there.
    """

    name: ClassVar[str]
    """The word missions use (``drive``)."""
    summary: ClassVar[str] = ""
    """One line for the reference."""
    params: ClassVar[tuple[Param, ...]] = ()
    """The parameters, in documentation order."""
    requires: ClassVar[frozenset[str]] = frozenset()
    """Capability names the action needs."""
    bounded_by: ClassVar[tuple[str, ...]] = ()
    """Parameters that end an otherwise endless action; without one of them, its state
    needs a ``timeout`` or a ``when`` (checked at load time)."""
    failure: ClassVar[str | None] = None
    """Why the action may end ``failed`` on any robot that has what it needs (``"stalled"``),
    or ``None``: a state running it with no ``on: {failed: ...}`` is warned at load time."""
    can_time_out: ClassVar[bool] = False
    """True if the action can end ``timeout`` by its own bound (``wait_until``): a state
    running it with neither a timeout nor ``on: {timeout: ...}`` is warned at load time."""
    drive_speeds: ClassVar[tuple[str, ...]] = ()
    """Parameters (mission names) that set the robot's speed over the floor, mm/s: checked
    against the robot's top speed and the slowest speed that moves it."""
    turn_rates: ClassVar[tuple[str, ...]] = ()
    """Parameters (mission names) that set the robot's turning rate in place, deg/s: checked
    against the fastest and slowest turn its wheels can make."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        init = vars(cls).get("__init__")
        if inspect.isfunction(init):
            # mypy refuses an assignment to a method, so the wrapper is set by name
            setattr(cls, "__init__", _reading_its_arguments(init))  # noqa: B010
        update = vars(cls).get("update")
        if inspect.isfunction(update) and is_student_class(cls):
            setattr(cls, "update", _returning_a_result(update))  # noqa: B010
        params = vars(cls).get("params")
        if "__init__" not in vars(cls) or not isinstance(params, tuple):
            return
        if not all(isinstance(param, Param) for param in params):
            return  # a student's mistake, which the mission builder explains
        if not any(param.default is FROM_INIT for param in params):
            return
        signature = inspect.signature(cls.__init__)
        filled = []
        for param in params:
            if param.default is FROM_INIT:
                given = signature.parameters.get(param.kwarg)
                if given is None or given.default is inspect.Parameter.empty:
                    raise TypeError(
                        f"{cls.__name__} parameter {param.name!r}: FROM_INIT needs a default"
                        f" for {param.kwarg} in __init__"
                    )
                param = dataclasses.replace(param, default=given.default)
            filled.append(param)
        cls.params = tuple(filled)

    guessed_params: ClassVar[Mapping[str, str]] = {}
    """Parameters a beginner guesses that the action does not have, and how it says that
    instead (``direction``: a negative distance drives backward), for the message that
    refuses them in YAML and in Python."""

    @classmethod
    def conflicts(cls, values: Mapping[str, Any]) -> list[tuple[str, str, str | None]]:
        """Parameters given together that the action cannot both follow (none by default).

        Args:
            values: The converted keyword arguments (``distance_mm=500.0``).

        Returns:
            ``(parameter, message, hint)`` for each, located at the parameter by the loader.
        """
        return []

    @classmethod
    def example(cls, *names: str) -> tuple[str, str]:
        """How a YAML mission writes this action's parameters ``names``, each with a value,
        and a Python mission the whole call with them (every parameter without a default
        is in both when none are named, and in the call always).

        Returns:
            ``(yaml, python)``: ``("`timeout: 10 s`",
            "WaitUntil(condition=\"range.distance_cm < 20\", timeout_s=10)")``.
        """
        yaml = " and ".join(f"`{p.yaml_example}`" for p in cls._chosen(names))
        return yaml, cls.written(*names)[1]

    @classmethod
    def written(cls, *names: str) -> tuple[str, str]:
        """The whole action with its parameters ``names`` and every one without a default
        (its first parameter when that is none), as a YAML and a Python mission write it:
        ``("{rotate: {angle: 90 deg}}", "Rotate(angle_deg=90)")``,
        ``("{drive: {distance: 50 cm}}", "Drive(distance_mm=500)")``.
        """
        params = params_of(cls)
        chosen = [p for p in params if p.required or p.name in names] or params[:1]
        label = getattr(cls, "name", cls.__name__)
        yaml = f"{{{label}: {{{', '.join(p.yaml_example for p in chosen)}}}}}"
        return yaml, f"{cls.__name__}({', '.join(p.python_example for p in chosen)})"

    @classmethod
    def _chosen(cls, names: Sequence[str]) -> list[Param]:
        params = params_of(cls)
        by_name = {p.name: p for p in params}
        return [by_name[n] for n in names] if names else [p for p in params if p.required]

    @classmethod
    def needs(cls, message: str, *names: str) -> UnderSpecifiedError:
        """The error for this action made without a value it needs: ``message`` (a sentence
        both syntaxes share), with the examples of :meth:`example` for ``names``."""
        yaml, python = cls.example(*names)
        return UnderSpecifiedError(message, yaml=yaml, python=python)

    @classmethod
    def under_specified(cls, missing: Sequence[str]) -> UnderSpecifiedError | None:
        """The error for this action made without the parameters ``missing`` (mission
        names), or ``None`` if they are not all parameters of it.

        A YAML mission gets each missing parameter (``'rotate' needs 'angle', how far to
        turn (positive = right)``, write `angle: 90 deg`); a Python mission its keywords and
        the whole call (``Rotate needs 'angle_deg', ...``, write ``Rotate(angle_deg=90)``).
        """
        by_name = {p.name: p for p in params_of(cls)}
        if not missing or any(name not in by_name for name in missing):
            return None
        wanted = [by_name[name] for name in missing]
        label = getattr(cls, "name", cls.__name__)
        yaml, python = cls.example(*missing)
        return UnderSpecifiedError(
            f"'{label}' needs " + ", and ".join(f"'{p.name}', {p.doc}" for p in wanted),
            yaml=yaml,
            python=python,
            python_message=f"{cls.__name__} needs "
            + ", and ".join(f"'{p.kwarg}', {p.doc}" for p in wanted),
        )

    @classmethod
    def misdefined(cls) -> tuple[str, str] | None:
        """What is wrong with how this class defines what roboscript reads and calls on it,
        as ``(message, fix)``, or ``None``: :attr:`requires` is a set of capability names,
        and each of ``start``, ``update`` and ``stop`` is called with the context,
        ``method(self, ctx)`` (``def update(ctx):`` forgets ``self``)."""
        requires: object = getattr(cls, "requires", frozenset())
        if not isinstance(requires, set | frozenset) or not all(
            isinstance(need, str) for need in requires
        ):  # requires = "drive_base" would need each of its letters
            written = f'{{"{requires}"}}' if isinstance(requires, str) else '{"drive_base"}'
            return (
                f"{cls.__name__}.requires is a set of capability names, not {requires!r}",
                f"write requires = frozenset({written})",
            )
        unknown = sorted(need for need in requires if need not in cap.CAPABILITY_NAMES)
        if unknown:  # requires = frozenset({"drivebase"}): no robot has it
            close = difflib.get_close_matches(unknown[0], cap.CAPABILITY_NAMES, n=1)
            return (
                f"{cls.__name__}.requires names '{unknown[0]}', which is no part a robot has",
                f"did you mean '{close[0]}'?"
                if close
                else f"the parts a robot has: {', '.join(cap.CAPABILITY_NAMES)}",
            )
        for method in ("start", "update", "stop"):
            function = getattr(cls, method, None)
            function = getattr(function, "__wrapped__", function)
            if not inspect.isfunction(function):
                continue
            try:
                inspect.signature(function).bind(cls, None)
            except TypeError:
                return (
                    (
                        f"{cls.__name__}.{method} must take self and ctx, as roboscript calls it"
                        " with the robot's context"
                    ),
                    f"def {method}(self, ctx):",
                )
            except ValueError:
                continue
            waits = (
                "async def"
                if inspect.iscoroutinefunction(function) or inspect.isasyncgenfunction(function)
                else "yield"
                if inspect.isgeneratorfunction(function)
                else None
            )
            if waits is not None:  # copied from SPIKE's runloop: update() would never run
                return (
                    (
                        f"{cls.__name__}.{method} is written with {waits}, but roboscript calls"
                        " it once every tick and does not wait for it, so it would never run"
                    ),
                    (
                        f"write def {method}(self, ctx): without await or yield, returning at"
                        " once: None while it is still going, Result.done() when it has finished"
                    ),
                )
        return None

    def written_call(self) -> str:
        """This action as a Python mission writes it, with the values it holds that are not
        its defaults (``Drive(distance_mm=500)``), for a fix that names the student's own
        actions; ``Drive(...)`` when it holds none that read back as written."""
        shown = []
        for param in params_of(type(self)):
            value = getattr(self, param.kwarg, param.default)
            if value is REQUIRED or value is None or value == param.default:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float | str):
                continue  # a condition or a student's object: not written back here
            shown.append(
                f"{param.kwarg}={value:g}"
                if not isinstance(value, str)
                else f'{param.kwarg}="{value}"'
            )
        return f"{type(self).__name__}({', '.join(shown) or '...'})"

    @classmethod
    def given_too_many(cls, given: Sequence[Any]) -> UnderSpecifiedError | None:
        """The error for this action given more values without their names than it takes,
        when the action has words of its own for it (``Parallel(a, b, c)``: its list without
        the brackets), else ``None``: Python's own message, which a mission's check turns
        into the values' names (:mod:`roboscript.mission.student_code`).

        Args:
            given: The values given without names, in order.
        """
        return None

    feedback: str = ""
    """A short progress text for status lines (``"driving 230/500 mm"``)."""

    def start(self, ctx: ActionContext) -> None:  # noqa: B027 - optional hook
        """Called when the state is entered."""

    @abc.abstractmethod
    def update(self, ctx: ActionContext) -> Result | None:
        """Called every tick; return ``None`` while running, else the :class:`Result`."""

    def stop(self, ctx: ActionContext) -> None:  # noqa: B027 - optional hook
        """Called when the state is left, whether the action ended or was interrupted."""


class UpdateReturnError(TypeError):
    """A student's action whose ``update`` returned what is neither a :class:`Result` nor
    ``None`` (``True``, ``Result.done`` without its brackets): told in the student's terms,
    since the code that then reads the result is roboscript's, not theirs.

    Attributes:
        problem: What it returned (``returned True instead of a Result``).
        fix: What to write instead.
        filename: The file of its ``def update``, and ``line`` that line.
    """

    def __init__(self, problem: str, fix: str, filename: str, line: int) -> None:
        self.problem = problem
        self.fix = fix
        self.filename = filename
        self.line = line
        super().__init__(f"{problem} ({fix})")


RESULT_HINT = "return Result.done() when it has finished, and None while it is still going"
"""What an action's ``update`` returns, as every message about what it returned says it."""


def _returning_a_result(update: Callable[..., Any]) -> Callable[..., Any]:
    """A student's ``update``, its value checked: a :class:`Result` or ``None``."""

    @functools.wraps(update)
    def checked(self: Action, ctx: ActionContext) -> Result | None:
        result = update(self, ctx)
        if result is None or isinstance(result, Result):
            return result
        if getattr(result, "__self__", None) is Result:  # return Result.done
            name = result.__name__
            problem = f"returned Result.{name} without calling it"
            fix = f"write return Result.{name}({'' if name == 'done' else '...'})"
        else:
            shown = repr(result) if len(repr(result)) <= 40 else type(result).__name__
            problem, fix = f"returned {shown} instead of a Result", RESULT_HINT
        code = update.__code__
        raise UpdateReturnError(problem, fix, code.co_filename, code.co_firstlineno)

    return checked


def _reading_its_arguments(init: Callable[..., None]) -> Callable[..., None]:
    """``init``, an action's ``__init__``, reading what it is given as a mission would:

    * a quantity written as text (``Drive(distance_mm="50 cm")``) is read in the keyword's
      unit before ``init`` sees it, by the rule YAML's values follow (text it cannot read is
      left for the mission's check, which names it at its keyword, unless ``init`` compares
      it first: then that is the error, not Python's ``'<' not supported``);
    * a call without a parameter it needs is answered by :meth:`Action.under_specified` (an
      example to copy) instead of Python's ``missing 1 required positional argument``.
    """
    try:
        signature: inspect.Signature | None = inspect.signature(init)
    except (TypeError, ValueError):  # a student's odd __init__: taken as it is
        signature = None

    @functools.wraps(init)
    def wrapped(self: Action, *args: Any, **kwargs: Any) -> None:
        unread = None
        if signature is not None and any(isinstance(v, str) for v in (*args, *kwargs.values())):
            args, kwargs, unread = _quantities_read(type(self), signature, self, args, kwargs)
        try:
            init(self, *args, **kwargs)
        except TypeError as exc:
            if exc.__traceback__ is not None and exc.__traceback__.tb_next is not None:
                if unread is not None:  # init compared text it could not read
                    raise unread from None
                wrong = (
                    _mistyped(type(self), signature, self, args, kwargs)
                    if signature is not None and raised_by_roboscript(exc)
                    else None  # a student's own __init__ keeps Python's words, at its line
                )
                if wrong is not None:  # init compared a list or None with a number
                    raise wrong from None
                raise  # raised inside __init__, not by the call
            takes = None if signature is None else _positional(signature)
            if takes is not None and len(args) > len(takes):
                too_many = type(self).given_too_many(args)
                if too_many is not None:
                    raise too_many from None
            missing = [] if signature is None else _missing(signature, self, args, kwargs)
            by_kwarg = {p.kwarg: p.name for p in params_of(type(self))}
            names = [by_kwarg.get(kwarg, kwarg) for kwarg in missing]
            error = type(self).under_specified(names) if names else None
            if error is None:
                raise
            raise error from None

    return wrapped


def params_of(cls: type[Action]) -> list[Param]:
    """The parameters an action class declares, safely: a student's ``params`` that are not
    a tuple of :class:`Param` give none (the mission builder says what is wrong with them)."""
    params = getattr(cls, "params", ())
    return [p for p in params if isinstance(p, Param)] if isinstance(params, tuple) else []


def _quantities_read(
    cls: type[Action],
    signature: inspect.Signature,
    self: Action,
    args: tuple[Any, ...],
    kwargs: dict[str, Any],
) -> tuple[tuple[Any, ...], dict[str, Any], ValueError | None]:
    """``args`` and ``kwargs`` with each quantity given as text read in its keyword's unit,
    and the error for the first text that could not be read (``None`` if all could)."""
    try:
        bound = signature.bind_partial(self, *args, **kwargs)
    except TypeError:  # a wrong call, which the call itself reports
        return args, kwargs, None
    unread = None
    label = getattr(cls, "name", cls.__name__)
    for param in params_of(cls):
        value = bound.arguments.get(param.kwarg)
        if not isinstance(value, str) or param.kind not in DIMENSIONS or param.kind == "count":
            continue
        try:
            bound.arguments[param.kwarg] = parse_quantity(value, param.kind)
        except ValueError as exc:
            unread = unread or ValueError(f"{label} {param.name}: {exc}")
    return bound.args[1:], bound.kwargs, unread


def _mistyped(
    cls: type[Action],
    signature: inspect.Signature,
    self: Action,
    args: tuple[Any, ...],
    kwargs: dict[str, Any],
) -> ValueError | None:
    """The error for the first quantity given as something that is no number or text
    (``Wait(duration_s=[2])``, ``Wait(duration_s=None)``), said as a mission's check says it,
    or ``None`` if every quantity given is a number."""
    try:
        bound = signature.bind_partial(self, *args, **kwargs)
    except TypeError:
        return None
    label = getattr(cls, "name", cls.__name__)
    for param in params_of(cls):
        if param.kind not in DIMENSIONS or param.kwarg not in bound.arguments:
            continue
        value = bound.arguments[param.kwarg]
        if param.kind == "count":
            if isinstance(value, bool) or not isinstance(value, int):
                return ValueError(f"{label} {param.name}: expected a whole number, got {value!r}")
            continue
        try:
            parse_quantity(value, param.kind)
        except ValueError as exc:
            return ValueError(f"{label} {param.name}: {exc}")
    return None


def _positional(signature: inspect.Signature) -> list[str] | None:
    """The keywords of ``__init__`` that take a value without its name, in order (not
    ``self``), or ``None`` when it takes any number (``*args``)."""
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    parameters = list(signature.parameters.values())[1:]
    if any(p.kind is inspect.Parameter.VAR_POSITIONAL for p in parameters):
        return None
    return [p.name for p in parameters if p.kind in kinds]


def _missing(
    signature: inspect.Signature, self: Action, args: tuple[Any, ...], kwargs: dict[str, Any]
) -> list[str]:
    """The keywords without a default that a call of ``__init__`` left out (none if the call
    was wrong in another way: an unknown keyword, one argument too many)."""
    try:
        bound = signature.bind_partial(self, *args, **kwargs)
    except TypeError:
        return []
    named = (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)
    return [
        name
        for name, parameter in signature.parameters.items()
        if name not in bound.arguments
        and parameter.kind in named
        and parameter.default is inspect.Parameter.empty
    ]
