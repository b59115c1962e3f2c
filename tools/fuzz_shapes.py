"""Hostile mission files for the fuzz campaign (``tools/fuzz_campaign.py``).

Every generator takes a :class:`random.Random` and returns the files of one input: a mapping
from a file name (relative to the input's own folder) to its bytes, the first entry being the
mission to check and run. Four kinds:

* ``mutated_yaml``: a mission of ``missions/`` with 1-6 edits of its text (characters and
  YAML tokens inserted, replaced, deleted, lines duplicated, indented with tabs, values
  swapped for hostile ones);
* ``generated_yaml``: a mission built from parts, some of them the shapes issue 17 lists:
  huge numbers (``1e400``, 5000 digits), deep nesting, alias bombs, wrong types, unicode and
  lone surrogates, tabs, missing and unknown states, unknown actions, 5000-character names,
  malformed timestamps, files that are devices or lie outside the mission's folder;
* ``valued_yaml``: a mission of ``missions/`` with its numbers and conditions replaced by
  others that may pass ``check`` (so that they reach ``run``);
* ``condition``: a small mission whose ``when`` holds one generated condition;
* ``python``: a Python mission, generated from parts or a mutated ``missions/*.py``.

Deterministic: the same ``Random`` state gives the same files.
"""

from __future__ import annotations

import random
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SEED_YAML = {p.name: p.read_text(encoding="utf-8") for p in sorted(ROOT.glob("missions/*.yaml"))}
SEED_PY = {p.name: p.read_text(encoding="utf-8") for p in sorted(ROOT.glob("missions/*.py"))}

Files = dict[str, bytes]

HOSTILE_NUMBERS = [
    "1e400",
    "-1e400",
    "1e-400",
    "nan",
    ".nan",
    ".inf",
    "-.inf",
    "inf Hz",
    "9" * 5000,
    "-" + "9" * 400,
    "0x" + "f" * 300,
    "1_000_000_000_000_000_000_000",
    "-9.2e18",
    "-1e9",
    "1e9",
    "0",
    "-0",
    "0.0000001",
    "2001-13-45",
    "2001-12-14t21:59:43.10-05:00",
    "12:30:00",
    "0o777",
    "1e400 cm",
    "10 parsecs",
    "-5 cm",
    "5 cm/s/s",
    "3 s s",
    "",
    "~",
    "null",
    "yes",
    "[1, 2]",
    "{a: 1}",
    "'10 cm'",
    "é cm",
]
"""Values put where a mission expects a number with a unit."""

UNITS = {
    "distance": ["cm", "mm", "m", ""],
    "speed": ["cm/s", "mm/s"],
    "angle": ["deg", ""],
    "turn_rate": ["deg/s"],
    "frequency": ["Hz", "kHz"],
    "duration": ["s", "ms"],
    "steps": [""],
    "times": [""],
    "index": [""],
}

ACTIONS: dict[str, list[str]] = {
    "drive": ["distance", "speed", "duration"],
    "rotate": ["angle", "turn_rate"],
    "play_tone": ["frequency", "duration"],
    "wait": ["duration"],
    "follow_wall": ["side", "distance", "speed", "until", "duration"],
    "follow_line": ["speed", "edge", "until", "duration"],
    "wait_until": ["condition", "timeout"],
    "display": ["text"],
    "set_led": ["index", "color"],
    "servo": ["index", "angle", "duration"],
    "walk": ["steps"],
    "turn": ["steps"],
    "stop": [],
}

WEIRD_NAMES = [
    "x" * 5000,
    "état",
    "\\ud800",
    "\\U0001F916",
    "a b",
    "a.b",
    "__class__",
    "1",
    "true",
    "null",
    "on",
    "-",
    "\\t",
    "'quoted'",
]
"""State, action and parameter names nobody should write (YAML double-quoted escapes)."""

