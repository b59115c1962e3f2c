"""A classroom's mistakes, each in a file of its own, as ``roboscript check`` answers them.

What a class of beginners writes on its first day: YAML's surprises (``1:30`` read as 90,
``010`` as 8, ``~`` for no value), what a word processor or a web page does to a file (tabs,
curly quotes, non-breaking spaces, a byte-order mark, Windows line ends, a ``.docx``), prompts
and fences copied with the code, Python without its imports or its ``self``, actions, sensors
and parameters misspelt wherever they are written, units in every form, conditions no reading
can make true and a ``time.sleep`` in code run every tick. Each gets one sentence at
``file:line:col`` in the student's terms, or nothing when it means what it says (``on`` as a
state's name, a file with Windows line ends). All files are checked by one ``roboscript check``
run, as a class's folder is.
"""

from __future__ import annotations

import io
import re
import zipfile
from pathlib import Path

import pytest
from helpers import checked_by_file, run_cli

Y = """\
mission: m
states:
  go:
    do: DO
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
      - {if: "IF", goto: end}
  end: {final: success}
"""
P = """\
from roboscript import Drive, Mission, state


class M(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end",
               when=[("near", "end")])
    end = state(final="success")

    def near(self):
        BODY
"""
PA = """\
import time

from roboscript import Action, Mission, Result, state


class Pause(Action):
    name = "pause"
    requires = frozenset({"drive_base"})

    def update(self, ctx):
        BODY


class M(Mission):
    go = state(Pause(), initial=True, timeout_s=5, on_done="end", on_failed="end",
               on_timeout="end")
    end = state(final="success")
"""
PS = """\
from roboscript import Drive, Mission, PlayTone, Rotate, Wait, state


class M(Mission):
    go = state(ACTION, initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""


def y(do: str) -> str:
    """A mission whose state 'go' runs ``do``."""
    return Y.replace("DO", do)


def yw(cond: str) -> str:
    """A mission whose state 'go' moves on when ``cond`` holds."""
    return YW.replace("IF", cond)


def p(body: str) -> str:
    """A Python mission whose condition 'near' is ``body``."""
    return P.replace("BODY", body)


def pa(body: str) -> str:
    """A Python mission whose own action's update() is ``body``."""
    return PA.replace("BODY", body)


def ps(action: str) -> str:
    """A Python mission whose state 'go' runs ``action``."""
    return PS.replace("ACTION", action)


