"""The reference documents every action, parameter and condition name that exists."""

from __future__ import annotations

import re
from pathlib import Path

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
