# Runs roboscript's hub agent, unchanged, on these stand-ins: reads the recorded host session
# (/session.txt: one "elapsed_ms hex" line per tunnel message, then "end elapsed_ms").
import sys

import runloop
import vclock

sys.modules["time"] = vclock.TimeModule()
with open("/session.txt") as lines:
    for line in lines:
        when, data = line.split()
        if when == "end":
            runloop.end_ms = int(data)
        else:
            runloop.session.append((int(when), bytes.fromhex(data)))
import hub_agent  # noqa: E402,F401 - importing it starts it, as on the hub
