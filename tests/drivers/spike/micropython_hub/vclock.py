# A virtual millisecond clock for the agent under real MicroPython. Ticks values are made with
# MicroPython's own time.ticks_add, so they wrap exactly as the hub's do; the session starts
# just before the wrap.
import time as _real_time

_START = _real_time.ticks_add(0, -1000)  # 1000 ms before ticks_ms wraps to 0
elapsed_ms = 0


def ticks_ms():
    return _real_time.ticks_add(_START, elapsed_ms)


def advance(ms):
    global elapsed_ms
    elapsed_ms += ms


class TimeModule:
    """What the agent imports from ``time``: the virtual ticks_ms, MicroPython's arithmetic."""

    ticks_add = staticmethod(_real_time.ticks_add)
    ticks_diff = staticmethod(_real_time.ticks_diff)
    ticks_ms = staticmethod(ticks_ms)