FILE_REFERENCES = [
    "/dev/urandom",
    "/dev/zero",
    "/dev/null",
    "/etc/passwd",
    "../../../etc/passwd",
    "/usr/lib/python3/dist-packages/this.py",
    "/proc/self/status",
    ".",
    "..",
    "missing.yaml",
    "side.yaml",
    "side.py",
    "fifo",
    "x" * 5000,
]
"""Things a mission may name as its robot, world, behaviours or an inner mission."""

CONDITION_NAMES = [
    "range.distance_cm",
    "range.distance_mm",
    "side_range.distance_cm",
    "bumper.any",
    "bumper.left",
    "line.center",
    "line.any",
    "heading_deg",
    "elapsed",
    "state_time",
    "visits.a",
    "visits.b",
    "visits.nowhere",
    "colour.red",
    "range",
    "range.__class__",
    "joints.x",
]

CONDITION_LEAVES = [
    *CONDITION_NAMES,
    "20",
    "0",
    "1.5",
    "-3",
    "20 cm",
    "3 s",
    "90 deg",
    "1e400",
    "10**400",
    "1" + "0" * 400,
    "1" + "0" * 5000,
    "true",
    "false",
    "nan",
    "inf",
    "'x'",
    "\\ud800",
    "é",
    "0x10",
    "1_0",
]

BINARY = ["<", "<=", ">", ">=", "==", "!=", "and", "or", "+", "-", "*", "/", "**", "%", "//"]


def _number(rng: random.Random, kind: str) -> str:
    if rng.random() < 0.35:
        return rng.choice(HOSTILE_NUMBERS)
    unit = rng.choice(UNITS.get(kind, [""]))
    magnitude = rng.choice([0, 1, 5, 20, 90, 150, 440, 1000, 20000, 1e6])
    value = rng.choice([magnitude, -magnitude, rng.uniform(-2 * magnitude, 2 * magnitude)])
    text = f"{value:g}" if isinstance(value, float) else str(value)
    return f"{text} {unit}".strip()


def _quote(text: str) -> str:
    """``text`` as a YAML double-quoted scalar (backslash escapes in ``text`` kept as such)."""
    return '"' + text.replace('"', '\\"') + '"'


def condition(rng: random.Random, depth: int = 0) -> str:
    """A condition: mostly well formed, sometimes hostile (deep, huge, unknown names)."""
    roll = rng.random()
    if depth == 0 and roll < 0.04:
        n = rng.choice([50, 200, 1000, 5000])
        return "(" * n + "elapsed" + ")" * n + " > 1"
    if depth == 0 and roll < 0.08:
        n = rng.choice([100, 1000, 3000])
        return " and ".join(["elapsed > 1"] * n)
    if depth == 0 and roll < 0.11:
        return "not " * rng.choice([100, 1000, 5000]) + "bumper.any"
    if depth == 0 and roll < 0.13:
        return "-" * rng.choice([100, 2000]) + "1 < elapsed"
    if depth > 3 or rng.random() < 0.3:
        return rng.choice(CONDITION_LEAVES)
    shape = rng.random()
    if shape < 0.15:
        return f"not {condition(rng, depth + 1)}"
    if shape < 0.25:
        return f"({condition(rng, depth + 1)})"
    if shape < 0.3:
        parts = [condition(rng, depth + 1) for _ in range(3)]
        return " < ".join(parts)
    return f"{condition(rng, depth + 1)} {rng.choice(BINARY)} {condition(rng, depth + 1)}"


def tame_condition(rng: random.Random, depth: int = 0) -> str:
    """A condition that may well compile: known names, numbers in range, shallow."""
    if depth > 2 or rng.random() < 0.4:
        name = rng.choice(CONDITION_NAMES[:11])
        return f"{name} {rng.choice(BINARY[:6])} {rng.choice(['0', '1', '20', '-90', '0.5'])}"
    joiner = rng.choice([" and ", " or "])
    left, right = tame_condition(rng, depth + 1), tame_condition(rng, depth + 1)
    return f"{'not ' if rng.random() < 0.2 else ''}({left}{joiner}{right})"


