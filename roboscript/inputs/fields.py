"""Reading the fields of a YAML file into values, with every mistake located at ``file:line:col``.

Files are read with :func:`roboscript.inputs.source.load_yaml`, so each mapping and list knows
where its items were written. A :class:`FieldReader` turns a wrong field into the file kind's
:class:`~roboscript.errors.InputError` (``MissionError``, ``WorldError``, ``ProfileError``,
``SpecError``) at that place, with a "did you mean" where one fits, so a mistake reads the same
in every file the project accepts::

    square.yaml:3:3: error: unknown key 'stats' in a mission (did you mean 'states'?)

Readers that stop at the first mistake raise what :meth:`FieldReader.fail` returns; readers
that collect every problem (missions) keep what :meth:`FieldReader.unknown_keys` returns.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from roboscript.errors import InputError, did_you_mean
from roboscript.inputs.quantities import DIMENSIONS, QuantityError, parse_quantity
from roboscript.inputs.source import Location, Mark, YamlList, YamlMap

__all__ = ["FieldReader", "did_you_mean", "unknown_key_hint"]


def unknown_key_hint(key: str, keys: Iterable[str]) -> str:
    """The hint for an unknown key: the near miss, else the keys that exist."""
    keys = list(keys)
    return did_you_mean(key, keys) or f"expected one of: {', '.join(keys)}"


def _shown(value: object) -> str:
    """A value in a message: the text as written, a number beyond any float by its size."""
    if isinstance(value, str):
        return f"'{value.strip()}'"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{'-' if value < 0 else ''}infinity"
    if isinstance(value, int):  # str() of it could pass Python's 4300-digit limit
        return f"a {int(value.bit_length() * math.log10(2)) + 1}-digit number"
    return repr(value)


class FieldReader:
    """Typed access to the fields of one file.

    Args:
        path: The file name to put in error messages.
        error: The :class:`~roboscript.errors.InputError` subclass for this kind of file.
    """

    def __init__(self, path: str, error: type[InputError] = InputError) -> None:
        self.path = path
        self.error = error

    def fail(
        self,
        message: str,
        mark: Mark | None,
        hint: str | None = None,
        severity: str = "error",
    ) -> InputError:
        """An error of this file's kind at ``mark`` (to raise or to collect)."""
        line, col = mark if mark else (None, None)
        return self.error(message, path=self.path, line=line, col=col, hint=hint, severity=severity)

    def fail_at(
        self, message: str, where: Location, hint: str | None = None, severity: str = "error"
    ) -> InputError:
        """An error of this file's kind at ``where``, which may be in another file."""
        return self.error(
            message, path=where.path, line=where.line, col=where.col, hint=hint, severity=severity
        )

    def loc(self, mark: Mark | None) -> Location:
        """``mark`` in this file, as a :class:`Location`."""
        return Location.at(self.path, mark)

    # ----------------------------------------------------------------------------- shapes

    def mapping(self, value: Any, what: str, mark: Mark | None) -> YamlMap:
        """``value`` as a mapping, or an error saying ``what`` must be one."""
        if not isinstance(value, YamlMap):
            example = f" such as {{{what}: ...}}" if " " not in what else ""
            raise self.fail(f"{what} must be a mapping{example}", mark)
        return value

    def items(self, value: Any, what: str, mark: Mark | None) -> list[tuple[Any, Mark]]:
        """The items of a YAML list with where each was written."""
        if not isinstance(value, YamlList):
            raise self.fail(f"{what} must be a list (one '- ' line per item)", mark)
        return list(zip(value, value.item_marks, strict=True))

    # ------------------------------------------------------------------------------- keys

    def unknown_keys(
        self,
        data: YamlMap,
        keys: Sequence[str],
        what: str,
        meant: Callable[[str, Any], str | None] | None = None,
    ) -> list[InputError]:
        """One error per key of ``data`` outside ``keys``, in the one shape every file uses:
        ``unknown key 'K' in WHAT (did you mean 'X'?)``.

        ``meant(key, value)`` may give a better hint for a key known to be mixed up with
        another (``next`` for ``on``); when it gives ``None`` the near miss is the hint.
        """
        return [
            self.fail(
                f"unknown key '{key}' in {what}",
                data.key_mark(key),
                (meant(key, data[key]) if meant is not None else None)
                or unknown_key_hint(key, keys),
            )
            for key in data
            if key not in keys
        ]

    def allowed(
        self, data: YamlMap, keys: Sequence[str], what: str, required: Sequence[str] = ()
    ) -> None:
        """Refuse keys outside ``keys``, and require those in ``required``."""
        for problem in self.unknown_keys(data, keys, what):
            raise problem
        for key in required:
            if key not in data:
                raise self.fail(f"{what} needs '{key}'", data.mark)

    # ----------------------------------------------------------------------------- values

    def value_quantity(
        self, value: Any, dimension: str, mark: Mark | None, default_unit: str | None = None
    ) -> float:
        """``value`` converted to the base unit of ``dimension`` (mm, mm/s, s, deg, Hz).

        Raises:
            InputError: ``value`` is not a quantity of ``dimension``, or not a finite one
                (``1e400 mm``, ``.inf``, ``.nan``).
        """
        try:
            found = parse_quantity(value, dimension, default_unit)
        except QuantityError as exc:
            raise self.fail(exc.message, mark, exc.hint) from None
        except OverflowError:  # a whole number beyond any float, given from code
            found = math.inf
        if not math.isfinite(found):
            name = DIMENSIONS[dimension].name
            raise self.fail(
                f"{_shown(value)} is not a {name} a robot can use", mark, f"write a finite {name}"
            )
        return found

    def quantity(
        self, data: YamlMap, key: str, dimension: str, default_unit: str | None = None
    ) -> float:
        """``data[key]`` converted to the base unit of ``dimension`` (mm, s, deg, Hz)."""
        return self.value_quantity(data[key], dimension, data.value_mark(key), default_unit)

    def positive(
        self,
        data: YamlMap,
        key: str,
        dimension: str,
        default_unit: str | None = None,
        maximum: tuple[float, str] | None = None,
    ) -> float:
        """A quantity that must be above zero, and at most ``maximum`` (in the base unit, and
        as written for the reader, ``(86400.0, "1 day")``) where given."""
        value = self.quantity(data, key, dimension, default_unit)
        if value <= 0:
            raise self.fail(f"'{key}' must be more than 0", data.value_mark(key))
        if maximum is not None and value > maximum[0]:
            raise self.fail(f"'{key}' must be at most {maximum[1]}", data.value_mark(key))
        return value

    def text(self, data: YamlMap, key: str) -> str:
        """``data[key]`` as non-empty text."""
        value = data[key]
        if isinstance(value, bool) or not isinstance(value, str | int | float) or value == "":
            raise self.fail(f"'{key}' must be a word or text", data.value_mark(key))
        return str(value)

    def integer(self, data: YamlMap, key: str, minimum: int = 0) -> int:
        """``data[key]`` as a whole number of at least ``minimum``."""
        value = data[key]
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            raise self.fail(
                f"'{key}' must be a whole number of at least {minimum}", data.value_mark(key)
            )
        return value

    def choice(self, data: YamlMap, key: str, choices: Sequence[str]) -> str:
        """``data[key]``, one of ``choices``."""
        value = data[key]
        if not isinstance(value, str) or value not in choices:
            hint = did_you_mean(str(value), choices) if isinstance(value, str) else None
            raise self.fail(
                f"'{key}' must be one of: {', '.join(choices)} (got {value!r})",
                data.value_mark(key),
                hint,
            )
        return value

    def names(self, data: YamlMap, key: str) -> list[tuple[str, Mark]]:
        """``data[key]`` as one name or a list of names, each with where it was written."""
        value = data[key]
        if isinstance(value, str) and value:
            return [(value, data.value_mark(key))]
        if isinstance(value, YamlList) and value:
            found = []
            for item, mark in zip(value, value.item_marks, strict=True):
                if not isinstance(item, str) or not item:
                    raise self.fail(f"'{key}' lists names; this item is {item!r}", mark)
                found.append((item, mark))
            return found
        raise self.fail(
            f"'{key}' must be a name or a list of names such as [a, b]", data.value_mark(key)
        )
