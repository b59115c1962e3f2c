"""A beginner's mistakes, as ``roboscript check`` answers them: one sentence at ``file:line:col``
with the fix, never a traceback, and never a mission accepted that would not do what was meant.

Every file below is checked by one ``roboscript check`` run (a program of its own, as a
student runs it), so a mistake in one file cannot hide behind another's, and each test reads
the lines printed for its own file.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import checked_by_file, run_cli

from roboscript.actions.composite import Repeat

YAML_REPEAT = """\
mission: m
states:
  go:
    do: {repeat: {times: TIMES, do: {rotate: {angle: 90 deg}}}}
    on: {done: end, failed: end}
  end: {final: success}
"""

PY_REPEAT = """\
from roboscript import Mission, Repeat, Rotate, state

class M(Mission):
    go = state(Repeat(Rotate(angle_deg=90), times=TIMES), initial=True, on_done="end",
               on_failed="end")
    end = state(final="success")
"""

CONDITION = """\
import functools
from roboscript import Drive, Mission, state

class M(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end",
               when=[("near", "end")])
    end = state(final="success")

    DEFINITION
"""

CHANGES = """\
import roboscript
from roboscript import Drive, Mission, state
from roboscript.profiles import get_profile

class MyDrive(Drive):
    pass

CHANGE

class M(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end",
               when=[("hack", "end")])
    end = state(final="success")

    def hack(self):
        IN_METHOD
        return False
"""

BEHAVIOUR = """\
from roboscript import Action, Mission, Result, state


class Spin(Action):
    name = "spin"
    requires = frozenset({"drive_base"})

    def update(self, ctx):
        ctx.drive_base.set_wheel_speeds(100, -100)
        return None


class M(Mission):
    go = state(Spin(), initial=True, timeout_s=2, on_timeout="end")
    end = state(final="success")
"""

YAML_WHEN = """\
mission: m
states:
  go:
    do: {drive: {distance: 50 cm}}
    on: {done: end, failed: end}
    when:
      - {if: "IF", goto: end}
  end: {final: success}