def _action(rng: random.Random, states: list[str], depth: int = 0) -> str:
    """An action as YAML flow text."""
    roll = rng.random()
    if roll < 0.05:
        return rng.choice(["nothing", "fly", "drive_fast", "'drive'", "[drive]", "42", "{}"])
    if roll < 0.1 and depth < 3:
        children = ", ".join(_action(rng, states, depth + 1) for _ in range(rng.randint(0, 3)))
        return f"{{parallel: {{{rng.choice(['all', 'any', 'some'])}: [{children}]}}}}"
    if roll < 0.14 and depth < 3:
        return (
            f"{{repeat: {{times: {_number(rng, 'times')}, do: {_action(rng, states, depth + 1)}}}}}"
        )
    if roll < 0.17:
        return f"{{mission: {_quote(rng.choice(FILE_REFERENCES))}}}"
    if roll < 0.2 and depth < 2:
        return (
            "{initial: a, states: {a: {do: {wait: {duration: 0.1 s}}, on: {done: b}},"
            " b: {final: success}}}"
        )
    name = rng.choice(list(ACTIONS))
    params = []
    for param in ACTIONS[name]:
        if rng.random() < 0.6:
            if param in ("until", "condition"):
                value = _quote(condition(rng))
            elif param == "side":
                value = rng.choice(["left", "right", "up", "1"])
            elif param == "edge":
                value = rng.choice(["center", "left", "middle"])
            elif param == "text":
                value = _quote(rng.choice(["hi", "x" * 5000, "\\ud800", "\\x00", "é"]))
            elif param == "color":
                value = rng.choice(
                    ["red", "'#ff0000'", "'#zzzzzz'", "[300, -1, 2]", "[1]", "mauve"]
                )
            else:
                value = _number(rng, param)
            params.append(f"{param}: {value}")
    if rng.random() < 0.08:
        params.append(f"{rng.choice(['distanse', 'speeed', 'x', 'frequency'])}: 1")
    if not params and rng.random() < 0.5:
        return name
    return f"{{{name}: {{{', '.join(params)}}}}}"


def _target(rng: random.Random, states: list[str]) -> str:
    if rng.random() < 0.08:
        return rng.choice(["nowhere", "'A'", "[a]", "null", _quote(rng.choice(WEIRD_NAMES))])
    return rng.choice(states)


