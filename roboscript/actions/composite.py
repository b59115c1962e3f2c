"""Actions made of actions: ``parallel`` and ``repeat``.

``parallel`` runs several actions at once (drive while a tune plays) and ends when all of them
have (``all``) or when the first one has (``any``); ``repeat`` runs one action several times in
a row. Each child is made fresh from its factory when the composite starts, so a state that is
entered again starts from scratch.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from roboscript.actions.base import Action, ActionContext, Outcome, Result

__all__ = ["Parallel", "Repeat"]

ActionFactory = Callable[[], Action]


class Parallel(Action):
    """Run actions together.

    Args:
        factories: Makers of the child actions.
        mode: ``"all"``: done when every child is done, failed as soon as one fails;
            ``"any"``: done as soon as one child is done (the others are stopped), failed
            only if every child failed.

    Outcomes: as above; a child's ``timeout`` counts as a failure.
    """

    name = "parallel"
    summary = "Run actions at the same time."

    def __init__(self, factories: Sequence[ActionFactory], mode: str = "all") -> None:
        if mode not in ("all", "any"):
            raise ValueError("parallel runs 'all' or 'any'")
        if not factories:
            raise ValueError("parallel needs at least one action")
        self.factories = list(factories)
        self.mode = mode
        self._children: list[Action] = []
        self._results: list[Result | None] = []

    def start(self, ctx: ActionContext) -> None:
        self._children = [make() for make in self.factories]
        self._results = [None] * len(self._children)
        for child in self._children:
            child.start(ctx)

    def update(self, ctx: ActionContext) -> Result | None:
        for index, child in enumerate(self._children):
            if self._results[index] is None:
                result = child.update(ctx)
                if result is not None:
                    self._results[index] = result
                    child.stop(ctx)
                    if self.mode == "all" and result.outcome is not Outcome.DONE:
                        self._stop_running(ctx)
                        return Result.failed(
                            f"{child.name}: {result.reason or result.outcome.value}"
                        )
                    if self.mode == "any" and result.outcome is Outcome.DONE:
                        self._stop_running(ctx)
                        return Result.done()
        self.feedback = " | ".join(c.feedback for c in self._children if c.feedback)
        if all(result is not None for result in self._results):
            if self.mode == "all":
                return Result.done()
            first = next(r for r in self._results if r is not None)
            return Result.failed(f"every action failed (first: {first.reason})")
        return None

    def _stop_running(self, ctx: ActionContext) -> None:
        for index, child in enumerate(self._children):
            if self._results[index] is None:
                child.stop(ctx)
                self._results[index] = Result.failed("stopped")

    def stop(self, ctx: ActionContext) -> None:
        self._stop_running(ctx)


class Repeat(Action):
    """Run one action several times in a row.

    Args:
        factory: Maker of the action to repeat.
        times: How many times (at least 1).

    Outcomes: ``done`` after the last run; the first run that does not end ``done`` ends the
    repeat with its outcome.
    """

    name = "repeat"
    summary = "Run an action several times."

    def __init__(self, factory: ActionFactory, times: int) -> None:
        if times < 1:
            raise ValueError("repeat needs 'times' of at least 1")
        self.factory = factory
        self.times = times
        self.count = 0
        self._child: Action | None = None

    def start(self, ctx: ActionContext) -> None:
        self.count = 0
        self._child = self.factory()
        self._child.start(ctx)

    def update(self, ctx: ActionContext) -> Result | None:
        assert self._child is not None
        result = self._child.update(ctx)
        self.feedback = f"{self.count + 1}/{self.times}: {self._child.feedback}"
        if result is None:
            return None
        self._child.stop(ctx)
        if result.outcome is not Outcome.DONE:
            return result
        self.count += 1
        if self.count >= self.times:
            self._child = None
            return Result.done()
        self._child = self.factory()
        self._child.start(ctx)
        return None

    def stop(self, ctx: ActionContext) -> None:
        if self._child is not None:
            self._child.stop(ctx)
            self._child = None
