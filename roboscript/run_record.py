"""What happened in one mission run: the record ``run``, ``grade``, the API and the page share.

:class:`RunRecord` holds what every run reports (how the mission ended, its states and why it
entered each, and on a simulated robot what the simulator saw, :class:`SimulatedRun`). Its
JSON is derived from its fields, in their order, by one rule (:func:`to_json_value`): a field
is a key of the same name; a record or a named tuple (:class:`Pose`, :class:`Tone`) is an
object of its fields; any other tuple is a list. So ``roboscript run --json``, the Python
API's :attr:`~roboscript.api.RunResult.summary`, the record of each graded run and the
browser page's summary are one object, and a field added here shows up in all of them.

A run's wider result extends the record by subclassing it (the API's
:class:`~roboscript.api.RunResult` adds the recording and the warnings; the grader's
:class:`~roboscript.grading.record.GradedRecord` adds where each collision was and the body's
size); its own fields are serialised by the same rule unless marked :data:`NOT_SERIALISED`.

Times are on the mission clock: 0 is the moment the mission started. Poses are
``(x mm east, y mm north, heading deg clockwise from north)``.
"""

from __future__ import annotations

import functools
import json
import math
import types
from collections.abc import Callable, Mapping
from dataclasses import MISSING, Field, dataclass, field, fields, is_dataclass
from typing import (
    TYPE_CHECKING,
    Any,
    Literal,
    NamedTuple,
    Union,
    cast,
    get_args,
    get_origin,
    get_type_hints,
)

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: not a dependency

__all__ = [
    "NOT_SERIALISED",
    "OMITTED_WHEN_DEFAULT",
    "Pose",
    "RunRecord",
    "SimulatedRun",
    "Tone",
    "from_json_value",
    "misfit",
    "to_json_value",
]

NOT_SERIALISED: Mapping[str, bool] = types.MappingProxyType({"json": False})
"""A field's ``metadata`` for a value that stays in the process (a world, a recording)."""

OMITTED_WHEN_DEFAULT: Mapping[str, bool] = types.MappingProxyType({"omit_default": True})
"""A field's ``metadata`` for a value written only when it is not its default: a count of
what was left out (0), the simulator's part on a real robot (``None``)."""


class Pose(NamedTuple):
    """Where the robot is: mm east and north of the world's origin, heading deg clockwise from
    north. A tuple (``x, y, heading = pose``); in JSON ``{"x_mm", "y_mm", "heading_deg"}``."""

    x_mm: float
    y_mm: float
    heading_deg: float


class Tone(NamedTuple):
    """A tone the robot started: when (s on the mission clock), how high (Hz), how long (s).
    A tuple (``t, hz, s = tone``); in JSON ``{"t_s", "frequency_hz", "duration_s"}``."""

    t_s: float
    frequency_hz: float
    duration_s: float


@dataclass(frozen=True)
class SimulatedRun:
    """What the simulator saw of a run (``run --json``'s ``sim``).

    Attributes:
        seed: The simulator seed.
        world: The world's name.
        final_pose: Where the robot ended (the simulated body's true pose).
        distance_travelled_mm: Path length of the body centre since the mission started, mm.
        collisions: How many times the body hit a wall.
        tones: Every tone started (a run of hours lists the first ones only).
        path: Samples ``(t s, x mm, y mm, heading deg)`` every 0.1 s from the mission's start.
        tones_not_listed: Tones heard but not listed in ``tones`` (written only when not 0).
    """

    seed: int
    world: str
    final_pose: Pose
    distance_travelled_mm: float
    collisions: int
    tones: tuple[Tone, ...]
    path: tuple[tuple[float, float, float, float], ...]
    tones_not_listed: int = field(default=0, metadata=OMITTED_WHEN_DEFAULT)