"""

AGAIN = "(write `repeat: {times: 4, do: {rotate: {angle: 90 deg}}}`)"
AGAIN_PY = "(write Repeat(Rotate(angle_deg=90), times=4))"
AN_HOUR = (
    "error: repeat times: 1,000,000,000 runs cannot finish within a mission's longest run"
    " (an hour, which holds at most 180,000 runs)"
)
OWN_DRIVE = (
    "error: this changes roboscript's own Drive (update), which every mission shares, so"
    " roboscript keeps it as it is (make one of your own that extends it: class"
    " MyDrive(Drive): ..., and use MyDrive(...) in your states)"
)

MISTAKES: dict[str, tuple[str, list[str]]] = {
    # --- repeat's times: a whole number of runs that fits in an hour
    "repeat_1e9.yaml": (
        YAML_REPEAT.replace("TIMES", "1e9"),
        [f"4:26: {AN_HOUR} (write `times: 180000` or fewer)"],
    ),
    "repeat_billion.yaml": (
        YAML_REPEAT.replace("TIMES", "1000000000"),
        [f"4:26: {AN_HOUR} (write `times: 180000` or fewer)"],
    ),
    "repeat_negative.yaml": (
        YAML_REPEAT.replace("TIMES", "-1"),
        [f"4:26: error: repeat times: -1 is not a number of runs (at least 1) {AGAIN}"],
    ),
    "repeat_zero.yaml": (
        YAML_REPEAT.replace("TIMES", "0"),
        [f"4:26: error: repeat times: 0 would not run the action at all (at least 1) {AGAIN}"],
    ),
    "repeat_half.yaml": (
        YAML_REPEAT.replace("TIMES", "2.5"),
        [f"4:26: error: repeat times is a whole number of runs, and 2.5 is not one {AGAIN}"],
    ),
    "repeat_point_zero.yaml": (
        YAML_REPEAT.replace("TIMES", "4.0"),
        [
            (
                "4:26: error: repeat times is a whole number of runs, and 4.0 is not one (a whole"
                " number has no decimal point) (write `times: 4`)"
            )
        ],
    ),
    "repeat_yes.yaml": (
        YAML_REPEAT.replace("TIMES", "true"),
        [
            (
                "4:26: error: repeat needs 'times', a whole number of at least 1, and true is not"
                f" a number {AGAIN}"
            )
        ],
    ),
    "repeat_e_notation.yaml": (
        YAML_REPEAT.replace("TIMES", "12e3"),
        [
            (
                "4:26: error: repeat times is a whole number written out in digits, and 12e3 is"
                " not (write `times: 12000`)"
            )
        ],
    ),
    "repeat_billion.py": (
        PY_REPEAT.replace("TIMES", "10**9"),
        [f"4:16: {AN_HOUR} (write Repeat(Rotate(angle_deg=90), times=180000) or fewer)"],
    ),
    "repeat_negative.py": (
        PY_REPEAT.replace("TIMES", "-3"),
        [f"4:16: error: repeat times: -3 is not a number of runs (at least 1) {AGAIN_PY}"],
    ),
    "repeat_zero.py": (
        PY_REPEAT.replace("TIMES", "0"),
        [f"4:16: error: repeat times: 0 would not run the action at all (at least 1) {AGAIN_PY}"],
    ),
    "repeat_half.py": (
        PY_REPEAT.replace("TIMES", "2.5"),
        [f"4:16: error: repeat times is a whole number of runs, and 2.5 is not one {AGAIN_PY}"],
    ),
    "repeat_yes.py": (
        PY_REPEAT.replace("TIMES", "True"),
        [
            (
                "4:16: error: repeat needs 'times', a whole number of at least 1, and True is not"
                f" a number {AGAIN_PY}"
            )
        ],
    ),
    # --- a condition that is not a plain method
    "condition_static.py": (
        CONDITION.replace("DEFINITION", "@staticmethod\n    def near():\n        return True"),
        [
            (
                "10:5: error: condition 'near' is a @staticmethod, and a condition is a plain"
                " method that reads the robot through self (take away the @staticmethod above it"
                " and write def near(self) -> bool:)"
            )
        ],
    ),
    "condition_class.py": (
        CONDITION.replace("DEFINITION", "@classmethod\n    def near(cls):\n        return True"),
        [
            (
                "10:5: error: condition 'near' is a @classmethod, and a condition is a plain method"
                " that reads the robot through self (take away the @classmethod above it and"
                " write def near(self) -> bool:)"
            )
        ],
    ),
    "condition_cached.py": (
        CONDITION.replace(
            "DEFINITION", "@functools.lru_cache\n    def near(self):\n        return True"
        ),
        [
            (
                "10:5: error: condition 'near' has a decorator that makes it something other than"
                " a method, and a condition is a plain method (take away the line starting with @"
                " above def near(self))"
            )
        ],
    ),
    "condition_property.py": (
        CONDITION.replace("DEFINITION", "@property\n    def near(self):\n        return True"),
        [
            (
                "10:5: error: condition 'near' is a property, and a condition is a plain method"
                " (take away the @property above def near(self))"
            )
        ],
    ),
    "condition_value.py": (
        CONDITION.replace("DEFINITION", "near = True"),
        [
            (
                "6:23: error: 'near' is True, set once when the class is made, so it cannot be a"
                " condition, which is asked again at every tick (define it as a method: def"
                " near(self) -> bool: return ... (True or False))"
            )
        ],
    ),
    # --- changing roboscript's own classes and names
    "change_update.py": (
        CHANGES.replace("CHANGE", "Drive.update = lambda self, ctx: None").replace(
            "IN_METHOD", "pass"
        ),
        [f"8:1: {OWN_DRIVE}"],
    ),
    "change_setattr.py": (
        CHANGES.replace("CHANGE", "setattr(Drive, 'update', lambda self, ctx: None)").replace(
            "IN_METHOD", "pass"
        ),
        [f"8:1: {OWN_DRIVE}"],
    ),
    "change_name.py": (
        CHANGES.replace("CHANGE", "roboscript.Drive = MyDrive").replace("IN_METHOD", "pass"),
        [
            (
                "8:1: error: this puts something of its own in the place of roboscript's 'Drive',"
                " and roboscript's names stay as roboscript makes them (give yours a name of its"
                " own and use that name, e.g. MyDrive)"
            )
        ],
    ),
    "change_at_run_time.py": (
        CHANGES.replace("CHANGE", "").replace("IN_METHOD", "Drive.update = lambda self, ctx: None"),
        [f"16:9: {OWN_DRIVE}"],
    ),
    "change_robot_at_run_time.py": (
        CHANGES.replace("CHANGE", "").replace(
            "IN_METHOD", 'get_profile("mirto").gains["heading"] = (50.0, 0.0, 0.0)'
        ),
        [
            (
                "16:9: error: this changes the built-in robot 'mirto' (gains), and a built-in"
                " robot stays as it is built: the simulated robot would not have the change (a"
                " robot of your own is a profile file beside the mission, e.g. my_mirto.yaml"
                " holding 'extends: mirto' and 'gains: ...'; then write robot = \"my_mirto.yaml\")"
            )
        ],
    ),
    # Python's own names: roboscript's code calls them too (the next files' errors are
    # printed with the print this one replaced), so they are put back and refused.
    "change_python_print.py": (
        CHANGES.replace("CHANGE", '__builtins__["print"] = None').replace("IN_METHOD", "pass"),
        [
            (
                "8:1: error: this changes Python's own 'print', which roboscript's code uses"
                " too, so Python's stays as it is (give yours a name of its own and use that"
                " name, e.g. my_print)"
            )
        ],
    ),
    "change_python_at_run_time.py": (
        CHANGES.replace("CHANGE", "import builtins").replace(
            "IN_METHOD", "builtins.len = lambda thing: 0"
        ),
        [
            (
                "16:9: error: this changes Python's own 'len', which roboscript's code uses"
                " too, so Python's stays as it is (give yours a name of its own and use that"
                " name, e.g. my_len)"
            )
        ],
    ),
    # --- conditions written as another language writes them
    "condition_ampersand.yaml": (
        YAML_WHEN.replace("IF", "bumper.left & bumper.right"),
        [
            (
                "7:27: error: cannot read the condition 'bumper.left & bumper.right': '&' is not a"
                " condition word (write 'and': bumper.left and bumper.right)"
            )
        ],
    ),
    "condition_bar.yaml": (
        YAML_WHEN.replace("IF", "bumper.left | line.any"),
        [
            (
                "7:27: error: cannot read the condition 'bumper.left | line.any': '|' is not a"
                " condition word (write 'or': bumper.left or line.any)"
            )
        ],
    ),
    "condition_visits_called.yaml": (
        YAML_WHEN.replace("IF", "visits(go) > 2"),
        [
            (
                "7:15: error: a condition cannot call functions (a state's visits are read with a"
                " '.': write visits.go)"
            )
        ],
    ),
    "condition_elapsed_called.yaml": (
        YAML_WHEN.replace("IF", "elapsed() > 2"),
        [
            (
                "7:15: error: a condition cannot call functions (a value is read without brackets:"
                " write elapsed)"
            )
        ],
    ),
    "condition_unclosed.yaml": (
        YAML_WHEN.replace("IF", "(range.distance_cm < 20"),
        [
            (
                "7:15: error: cannot read the condition '(range.distance_cm < 20': this '(' is"
                " never closed (add ')' where what it groups ends)"
            )
        ],
    ),
    "condition_only_a_number.yaml": (
        YAML_WHEN.replace("IF", "20"),
        [
            (
                "7:15: error: the condition '20' is only a number, which never changes, so it would"
                " always count as true (compare a value with it, e.g. range.distance_cm < 20)"
            )
        ],
    ),
    "condition_a_reading_alone.yaml": (
        YAML_WHEN.replace("IF", "visits.go and bumper.any"),
        [
            (
                "7:15: error: 'visits.go' is a number, not true or false, so it would count as true"
                " whenever it is not 0 (compare it, e.g. visits.go >= 2)"
            )
        ],
    ),
    "condition_percent.yaml": (
        YAML_WHEN.replace("IF", "color.reflection > 50%"),
        [
            (
                "7:36: error: cannot read the condition 'color.reflection > 50%': '%' is not a unit"
                " a condition knows (a value is in the unit its name ends in, a reflection in"
                " percent: color.reflection > 50)"
            )
        ],
    ),
    "comment_in_braces.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm # half a metre}}\n"
            "    on: {done: end, failed: end}\n  end: {final: success}\n"
        ),
        [
            (
                "4:17: error: this `{` is never closed (a ' #' starts a comment, which hides the"
                " rest of the line, its `}` too: put the comment after the `}`, or take it away)"
            )
        ],
    ),
    "condition_async.py": (
        CONDITION.replace("DEFINITION", "async def near(self):\n        return True"),
        [
            (
                "9:5: error: condition 'near' is written 'async def', so calling it only makes a"
                " coroutine, which counts as true at once (write def near(self) -> bool:, without"
                " async)"
            )
        ],
    ),
    "unknown_value_on_self.py": (
        CONDITION.replace("DEFINITION", "def near(self):\n        return self.camera.sees_red"),
        [
            (
                "10:16: error: M has no 'camera' (a value of your own needs a first value in the"
                " class, camera = 0; the robot's sensors are self.bumper, self.buttons, self.color,"
                " self.driven, self.line, self.pose, self.range, self.side_range)"
            )
        ],
    ),
    "time_on_self.py": (
        CONDITION.replace("DEFINITION", "def near(self):\n        return self.time > 5"),
        [
            (
                "10:16: error: M has no 'time' (a mission has two clocks: self.elapsed, the"
                " seconds since the mission started, and self.state_time, the seconds since this"
                " state began)"
            )
        ],
    ),
    "time_in_yaml.yaml": (
        YAML_WHEN.replace("IF", "timer > 5"),
        [
            (
                "7:15: error: unknown name 'timer' in a condition: a condition reads two clocks"
                " (write elapsed, the seconds since the mission started, or state_time, the"
                " seconds since this state began: e.g. state_time > 5)"
            )
        ],
    ),
    "never_true.yaml": (
        YAML_WHEN.replace("IF", "range.distance_cm < 20 and range.distance_cm > 30"),
        [
            (
                "7:15: error: the condition 'range.distance_cm < 20 and range.distance_cm > 30'"
                " can never be true: range.distance_cm is never below 20 and above 30 at once"
                " (to go when either holds, write or: range.distance_cm < 20 or"
                " range.distance_cm > 30)"
            )
        ],
    ),
    "when_pair_without_brackets.py": (
        CONDITION.replace('when=[("near", "end")]', 'when=["near", "end"]').replace(
            "DEFINITION", "def near(self):\n        return self.bumper.any"
        ),
        [
            (
                "6:21: error: state 'go': each 'when' entry is (condition, state), in its own"
                ' brackets (write when=[("near", "end")])'
            )
        ],
    ),
    "condition_colon.yaml": (
        YAML_WHEN.replace("IF", "bumper.any:"),
        [
            (
                "7:25: error: cannot read the condition 'bumper.any:': a condition has no ':' at"
                " its end (take it away: bumper.any)"
            )
        ],
    ),
    "states_empty.yaml": (
        "mission: m\nstates: {}\n",
        [
            (
                "2:1: error: a mission needs 'states:', a mapping of state names to states (under"
                " states:, indented, write each state by its name, e.g. go: {final: success})"
            )
        ],
    ),
    "method_twice.py": (
        CONDITION.replace(
            "DEFINITION",
            "def near(self):\n        return self.bumper.any\n\n    def near(self):\n"
            "        return self.bumper.left",
        ),
        [
            (
                "12:5: error: method 'near' is written twice (first on line 9), and Python keeps"
                " only the second (keep one of the two, or give one of them another name)"
            )
        ],
    ),
    "is_a_number.py": (
        CONDITION.replace(
            "DEFINITION", "def near(self):\n        return self.range.distance_cm is 20"
        ),
        [
            (
                "10:16: error: 'is 20' asks whether two things are one and the same object, which a"
                " value read from the robot never is, so it is always false (compare values with =="
                ": self.range.distance_cm == 20)"
            )
        ],
    ),
    "and_in_capitals.py": (
        CONDITION.replace(
            "DEFINITION", "def near(self):\n        return self.bumper.left AND self.bumper.right"
        ),
        ["10:33: error: invalid syntax (Python writes and, or and not in lower case)"],
    ),
    # --- words and parameters a beginner guesses
    "loop.yaml": (
        YAML_REPEAT.replace("repeat: {times: TIMES,", "loop: {times: 4,"),
        ["4:10: error: unknown action 'loop' (the action for that is 'repeat')"],
    ),
    "drive_direction.yaml": (
        YAML_REPEAT.replace(
            "repeat: {times: TIMES, do: {rotate: {angle: 90 deg}}}",
            "drive: {distance: 50 cm, direction: backward}",
        ),
        [
            (
                "4:35: error: 'drive' has no parameter 'direction' (a drive has no direction: a"
                " negative distance drives backward)"
            )
        ],
    ),
    "turn_by_angle.yaml": (
        YAML_REPEAT.replace(
            "repeat: {times: TIMES, do: {rotate: {angle: 90 deg}}}", "turn: {angle: 90 deg}"
        ),
        [
            (
                "4:17: error: 'turn' has no parameter 'angle' (turn is a walking robot's turn, by"
                " steps; a robot on wheels turns by an angle with rotate)"
            ),
        ],
    ),
    "rotate_direction.py": (
        PY_REPEAT.replace(
            "Repeat(Rotate(angle_deg=90), times=TIMES)", "Rotate(angle_deg=90, direction='left')"
        ),
        [
            (
                "4:16: error: Rotate() has no parameter 'direction' (a rotate has no direction: a"
                " positive angle turns right, a negative one left)"
            )
        ],
    ),
    "repeat_times_first.py": (
        PY_REPEAT.replace(
            "Repeat(Rotate(angle_deg=90), times=TIMES)", "Repeat(4, Rotate(angle_deg=90))"
        ),
        [
            (
                "4:16: error: repeat takes the action first, then how many times (write"
                " Repeat(Rotate(angle_deg=90), times=4))"
            )
        ],
    ),
    # --- YAML's indentation and colons
    "states_at_the_left_edge.yaml": (
        (
            "mission: m\nstates:\ngo:\n  do: {drive: {distance: 50 cm}}\n"
            "  on: {done: end, failed: end}\nend: {final: success}\n"
        ),
        [
            (
                "3:1: error: unknown key 'go' in a mission ('go' is a state: indent it two spaces,"
                " under 'states:')"
            ),
            (
                "6:1: error: unknown key 'end' in a mission ('end' is a state: indent it two"
                " spaces, under 'states:')"
            ),
        ],
    ),
    "outcomes_not_under_on.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on:\n"
            "    done: end\n  end: {final: success}\n"
        ),
        [
            "5:8: error: 'on' maps outcomes to states, e.g. on: {done: next, timeout: stuck}",
            (
                "6:5: error: unknown key 'done' in state 'go' ('done' is an outcome: it goes under"
                " 'on:', indented two more spaces (or write on: {done: end}))"
            ),
        ],
    ),
    "states_listed_by_name.yaml": (
        "mission: m\nstates:\n  - name: go\n    do: {drive: {distance: 50 cm}}\n",
        [
            (
                "3:3: error: 'states:' is written as a list (its lines start with '- '), but it"
                " maps each state's name to the state (take away the '- ' and line the names up:"
                " write go: rather than - name: go)"
            )
        ],
    ),
    "two_keys_on_a_line.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: drive: {distance: 50 cm}\n"
            "    on: {done: end, failed: end}\n  end: {final: success}\n"
        ),
        [
            (
                "4:14: error: a ':' is not allowed here: this line holds two keys (a value that is"
                " itself a 'key: value' goes in braces: do: {drive: {distance: 50 cm}}; text"
                " holding ': ' goes in quotes)"
            )
        ],
    ),
    "count_in_a_name_of_the_file.py": (
        (
            "from roboscript import Mission, Rotate, state\n\ncount = 0\n\n\nclass M(Mission):\n"
            '    turn = state(Rotate(angle_deg=90), initial=True, on_failed="end",\n'
            '                 on_done=[("four_done", "end"), "turn"])\n'
            '    end = state(final="success")\n\n'
            "    def four_done(self):\n        count += 1\n        return count >= 4\n"
        ),
        [
            (
                "12:9: error: 'count' is read here before this method gives it a value: a method"
                " that sets 'count' has a 'count' of its own, which starts with no value each time"
                " the method runs (keep it on the mission: write self.count (with count = 0 in the"
                " class))"
            )
        ],
    ),
    # --- a behaviour of the student's own
    "behaviour_requires_typo.py": (
        BEHAVIOUR.replace('"drive_base"', '"drivebase"'),
        [
            (
                "14:16: error: Spin.requires names 'drivebase', which is no part a robot has (did"
                " you mean 'drive_base'?)"
            )
        ],
    ),
    "behaviour_without_update.py": (
        BEHAVIOUR.replace(
            "    def update(self, ctx):\n        ctx.drive_base.set_wheel_speeds(100, -100)\n"
            "        return None\n",
            "    pass\n",
        ),
        [
            (
                "12:16: error: Spin has no update(self, ctx), the method roboscript calls on an"
                " action each tick (write def update(self, ctx): in the class, returning None while"
                " it runs and Result.done() when it has finished)"
            )
        ],
    ),
    # --- a state's shape
    "state_without_colon.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n"
            "    on: {done: end, failed: end}\n  end {final: success}\n"
        ),
        ["6:3: error: a ':' is missing after the state name 'end' (write end: {final: success})"],
    ),
    "timeout_without_timeout.yaml": (
        (
            "mission: m\nstates:\n  go:\n    do: {drive: {distance: 50 cm}}\n"
            "    on: {done: end, failed: end, timeout: stuck}\n  end: {final: success}\n"
            "  stuck: {final: failure}\n"
        ),
        [
            (
                "5:43: warning: state 'go' goes to 'stuck' when it times out, but it has no"
                " timeout, so it never times out (add 'timeout: 10 s' to the state)"
            )
        ],
    ),
    "state_as_text.py": (
        CONDITION.replace('end = state(final="success")', 'end = "success"').replace(
            "DEFINITION", "def near(self):\n        return self.bumper.any"
        ),
        [
            (
                "5:62: error: 'end' is text in the class, not a state (make it a state: end ="
                ' state(final="success"))'
            )
        ],
    ),
    # --- Python written as another language writes it
    "lower_case_true.py": (
        CONDITION.replace("DEFINITION", "def near(self):\n        return true"),
        ["10:16: error: name 'true' is not defined (Python writes it True, with a capital letter)"],
    ),
    "builtin_for_sensor.py": (
        CONDITION.replace("DEFINITION", "def near(self):\n        return range.distance_cm < 20"),
        [
            (
                "10:16: error: 'range' here is Python's own range, not the robot's range sensor (a"
                " sensor is read through self: self.range.distance_cm)"
            )
        ],
    ),
    "else_if.py": (
        CONDITION.replace(
            "DEFINITION",
            "def near(self):\n        if self.bumper.any:\n            return True\n"
            "        else if self.range.distance_cm < 20:\n            return True\n"
            "        return False",
        ),
        ["12:14: error: expected ':' (Python writes 'else if' as elif: elif CONDITION:)"],
    ),
    "braces.py": (
        CONDITION.replace(
            "DEFINITION", "def near(self):\n        if (self.bumper.any) {\n            return True"
        ),
        [
            (
                "10:30: error: syntax error: '{' was never closed (Python has no braces: end the"
                " line with ':' and indent the lines of its block)"
            )
        ],
    ),
    "double_ampersand.py": (
        CONDITION.replace(
            "DEFINITION",
            "def near(self):\n        return self.bumper.left && self.bumper.right",
        ),
        ["10:34: error: invalid syntax (Python writes && as and, || as or, and ! as not)"],
    ),
}


@pytest.fixture(scope="module")
def checked(tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[str]]:
    """What one ``roboscript check`` of every mistake's file prints, by file."""
    folder: Path = tmp_path_factory.mktemp("mistakes")
    # The one mission that changes Drive comes first: the files after it must still see
    # roboscript's own Drive (a change is put back).
    names = sorted(MISTAKES, key=lambda name: name != "change_update.py")
    for name in names:
        (folder / name).write_text(MISTAKES[name][0], encoding="utf-8")
    printed, summary = checked_by_file(folder, names)
    refused = sum(any(": error:" in line for line in MISTAKES[name][1]) for name in names)
    assert summary == f"checked {len(names)} files: {refused} with errors"
    return printed


