"""A second classroom's mistakes, each in a file of its own, as ``roboscript check`` answers them.

What 12 to 16 year olds write when a mission is new to them: a state indented one space too
far, a way round the states that never ends, a state's name misspelt, a speed written as a
word, an angle in radians, ``=`` for ``==``, a last state with no ``final``, actions named as
other robots' libraries name them (``move_forward``, ``turn`` by an angle, ``rotate`` by
``degrees``, ``wait`` for a ``time``), a prompt copied with the code, a file saved empty or with
another ending (``.txt``, ``.PY``), a class without its ``(Mission)``, ``Result.DONE`` in
capitals, half a comparison after ``and``, a condition made of fixed values only (``True``,
``1 < 2``, ``if 5:``) and a ``time.sleep`` in a helper function that code run every tick
calls. Each gets one sentence at ``file:line:col`` in the student's terms, or nothing when it
means what it says (a last ``true`` choice as an otherwise, a file saved as ``.yml``). All
files are checked by one ``roboscript check`` run, as a class's folder is.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers import checked_by_file, run_cli

Y = """\
mission: m
states:
  go:
    do: {drive: {distance: 50 cm}}
    on: {done: end, failed: end}
  end: {final: success}
"""
YW = """\
mission: m
states:
  go:
    do: {drive: {distance: 50 cm}}
    on: {done: end, failed: end}
    when:
      - {if: IF, goto: end}
  end: {final: success}
"""
P = """\
from roboscript import Drive, Mission, Rotate, Turn, Wait, state