@dataclass(frozen=True)
class RunRecord:
    """One finished mission run: how it ended, its states, and what the simulator saw.

    Attributes:
        mission: The mission's name.
        robot: The robot profile's name.
        outcome: ``success``, ``failure`` or ``error`` (the robot or link failed, the code got
            stuck, or the run was interrupted).
        final_state: The state the mission ended in, or ``None``.
        reason: One sentence when the outcome is not ``success``, else ``None``.
        duration_s: Mission time when it ended, s (to the ms).
        states: Every state entered, as ``(t s, name)`` (a long loop keeps the first and last
            ones only: ``states_dropped`` counts the rest).
        transitions: The same states with why each was entered: ``{"t_s", "state",
            "cause"}`` objects, ``cause`` as a recording's ``why``; empty when the run's
            causes are not known (a graded run).
        states_dropped: States entered but left out of ``states`` (written only when not 0).
        code_stopped: ``"too slow"`` or ``"hung"`` when the mission's code was stopped (the
            outcome is then ``error``; :mod:`roboscript.watchdog`), else ``""`` (not written).
        sim: What the simulator saw, or ``None`` on a real robot (then not written).
    """

    mission: str
    robot: str
    outcome: str
    final_state: str | None
    reason: str | None
    duration_s: float
    states: tuple[tuple[float, str], ...]
    transitions: tuple[Mapping[str, Any], ...] = ()
    states_dropped: int = field(default=0, metadata=OMITTED_WHEN_DEFAULT)
    code_stopped: str = field(default="", metadata=OMITTED_WHEN_DEFAULT)
    sim: SimulatedRun | None = field(default=None, metadata=OMITTED_WHEN_DEFAULT)

    def to_dict(self) -> dict[str, Any]:
        """The record as a JSON object (``run --json``'s), derived from the fields."""
        return _record_dict(self)

    def to_json(self, indent: int | None = None) -> str:
        """The record as JSON text (``roboscript run --json`` prints it with ``indent=2``)."""
        return json.dumps(self.to_dict(), indent=indent)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], **kept: Any) -> Self:
        """The record :meth:`to_dict` made; ``kept`` gives the fields that are not serialised.

        Raises:
            KeyError: A field without a default is missing.
            TypeError, ValueError: A value does not fit its field.
        """
        return cast("Self", _from_dict(cls, data, kept))

    @classmethod
    def from_json(cls, text: str, **kept: Any) -> Self:
        """The record :meth:`to_json` wrote (see :meth:`from_dict`)."""
        return cls.from_dict(json.loads(text), **kept)


def _serialised(item: Field[Any]) -> bool:
    return bool(item.metadata.get("json", True))


def _record_dict(record: Any) -> dict[str, Any]:
    data: dict[str, Any] = {}
    for item in fields(record):
        if not _serialised(item):
            continue
        value = getattr(record, item.name)
        if item.metadata.get("omit_default") and value == item.default:
            continue
        data[item.name] = to_json_value(value)
    return data


def to_json_value(value: Any) -> Any:
    """``value`` as JSON-ready data: a dataclass or a named tuple becomes an object of its
    fields (in their order), any other tuple or list a list, a mapping an object."""
    if value is None or isinstance(value, str | int | float):
        return value  # most values of a run (every path sample's numbers): answered first
    if is_dataclass(value) and not isinstance(value, type):
        return _record_dict(value)
    if isinstance(value, tuple) and hasattr(value, "_fields"):
        return {name: to_json_value(v) for name, v in zip(value._fields, value, strict=True)}
    if isinstance(value, tuple | list):
        return [to_json_value(v) for v in value]
    if isinstance(value, Mapping):
        return {key: to_json_value(v) for key, v in value.items()}
    return value


@functools.cache
def _hints(kind: Any) -> dict[str, Any]:
    """A record's field types, resolved once per class (the annotations are strings)."""
    return get_type_hints(kind)


def _from_dict(cls: Any, data: Mapping[str, Any], kept: Mapping[str, Any]) -> Any:
    hints = _hints(cls)
    values: dict[str, Any] = dict(kept)
    for item in fields(cls):
        if not _serialised(item) or item.name in values:
            continue
        if item.name in data:
            values[item.name] = _reader(hints[item.name])(data[item.name])
        elif item.default is MISSING and item.default_factory is MISSING:
            raise KeyError(item.name)
    return cls(**values)


def from_json_value(kind: Any, value: Any) -> Any:
    """The value of type ``kind`` that :func:`to_json_value` turned into ``value``.

    Raises:
        TypeError, ValueError: ``value`` does not have the shape of ``kind``.
    """
    return _reader(kind)(value)


def _as_is(value: Any) -> Any:
    return value