def generated_yaml(rng: random.Random) -> Files:
    """A mission built from parts, with hostile shapes mixed in."""
    special = rng.random()
    if special < 0.03:  # an alias bomb ("billion laughs")
        lines = ['a: &a ["x", "x", "x", "x", "x", "x", "x", "x", "x"]']
        for i in range(1, rng.choice([6, 9, 12])):
            lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}" if i > 1 else "*a"] * 9) + "]")
        lines.append("states: {s: {final: success}}")
        return {"mission.yaml": "\n".join(lines).encode()}
    if special < 0.06:  # deep nesting
        n = rng.choice([100, 1000, 10000, 50000])
        body = rng.choice(["[" * n + "]" * n, "{a: " * n + "1" + "}" * n, "- " * n + "x"])
        return {"mission.yaml": f"states:\n  s: {{final: success}}\nx: {body}\n".encode()}
    if special < 0.07:  # a big file
        size = rng.choice([1, 5, 20]) * 1024 * 1024
        return {"mission.yaml": b"states:\n  s: {final: success}\n#" + b"x" * size + b"\n"}
    if special < 0.08:  # not text
        return {"mission.yaml": bytes(rng.randrange(256) for _ in range(rng.choice([10, 1000])))}

    count = rng.randint(1, 6)
    names = [f"s{i}" for i in range(count)]
    if rng.random() < 0.1:
        names[rng.randrange(count)] = _quote(rng.choice(WEIRD_NAMES))
    lines: list[str] = []
    files: Files = {}
    if rng.random() < 0.6:
        name = rng.choice(["gen", "x" * 5000, "é", "\\ud800"])
        lines.append(f"mission: {_quote(name)}")
    if rng.random() < 0.25:
        robot = rng.choice(
            [
                "mirto",
                "spike-prime",
                "plen2",
                "stackmod-rover",
                "mirt",
                "side.yaml",
                *FILE_REFERENCES,
            ]
        )
        lines.append(f"robot: {_quote(robot)}")
        if robot == "side.yaml":
            files["side.yaml"] = rng.choice(
                [b"extends: mirto\n", b"extends: mirto\ntrack_mm: 1e400\n", b"extends: [1]\n"]
            )
    if rng.random() < 0.2:
        world = rng.choice(["square-room", "sqare-room", "maze", "side.yaml", *FILE_REFERENCES])
        lines.append(f"world: {_quote(world)}")
        if world == "side.yaml":
            files["side.yaml"] = rng.choice(
                [b"walls:\n  - box: {x: 0, y: 0, w: 1e400, h: 1}\n", b"walls: 5\n"]
            )
    if rng.random() < 0.1:
        lines.append(f"behaviours: [{_quote(rng.choice(FILE_REFERENCES))}]")
    if rng.random() < 0.7:
        lines.append(f"initial: {_target(rng, names)}")
    if rng.random() < 0.04:
        lines.append("states: " + rng.choice(["5", "[]", "~", "'states'", "{}"]))
        return {"mission.yaml": "\n".join(lines).encode(), **files}
    lines.append("states:")
    for name in names:
        lines.append(f"  {name}:")
        if rng.random() < 0.2:
            lines.append(f"    final: {rng.choice(['success', 'failure', 'maybe', 'true'])}")
        if rng.random() < 0.85:
            lines.append(f"    do: {_action(rng, names)}")
        if rng.random() < 0.3:
            lines.append(f"    timeout: {_number(rng, 'duration')}")
        if rng.random() < 0.3:
            lines.append(f"    during: [{_action(rng, names)}]")
        if rng.random() < 0.7:
            outcome = rng.choice(["done", "failed", "timeout", "finished"])
            if rng.random() < 0.5:
                lines.append(f"    on: {{{outcome}: {_target(rng, names)}}}")
            else:
                lines.append(
                    f"    on: {{{outcome}: [{{if: {_quote(condition(rng))}, "
                    f"goto: {_target(rng, names)}}}, {{goto: {_target(rng, names)}}}]}}"
                )
        if rng.random() < 0.4:
            lines.append(
                f"    when: [{{if: {_quote(condition(rng))}, goto: {_target(rng, names)}}}]"
            )
    if rng.random() < 0.5 or not any("final" in line for line in lines):
        lines.append("  end: {final: success}")
    text = "\n".join(lines) + "\n"
    if rng.random() < 0.1:
        text = text.replace("  ", "\t", rng.randint(1, 3))
    if rng.random() < 0.05:  # an anchor reused where another state is expected
        text = text.replace("  s0:", "  s0: &s", 1) + "  copy: *s\n"
    return {"mission.yaml": text.encode("utf-8"), **files}


def condition_mission(rng: random.Random) -> Files:
    """A small mission whose ``when`` holds one generated condition."""
    text = (
        "states:\n"
        "  a:\n"
        "    do: {drive: {distance: 30 cm}}\n"
        f"    when: [{{if: {_quote(condition(rng))}, goto: b}}]\n"
        "    on: {done: b}\n"
        "  b: {final: success}\n"
    )
    return {"mission.yaml": text.encode("utf-8")}


TOKENS_YAML = [
    ":",
    "{",
    "}",
    "[",
    "]",
    "-",
    " ",
    "\n",
    "\t",
    "'",
    '"',
    "&a",
    "*a",
    "!!python/object:os.system",
    "!!binary",
    "!!timestamp 2001-13-45",
    "? ",
    "|",
    ">",
    "%YAML 1.1\n",
    "---\n",
    "...\n",
    "\x00",
    "\ufeff",
    "é",
    "\u202e",
    "states",
    "do",
    "on",
    "when",
    "final",
    "goto",
    "if",
    "initial",
    "<<: *a",
]