@pytest.mark.parametrize("name", sorted(MISTAKES))
def test_each_beginners_mistake_is_answered_in_one_located_sentence(
    checked: dict[str, list[str]], name: str
) -> None:
    assert checked[name] == MISTAKES[name][1]


def test_a_repeat_may_run_as_many_times_as_an_hour_holds(tmp_path: Path) -> None:
    (tmp_path / "most.yaml").write_text(
        YAML_REPEAT.replace("TIMES", str(Repeat.most_times)), encoding="utf-8"
    )
    result = run_cli("check", "most.yaml", cwd=tmp_path)
    assert result.returncode == 0, result.stderr


def test_the_same_typo_on_many_lines_is_told_in_full_three_times_then_counted(
    tmp_path: Path,
) -> None:
    lines = ["mission: m", "states:"]
    for i in range(300):
        lines += [f"  s{i}:", "    do: {dirve: {distance: 10 cm}}", f"    on: {{done: s{i + 1}}}"]
    (tmp_path / "many.yaml").write_text("\n".join([*lines, "  s300: {final: success}\n"]))
    result = run_cli("check", "many.yaml", cwd=tmp_path)
    typo = "error: unknown action 'dirve' (did you mean 'drive'?)"
    assert result.stderr.splitlines() == [
        f"many.yaml:4:10: {typo}",
        f"many.yaml:7:10: {typo}",
        f"many.yaml:10:10: {typo}",
        (
            "many.yaml:13:10: error: and 297 more like it at lines 13, 16, 19, 22, 25, 28, 31, 34,"
            " 37, ..., 901"
        ),
        "checked 1 file: 1 with errors",
    ]