@functools.cache
def _reader(kind: Any) -> Callable[[Any], Any]:
    """How to read a JSON value of type ``kind``, worked out once per type (a run's path has
    thousands of samples of one type)."""
    origin = get_origin(kind)
    if origin in (Union, types.UnionType):
        (inner,) = [arg for arg in get_args(kind) if arg is not type(None)]
        read_inner = _reader(inner)
        return lambda value: None if value is None else read_inner(value)
    if isinstance(kind, type) and is_dataclass(kind):
        return lambda value: _from_dict(kind, _object(value, kind), {})
    if isinstance(kind, type) and issubclass(kind, tuple) and hasattr(kind, "_fields"):
        hints = _hints(kind)
        readers = {name: _reader(hints[name]) for name in kind._fields}
        return lambda value: kind(
            **{name: read(_object(value, kind)[name]) for name, read in readers.items()}
        )
    if origin is tuple:
        return _tuple_reader(get_args(kind))
    if origin is not None and issubclass(origin, Mapping):
        return lambda value: dict(_object(value, origin))
    return _as_is


def _tuple_reader(args: tuple[Any, ...]) -> Callable[[Any], Any]:
    if len(args) == 2 and args[1] is Ellipsis:
        read_item = _reader(args[0])
        return lambda value: tuple(read_item(v) for v in _list(value, None))
    readers = [_reader(arg) for arg in args]
    if all(read is _as_is for read in readers):
        return lambda value: tuple(_list(value, len(readers)))
    return lambda value: tuple(
        read(v) for read, v in zip(readers, _list(value, len(readers)), strict=True)
    )


def _list(value: Any, length: int | None) -> list[Any]:
    if not isinstance(value, list):
        raise TypeError(f"expected a list, got {type(value).__name__}")
    if length is not None and len(value) != length:
        raise ValueError(f"expected {length} values, got {len(value)}")
    return value


def _object(value: Any, kind: type[Any]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise TypeError(f"expected an object for {kind.__name__}, got {type(value).__name__}")
    return value


def misfit(kind: Any, value: Any, where: str = "") -> str | None:
    """What is wrong with ``value`` as a value of type ``kind`` (one sentence naming where, as
    ``'sim.path[3][1]' must be a number``), or ``None`` when it fits.

    Checks what :func:`from_json_value` cannot: a record read from a file that someone may have
    damaged or forged is of its types all the way down (numbers finite, no ``True`` for a
    number, lists of the right length), before any report computes with it.
    """
    origin = get_origin(kind)
    if origin in (Union, types.UnionType):
        if value is None and type(None) in get_args(kind):
            return None
        (inner,) = [arg for arg in get_args(kind) if arg is not type(None)]
        return misfit(inner, value, where)
    if origin is Literal:
        allowed = get_args(kind)
        return None if value in allowed else f"'{where}' must be one of {', '.join(allowed)}"
    if kind is Any:
        return None
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            return f"'{where}' must be a number"
        return None if math.isfinite(value) else f"'{where}' must be a finite number"
    if kind is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
        return None if ok else f"'{where}' must be a whole number"
    if kind in (str, bool):
        return None if isinstance(value, kind) else f"'{where}' must be {_KIND_WORDS[kind]}"
    if isinstance(kind, type) and is_dataclass(kind):
        if not isinstance(value, kind):
            return f"'{where}' must be an object"
        hints = _hints(kind)
        for item in fields(kind):
            if _serialised(item):
                found = misfit(hints[item.name], getattr(value, item.name), _at(where, item.name))
                if found:
                    return found
        return None
    if isinstance(kind, type) and issubclass(kind, tuple) and hasattr(kind, "_fields"):
        if not isinstance(value, tuple) or len(value) != len(kind._fields):
            return f"'{where}' must be an object"
        hints = _hints(kind)
        for name, item in zip(kind._fields, value, strict=True):
            found = misfit(hints[name], item, _at(where, name))
            if found:
                return found
        return None
    if origin is tuple:
        return _tuple_misfit(get_args(kind), value, where)
    if origin is not None and issubclass(origin, Mapping):
        return None if isinstance(value, Mapping) else f"'{where}' must be an object"
    if origin is dict or kind is dict:
        return None if isinstance(value, dict) else f"'{where}' must be an object"
    return None


_KIND_WORDS = {str: "text", bool: "true or false"}


def _at(where: str, name: str) -> str:
    return f"{where}.{name}" if where else name


def _tuple_misfit(args: tuple[Any, ...], value: Any, where: str) -> str | None:
    if not isinstance(value, tuple | list):
        return f"'{where}' must be a list"
    if len(args) == 2 and args[1] is Ellipsis:
        items = [(args[0], item) for item in value]
    elif len(value) != len(args):
        return f"'{where}' must be a list of {len(args)} values"
    else:
        items = list(zip(args, value, strict=True))
    for index, (kind, item) in enumerate(items):
        found = misfit(kind, item, f"{where}[{index}]")
        if found:
            return found
    return None