def _mutate_text(rng: random.Random, text: str, tokens: list[str]) -> str:
    for _ in range(rng.randint(1, 6)):
        position = rng.randint(0, len(text))
        kind = rng.random()
        if kind < 0.25:
            text = text[:position] + rng.choice(tokens) + text[position + 1 :]
        elif kind < 0.45:
            text = text[:position] + rng.choice(tokens) + text[position:]
        elif kind < 0.6:
            text = text[:position] + text[position + rng.randint(1, 12) :]
        elif kind < 0.7:
            lines = text.splitlines(keepends=True)
            if lines:
                index = rng.randrange(len(lines))
                lines.insert(index, lines[index] * rng.choice([1, 2, 50]))
                text = "".join(lines)
        elif kind < 0.8:  # a number swapped for a hostile one
            digits = [i for i, c in enumerate(text) if c.isdigit()]
            if digits:
                at = rng.choice(digits)
                end = at
                while end < len(text) and (text[end].isdigit() or text[end] == "."):
                    end += 1
                text = text[:at] + rng.choice(HOSTILE_NUMBERS) + text[end:]
        elif kind < 0.87:  # a line indented with a tab
            lines = text.splitlines(keepends=True)
            if lines:
                index = rng.randrange(len(lines))
                lines[index] = "\t" + lines[index].lstrip(" ")
                text = "".join(lines)
        elif kind < 0.94:  # a state name or reference broken
            text = text.replace(
                rng.choice(["side", "corner", "beep", "forward", "turn", "a"]),
                rng.choice(["x" * 5000, "sidé", "", "side side"]),
                1,
            )
        else:  # swapped lines
            lines = text.splitlines(keepends=True)
            if len(lines) > 1:
                i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
                lines[i], lines[j] = lines[j], lines[i]
                text = "".join(lines)
    return text


PLAUSIBLE = {
    "cm": ["0.1", "1", "30", "50", "300", "5000", "-40", "0"],
    "mm": ["1", "200", "-100", "100000", "0.5"],
    "cm/s": ["1", "15", "50", "100", "500", "0.01"],
    "mm/s": ["1", "150", "1000", "100000"],
    "deg": ["0", "1", "90", "-90", "720", "-3600", "0.1", "359.9"],
    "deg/s": ["1", "60", "1000", "0.5"],
    "Hz": ["20", "440", "19999", "20000", "880", "0.5", "25000"],
    "ms": ["1", "200", "0", "5000"],
    "s": ["0", "0.01", "1", "10", "25", "1e6"],
}
_VALUE = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?\s*(cm/s|mm/s|deg/s|cm|mm|deg|Hz|ms|s)\b")
_CONDITION = re.compile(r'if: "([^"]*)"')


def valued_yaml(rng: random.Random) -> Files:
    """A mission of ``missions/`` whose numbers and conditions are replaced with others that
    may well pass ``check``: extreme but plausible values, generated conditions."""
    name = rng.choice(sorted(SEED_YAML))

    def value(match: re.Match[str]) -> str:
        unit = match.group(1)
        if rng.random() < 0.7:
            return match.group(0)
        return f"{rng.choice(PLAUSIBLE[unit])} {unit}"

    def guard(match: re.Match[str]) -> str:
        if rng.random() < 0.5:
            return match.group(0)
        return f"if: {_quote(tame_condition(rng))}"

    text = _CONDITION.sub(guard, _VALUE.sub(value, SEED_YAML[name]))
    text = re.sub(r"steps: -?\d+", lambda m: f"steps: {rng.choice(PLAUSIBLE_STEPS)}", text)
    return {"mission.yaml": text.encode("utf-8")}


