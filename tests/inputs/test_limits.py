"""Hostile files are refused before any expensive work, in one located sentence."""

from __future__ import annotations

import os
import socket
from pathlib import Path

import pytest

from roboscript.errors import InputError, MissionError
from roboscript.inputs import limits
from roboscript.inputs.source import YamlMap, load_yaml, load_yaml_text, read_source


def refused(text: str) -> str:
    with pytest.raises(InputError) as info:
        load_yaml_text(text, "f.yaml")
    return str(info.value)


def billion_laughs() -> str:
    lines = ['a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for before, name in zip("abcdefgh", "bcdefghi", strict=True):
        lines.append(f"{name}: &{name} [" + ",".join([f"*{before}"] * 9) + "]")
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- aliases


def test_a_billion_laughs_is_refused_at_the_alias_that_crosses_the_budget() -> None:
    # a to e hold 10 + 91 + 820 + 7381 + 66430 values; the first *e in f passes 100000.
    assert refused(billion_laughs()) == (
        "f.yaml:6:8: error: the aliases (*name) here expand to more than 100000 values"
        " (a roboscript file holds at most 100000 values, aliases expanded)"
    )


def test_aliases_within_the_budget_are_read_and_shared() -> None:
    data = load_yaml_text("a: &x [1, 2]\nb: *x\nc: *x\n")
    assert data == {"a": [1, 2], "b": [1, 2], "c": [1, 2]}


def test_the_budget_counts_every_use_of_an_alias() -> None:
    # 1 + 2 + 3 values for the list, then each *x adds 3: the map itself is the first value.
    per_use = 3
    uses = (limits.MAX_VALUES - 1 - 2 - 3) // per_use - 1  # leaves room for the keys
    keys_and_uses = "".join(f"k{i}: *x\n" for i in range(uses // 2))
    load_yaml_text("a: &x [1, 2]\n" + keys_and_uses)  # within the budget
    too_many = "".join(f"k{i}: *x\n" for i in range(uses))
    assert "expand to more than" in refused("a: &x [1, 2]\n" + too_many)


def test_an_alias_inside_what_it_names_is_refused() -> None:
    assert refused("a: &a [1, *a]\n") == (
        "f.yaml:1:11: error: the alias *a is used inside the value it names,"
        " so that value would never end"
    )
    assert refused("a: &m {b: 1, <<: *m}\n").startswith("f.yaml:1:18: error: the alias *m")


def test_a_file_with_too_many_values_even_without_aliases_is_refused() -> None:
    text = "[" + ",".join(["0"] * limits.MAX_VALUES) + "]\n"
    assert refused(text) == (
        f"f.yaml:1:{2 * limits.MAX_VALUES}: error: the file holds more than 100000 values"
        " (a roboscript file holds at most 100000 values)"
    )


# ----------------------------------------------------------------------------- nesting


def test_nesting_deeper_than_the_limit_is_refused_where_it_opens() -> None:
    assert refused("a: " + "[" * 5000 + "]" * 5000 + "\n") == (
        "f.yaml:1:53: error: the values here are nested more than 50 deep"
        " (a roboscript file nests at most 50 levels)"
    )
    block = "".join(" " * i + f"k{i}:\n" for i in range(60))
    assert refused(block).startswith("f.yaml:51:51: error: the values here are nested")


def test_nesting_up_to_the_limit_is_read() -> None:
    depth = limits.MAX_DEPTH - 1  # the top mapping is the first level
    data = load_yaml_text("a: " + "[" * depth + "1" + "]" * depth + "\n")
    for _ in range(depth + 1):  # the key, then each list
        data = data["a"] if isinstance(data, YamlMap) else data[0]
    assert data == 1


# ---------------------------------------------------------------------- numbers, names


def test_a_5000_digit_integer_is_refused_at_its_place() -> None:
    assert refused("a: 1\nb: " + "9" * 5000 + "\n") == (
        "f.yaml:2:4: error: this number has 5000 digits; roboscript reads at most 40"
    )


def test_integers_up_to_the_limit_are_read() -> None:
    assert load_yaml_text("a: " + "9" * 40 + "\n") == {"a": int("9" * 40)}


def test_a_tagged_value_that_does_not_fit_its_tag_is_located() -> None:
    assert refused("a: 1\nb: !!float abc\n") == (
        "f.yaml:2:4: error: cannot read 'abc' as !!float (could not convert string to float: 'abc')"
    )


def test_dates_and_other_yaml_11_types_stay_text() -> None:
    data = load_yaml_text("a: 2024-13-45\nb: 2024-01-05\nc: =\nd: 12:30:00.5x\n")
    assert data == {"a": "2024-13-45", "b": "2024-01-05", "c": "=", "d": "12:30:00.5x"}


@pytest.mark.parametrize("tag", ["timestamp", "set", "binary", "omap", "pairs"])
def test_tags_for_types_no_file_uses_are_refused(tag: str) -> None:
    assert (
        refused(f"a: !!{tag} x\n")
        == f"f.yaml:1:4: error: tag !!{tag} is not allowed in roboscript files"
    )


def test_an_over_long_name_is_refused_at_its_place() -> None:
    name = "s" * 201
    assert refused(f"states:\n  {name}: {{}}\n") == (
        "f.yaml:2:3: error: this name is 201 characters long; names are at most 200"
        " ('ssssssssssssssssssss...')"
    )
    assert refused(f"initial: {name}\n").startswith("f.yaml:1:10: error: this name is 201")
    assert load_yaml_text(f"a: {'s' * 200}\n") == {"a": "s" * 200}
    text = " ".join(["word"] * 100)  # free text (a description) is not a name
    assert load_yaml_text(f"description: {text}\n") == {"description": text}


# --------------------------------------------------------------------------- encodings


def test_invalid_utf8_is_located_at_the_first_bad_byte(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_bytes(b"a: 1\nb: \xc3\xa9\xff\n")
    with pytest.raises(MissionError) as info:
        load_yaml(path, error=MissionError)
    assert (
        str(info.value)
        == f"{path}:2:5: error: byte 0xFF is not UTF-8 text (save the file as UTF-8)"
    )


def test_a_lone_surrogate_is_located(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_bytes(b"a: x\xed\xa0\x80\n")  # U+D800 encoded: not UTF-8
    with pytest.raises(InputError) as info:
        load_yaml(path)
    assert (
        str(info.value)
        == f"{path}:1:5: error: byte 0xED is not UTF-8 text (save the file as UTF-8)"
    )
    assert refused("a: x\ud800\n") == (
        "f.yaml:1:5: error: the file contains a character YAML does not allow (U+D800)"
    )


# ------------------------------------------------------------------------- the file itself


def test_a_file_over_the_size_limit_is_refused_unread(tmp_path: Path) -> None:
    path = tmp_path / "big.yaml"
    with path.open("wb") as file:
        file.truncate(limits.MAX_FILE_BYTES + 1)  # sparse: its size is all that is checked
    with pytest.raises(InputError) as info:
        read_source(path)
    assert str(info.value) == (
        f"{path}: error: the file is 1048577 bytes; roboscript reads files of at most 1 MiB"
        " (1048576 bytes)"
    )


def test_a_file_at_the_size_limit_is_read(tmp_path: Path) -> None:
    path = tmp_path / "full.yaml"
    path.write_text("#" * (limits.MAX_FILE_BYTES - 1) + "\n", encoding="utf-8")
    assert len(read_source(path)) == limits.MAX_FILE_BYTES


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
def test_a_device_is_refused_without_reading_it() -> None:
    with pytest.raises(InputError) as info:
        load_yaml("/dev/zero")
    assert str(info.value) == (
        "/dev/zero: error: this is a character device, not an ordinary file"
        " (give the path of a file)"
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
def test_a_named_pipe_is_refused_without_opening_it(tmp_path: Path) -> None:
    path = tmp_path / "pipe.yaml"
    os.mkfifo(path)  # opening it to read would wait for a writer forever
    with pytest.raises(InputError) as info:
        load_yaml(path)
    assert str(info.value) == (
        f"{path}: error: this is a named pipe, not an ordinary file (give the path of a file)"
    )


@pytest.mark.skipif(not hasattr(socket, "AF_UNIX"), reason="needs unix sockets")
def test_a_socket_and_a_folder_are_refused(tmp_path: Path) -> None:
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(tmp_path / "s.yaml"))
        with pytest.raises(InputError, match="this is a socket, not an ordinary file"):
            load_yaml(tmp_path / "s.yaml")
    with pytest.raises(InputError) as info:
        load_yaml(tmp_path)
    assert (
        str(info.value)
        == f"{tmp_path}: error: this is a folder, not a file (give the path of a file)"
    )


def test_a_mapping_merged_earlier_in_a_merge_list_wins_as_yaml_says() -> None:
    # '<<: [*a, *b]': a key both give is a's (PyYAML's safe_load reads it so too)
    from roboscript.inputs.source import load_yaml_text

    text = "a: &a {x: 1, y: 1}\nb: &b {x: 2, z: 2}\nc: {<<: [*a, *b], y: 3}\n"
    assert dict(load_yaml_text(text)["c"]) == {"x": 1, "y": 3, "z": 2}
