# Stand-in for SPIKE App 3's runloop module (LEGO's documentation: run(*functions),
# sleep_ms(duration)), on the virtual clock. run() steps each coroutine in turn, one virtual
# millisecond a round, and hands the host's recorded tunnel messages to the agent on time.
import vclock

session = []  # (elapsed ms, payload bytes): set by the session runner
end_ms = 0


class _Sleep:
    def __init__(self, duration_ms):
        self.end_ms = vclock.elapsed_ms + duration_ms

    def __iter__(self):
        return self

    def __next__(self):
        if vclock.elapsed_ms >= self.end_ms:
            raise StopIteration(None)
        # otherwise: not yet (None goes up to the run loop, which steps the clock)


def sleep_ms(duration):
    return _Sleep(duration)


def run(*functions):
    import hub

    tasks = list(functions)
    while vclock.elapsed_ms < end_ms:
        while session and session[0][0] <= vclock.elapsed_ms:
            _, payload = session.pop(0)
            hub.tunnel.receive(payload)
        for task in tasks:
            try:
                task.send(None)
            except StopIteration:
                tasks.remove(task)
        vclock.advance(1)
    print("END", vclock.elapsed_ms)