def docx(text: str) -> bytes:
    """A Word document holding ``text``, as a word processor saves it."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("[Content_Types].xml", "<Types/>")
        z.writestr(
            "word/document.xml",
            f"<w:document><w:body><w:p><w:r><w:t>{text}</w:t></w:r></w:p></w:body></w:document>",
        )
    return buf.getvalue()


GOOD_Y = y("{drive: {distance: 50 cm}}")
GOOD_P = p("return self.bumper.any")


MISTAKES: dict[str, tuple[str | bytes, list[str]]] = {
    # ---- YAML 1.1 surprises
    "yaml_clock_duration.yaml": (
        y("{wait: {duration: 1:30}}"),
        [
            (
                "4:27: error: YAML reads 1:30 as the number 90, counting in sixties as a clock"
                " does, and roboscript reads a number with its unit (for 1 min 30 s, write `90 s`"
                " or `1.5 min`)"
            ),
        ],
    ),
    "yaml_clock_timeout.yaml": (
        GOOD_Y.replace("    on:", "    timeout: 1:30\n    on:").replace(
            "failed: end}", "failed: end, timeout: end}"
        ),
        [
            (
                "5:14: error: YAML reads 1:30 as the number 90, counting in sixties as a clock"
                " does, and roboscript reads a number with its unit (for 1 min 30 s, write `90 s`"
                " or `1.5 min`)"
            ),
        ],
    ),
    "yaml_clock_quoted.yaml": (
        y("{wait: {duration: '1:30'}}"),
        [
            (
                "4:27: error: wait duration: '1:30' is written as a clock writes a time, and a"
                " time is one number with its unit (for 1 min 30 s, write `90 s` or `1.5 min`)"
            ),
        ],
    ),
    "yaml_clock_hours.yaml": (
        y("{wait: {duration: 1:00:00}}"),
        [
            (
                "4:27: error: YAML reads 1:00:00 as the number 3600, counting in sixties as a"
                " clock does, and roboscript reads a number with its unit (for 1 h, write `3600 s`"
                " or `60 min`)"
            ),
        ],
    ),
    "yaml_octal_distance.yaml": (
        y("{drive: {distance: 010}}"),
        [
            (
                "4:28: error: 010 starts with a 0, so YAML reads it as an octal number: 8 (write"
                " 10, without the leading 0)"
            ),
        ],
    ),
    "yaml_octal_angle.yaml": (
        y("{rotate: {angle: 045}}"),
        [
            (
                "4:26: error: 045 starts with a 0, so YAML reads it as an octal number: 37 (write"
                " 45, without the leading 0)"
            ),
        ],
    ),
    "yaml_tilde_speed.yaml": (
        y("{drive: {distance: 50 cm, speed: ~}}"),
        [
            (
                "4:42: error: 'speed' of 'drive' has no value: YAML reads `~`, `null` and nothing"
                " after the ':' as no value (write speed: 15 cm/s, or leave speed out for its"
                " default)"
            ),
        ],
    ),
    "yaml_null_target.yaml": (
        GOOD_Y.replace("done: end", "done: null"),
        [
            (
                "5:16: error: 'done' has no value: YAML reads `~`, `null` and nothing after the"
                " ':' as no value (write the state it goes to, e.g. done: end)"
            ),
        ],
    ),
    "yaml_empty_initial.yaml": (
        GOOD_Y.replace("states:", "initial:\nstates:"),
        [
            (
                "2:9: error: 'initial' has no value: YAML reads `~`, `null` and nothing after the"
                " ':' as no value (write the state to start in, e.g. initial: go)"
            ),
        ],
    ),
    "yaml_empty_final.yaml": (
        GOOD_Y.replace("  end: {final: success}", "  end:\n    final:"),
        [
            (
                "7:11: error: 'final' in state 'end' has no value: YAML reads `~`, `null` and"
                " nothing after the ':' as no value (write final: success or final: failure, or"
                " leave 'final' out)"
            ),
        ],
    ),
    "yaml_empty_goto.yaml": (
        YW.replace('{if: "IF", goto: end}', "{if: bumper.any, goto: }"),
        [
            (
                "7:31: error: 'goto' in this choice has no value: YAML reads `~`, `null` and"
                " nothing after the ':' as no value (write the state it goes to, e.g. goto: end)"
            ),
        ],
    ),
    "yaml_empty_if.yaml": (
        YW.replace('{if: "IF", goto: end}', "{if: , goto: end}"),
        [
            (
                "7:13: error: 'if' in this choice has no value: YAML reads `~`, `null` and nothing"
                " after the ':' as no value (write the condition, e.g. if: range.distance_cm < 20)"
            ),
        ],
    ),
    "yaml_empty_distance.yaml": (
        y("{drive: {distance: }}"),
        [
            (
                "4:27: error: 'distance' of 'drive' has no value: YAML reads `~`, `null` and"
                " nothing after the ':' as no value (write distance: 50 cm)"
            ),
        ],
    ),
    "yaml_state_named_on.yaml": (
        (
            "mission: m\n"
            "initial: on\n"
            "states:\n"
            "  on:\n"
            "    do: {wait: {duration: 2 s}}\n"
            "    on: {done: off}\n"
            "  off: {final: success}\n"
        ),
        [],
    ),
    "yaml_state_named_yes_no.yaml": (
        GOOD_Y.replace("done: end, failed: end", "done: yes, failed: no").replace(
            "  end: {final: success}", "  yes: {final: success}\n  no: {final: failure}"
        ),
        [],
    ),
    "yaml_e_notation_distance.yaml": (
        y("{drive: {distance: 1e3}}"),
        [
            (
                "4:28: warning: drive distance: 1e3 taken as 1e3 mm; write `1e3 mm` (or did you"
                " mean 1e3 cm?)"
            ),
        ],
    ),
    "yaml_half_without_zero.yaml": (
        y("{drive: {distance: .5 m}}"),
        [],
    ),
    "yaml_equals_value.yaml": (
        y("{drive: {distance: =}}"),
        [
            "4:28: error: drive distance: expected a distance such as '50 cm', got '='",
        ],
    ),
    "yaml_equals_for_colon.yaml": (
        y("{drive: {distance = 50 cm}}"),
        [
            ("4:18: error: 'drive' has no parameter 'distance = 50 cm' (did you mean 'distance'?)"),
        ],
    ),
    "yaml_equals_for_colon_block.yaml": (
        GOOD_Y.replace("    on:", "    timeout = 10 s\n    on:"),
        [
            (
                "5:5: error: this line needs a ':' after its key (write 'key: value', or indent it"
                " as part of the line above)"
            ),
        ],
    ),
    "yaml_timeout_yes.yaml": (
        GOOD_Y.replace("    on:", "    timeout: yes\n    on:"),
        [
            "5:14: error: state 'go': timeout: expected a time such as '200 ms', got 'yes'",
        ],
    ),
    "yaml_final_yes.yaml": (
        GOOD_Y.replace("final: success", "final: yes"),
        [
            (
                "6:16: error: state 'end': final is 'success' or 'failure', got 'yes' ('yes' is a"
                " word here, not true: write final: success)"
            ),
        ],
    ),
    "yaml_timeout_off.yaml": (
        GOOD_Y.replace("    on:", "    timeout: off\n    on:"),
        [
            (
                "5:14: error: state 'go': timeout: expected a time such as '200 ms', got 'off'"
                " ('off' is a word here: a state with no time limit has no 'timeout', so take it"
                " away)"
            ),
        ],
    ),
    "yaml_timeout_false.yaml": (
        GOOD_Y.replace("    on:", "    timeout: false\n    on:"),
        [
            (
                "5:14: error: state 'go': timeout: expected a time, got False (a state with no"
                " time limit has no 'timeout', so take it away)"
            ),
        ],
    ),
    "yaml_final_no.yaml": (
        GOOD_Y.replace(
            "    on: {done: end, failed: end}", "    on: {done: end, failed: end}\n    final: no"
        ),
        [
            (
                "6:12: error: state 'go': final is 'success' or 'failure', got 'no' ('no' is a"
                " word here, not false: a state that does not end the mission has no 'final', so"
                " take it away; final: failure ends it in failure)"
            ),
        ],
    ),
    "yaml_final_true.yaml": (
        GOOD_Y.replace("final: success", "final: true"),
        [],
    ),
    "python_clock_time.py": (
        ps("Wait(duration_s=1:30)"),
        [
            (
                "5:33: error: invalid syntax (a time is one number in its keyword's unit: for 1"
                " min 30 s, write duration_s=90)"
            ),
        ],
    ),
    "python_leading_zero.py": (
        ps("Drive(distance_mm=010)"),
        [
            (
                "5:34: error: syntax error: leading zeros in decimal integer literals are not"
                " permitted; use an 0o prefix for octal integers (write 10, without the leading"
                " 0)"
            ),
        ],
    ),
    "python_letter_o.py": (
        ps("Drive(distance_mm=5O0)"),
        [
            (
                "5:34: error: syntax error: invalid decimal literal ('5O0' has the letter O where"
                " a zero was meant: write 500)"
            ),
        ],
    ),
    "python_degree_sign.py": (
        ps("Rotate(angle_deg=90°)"),
        [
            (
                "5:35: error: syntax error: invalid character '°' (U+00B0) (a number in code has"
                " no unit sign: its keyword says the unit, e.g. angle_deg=90)"
            ),
        ],
    ),
    # ---- Python conditions no reading can make true
    "never_negative_distance.py": (
        p("return self.range.distance_cm < 0"),
        [
            (
                "10:16: error: 'self.range.distance_cm < 0' can never be true: a distance sensor"
                " reads 0 or more, never below 0 (compare with a distance it can read, e.g."
                " self.range.distance_cm < 20)"
            ),
        ],
    ),
    "never_between.py": (
        p("return self.range.distance_cm < 10 and self.range.distance_cm > 50"),
        [
            (
                "10:16: error: 'self.range.distance_cm < 10 and self.range.distance_cm > 50' can"
                " never be true: self.range.distance_cm is never below 10 and above 50 at once (to"
                " go when either holds, write or: self.range.distance_cm < 10 or"
                " self.range.distance_cm > 50)"
            ),
        ],
    ),
    "never_chained.py": (
        p("return 50 < self.range.distance_cm < 10"),
        [
            (
                "10:16: error: '50 < self.range.distance_cm < 10' can never be true:"
                " self.range.distance_cm is never below 10 and above 50 at once"
            ),
        ],
    ),
    "never_none.py": (
        p("return self.bumper.any == None"),
        [
            (
                "10:16: error: 'self.bumper.any == None' can never be true: self.bumper.any is"
                " True or False, never None (use it as it is: self.bumper.any (or not"
                " self.bumper.any))"
            ),
        ],
    ),
    "never_is_none.py": (
        p("return self.range.distance_mm is None"),
        [
            (
                "10:16: error: 'self.range.distance_mm is None' can never be true:"
                " self.range.distance_mm is a number, never None (compare it with a number, e.g."
                " self.range.distance_mm < 20)"
            ),
        ],
    ),
    "never_in_if.py": (
        p(
            "if self.range.distance_mm <= -1:\n            return True\n        return self.bumpe"
            "r.any"
        ),
        [
            (
                "10:12: warning: 'self.range.distance_mm <= -1' can never be true: a distance"
                " sensor reads 0 or more, never at most -1 (compare with a distance it can read,"
                " e.g. self.range.distance_mm < 20)"
            ),
        ],
    ),
    "never_distance_text.py": (
        p('return self.range.distance_cm < "20 cm"'),
        [
            (
                "10:41: error: self.range.distance_cm is compared with the text '20 cm', and a"
                " sensor's value is a number (or True/False) (compare it with a number in cm: '20"
                " cm' is 20)"
            ),
        ],
    ),
    "honest_between.py": (
        p("return self.range.distance_cm > 10 and self.range.distance_cm < 50"),
        [],
    ),
    "honest_zero.py": (
        p("return self.range.distance_cm <= 0"),
        [],
    ),
    # ---- sleeping in code run every tick
    "sleep_in_update.py": (
        pa("time.sleep(2)\n        return Result.done()"),
        [
            (
                "11:9: warning: time.sleep(2) in Pause.update() holds up the whole robot for 2 s:"
                " Pause.update() is run once every tick (0.02 s), and while it sleeps no condition"
                " is checked, no timeout counted and no other action run (a condition or update()"
                " must return at once; wait with a state's action or timeout, never time.sleep:"
                ' e.g. a state of its own, pause = state(Wait(duration_s=2), on_done="next"))'
            ),
        ],
    ),
    "sleep_in_loop_in_update.py": (
        pa("while ctx.elapsed < 2:\n            time.sleep(0.1)\n        return Result.done()"),
        [
            (
                "12:13: warning: time.sleep(0.1) in Pause.update() holds up the whole robot for"
                " 0.1 s: Pause.update() is run once every tick (0.02 s), and while it sleeps no"
                " condition is checked, no timeout counted and no other action run (a condition or"
                " update() must return at once; wait with a state's action or timeout, never"
                " time.sleep: e.g. a state of its own, pause = state(Wait(duration_s=2),"
                ' on_done="next"))'
            ),
        ],
    ),
    "sleep_in_a_drive_of_its_own.py": (
        (
            "import time\n\nfrom roboscript import Drive, Mission, state\n\n\n"
            "class Cruise(Drive):\n    def update(self, ctx):\n        time.sleep(0.5)\n"
            "        return super().update(ctx)\n\n\nclass M(Mission):\n"
            '    go = state(Cruise(distance_mm=300), initial=True, on_done="end")\n'
            '    end = state(final="success")\n'
        ),
        [
            (
                "8:9: warning: time.sleep(0.5) in Cruise.update() holds up the whole robot for"
                " 0.5 s: Cruise.update() is run once every tick (0.02 s), and while it sleeps no"
                " condition is checked, no timeout counted and no other action run (a condition or"
                " update() must return at once; wait with a state's action or timeout, never"
                " time.sleep: e.g. a state of its own, pause = state(Wait(duration_s=2),"
                ' on_done="next"))'
            ),
            (
                "13:16: warning: if 'drive' fails (stalled) in state 'go', the mission ends in"
                ' failure (add on_failed="STATE" to handle it)'
            ),
        ],
    ),
    "sleep_imported_alone.py": (
        pa("sleep(1)\n        return Result.done()").replace(
            "import time\n", "from time import sleep\n"
        ),
        [
            (
                "11:9: warning: sleep(1) in Pause.update() holds up the whole robot for 1 s:"
                " Pause.update() is run once every tick (0.02 s), and while it sleeps no condition"
                " is checked, no timeout counted and no other action run (a condition or update()"
                " must return at once; wait with a state's action or timeout, never time.sleep:"
                ' e.g. a state of its own, pause = state(Wait(duration_s=2), on_done="next"))'
            ),
        ],
    ),
    "sleep_module_renamed.py": (
        pa("t.sleep(1)\n        return Result.done()").replace(
            "import time\n", "import time as t\n"
        ),
        [
            (
                "11:9: warning: t.sleep(1) in Pause.update() holds up the whole robot for 1 s:"
                " Pause.update() is run once every tick (0.02 s), and while it sleeps no condition"
                " is checked, no timeout counted and no other action run (a condition or update()"
                " must return at once; wait with a state's action or timeout, never time.sleep:"
                ' e.g. a state of its own, pause = state(Wait(duration_s=2), on_done="next"))'
            ),
        ],
    ),
    "sleep_in_helper.py": (
        pa(
            "self.rest()\n        return Result.done()\n\n    def rest(self):\n        time.sleep"
            "(0.5)"
        ),
        [
            (
                "15:9: warning: time.sleep(0.5) in Pause.rest() holds up the whole robot for 0.5"
                " s: Pause.rest() is run once every tick (0.02 s), and while it sleeps no"
                " condition is checked, no timeout counted and no other action run (a condition or"
                " update() must return at once; wait with a state's action or timeout, never"
                " time.sleep: e.g. a state of its own, pause = state(Wait(duration_s=2),"
                ' on_done="next"))'
            ),
        ],
    ),
    "sleep_in_condition.py": (
        "import time\n\n" + p("time.sleep(1)\n        return self.bumper.any"),
        [
            (
                "12:9: warning: time.sleep(1) in near() holds up the whole robot for 1 s: near()"
                " is run once every tick (0.02 s), and while it sleeps no condition is checked, no"
                " timeout counted and no other action run (a condition or update() must return at"
                " once; wait with a state's action or timeout, never time.sleep: e.g. a state of"
                ' its own, pause = state(Wait(duration_s=2), on_done="next"))'
            ),
        ],
    ),
    "sleep_zero.py": (
        pa("time.sleep(0)\n        return Result.done()"),
        [],
    ),
    # ---- what a word processor or a web page does to a file
    "tab_indent.yaml": (
        GOOD_Y.replace("    on:", "\ton:"),
        [
            "5:1: error: a tab at 5:1: YAML indents with spaces",
        ],
    ),
    "tab_after_key.yaml": (
        GOOD_Y.replace("mission: m", "mission:\tm"),
        [
            "1:9: error: a tab at 1:9: YAML needs spaces here, not tabs",
        ],
    ),
    "smart_quotes.yaml": (
        yw("“bumper.any”").replace('"“bumper.any”"', "“bumper.any”"),
        [
            (
                "7:14: error: cannot read the condition '“bumper.any”': '“' is a curly quote,"
                " as a word processor writes it (type straight quotes around the condition, or"
                ' none: "bumper.any")'
            ),
        ],
    ),
    "smart_single_quotes.yaml": (
        y("{drive: {distance: ‘50 cm’}}"),
        [
            (
                "4:28: error: drive distance: '‘50 cm’' is in curly quotes, as a word processor"
                " writes them (type straight quotes, or none: 50 cm)"
            ),
        ],
    ),
    "smart_quotes.py": (
        GOOD_P.replace('on_done="end"', "on_done=“end”"),
        [
            (
                "5:62: error: syntax error: invalid character '“' (U+201C) (a curly quote, as a"
                " word processor writes it: type straight quotes, \" or ')"
            ),
        ],
    ),
    "smart_apostrophes.py": (
        GOOD_P.replace('final="success"', "final=‘success’"),
        [
            (
                "7:23: error: syntax error: invalid character '‘' (U+2018) (a curly quote, as a"
                " word processor writes it: type straight quotes, \" or ')"
            ),
        ],
    ),
    "nbsp_indent.yaml": (
        GOOD_Y.replace("    on:", "\u00a0\u00a0\u00a0\u00a0on:"),
        [
            (
                "5:1: error: this line is indented with non-breaking spaces, copied from a web"
                " page or a document, and YAML indents with plain spaces (indent it again with the"
                " space bar)"
            ),
        ],
    ),
    "nbsp_in_value.yaml": (
        y("{drive: {distance: 50\u00a0cm}}"),
        [],
    ),
    "zero_width_space.yaml": (
        y("{drive\u200b: {distance: 50 cm}}"),
        [
            (
                "4:10: error: unknown action 'drive\u200b' ('drive' holds an invisible character,"
                " U+200B, copied from a web page or a document: type 'drive' again)"
            ),
        ],
    ),
    "en_dash_minus.yaml": (
        y("{rotate: {angle: –90 deg}}"),
        [
            (
                "4:26: error: rotate angle: '–90 deg' starts with a dash, as a word processor"
                " writes a minus (type the minus key: -90 deg)"
            ),
        ],
    ),
    "en_dash_minus.py": (
        ps("Rotate(angle_deg=–90)"),
        [
            (
                "5:33: error: syntax error: invalid character '–' (U+2013) (a dash, as a word"
                " processor writes a minus: type the minus key, -)"
            ),
        ],
    ),
    "fullwidth_colon.yaml": (
        GOOD_Y.replace("mission: m", "mission： m"),
        [
            (
                "1:8: error: '：' is a full-width colon, and YAML reads only ':' (type ':' with the"
                " keyboard set to English)"
            ),
        ],
    ),
    "bom.yaml": (
        "\ufeff" + GOOD_Y,
        [],
    ),
    "bom.py": (
        "\ufeff" + GOOD_P,
        [],
    ),
    "crlf.yaml": (
        GOOD_Y.replace("\n", "\r\n"),
        [],
    ),
    "crlf.py": (
        GOOD_P.replace("\n", "\r\n"),
        [],
    ),
    "cr_only.yaml": (
        GOOD_Y.replace("\n", "\r"),
        [],
    ),
    "utf16.yaml": (
        ("\ufeff" + GOOD_Y).encode("utf-16-le"),
        [
            "1:1: error: byte 0xFF is not UTF-8 text (save the file as UTF-8)",
        ],
    ),
    "latin1.yaml": (
        GOOD_Y.replace("mission: m", "mission: m\ndescription: café").encode("latin-1"),
        [
            "2:17: error: byte 0xE9 is not UTF-8 text (save the file as UTF-8)",
        ],
    ),
    "markdown_fence.yaml": (
        "```yaml\n" + GOOD_Y + "```\n",
        [
            (
                "1:1: error: this line is a Markdown code fence (```), copied with the mission"
                " (take away each ``` line: the file holds the mission alone)"
            ),
        ],
    ),
    "markdown_fence.py": (
        "```python\n" + GOOD_P + "```\n",
        [
            (
                "1:1: error: this line is a Markdown code fence (```), copied with the mission"
                " (take away each ``` line: the file holds the mission alone)"
            ),
        ],
    ),
    "html_entities.yaml": (
        yw("range.distance_cm &lt; 20"),
        [
            (
                "7:33: error: '&lt;' is how a web page's source writes '<' (write"
                " range.distance_cm < 20)"
            ),
        ],
    ),
    "mission.txt": (
        GOOD_Y,
        [
            (
                " error: a mission file ends in .yaml or .py (got '.txt') (save it as"
                " mission.yaml, or mission.py for a Python mission: the ending tells roboscript"
                " how to read it)"
            ),
        ],
    ),
    "mission.docx": (
        docx(GOOD_Y),
        [
            (
                " error: a mission file ends in .yaml or .py (got '.docx') (mission.docx is a Word"
                " document, not plain text: copy the mission into a plain-text editor (the one you"
                " write code in) and save it as mission.yaml, or .py for a Python mission)"
            ),
        ],
    ),
    "mission.yaml.txt": (
        GOOD_Y,
        [
            (
                " error: a mission file ends in .yaml or .py (got '.txt') (rename it to"
                " mission.yaml: the editor added '.txt', which Windows hides from the file's name)"
            ),
        ],
    ),
    "mission.py.txt": (
        GOOD_P,
        [
            (
                " error: a mission file ends in .yaml or .py (got '.txt') (rename it to"
                " mission.py: the editor added '.txt', which Windows hides from the file's name)"
            ),
        ],
    ),
    "MISSION.YAML": (
        GOOD_Y,
        [],
    ),
    "json_mission.yaml": (
        (
            '{"mission": "m", "states": {"go": {"do": {"drive": {"distance": "50 cm"}},'
            ' "on": {"done": "end", "failed": "end"}}, "end": {"final": "success"}}}\n'
        ),
        [],
    ),
    "empty.yaml": (
        "",
        [
            (
                "1:1: error: a mission file is a mapping with 'mission:', 'initial:' and 'states:'"
                " (this file is empty, or holds only comments: is it saved?)"
            ),
        ],
    ),
    "only_comments.yaml": (
        "# my mission\n# TODO\n",
        [
            (
                "1:1: error: a mission file is a mapping with 'mission:', 'initial:' and 'states:'"
                " (this file is empty, or holds only comments: is it saved?)"
            ),
        ],
    ),
    "empty.py": (
        "",
        [
            (
                "1:1: error: this file holds no mission (write a class that extends Mission: class"
                " MyMission(Mission): ...)"
            ),
        ],
    ),
    # ---- copied prompts and transcripts
    "python_prompt.py": (
        "\n".join(">>> " + line if line else ">>>" for line in GOOD_P.splitlines()) + "\n",
        [
            (
                "1:1: error: this line starts with '>>> ', the prompt of Python's interactive"
                " shell, copied with the code (take away '>>> ' and '... ' at the start of each"
                " line, keeping the indentation after them)"
            ),
        ],
    ),
    "python_prompt_first_line.py": (
        ">>> " + GOOD_P,
        [
            (
                "1:1: error: this line starts with '>>> ', the prompt of Python's interactive"
                " shell, copied with the code (take away '>>> ' and '... ' at the start of each"
                " line, keeping the indentation after them)"
            ),
        ],
    ),
    "ipython_prompt.py": (
        "In [1]: " + GOOD_P,
        [
            (
                "1:1: error: this line starts with 'In [1]: ', the prompt of IPython or a"
                " notebook, copied with the code (take away 'In [1]: ' and '...: ' at the start of"
                " each line, keeping the indentation after them)"
            ),
        ],
    ),
    "shell_prompt.yaml": (
        "$ roboscript run m.yaml\n" + GOOD_Y,
        [
            (
                "1:1: error: this line is a command typed in a terminal, copied with the mission"
                " (take it away: type commands in the terminal, and keep the file for the mission)"
            ),
        ],
    ),
    "shell_prompt.py": (
        "$ roboscript run m.py\n" + GOOD_P,
        [
            (
                "1:1: error: this line is a command typed in a terminal, copied with the mission"
                " (take it away: type commands in the terminal, and keep the file for the mission)"
            ),
        ],
    ),
    "dots_prompt.py": (
        GOOD_P.replace("    def near", "... def near"),
        [
            (
                "9:1: error: this line starts with '... ', the prompt Python's interactive shell"
                " shows inside a block, copied with the code (take away '>>> ' and '... ' at the"
                " start of each line, keeping the indentation after them)"
            ),
        ],
    ),
    "placeholder_next.yaml": (
        GOOD_Y.replace("done: end", "done: NEXT"),
        [
            (
                "5:16: error: there is no state 'NEXT' (NEXT stands for a state of yours in the"
                " examples: write the name of one of them (end, go))"
            ),
        ],
    ),
    "placeholder_dots.yaml": (
        y("{drive: {...}}"),
        [
            (
                "4:18: error: '...' stands for the parameters an example leaves to you (write"
                " them: {drive: {distance: 50 cm}})"
            ),
        ],
    ),
    "placeholder_dots.py": (
        ps("Drive(...)"),
        [
            (
                "5:16: error: drive distance: '...' stands for the value an example leaves to you:"
                " write distance_mm=500"
            ),
        ],
    ),
    # ---- YAML's indentation
    "state_keys_dedented.yaml": (
        (
            "mission: m\n"
            "states:\n"
            "  go:\n"
            "  do: {drive: {distance: 50 cm}}\n"
            "  on: {done: end, failed: end}\n"
            "  end: {final: success}\n"
        ),
        [
            (
                "4:3: error: 'do:' is indented as far as the state names, so it makes a state"
                " called 'do' (indent it two more spaces, under 'go:', to make it part of state"
                " 'go')"
            ),
            (
                "5:3: error: 'on:' is indented as far as the state names, so it makes a state"
                " called 'on' (indent it two more spaces, under 'go:', to make it part of state"
                " 'go')"
            ),
        ],
    ),
    "three_space_indent.yaml": (
        (
            "mission: m\n"
            "states:\n"
            "   go:\n"
            "     do: {drive: {distance: 50 cm}}\n"
            "    on: {done: end, failed: end}\n"
            "   end: {final: success}\n"
        ),
        [
            (
                "5:5: error: this line is indented differently from the lines above it (YAML nests"
                " by indentation: line it up, with spaces, with the key or '- ' item it belongs"
                " with)"
            ),
        ],
    ),
    "do_over_indented.yaml": (
        (
            "mission: m\n"
            "states:\n"
            "  go:\n"
            "      do: {drive: {distance: 50 cm}}\n"
            "    on: {done: end, failed: end}\n"
            "  end: {final: success}\n"
        ),
        [
            (
                "5:5: error: this line is indented differently from the lines above it (YAML nests"
                " by indentation: line it up, with spaces, with the key or '- ' item it belongs"
                " with)"
            ),
        ],
    ),
    "list_dash_no_space.yaml": (
        (
            "mission: m\n"
            "states:\n"
            "  go:\n"
            "    do: {drive: {distance: 50 cm}}\n"
            "    on: {done: end, failed: end}\n"
            "    when:\n"
            "      -{if: bumper.any, goto: end}\n"
            "  end: {final: success}\n"
        ),
        [
            (
                "7:7: error: '-' starts a list item only with a space after it (write - {if:"
                " bumper.any, goto: end})"
            ),
        ],
    ),
    "no_space_after_colon_top.yaml": (
        GOOD_Y.replace("mission: m", "mission:m"),
        [
            (
                "1:8: error: 'mission:m' has no space after its ':', so YAML reads it as one word"
                " (write mission: m)"
            ),
        ],
    ),
    "missing_closing_brace.yaml": (
        y("{drive: {distance: 50 cm}"),
        [
            "4:9: error: this `{` is never closed (close it with `}` before 5:5)",
        ],
    ),
    # ---- Python's shape
    "no_import.py": (
        GOOD_P.replace("from roboscript import Drive, Mission, state\n", ""),
        [
            (
                "3:9: error: NameError: name 'Mission' is not defined (add 'from roboscript import"
                " Mission')"
            ),
        ],
    ),
    "missing_state_import.py": (
        GOOD_P.replace("Drive, Mission, state", "Drive, Mission"),
        [
            (
                "5:10: error: NameError: name 'state' is not defined (add 'from roboscript import"
                " state')"
            ),
        ],
    ),
    "missing_action_import.py": (
        GOOD_P.replace("Drive, Mission, state", "Mission, state"),
        [
            (
                "5:16: error: NameError: name 'Drive' is not defined (add 'from roboscript import"
                " Drive')"
            ),
        ],
    ),
    "import_module_only.py": (
        GOOD_P.replace("from roboscript import Drive, Mission, state", "import roboscript"),
        [
            (
                "4:9: error: NameError: name 'Mission' is not defined (add 'from roboscript import"
                " Mission')"
            ),
        ],
    ),
    "lowercase_import.py": (
        GOOD_P.replace(
            "from roboscript import Drive, Mission, state",
            "from roboscript import drive, mission, state",
        ),
        [
            "1:1: error: roboscript has no 'drive' to import (did you mean 'Drive'?)",
        ],
    ),
    "wildcard_import.py": (
        GOOD_P.replace("from roboscript import Drive, Mission, state", "from roboscript import *"),
        [],
    ),
    "states_in_init.py": (
        GOOD_P.replace(
            "    go = state(", "    def __init__(self):\n        self.go = state("
        ).replace("    end = state(", "        self.end = state("),
        [
            (
                "6:9: error: mission M has no states (write each state in the class body, not in a"
                " method: go = state(...))"
            ),
        ],
    ),
    "count_in_init.py": (
        p("self.count += 1\n        return self.count > 3").replace(
            '    end = state(final="success")\n',
            '    end = state(final="success")\n\n    def __init__(self):\n        self.count = 0\n',
        ),
        [],
    ),
    "count_on_class_read_plain.py": (
        p("count = count + 1\n        return count > 3").replace(
            '    end = state(final="success")\n',
            '    end = state(final="success")\n    count = 0\n',
        ),
        [
            (
                "11:9: error: 'count' is read here before this method gives it a value: a method"
                " that sets 'count' has a 'count' of its own, which starts with no value each time"
                " the method runs (keep it on the mission: write self.count (with count = 0 in the"
                " class))"
            ),
        ],
    ),
    "action_without_parentheses.py": (
        ps("Drive"),
        [
            (
                "5:16: error: state 'go': Drive is a kind of action; call it to make one (write"
                " Drive(distance_mm=500))"
            ),
        ],
    ),
    "action_class_with_keywords_missing.py": (
        ps("Drive()"),
        [
            (
                "5:16: error: drive needs a distance or a duration (write Drive(distance_mm=500)"
                " or Drive(duration_s=2))"
            ),
        ],
    ),
    "action_lowercase.py": (
        ps("drive(distance_mm=500)"),
        [
            "5:16: error: NameError: name 'drive' is not defined (did you mean 'Drive'?)",
        ],
    ),
    "state_without_call.py": (
        GOOD_P.replace('end = state(final="success")', "end = state"),
        [
            (
                "7:11: error: 'end = state' names the state function without calling it (call"
                ' it: end = state(...), e.g. end = state(final="success"))'
            ),
        ],
    ),
    "condition_without_self.py": (
        GOOD_P.replace("def near(self):", "def near():"),
        [
            "9:5: error: condition method 'near' must take only self (def near(self):)",
        ],
    ),
    "sensor_without_self.py": (
        p("return bumper.any"),
        [
            (
                "10:16: error: name 'bumper' is not defined (inside a method, the mission's own"
                " values are read through self: self.bumper)"
            ),
        ],
    ),
    "condition_called_in_when.py": (
        GOOD_P.replace('("near", "end")', '(near(), "end")'),
        [
            (
                "6:23: error: NameError: name 'near' is not defined (a condition is named in"
                " quotes: write 'near')"
            ),
        ],
    ),
    "condition_method_in_when_unquoted.py": (
        GOOD_P.replace('("near", "end")', '(near, "end")'),
        [
            (
                "6:23: error: NameError: name 'near' is not defined (a condition is named in"
                " quotes: write 'near')"
            ),
        ],
    ),
    "target_unquoted.py": (
        GOOD_P.replace('on_done="end"', "on_done=end"),
        [
            (
                "5:62: error: NameError: name 'end' is not defined (a state is named in quotes:"
                " write 'end')"
            ),
        ],
    ),
    "condition_returns_action.py": (
        p("return Drive(distance_mm=-100)"),
        [
            (
                "10:16: error: Drive(...) in condition method 'near' is made and thrown away: a"
                " condition cannot run an action (run it in a state of its own, e.g. turn ="
                " state(Drive(...), ...), and go there when the condition holds: when=[('near',"
                " 'turn')])"
            ),
        ],
    ),
    "condition_yields_action.py": (
        p("yield Drive(distance_mm=-100)"),
        [
            (
                "10:9: error: condition method 'near' uses yield, so it returns a generator, which"
                " counts as true at once (write return, not yield: a condition returns True or"
                " False; an action runs in a state of its own)"
            ),
            (
                "10:15: error: Drive(...) in condition method 'near' is made and thrown away: a"
                " condition cannot run an action (run it in a state of its own, e.g. turn ="
                " state(Drive(...), ...), and go there when the condition holds: when=[('near',"
                " 'turn')])"
            ),
        ],
    ),
    "update_returns_action.py": (
        pa("return Drive(distance_mm=100)").replace(
            "from roboscript import Action,", "from roboscript import Drive, Action,"
        ),
        [
            (
                "11:9: warning: Pause.update() returns Drive(...), an action, which update() cannot"
                " run, and roboscript reads what update() returns as how the action is going: a"
                " Result, or None while it runs (run it in a state of its own, and go there when"
                " this one is done; return Result.done() when it has finished, and None while it"
                " is still going)"
            ),
        ],
    ),
    "update_returns_true.py": (
        pa("return True"),
        [
            (
                "11:9: warning: Pause.update() returns True, and roboscript reads what update()"
                " returns as how the action is going: a Result, or None while it runs (return"
                " Result.done() when it has finished, and None while it is still going)"
            ),
        ],
    ),
    "update_returns_string.py": (
        pa('return "done"'),
        [
            (
                "11:9: warning: Pause.update() returns 'done', and roboscript reads what update()"
                " returns as how the action is going: a Result, or None while it runs (return"
                " Result.done() when it has finished, and None while it is still going)"
            ),
        ],
    ),
    "condition_prints_only.py": (
        p("print(self.range.distance_cm)"),
        [
            (
                "9:5: warning: condition method 'near' never returns a value, so it never holds"
                " (return True or False, e.g. return self.bumper.any)"
            ),
        ],
    ),
    "condition_assigns.py": (
        p("return self.bumper.any = True"),
        [
            "10:32: error: invalid syntax",
        ],
    ),
    "condition_one_equals.py": (
        p("if self.bumper.any = True:\n            return True\n        return False"),
        [
            (
                "10:12: error: syntax error: cannot assign to attribute here. Maybe you meant '=='"
                " instead of '='?"
            ),
        ],
    ),
    "missing_colon_def.py": (
        GOOD_P.replace("def near(self):", "def near(self)"),
        [
            (
                "9:19: error: expected ':' (a line starting with class, def, if, elif, else, for"
                " or while ends with ':')"
            ),
        ],
    ),
    "initial_missing.py": (
        GOOD_P.replace("initial=True, ", ""),
        [
            (
                "4:1: error: mission M has no initial state (mark the first state, e.g. go ="
                " state(..., initial=True))"
            ),
        ],
    ),
    "initial_twice.py": (
        GOOD_P.replace(
            'end = state(final="success")', 'end = state(final="success", initial=True)'
        ),
        [
            "7:42: error: states 'go' and 'end' are both initial; a mission starts in one",
        ],
    ),
    "final_misspelt.py": (
        GOOD_P.replace('final="success"', 'final="sucess"'),
        [
            (
                "7:23: error: state 'end': final is 'success' or 'failure', got 'sucess' (did you"
                " mean 'success'?)"
            ),
        ],
    ),
    "on_done_case.py": (
        GOOD_P.replace('on_done="end"', 'on_done="End"'),
        [
            "5:62: error: there is no state 'End' (did you mean 'end'?)",
        ],
    ),
    "when_not_list.py": (
        GOOD_P.replace('when=[("near", "end")]', 'when=("near", "end")'),
        [],
    ),
    "mission_not_subclass.py": (
        GOOD_P.replace("class M(Mission):", "class M:"),
        [
            (
                "4:1: error: class M has states but does not extend Mission, so it is no mission"
                " (write class M(Mission):, and import Mission from roboscript)"
            ),
        ],
    ),
    "run_at_bottom.py": (
        GOOD_P + "\n\nM().run()\n",
        [
            (
                "13:1: error: a mission has no run(): take this line away (roboscript run and"
                " python both run the mission a file defines; to say so in the file, write"
                ' M.main() under if __name__ == "__main__":)'
            ),
        ],
    ),
    "main_guard.py": (
        GOOD_P + '\n\nif __name__ == "__main__":\n    M.main()\n',
        [],
    ),
    "while_loop_wait.py": (
        p("while not self.bumper.any:\n            pass\n        return True"),
        [
            (
                "10:9: error: this loop waits for self.bumper.any to change, but what a condition"
                " reads stays as it is while the condition runs (the next reading comes at the"
                " next tick), so the loop never ends (return at once, e.g. return self.bumper.any:"
                " roboscript asks the condition again at every tick)"
            ),
        ],
    ),
    "while_loop_wait_for_time.py": (
        p("while self.state_time < 2:\n            print('waiting')\n        return True"),
        [
            (
                "10:9: error: this loop waits for self.state_time to change, but what a condition"
                " reads stays as it is while the condition runs (the next reading comes at the"
                " next tick), so the loop never ends (return at once, e.g. return self.state_time"
                " >= 2: roboscript asks the condition again at every tick)"
            ),
        ],
    ),
    # a loop with a way out: check cannot tell whether it is taken; run stops it at its line
    "loop_until_return.py": (
        p("while True:\n            if self.bumper.any:\n                return True"),
        [],
    ),
    "honest_loop_counting.py": (
        p(
            "n = 0\n        while n < 3 and self.bumper.any:\n            n += 1\n"
            "        return n == 3"
        ),
        [],
    ),
    "indent_mixed_tabs.py": (
        GOOD_P.replace("        return self.bumper.any", "\treturn self.bumper.any"),
        [
            (
                "10:1: error: syntax error: inconsistent use of tabs and spaces in indentation"
                " (indent with spaces only: a tab looks like spaces but Python counts it apart)"
            ),
        ],
    ),
    "indent_wrong.py": (
        GOOD_P.replace("        return self.bumper.any", "    return self.bumper.any"),
        [
            (
                "10:5: error: expected an indented block after function definition on line 9"
                " (indent the lines that belong to it 4 spaces further than the line ending in ':')"
            ),
        ],
    ),
    # ---- misspelt actions, sensors and parameters, in every position
    "action_misspelt.yaml": (
        y("{drvie: {distance: 50 cm}}"),
        [
            "4:10: error: unknown action 'drvie' (did you mean 'drive'?)",
        ],
    ),
    "action_misspelt_in_parallel.yaml": (
        y(
            "{parallel: {all: [{drive: {distance: 50 cm}}, {play_tone: {frequncy: 440 Hz, duratio"
            "n: 1 s}}]}}"
        ),
        [
            "4:68: error: 'play_tone' has no parameter 'frequncy' (did you mean 'frequency'?)",
        ],
    ),
    "action_misspelt_in_repeat.yaml": (
        y("{repeat: {times: 4, do: {roate: {angle: 90 deg}}}}"),
        [
            "4:34: error: unknown action 'roate' (did you mean 'rotate'?)",
        ],
    ),
    "action_misspelt_in_during.yaml": (
        GOOD_Y.replace(
            "    on:", "    during: [{play_tone: {frequency: 440 Hz, duraton: 1 s}}]\n    on:"
        ),
        [
            "5:46: error: 'play_tone' has no parameter 'duraton' (did you mean 'duration'?)",
        ],
    ),
    "action_capitalised.yaml": (
        y("{Drive: {distance: 50 cm}}"),
        [
            "4:10: error: unknown action 'Drive' (did you mean 'drive'?)",
        ],
    ),
    "param_misspelt.yaml": (
        y("{drive: {distanse: 50 cm}}"),
        [
            "4:18: error: 'drive' has no parameter 'distanse' (did you mean 'distance'?)",
        ],
    ),
    "param_python_name.yaml": (
        y("{drive: {distance_mm: 500}}"),
        [
            "4:18: error: 'drive' has no parameter 'distance_mm' (did you mean 'distance'?)",
        ],
    ),
    "sensor_misspelt.yaml": (
        yw("bumber.any"),
        [
            "7:15: error: unknown name 'bumber' in a condition (did you mean 'bumper'?)",
        ],
    ),
    "sensor_without_unit.yaml": (
        yw("range.distance < 20"),
        [
            (
                "7:21: error: 'range.distance' needs its unit in the name: 'range.distance_cm' or"
                " 'range.distance_mm' (e.g. range.distance_cm < 20, or give the number a unit:"
                " range.distance < 2 cm)"
            ),
        ],
    ),
    "sensor_attr_misspelt.yaml": (
        yw("range.distnce_cm < 20"),
        [
            (
                "7:21: error: 'range' has no 'distnce_cm' (it has distance_cm, distance_mm) (did"
                " you mean 'range.distance_cm'?)"
            ),
        ],
    ),
    "condition_single_equals.yaml": (
        yw("bumper.any = true"),
        [
            (
                "7:26: error: cannot read the condition 'bumper.any = true': '=' sets a value; a"
                " condition compares (write '==' to compare: bumper.any == true)"
            ),
        ],
    ),
    "condition_arrow_wrong.yaml": (
        yw("range.distance_cm =< 20"),
        [
            (
                "7:33: error: cannot read the condition 'range.distance_cm =< 20': '=<' is not a"
                " comparison (write it the other way round: range.distance_cm <= 20)"
            ),
        ],
    ),
    "condition_unit_in_number.yaml": (
        yw("range.distance_cm < 20cm"),
        [],
    ),
    "action_misspelt.py": (
        ps("Drvie(distance_mm=500)"),
        [
            "5:16: error: NameError: name 'Drvie' is not defined (did you mean 'Drive'?)",
        ],
    ),
    "param_misspelt.py": (
        ps("Rotate(angel_deg=90)"),
        [
            "5:16: error: Rotate() has no parameter 'angel_deg' (did you mean 'angle_deg'?)",
        ],
    ),
    "param_without_unit.py": (
        ps("Drive(distance=500)"),
        [
            "5:16: error: Drive() has no parameter 'distance' (did you mean 'distance_mm'?)",
        ],
    ),
    "param_yaml_name.py": (
        ps("PlayTone(frequency=440, duration=1)"),
        [
            ("5:16: error: PlayTone() has no parameter 'frequency' (did you mean 'frequency_hz'?)"),
        ],
    ),
    "sensor_misspelt.py": (
        p("return self.bumpers.any"),
        [
            "10:16: error: M has no 'bumpers' (did you mean 'bumper'?)",
        ],
    ),
    "sensor_attr_without_unit.py": (
        p("return self.range.distance < 20"),
        [
            (
                "10:16: error: self.range has no 'distance' (it has distance_mm, distance_cm) (did"
                " you mean 'distance_cm'?)"
            ),
        ],
    ),
    "sensor_capitalised.py": (
        p("return self.Range.distance_cm < 20"),
        [
            "10:16: error: M has no 'Range' (did you mean 'range'?)",
        ],
    ),
    # ---- units in every form
    "unit_no_space.yaml": (
        y("{drive: {distance: 50cm}}"),
        [],
    ),
    "unit_capitals.yaml": (
        y("{drive: {distance: 50 CM}}"),
        [],
    ),
    "unit_word.yaml": (
        y("{drive: {distance: 50 centimetres}}"),
        [
            (
                "4:28: error: drive distance: unknown unit 'centimetres' for a distance (write 50"
                " cm)"
            ),
        ],
    ),
    "unit_plural_cms.yaml": (
        y("{drive: {distance: 50 cms}}"),
        [
            "4:28: error: drive distance: unknown unit 'cms' for a distance (write 50 cm)",
        ],
    ),
    "unit_of_speed_for_distance.yaml": (
        y("{drive: {distance: 50 cm/s}}"),
        [
            (
                "4:28: error: drive distance: 'cm/s' is a unit of speed, but this is a distance"
                " (use mm, cm, m, in)"
            ),
        ],
    ),
    "unit_degree_sign.yaml": (
        y("{rotate: {angle: 90°}}"),
        [],
    ),
    "unit_rate_for_angle.yaml": (
        y("{rotate: {angle: 90 deg/s}}"),
        [
            (
                "4:26: error: rotate angle: 'deg/s' is a unit of turn rate, but this is an angle"
                " (use deg, degrees, rad, rev)"
            ),
        ],
    ),
    "unit_per_second_words.yaml": (
        y("{drive: {distance: 50 cm, speed: 20 cm per second}}"),
        [
            "4:42: error: drive speed: unknown unit 'cm per second' for a speed (write 20 cm/s)",
        ],
    ),
    "unit_seconds_word.yaml": (
        y("{wait: {duration: 2 seconds}}"),
        [
            "4:27: error: wait duration: unknown unit 'seconds' for a time (write 2 s)",
        ],
    ),
    "unit_hours.yaml": (
        y("{wait: {duration: 1 h}}"),
        [
            "4:27: error: wait duration: unknown unit 'h' for a time (use s, sec, ms, min)",
        ],
    ),
    "unit_trailing_dot.yaml": (
        y("{drive: {distance: 50 cm.}}"),
        [
            "4:28: error: drive distance: unknown unit 'cm.' for a distance (write 50 cm)",
        ],
    ),
    "unit_number_in_words.yaml": (
        y("{drive: {distance: fifty cm}}"),
        [
            "4:28: error: drive distance: expected a distance such as '50 cm', got 'fifty cm'",
        ],
    ),
    "unit_plus_sign.yaml": (
        y("{rotate: {angle: +90 deg}}"),
        [],
    ),
    "unit_ms_glued.yaml": (
        y("{wait: {duration: 200ms}}"),
        [],
    ),
    "unit_kmh.yaml": (
        y("{drive: {distance: 50 cm, speed: 1 km/h}}"),
        [
            "4:42: error: drive speed: unknown unit 'km/h' for a speed (write 27.78 cm/s)",
        ],
    ),
    "unit_percent_speed.yaml": (
        y("{drive: {distance: 50 cm, speed: 50%}}"),
        [
            (
                "4:42: error: drive speed: '%' is a unit of percent, but this is a speed (use"
                " mm/s, cm/s, m/s, in/s, mm/sec)"
            ),
        ],
    ),
    "unit_text_in_python.py": (
        ps('Drive(distance_mm="50 cm")'),
        [],
    ),
    "unit_cm_keyword.py": (
        ps("Drive(distance_cm=50)"),
        [
            (
                "5:16: error: Drive() has no parameter 'distance_cm' (write distance_mm=500, which"
                " is 50 cm)"
            ),
        ],
    ),
    "unit_radians_in_python.py": (
        "import math\n" + ps("Rotate(angle_deg=math.pi / 2)"),
        [
            (
                "6:33: warning: rotate angle: 1.5708 deg is a very small angle (if you meant"
                " radians, that is 90 deg: write angle_deg=90)"
            ),
        ],
    ),
    "unit_ms_for_seconds.py": (
        ps("Wait(duration_s=2000)"),
        [],
    ),
    "unit_m_s_for_mm_s.py": (
        ps("Drive(distance_mm=500, speed_mm_s=0.2)"),
        [
            (
                "5:50: warning: drive speed: 0.2 mm/s is too slow to overcome the wheels'"
                " friction, so mirto may not move and 'drive' may fail (stalled) (write speed: 10"
                " mm/s or more)"
            ),
        ],
    ),
    "unit_timeout_ms.py": (
        GOOD_P.replace("initial=True,", "initial=True, timeout_s=5000,"),
        [
            (
                "5:64: error: state 'go': timeout_s: 5000 s is longer than any run (at most 1"
                " hour) (write a time of at most 3600 s)"
            ),
        ],
    ),
    # ---- states and outcomes
    "initial_wrong_case.yaml": (
        GOOD_Y.replace("states:", "initial: Go\nstates:"),
        [
            "2:10: error: the initial state 'Go' is not one of the states (did you mean 'go'?)",
        ],
    ),
    "goto_wrong_case.yaml": (
        GOOD_Y.replace("done: end", "done: End"),
        [
            "5:16: error: there is no state 'End' (did you mean 'end'?)",
        ],
    ),
    "final_misspelt.yaml": (
        GOOD_Y.replace("final: success", "final: sucess"),
        [
            (
                "6:16: error: state 'end': final is 'success' or 'failure', got 'sucess' (did you"
                " mean 'success'?)"
            ),
        ],
    ),
    "outcome_fail.yaml": (
        GOOD_Y.replace("failed: end", "fail: end"),
        [
            (
                "5:21: error: unknown outcome 'fail' (outcomes: done, failed, timeout) (write"
                " failed: end)"
            ),
        ],
    ),
    "outcome_finished.yaml": (
        GOOD_Y.replace("done: end", "finished: end"),
        [
            (
                "5:10: error: unknown outcome 'finished' (outcomes: done, failed, timeout) (write"
                " done: end)"
            ),
        ],
    ),
    "state_name_with_space.yaml": (
        GOOD_Y.replace("  end: {final: success}", "  the end: {final: success}").replace(
            "done: end, failed: end", "done: the end, failed: the end"
        ),
        [],
    ),
    "state_twice.yaml": (
        GOOD_Y + "  go: {final: failure}\n",
        [
            (
                "7:3: error: 'go' is given twice (first on line 3) (keep one of the two, or give"
                " one of them another name)"
            ),
        ],
    ),
    "timeout_negative.yaml": (
        GOOD_Y.replace("    on:", "    timeout: -5 s\n    on:"),
        [
            (
                "5:14: error: state 'go': timeout is a positive number of seconds, got '-5 s'"
                " (write `timeout: 10 s`)"
            ),
        ],
    ),
    "timeout_bare.yaml": (
        GOOD_Y.replace("    on:", "    timeout: 10\n    on:"),
        [
            (
                "3:3: warning: if state 'go' times out the mission ends in failure (add 'on:"
                " {timeout: STATE}' to handle it)"
            ),
            "5:14: warning: state 'go': timeout: 10 taken as 10 s; write `10 s`",
        ],
    ),
}


@pytest.fixture(scope="module")
def checked(tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[str]]:
    """What one ``roboscript check`` of every file prints, by file."""
    folder: Path = tmp_path_factory.mktemp("classroom")
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
def test_each_classroom_mistake_gets_its_answer_at_its_place(
    checked: dict[str, list[str]], name: str
) -> None:
    assert checked[name] == MISTAKES[name][1]


def test_run_warns_of_a_sleep_in_update_before_the_robot_moves(tmp_path: Path) -> None:
    (tmp_path / "nap.py").write_text(str(MISTAKES["sleep_in_update.py"][0]), encoding="utf-8")
    result = run_cli("run", "nap.py", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines()[0] == "nap.py:" + MISTAKES["sleep_in_update.py"][1][0]


def test_a_sleep_in_a_yaml_missions_behaviour_is_told_at_its_line_with_a_yaml_wait(
    tmp_path: Path,
) -> None:
    (tmp_path / "spin.py").write_text(
        "import time\n\nfrom roboscript import Action, Result\n\n\nclass Spin(Action):\n"
        '    name = "spin"\n    requires = frozenset({"drive_base"})\n\n'
        "    def update(self, ctx):\n        time.sleep(1)\n        return Result.done()\n",
        encoding="utf-8",
    )
    (tmp_path / "m.yaml").write_text(
        "mission: m\nbehaviours: [spin.py]\nstates:\n  go:\n    do: {spin: {}}\n"
        "    on: {done: end, failed: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    result = run_cli("check", "m.yaml", cwd=tmp_path)
    told = (
        "spin.py:11:9: warning: time.sleep(1) in Spin.update() holds up the whole robot"
        " for 1 s: Spin.update() is run once every tick (0.02 s), and while it sleeps no"
        " condition is checked, no timeout counted and no other action run (a condition"
        " or update() must return at once; wait with a state's action or timeout, never"
        " time.sleep: e.g. a state of its own, pause: {do: {wait: {duration: 2 s}}, on:"
        " {done: next}})"
    )
    assert result.stderr.splitlines() == [
        told,
        "checked 1 file: 0 with errors",
    ]