class M(Mission):
    go = state(ACTION, initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""
PC = """\
from roboscript import Drive, Mission, Rotate, state


class M(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end",
               when=[("near", "end")])
    end = state(final="success")

    def near(self):
        BODY
"""
SLEEPY = """\
import time

from roboscript import Action, Mission, Result, state


def nap(seconds):
    time.sleep(seconds)


class Pause(Action):
    name = "pause"
    requires = frozenset({"drive_base"})

    def update(self, ctx):
        nap(1)
        return Result.done()


class M(Mission):
    go = state(Pause(), initial=True, timeout_s=5, on_done="end", on_failed="end",
               on_timeout="end")
    end = state(final="success")
"""
SLEEPY_CONDITION = """\
import time

from roboscript import Drive, Mission, state


def look_around():
    time.sleep(0.5)


class M(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end",
               when=[("near", "end")])
    end = state(final="success")

    def near(self):
        look_around()
        return self.bumper.any
"""


def yw(cond: str) -> str:
    """A mission whose state 'go' moves on when ``cond`` holds."""
    return YW.replace("IF", cond)


def p(action: str) -> str:
    """A Python mission whose state 'go' runs ``action``."""
    return P.replace("ACTION", action)


def pc(body: str) -> str:
    """A Python mission whose condition 'near' is ``body``."""
    return PC.replace("BODY", body)


G = p("Drive(distance_mm=500)")
PA = """\
from roboscript import Action, Mission, Result, state


class Pause(Action):
    name = "pause"
    requires = frozenset({"drive_base"})

    def update(self, ctx):
        BODY


class M(Mission):
    go = state(Pause(), initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""

MISTAKES: dict[str, tuple[str | bytes, list[str]]] = {
    "indent_end_state.yaml": (
        Y.replace("  end:", "   end:"),
        [
            (
                "6:4: error: this line is indented differently from the lines above it (YAML "
                "nests by indentation: line it up, with spaces, with the key or '- ' item it "
                "belongs with)"
            )
        ],
    ),
    "goes_round_for_ever.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n"
            "    on: {done: turn, failed: turn}\n"
            "  turn:\n    do: {rotate: {angle: 90 deg}}\n    on: {done: go, failed: go}\n"
        ),
        [
            (
                "3:3: error: mission 'm' can never finish: no final state can be reached from "
                "'go' (add a state with 'final: success' and a transition to it, e.g. on: "
                "{done: finished})"
            )
        ],
    ),
    "misspelt_target.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n"
            "    on: {done: trun, failed: end}\n"
            "  turn:\n    do: {rotate: {angle: 90 deg}}\n    on: {done: end, failed: end}\n"
            "  end: {final: success}\n"
        ),
        ["5:16: error: there is no state 'trun' (did you mean 'turn'?)"],
    ),
    "speed_fast.yaml": (
        Y.replace("50 cm}", "50 cm, speed: fast}"),
        ["4:42: error: drive speed: expected a speed such as '15 cm/s', got 'fast'"],
    ),
    "angle_in_radians.yaml": (
        Y.replace("drive: {distance: 50 cm}", "rotate: {angle: 1.57}"),
        [
            (
                "4:26: warning: rotate angle: 1.57 taken as 1.57 deg; write `1.57 deg` (or did "
                "you mean 1.57 rad?)"
            )
        ],
    ),
    "equals_in_condition.yaml": (
        yw('"range.distance_cm = 20"'),
        [
            (
                "7:33: error: cannot read the condition 'range.distance_cm = 20': '=' sets a "
                "value; a condition compares (write '==' to compare: range.distance_cm == 20)"
            )
        ],
    ),
    "end_without_final.yaml": (
        Y.replace("  end: {final: success}", "  end: {}"),
        [
            (
                "6:3: error: state 'end' has no way out (add 'on: {done: NEXT}', a 'when' "
                "condition, or 'final: success')"
            )
        ],
    ),
    "move_forward.yaml": (
        Y.replace("drive:", "move_forward:"),
        ["4:10: error: unknown action 'move_forward' (the action for that is 'drive')"],
    ),
    "walk_on_wheels.yaml": (
        Y.replace("drive: {distance: 50 cm}", "walk: {steps: 4}"),
        [
            (
                "4:10: error: 'walk' needs walker (legs that walk by gait motions), which mirto "
                "does not have (use drive/rotate on a wheeled robot)"
            )
        ],
    ),
    "turn_by_angle.yaml": (
        Y.replace("drive: {distance: 50 cm}", "turn: {angle: 90 deg}"),
        [
            (
                "4:17: error: 'turn' has no parameter 'angle' (turn is a walking robot's turn, "
                "by steps; a robot on wheels turns by an angle with rotate)"
            )
        ],
    ),
    "rotate_degrees.yaml": (
        Y.replace("drive: {distance: 50 cm}", "rotate: {degrees: 90}"),
        [
            (
                "4:19: error: 'rotate' has no parameter 'degrees' (how far a rotate turns is "
                "its angle, with its unit: angle: 90 deg, or angle_deg=90 in Python)"
            )
        ],
    ),
    "wait_time.yaml": (
        Y.replace("drive: {distance: 50 cm}", "wait: {time: 2 s}"),
        [
            (
                "4:17: error: 'wait' has no parameter 'time' (how long a wait lasts is its "
                "duration, with its unit: duration: 2 s, or duration_s=2 in Python)"
            )
        ],
    ),
    "wait_seconds_word.yaml": (
        Y.replace("drive: {distance: 50 cm}", "wait: {duration: 2 seconds}"),
        ["4:27: error: wait duration: unknown unit 'seconds' for a time (write 2 s)"],
    ),
    "prompt_copied.yaml": (
        "$ " + Y,
        ["1:1: error: unknown key '$ mission' in a mission (did you mean 'mission'?)"],
    ),
    "bom_and_windows_ends.yaml": (
        ("\ufeff" + Y).replace("\n", "\r\n").encode("utf-8"),
        [],
    ),
    "empty.yaml": (
        "",
        [
            (
                "1:1: error: a mission file is a mapping with 'mission:', 'initial:' and "
                "'states:' (this file is empty, or holds only comments: is it saved?)"
            )
        ],
    ),
    "saved_as.yml": (
        Y,
        [],
    ),
    "saved_upper.YAML": (
        Y,
        [],
    ),
    "saved_as.txt": (
        Y,
        [
            (
                " error: a mission file ends in .yaml or .py (got '.txt') (save it as "
                "saved_as.yaml, or saved_as.py for a Python mission: the ending tells "
                "roboscript how to read it)"
            )
        ],
    ),
    "condition_true.yaml": (
        yw('"True"'),
        [
            (
                "7:9: warning: the condition 'True' is made only of fixed values, so it never "
                "changes: it always holds, so state 'go' goes to 'end' at its first tick "
                "(compare a sensor's value, e.g. range.distance_cm < 20)"
            )
        ],
    ),
    "condition_one_less_than_two.yaml": (
        yw('"1 < 2"'),
        [
            (
                "7:9: warning: the condition '1 < 2' is made only of fixed values, so it never "
                "changes: it always holds, so state 'go' goes to 'end' at its first tick "
                "(compare a sensor's value, e.g. range.distance_cm < 20)"
            )
        ],
    ),
    "condition_false.yaml": (
        yw("false"),
        [
            (
                "7:9: warning: the condition 'false' is made only of fixed values, so it never "
                "changes: it never holds, so state 'go' never goes to 'end' this way (compare a "
                "sensor's value, e.g. range.distance_cm < 20)"
            )
        ],
    ),
    "otherwise_true.yaml": (
        YW.replace(
            "      - {if: IF, goto: end}",
            "      - {if: bumper.any, goto: end}\n      - {if: true, goto: end}",
        ),
        [],
    ),
    "final_sucess.yaml": (
        Y.replace("final: success", "final: sucess"),
        [
            (
                "6:16: error: state 'end': final is 'success' or 'failure', got 'sucess' (did "
                "you mean 'success'?)"
            )
        ],
    ),
    "do_as_text.yaml": (
        Y.replace("do: {drive: {distance: 50 cm}}", "do: drive 50 cm"),
        [
            (
                "4:9: error: 'do: drive 50 cm' gives 'drive' its settings as plain text (write "
                "them as a mapping: do: {drive: {distance: 50 cm}})"
            )
        ],
    ),
    "state_twice.yaml": (
        Y.replace(
            "  end:", "  go:\n    do: {rotate: {angle: 90 deg}}\n    on: {done: end}\n  end:"
        ),
        [
            (
                "6:3: error: 'go' is given twice (first on line 3) (keep one of the two, or "
                "give one of them another name)"
            )
        ],
    ),
    "empty.py": (
        "",
        [
            (
                "1:1: error: this file holds no mission (write a class that extends Mission: "
                "class MyMission(Mission): ...)"
            )
        ],
    ),
    "condition_without_self.py": (
        pc("return self.bumper.any").replace("def near(self)", "def near()"),
        ["9:5: error: condition method 'near' must take only self (def near(self):)"],
    ),
    "sensor_compared_with_number.py": (
        pc("return self.range < 20"),
        [
            (
                "10:16: error: self.range is the range sensor, not one of its values, so it is "
                "never a number nor True or False (read one of its values, e.g. "
                "self.range.distance_cm (it has distance_mm, distance_cm))"
            )
        ],
    ),
    "action_made_in_condition.py": (
        pc("if self.bumper.any:\n            Rotate(angle_deg=90)\n        return False"),
        [
            (
                "11:13: error: Rotate(...) in condition method 'near' is made and thrown away: "
                "a condition cannot run an action (run it in a state of its own, e.g. turn = "
                "state(Rotate(...), ...), and go there when the condition holds: when=[('near', "
                "'turn')])"
            )
        ],
    ),
    "python_no_final.py": (
        p("Drive(distance_mm=500)").replace('state(final="success")', "state()"),
        [
            (
                "6:5: error: state 'end' has no way out (add on_done=\"NEXT\", a when= "
                'condition, or final="success")'
            )
        ],
    ),
    "python_misspelt_target.py": (
        p("Drive(distance_mm=500)").replace('on_done="end"', 'on_done="ned"'),
        ["5:62: error: there is no state 'ned' (did you mean 'end'?)"],
    ),
    "python_prompt_copied.py": (
        (
            ">>> from roboscript import Drive, Mission, state\n>>> class M(Mission):\n"
            '...     go = state(Drive(distance_mm=500), initial=True, on_done="end",'
            ' on_failed="end")\n'
            '...     end = state(final="success")\n'
        ),
        [
            (
                "1:1: error: this line starts with '>>> ', the prompt of Python's interactive "
                "shell, copied with the code (take away '>>> ' and '... ' at the start of each "
                "line, keeping the indentation after them)"
            )
        ],
    ),
    "tabs_and_spaces.py": (
        p("Drive(distance_mm=500)")
        .replace("    go =", "\tgo =")
        .replace("    end =", "        end ="),
        [
            (
                "6:1: error: syntax error: inconsistent use of tabs and spaces in indentation "
                "(indent with spaces only: a tab looks like spaces but Python counts it apart)"
            )
        ],
    ),
    "turn_by_degrees.py": (
        p("Turn(angle_deg=90)"),
        [
            (
                "5:16: error: Turn() has no parameter 'angle_deg' (turn is a walking robot's "
                "turn, by steps; a robot on wheels turns by an angle with rotate)"
            )
        ],
    ),
    "rotate_degrees.py": (
        p("Rotate(degrees=90)"),
        [
            (
                "5:16: error: Rotate() has no parameter 'degrees' (how far a rotate turns is "
                "its angle, with its unit: angle: 90 deg, or angle_deg=90 in Python)"
            )
        ],
    ),
    "wait_seconds.py": (
        p("Wait(seconds=2)"),
        [
            (
                "5:16: error: Wait() has no parameter 'seconds' (how long a wait lasts is its "
                "duration, with its unit: duration: 2 s, or duration_s=2 in Python)"
            )
        ],
    ),
    "distance_in_cm.py": (
        p("Drive(distance_cm=50)"),
        [
            (
                "5:16: error: Drive() has no parameter 'distance_cm' (write distance_mm=500, "
                "which is 50 cm)"
            )
        ],
    ),
    "state_without_quotes.py": (
        p("Drive(distance_mm=500)").replace('on_done="end"', "on_done=end"),
        [
            (
                "5:62: error: NameError: name 'end' is not defined (a state is named in quotes: "
                "write 'end')"
            )
        ],
    ),
    "when_as_dict.py": (
        pc("return self.bumper.any").replace('when=[("near", "end")]', 'when={"near": "end"}'),
        [
            (
                "6:21: error: state 'go': when is a list of (condition, state) pairs, not a "
                "dict (write when=[('near', 'end')])"
            )
        ],
    ),
    "lambda_one_less_than_two.py": (
        pc("return self.bumper.any").replace(
            'when=[("near", "end")]', 'when=[(lambda m: 1 < 2, "end")]'
        ),
        [
            (
                "6:23: warning: the condition lambda reads nothing but fixed values, so it "
                "never changes: it is always true (compare a sensor's value, e.g. lambda m: "
                "m.range.distance_cm < 20)"
            )
        ],
    ),
    "condition_returns_true.py": (
        pc("return True"),
        [
            (
                "9:5: warning: condition method 'near' reads nothing but fixed values, so what "
                "it returns never changes: it is always true (compare a sensor's value, e.g. "
                "return self.range.distance_cm < 20)"
            )
        ],
    ),
    "if_five.py": (
        pc("if 5:\n            return self.bumper.any\n        return False"),
        [
            (
                "10:12: warning: 'if 5:' tests nothing but fixed values, so it never changes: "
                "it is always true (test a sensor's value, e.g. if self.range.distance_cm < 20:)"
            )
        ],
    ),
    "bumper_called.py": (
        pc("return self.bumper.any()"),
        [
            (
                "10:16: error: self.bumper.any is a value, not a function: it is read without "
                "() (write self.bumper.any)"
            )
        ],
    ),
    "sleep_in_helper_of_update.py": (
        SLEEPY,
        [
            (
                "7:5: warning: time.sleep(seconds) in nap(), called by Pause.update(), holds up "
                "the whole robot: Pause.update() is run once every tick (0.02 s), and while it "
                "sleeps no condition is checked, no timeout counted and no other action run (a "
                "condition or update() must return at once; wait with a state's action or "
                "timeout, never time.sleep: e.g. a state of its own, pause = "
                'state(Wait(duration_s=2), on_done="next"))'
            )
        ],
    ),
    "sleep_in_helper_of_condition.py": (
        SLEEPY_CONDITION,
        [
            (
                "7:5: warning: time.sleep(0.5) in look_around(), called by near(), holds up the "
                "whole robot for 0.5 s: near() is run once every tick (0.02 s), and while it "
                "sleeps no condition is checked, no timeout counted and no other action run (a "
                "condition or update() must return at once; wait with a state's action or "
                "timeout, never time.sleep: e.g. a state of its own, pause = "
                'state(Wait(duration_s=2), on_done="next"))'
            )
        ],
    ),
    "python_bom_and_windows_ends.py": (
        ("\ufeff" + G).replace("\n", "\r\n").encode("utf-8"),
        [],
    ),
    "curly_quotes.py": (
        G.replace('on_done="end"', "on_done=\u201cend\u201d"),
        [
            (
                "5:62: error: syntax error: invalid character '“' (U+201C) (a curly quote, as a "
                "word processor writes it: type straight quotes, \" or ')"
            )
        ],
    ),
    "action_without_state.py": (
        G.replace(
            'state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end")',
            "Drive(distance_mm=500)",
        ),
        [
            (
                "5:10: error: 'go' is an action, not a state: a state runs it (write go = "
                "state(Drive(distance_mm=500), ...))"
            )
        ],
    ),
    "class_without_mission.py": (
        G.replace("class M(Mission):", "class M:"),
        [
            (
                "4:1: error: class M has states but does not extend Mission, so it is no "
                "mission (write class M(Mission):, and import Mission from roboscript)"
            )
        ],
    ),
    "two_missions.py": (
        G
        + "\n\nclass N(Mission):\n"
        + '    go = state(Drive(distance_mm=500), initial=True, on_done="end")\n'
        + '    end = state(final="success")\n',
        [
            (
                "9:1: error: this file holds 2 missions (M, N); a mission file holds one (move "
                "each mission to a file of its own)"
            )
        ],
    ),
    "update_without_ctx.py": (
        PA.replace("BODY", "return Result.done()").replace("update(self, ctx)", "update(self)"),
        [
            (
                "13:16: error: Pause.update must take self and ctx, as roboscript calls it with "
                "the robot's context (def update(self, ctx):)"
            )
        ],
    ),
    "result_in_capitals.py": (
        PA.replace("BODY", "return Result.DONE"),
        [
            (
                "9:9: warning: Pause.update() returns Result.DONE, which Result does not have "
                "(its outcomes are written in small letters), and roboscript reads what "
                "update() returns as how the action is going: a Result, or None while it runs "
                "(write return Result.done())"
            )
        ],
    ),
    "saved_as_upper.PY": (
        G,
        [],
    ),
    "initial_lower_true.py": (
        G.replace("initial=True", "initial=true"),
        ["5:48: error: NameError: name 'true' is not defined (did you mean 'True'?)"],
    ),
    "unit_in_python_condition.py": (
        pc("return self.range.distance_cm < 20cm"),
        [
            (
                "10:42: error: syntax error: invalid decimal literal (a number in Python has no "
                "unit: for 20cm write 20, as distance_cm is in cm)"
            )
        ],
    ),
    "half_comparison_after_and.py": (
        pc("return self.range.distance_cm < 20 and > 5"),
        [
            (
                "10:48: error: invalid syntax (each side of and/or is a whole comparison: name "
                "the value again, e.g. self.range.distance_cm < 20 and self.range.distance_cm > "
                "5)"
            )
        ],
    ),
    "self_in_condition_name.py": (
        pc("return self.bumper.any").replace('("near", "end")', '("self.near", "end")'),
        [
            (
                "6:24: error: a condition written as text names things without 'self.' (a "
                "condition method is named alone, in quotes: write 'near')"
            )
        ],
    ),
    "condition_without_quotes.py": (
        pc("return self.bumper.any").replace('("near", "end")', '(near, "end")'),
        [
            (
                "6:23: error: NameError: name 'near' is not defined (a condition is named in "
                "quotes: write 'near')"
            )
        ],
    ),
    "sleep_in_a_method_a_lambda_calls.py": (
        SLEEPY_CONDITION.replace("def look_around():\n    time.sleep(0.5)\n", "")
        .replace('("near", "end")', '(lambda m: m.near(), "end")')
        .replace("        look_around()\n", "        time.sleep(0.5)\n"),
        [
            (
                "14:9: warning: time.sleep(0.5) in near(), called by the condition lambda, holds"
                " up the whole robot for 0.5 s: the condition lambda is run once every tick"
                " (0.02 s), and while it sleeps no condition is checked, no timeout counted and"
                " no other action run (a condition or update() must return at once; wait with a"
                " state's action or timeout, never time.sleep: e.g. a state of its own, pause ="
                ' state(Wait(duration_s=2), on_done="next"))'
            ),
        ],
    ),
    "sleep_in_a_function_condition.py": (
        SLEEPY_CONDITION.replace("def look_around():", "def near(m):")
        .replace("    time.sleep(0.5)\n", "    time.sleep(0.5)\n    return m.bumper.any\n")
        .replace('("near", "end")', '(near, "end")')
        .replace(
            "\n    def near(self):\n        look_around()\n        return self.bumper.any\n", ""
        ),
        [
            (
                "7:5: warning: time.sleep(0.5) in near() holds up the whole robot for 0.5 s:"
                " near() is run once every tick (0.02 s), and while it sleeps no condition is"
                " checked, no timeout counted and no other action run (a condition or update()"
                " must return at once; wait with a state's action or timeout, never time.sleep:"
                ' e.g. a state of its own, pause = state(Wait(duration_s=2), on_done="next"))'
            ),
        ],
    ),
    "states_as_a_list.yaml": (
        (
            "mission: m\nstates:\n  - go:\n      do: {drive: {distance: 50 cm}}\n      on: "
            "{done: end, failed: end}\n  - end: {final: success}\n"
        ),
        [
            (
                "3:3: error: 'states:' is written as a list (its lines start with '- '), but it "
                "maps each state's name to the state (take away the '- ' and line the names up: "
                "write go: rather than - go:)"
            )
        ],
    ),
    "then_for_on.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n    then: end\n  "
            "end: {final: success}\n"
        ),
        [
            (
                "5:5: error: unknown key 'then' in state 'go' (where a state goes next is "
                "written under 'on:', by outcome: write on: {done: end})"
            )
        ],
    ),
    "outcome_finished.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on: {finished: "
            "end}\n  end: {final: success}\n"
        ),
        [
            (
                "5:10: error: unknown outcome 'finished' (outcomes: done, failed, timeout) "
                "(write done: end)"
            )
        ],
    ),
    "two_actions_in_do.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do:\n      - drive: {distance: 50 cm}\n      - "
            "rotate: {angle: 90 deg}\n    on: {done: end, failed: end}\n  end: {final: "
            "success}\n"
        ),
        [
            (
                "5:7: error: 'do' names one action, e.g. do: {drive: {distance: 50 cm}} (to do "
                "one thing after another, give each its own state and go on with on: {done: "
                "NEXT})"
            )
        ],
    ),
    "comma_left_out.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on: {done: end "
            "failed: end}\n  end: {final: success}\n"
        ),
        ["5:26: error: expected `,` or `}` here (inside the `{` at 5:9)"],
    ),
    "brace_left_open.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}\n    on: {done: end, "
            "failed: end}\n  end: {final: success}\n"
        ),
        ["4:9: error: this `{` is never closed (close it with `}` before 5:5)"],
    ),
    "end_written_twice.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on: {done: "
            "end, failed: end}\n  end: {final: success}\n  end: {final: failure}\n"
        ),
        [
            (
                "7:3: error: 'end' is given twice (first on line 6) (keep one of the two, or "
                "give one of them another name)"
            )
        ],
    ),
}


@pytest.fixture(scope="module")
def checked(tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[str]]:
    """What one ``roboscript check`` of every file prints, by file."""
    folder: Path = tmp_path_factory.mktemp("sweep")
    for name, (text, _) in MISTAKES.items():
        (folder / name).write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
    printed, summary = checked_by_file(folder, list(MISTAKES))
    refused = sum(
        any(re.match(r"(\d+:\d+: | )error: ", line) for line in answer)
        for _, answer in MISTAKES.values()
    )
    assert summary == f"checked {len(MISTAKES)} files: {refused} with errors"
    return printed


@pytest.mark.parametrize("name", list(MISTAKES))
def test_each_beginners_mistake_gets_its_answer_at_its_place(
    checked: dict[str, list[str]], name: str
) -> None:
    assert checked[name] == MISTAKES[name][1]


@pytest.mark.parametrize(
    "name", ["sleep_in_helper_of_update.py", "sleep_in_helper_of_condition.py"]
)
def test_run_warns_of_a_sleep_in_a_helper_at_the_sleeps_line(tmp_path: Path, name: str) -> None:
    (tmp_path / name).write_text(str(MISTAKES[name][0]), encoding="utf-8")
    result = run_cli("run", name, cwd=tmp_path)
    assert "Traceback" not in result.stderr
    assert result.stderr.splitlines()[0] == f"{name}:" + MISTAKES[name][1][0]


def test_a_sleep_in_a_helper_in_another_file_of_the_students_is_told_in_that_file(
    tmp_path: Path,
) -> None:
    (tmp_path / "tools.py").write_text(
        "import time\n\n\ndef settle():\n    time.sleep(2)\n", encoding="utf-8"
    )
    (tmp_path / "m.py").write_text(
        str(MISTAKES["sleep_in_helper_of_condition.py"][0])
        .replace("def look_around():\n    time.sleep(0.5)\n", "")
        .replace("import time\n", "from tools import settle\n")
        .replace("look_around()", "settle()"),
        encoding="utf-8",
    )
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.stderr.splitlines()[0].startswith(
        "tools.py:5:5: warning: time.sleep(2) in settle(), called by near(), holds up the whole"
        " robot for 2 s"
    )
