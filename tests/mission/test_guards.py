"""The guard language: what it accepts, what it refuses, and that nothing executes."""

from __future__ import annotations

import pytest

from roboscript.mission.guards import GuardEnv, GuardError, compile_guard


class Env(GuardEnv):
    def __init__(self, **values: float | bool) -> None:
        self.values = values

    def sensor(self, root: str, attr: str | None) -> float | bool:
        return self.values[f"{root}.{attr}" if attr else root]

    def visits(self, state: str) -> int:
        return int(self.values.get(f"visits.{state}", 0))


@pytest.mark.parametrize(
    ("source", "values", "expected"),
    [
        ("range.distance_cm < 20", {"range.distance_cm": 15.0}, True),
        ("range.distance_cm < 20", {"range.distance_cm": float("inf")}, False),
        ("range.distance_cm < 200 mm", {"range.distance_cm": 15.0}, True),
        ("range.distance_mm < 20 cm", {"range.distance_mm": 250.0}, False),
        ("bumper.left or bumper.right", {"bumper.left": False, "bumper.right": True}, True),
        ("not bumper.any", {"bumper.any": False}, True),
        ("visits.side >= 4", {"visits.side": 4}, True),
        ("elapsed > 1.5 s and state_time < 500 ms", {"elapsed": 2.0, "state_time": 0.4}, True),
        ("heading_deg > 80 deg", {"heading_deg": 85.0}, True),
        ("10 < line.center <= 600", {"line.center": 600.0}, True),
        ("line.center - line.left > 100", {"line.center": 700.0, "line.left": 500.0}, True),
        ("true", {}, True),
    ],
)
def test_guards_evaluate(source: str, values: dict[str, float | bool], expected: bool) -> None:
    assert compile_guard(source, frozenset({"side"}))(Env(**values)) is expected


@pytest.mark.parametrize(
    "source",
    [
        "__import__('os').system('touch /tmp/roboscript-guard')",
        "range.__class__",
        "range.distance_cm.__class__ < 1",
        "[x for x in ()]",
        "lambda: 1",
        "range['distance_cm']",
        "open('/etc/passwd')",
        "'text' == 'text'",
        "(1).__class__",
        "bumper",
        "",
        "range.distance_cm <",
    ],
)
def test_anything_outside_the_language_is_refused(source: str) -> None:
    with pytest.raises(GuardError):
        compile_guard(source)


def test_guard_reports_the_capabilities_it_reads() -> None:
    guard = compile_guard("range.distance_cm < 20 and not bumper.any and elapsed > 1")
    assert guard.capabilities == {"range", "bumper"}