def test_a_count_kept_in_a_name_the_method_sets_is_told_in_a_sentence_as_it_runs(
    tmp_path: Path,
) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Mission, Rotate, state\n\ncount = 0\n\n\n"
        "def counted():\n    count += 1\n    return count\n\n\n"
        "class M(Mission):\n"
        '    turn = state(Rotate(angle_deg=90), initial=True, on_failed="end",\n'
        '                 on_done=[("four_done", "end"), "turn"])\n'
        '    end = state(final="success")\n\n'
        "    def four_done(self):\n        return counted() >= 4\n",
        encoding="utf-8",
    )
    result = run_cli("run", "m.py", "--quiet", cwd=tmp_path)
    assert result.returncode == 1
    assert "Traceback" not in result.stderr and "UnboundLocalError" not in result.stderr
    assert result.stderr.splitlines()[-1] == (
        "failure: your condition 'four_done' read 'count' before giving it a value in state"
        " 'turn': a method that sets 'count' has a 'count' of its own, which starts with no"
        " value each time the method runs; keep it on the mission: write self.count (with"
        " count = 0 in the class) (m.py:7)"
    )


@pytest.mark.parametrize("name", ["repeat_1e9.yaml", "change_update.py", "condition_static.py"])
def test_run_refuses_a_beginners_mistake_as_check_does_before_the_robot_moves(
    tmp_path: Path, checked: dict[str, list[str]], name: str
) -> None:
    (tmp_path / name).write_text(MISTAKES[name][0], encoding="utf-8")
    result = run_cli("run", name, cwd=tmp_path)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert [f"{name}:{line}" for line in checked[name]] == result.stderr.splitlines()
