"""Reading test-spec YAML fields into values, with every mistake located at ``file:line:col``.

The test spec is read with :func:`roboscript.mission.source.load_yaml`, so each mapping and
list knows where its items were written; :class:`SpecReader` turns a wrong field into a
:class:`~roboscript.errors.SpecError` at that place, with a "did you mean" where one fits.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from roboscript.errors import SpecError, did_you_mean
from roboscript.mission.quantities import QuantityError, parse_quantity
from roboscript.mission.source import Mark, YamlList, YamlMap

__all__ = ["SpecReader"]


class SpecReader:
    """Typed access to the fields of one test-spec file.

    Args:
        path: The file name to put in error messages.
    """

    def __init__(self, path: str) -> None:
        self.path = path

    def fail(self, message: str, mark: Mark | None, hint: str | None = None) -> SpecError:
        """A :class:`SpecError` at ``mark`` (to raise)."""
        line, col = mark if mark else (None, None)
        return SpecError(message, path=self.path, line=line, col=col, hint=hint)

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

    def allowed(
        self, data: YamlMap, keys: Sequence[str], what: str, required: Sequence[str] = ()
    ) -> None:
        """Refuse keys outside ``keys``, and require those in ``required``."""
        for key in data:
            if key not in keys:
                hint = did_you_mean(key, keys) or f"expected one of: {', '.join(keys)}"
                raise self.fail(f"unknown key '{key}' in {what}", data.key_mark(key), hint)
        for key in required:
            if key not in data:
                raise self.fail(f"{what} needs '{key}'", data.mark)

    def quantity(self, data: YamlMap, key: str, dimension: str, default_unit: str) -> float:
        """``data[key]`` converted to the base unit of ``dimension`` (mm, s, deg, Hz)."""
        try:
            return parse_quantity(data[key], dimension, default_unit)
        except QuantityError as exc:
            raise self.fail(str(exc), data.value_mark(key)) from None

    def positive(self, data: YamlMap, key: str, dimension: str, default_unit: str) -> float:
        """A quantity that must be above zero."""
        value = self.quantity(data, key, dimension, default_unit)
        if value <= 0:
            raise self.fail(f"'{key}' must be more than 0", data.value_mark(key))
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
