"""The reference documents every action, parameter and condition name that exists."""

from __future__ import annotations

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
    import re

    for target in re.findall(r"\]\(([^)#]+)\)", index):
        assert (ROOT / "docs" / target).exists(), f"docs/index.md links to missing {target}"