PLAUSIBLE_STEPS = ["1", "-1", "4", "100", "-1000", "0", "10000"]


def mutated_yaml(rng: random.Random) -> Files:
    """A mission of ``missions/`` with a few edits."""
    name = rng.choice(sorted(SEED_YAML))
    text = _mutate_text(rng, SEED_YAML[name], TOKENS_YAML)
    return {"mission.yaml": text.encode("utf-8", "surrogatepass")}


PY_ACTIONS = [
    "Drive(distance_mm={n})",
    "Drive(distance_mm={n}, speed_mm_s={n})",
    "Rotate(angle_deg={n})",
    "Rotate(angle_deg={n}, turn_rate_deg_s={n})",
    "PlayTone(frequency_hz={n}, duration_s={n})",
    "Wait(duration_s={n})",
    "Walk(steps={n})",
    "Nothing()",
    "Drive()",
    "Drive(distance_mm='ten')",
    "Drive(distance_mm=[1])",
    "Wait({n})",
]
PY_NUMBERS = [
    "1",
    "0",
    "-1",
    "500",
    "0.2",
    "10**400",
    "1e400",
    "float('nan')",
    "float('inf')",
    "-1e9",
    "-9.2e18",
    "True",
    "None",
    "'5 cm'",
    "2**64",
]
PY_CONDITIONS = [
    "self.visits('a') >= {n}",
    "self.range.distance_cm < {n}",
    "self.bumper.any",
    "self.elapsed > {n}",
    "self.heading_deg > {n}",
    "1 / 0",
    "self.nothing",
    "'yes'",
    "[1] * 10**9",
    "self.range.distance_cm < 10**400",
    "(" * 200 + "True" + ")" * 200,
    "not " * 500 + "True",
]


def generated_python(rng: random.Random) -> Files:
    """A Python mission built from parts (or one of ``missions/*.py`` mutated)."""
    if rng.random() < 0.4:
        name = rng.choice(sorted(SEED_PY))
        text = _mutate_text(rng, SEED_PY[name], [*TOKENS_YAML, "(", ")", ",", "=", "self.", "#"])
        return {"mission.py": text.encode("utf-8", "surrogatepass")}

    def number() -> str:
        return rng.choice(PY_NUMBERS)

    count = rng.randint(1, 4)
    names = [f"s{i}" for i in range(count)]
    lines = [
        "from roboscript import Drive, Mission, PlayTone, Rotate, Wait, Walk, state",
        "",
        "",
        "class Gen(Mission):",
        '    """Generated."""',
        "",
    ]
    for i, name in enumerate(names):
        action = rng.choice(PY_ACTIONS).format(n=number())
        args = [action]
        if i == 0 and rng.random() < 0.8:
            args.append("initial=True")
        if rng.random() < 0.7:
            args.append(f"on_done={rng.choice([*names, 'end', 'nowhere'])!r}")
        if rng.random() < 0.4:
            args.append(f"when=[('cond', {rng.choice([*names, 'end'])!r})]")
        if rng.random() < 0.2:
            args.append(f"timeout_s={number()}")
        lines.append(f"    {name} = state({', '.join(args)})")
    lines.append("    end = state(final='success')")
    lines.append("")
    lines.append("    def cond(self) -> bool:")
    lines.append(f"        return {rng.choice(PY_CONDITIONS).format(n=number())}")
    return {"mission.py": ("\n".join(lines) + "\n").encode("utf-8")}


KINDS = {
    "mutated_yaml": (0.3, mutated_yaml),
    "valued_yaml": (0.25, valued_yaml),
    "generated_yaml": (0.2, generated_yaml),
    "condition": (0.15, condition_mission),
    "python": (0.1, generated_python),
}


def make_input(rng: random.Random) -> tuple[str, Files]:
    """One input: its kind and its files."""
    roll = rng.random()
    for kind, (share, make) in KINDS.items():
        if roll < share:
            return kind, make(rng)
        roll -= share
    return "python", generated_python(rng)
