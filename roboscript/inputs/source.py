"""Safe YAML with positions: every mapping and list remembers where each item was written.

Missions, robot profiles, worlds and test specs are all read through :func:`load_yaml`, so
every error about them can name ``file:line:col``. Only the YAML safe subset is accepted:
tags such as ``!!python/object`` are refused, as are duplicate keys. This module is the
package's only user of ``yaml``.

A :data:`Mark` is a place in the file being read; a :class:`Location` is a place in any file
(a mark with its file), the one location type missions, worlds, profiles and test specs use.
"""

from __future__ import annotations

import re
from collections.abc import Hashable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from roboscript.errors import InputError

__all__ = ["Location", "Mark", "YamlList", "YamlMap", "load_yaml", "load_yaml_text"]

Mark = tuple[int, int]
"""A 1-based (line, column)."""


@dataclass(frozen=True)
class Location:
    """Where something was written: file, 1-based line and column."""

    path: str
    line: int | None = None
    col: int | None = None

    @classmethod
    def at(cls, path: str, mark: Mark | None) -> Location:
        """The place ``mark`` in ``path`` (the whole file when ``mark`` is ``None``)."""
        return cls(path, *(mark or (None, None)))

    def __str__(self) -> str:
        text = self.path
        if self.line is not None:
            text += f":{self.line}"
            if self.col is not None:
                text += f":{self.col}"
        return text


class YamlMap(dict[str, Any]):
    """A mapping from YAML that knows where its keys and values were written.

    Attributes:
        mark: Where the mapping starts.
        key_marks: Where each key was written.
        value_marks: Where each value starts.
        quoted: Keys whose value was written in quotes.
    """

    mark: Mark
    key_marks: dict[str, Mark]
    value_marks: dict[str, Mark]
    quoted: set[str]

    @classmethod
    def at(cls, mark: Mark, values: dict[str, Any] | None = None) -> YamlMap:
        """A mapping that was not written as one (an absent value, a value given alone),
        with every key and value placed at ``mark``."""
        made = cls(values or {})
        made.mark, made.key_marks, made.value_marks, made.quoted = mark, {}, {}, set()
        return made

    def key_mark(self, key: str) -> Mark:
        """Where ``key`` was written (the mapping's start if it was not)."""
        return self.key_marks.get(key, self.mark)

    def value_mark(self, key: str) -> Mark:
        """Where the value of ``key`` starts (the mapping's start if absent)."""
        return self.value_marks.get(key, self.mark)

    def text_mark(self, key: str, offset: int = 0) -> Mark:
        """Where character ``offset`` of the value of ``key`` was written (inside its quotes)."""
        line, col = self.value_mark(key)
        return line, col + (1 if key in self.quoted else 0) + offset


class YamlList(list[Any]):
    """A list from YAML that knows where each item was written."""

    mark: Mark
    item_marks: list[Mark]


def _mark(node: yaml.Node) -> Mark:
    return node.start_mark.line + 1, node.start_mark.column + 1


class _Loader(yaml.SafeLoader):
    """SafeLoader that keeps positions and refuses duplicate keys."""

    source_path: str = "<input>"
    error: type[InputError] = InputError

    def construct_yaml_map_with_marks(self, node: yaml.MappingNode) -> Iterator[YamlMap]:
        result = YamlMap()
        result.mark = _mark(node)
        result.key_marks = {}
        result.value_marks = {}
        result.quoted = set()
        yield result
        self.flatten_mapping(node)
        for key_node, value_node in node.value:
            key = self.construct_object(key_node, deep=True)
            if not isinstance(key, Hashable):
                line, col = _mark(key_node)
                raise self.error(
                    "a key must be a plain word", path=self.source_path, line=line, col=col
                )
            key = str(key)
            if key in result:
                line, col = _mark(key_node)
                first = result.key_marks[key][0]
                raise self.error(
                    f"'{key}' is given twice (first on line {first})",
                    path=self.source_path,
                    line=line,
                    col=col,
                )
            result[key] = self.construct_object(value_node, deep=True)
            result.key_marks[key] = _mark(key_node)
            result.value_marks[key] = _mark(value_node)
            if isinstance(value_node, yaml.ScalarNode) and value_node.style in ("'", '"'):
                result.quoted.add(key)

    def construct_yaml_seq_with_marks(self, node: yaml.SequenceNode) -> Iterator[YamlList]:
        result = YamlList()
        result.mark = _mark(node)
        result.item_marks = [_mark(item) for item in node.value]
        yield result
        result.extend(self.construct_object(item, deep=True) for item in node.value)


# YAML 1.1 reads on/off/yes/no as booleans, which would turn a state's "on:" into True.
# Booleans are only true/false, as in YAML 1.2.
_Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:bool"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool",
    re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"),
    list("tTfF"),
)
_Loader.add_constructor("tag:yaml.org,2002:map", _Loader.construct_yaml_map_with_marks)
_Loader.add_constructor("tag:yaml.org,2002:seq", _Loader.construct_yaml_seq_with_marks)


def load_yaml_text(
    text: str, path: str = "<input>", *, error: type[InputError] = InputError
) -> Any:
    """Parse YAML text safely, keeping positions.

    Args:
        text: The YAML document.
        path: The file name to put in error messages.
        error: The :class:`InputError` subclass to raise (``MissionError``, ``WorldError``...).

    Raises:
        InputError: The text is not valid YAML, uses a tag outside the safe subset, or repeats
            a key.
    """
    try:
        loader = _Loader(text)
    except yaml.reader.ReaderError as exc:
        # PyYAML checks for unprintable characters before it parses anything.
        offset = max(0, exc.position)
        bad_line = text.count("\n", 0, offset) + 1
        bad_col = offset - (text.rfind("\n", 0, offset) + 1) + 1
        code = f"U+{exc.character:04X}" if isinstance(exc.character, int) else repr(exc.character)
        raise error(
            f"the file contains a character YAML does not allow ({code})",
            path=path,
            line=bad_line,
            col=bad_col,
        ) from None
    loader.source_path = path
    loader.error = error
    try:
        return loader.get_single_data()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark else None
        col = mark.column + 1 if mark else None
        problem = exc.problem or "invalid YAML"
        if "could not determine a constructor" in str(exc):
            problem = f"tag {str(exc.problem).split()[-1]} is not allowed in roboscript files"
            problem = problem.replace("'", "")
        raise error(problem, path=path, line=line, col=col) from None
    except yaml.YAMLError as exc:
        raise error(f"invalid YAML: {exc}", path=path) from None
    finally:
        loader.dispose()


def load_yaml(path: str | Path, *, error: type[InputError] = InputError) -> Any:
    """Read and parse a YAML file safely (see :func:`load_yaml_text`).

    Raises:
        InputError: The file cannot be read or is not valid YAML.
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise error(f"cannot read the file: {exc.strerror}", path=str(path)) from None
    except UnicodeDecodeError:
        raise error("the file is not UTF-8 text", path=str(path)) from None
    return load_yaml_text(text, str(path), error=error)
