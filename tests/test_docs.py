"""The reference documents every action, parameter, condition name and command-line option that
exists."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest
from helpers import ROOT

from roboscript.actions import ACTIONS
from roboscript.mission.guards import guard_names

REFERENCE = (ROOT / "docs" / "reference" / "missions.md").read_text(encoding="utf-8")


def test_every_action_and_parameter_is_documented() -> None:
    for name, cls in ACTIONS.items():
        assert f"### `{name}`" in REFERENCE, f"docs/reference/missions.md lacks action {name}"
        for param in cls.params:
            assert f"| `{param.name}` |" in REFERENCE, f"{name}.{param.name} is undocumented"


def test_every_condition_name_is_documented() -> None:
    for name in guard_names():
        if name == "visits.STATE":
            assert "`visits.STATE`" in REFERENCE
        else:
            assert f"`{name}`" in REFERENCE, f"condition name {name} is undocumented"


def test_docs_index_links_exist() -> None:
    index = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)#]+)\)", index):
        assert (ROOT / "docs" / target).exists(), f"docs/index.md links to missing {target}"


def _anchors(page: Path) -> set[str]:
    """The anchors GitHub makes of a page's headings: lower case, spaces as hyphens, other
    punctuation dropped."""
    found = set()
    for heading in re.findall(r"^#+ (.*)$", page.read_text(encoding="utf-8"), re.MULTILINE):
        found.add(re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-"))
    return found


def test_every_link_between_the_pages_leads_to_a_page_and_heading_that_exist() -> None:
    pages = [ROOT / "README.md", *(ROOT / "docs").rglob("*.md"), *(ROOT / "drivers").rglob("*.md")]
    for page in sorted(pages):
        text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.DOTALL)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if target.startswith(("http://", "https://", "mailto:")):
                continue
            path, _, anchor = target.partition("#")
            linked = (page.parent / path).resolve() if path else page
            assert linked.exists(), f"{page.relative_to(ROOT)} links to missing {target}"
            if anchor and linked.suffix == ".md":
                assert anchor in _anchors(linked), f"{page.relative_to(ROOT)}: no heading {target}"


def _synopsis(page: Path) -> dict[str, set[str]]:
    """The options each command's lines of ``page``'s usage block name, by command."""
    block = page.read_text(encoding="utf-8").split("```\nroboscript ", 1)[1].split("```", 1)[0]
    commands: dict[str, set[str]] = {}
    command = ""
    for line in f"roboscript {block}".splitlines():
        words = line.split()
        if words[:1] == ["roboscript"]:  # a command's first line; the next ones go on with it
            command = "web build" if words[1:3] == ["web", "build"] else words[1]
        named = re.findall(r"(?<![\w-])(--?[a-z][\w-]*)", line)
        commands.setdefault(command, set()).update(named)
    return commands


def _options(parser: argparse.ArgumentParser) -> list[set[str]]:
    """The options ``parser`` takes, as its ``--help`` lists them: each with its spellings
    (``-o`` and ``--output``)."""
    return [
        set(action.option_strings)
        for action in parser._actions
        if action.help != argparse.SUPPRESS
        and action.option_strings
        and "--help" not in action.option_strings
    ]


def _commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """``parser``'s commands by name."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


@pytest.mark.parametrize("page", ["README.md", "docs/reference/cli.md"])
def test_the_usage_block_names_every_command_and_option_the_command_line_takes(
    page: str,
) -> None:
    from roboscript.cli import _parser

    commands = _commands(_parser())
    taken = {name: _options(command) for name, command in commands.items() if name != "web"}
    taken["web build"] = _options(_commands(commands["web"])["build"])
    written = _synopsis(ROOT / page)
    assert sorted(written) == sorted(taken)
    for command, options in taken.items():
        # each option under one of its spellings, and nothing the command does not take
        assert [sorted(o) for o in options if not o & written[command]] == [], command
        assert written[command] <= set().union(*options), command
