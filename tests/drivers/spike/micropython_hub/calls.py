# Every hub API call the agent makes, printed for the test (one line each).
import vclock


def record(name, *args):
    print("CALL", vclock.elapsed_ms, name, " ".join(str(a) for a in args))


class Pending:
    """An action that ends later. LEGO does not document the awaitable type its motor calls
    return; this one is a plain iterator, the least MicroPython's ``await`` accepts."""

    def __init__(self, duration_ms, result):
        self.end_ms = vclock.elapsed_ms + duration_ms
        self.result = result

    def __iter__(self):
        return self

    def __next__(self):
        if vclock.elapsed_ms >= self.end_ms:
            raise StopIteration(self.result)
        # otherwise: not yet (None goes up to the run loop, which steps the clock)
