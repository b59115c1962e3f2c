"""Actions made of actions: ``parallel`` and ``repeat``.

``parallel`` runs several actions at once (drive while a tune plays) and ends when all of them
have (``all``) or when the first one has (``any``); ``repeat`` runs one action several times in
a row. Each child is made fresh from its factory when the composite starts, so a state that is
entered again starts from scratch.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from roboscript.actions.base import Action, ActionContext, Outcome, Result, UnderSpecifiedError
from roboscript.actions.motion import Drive, Rotate
from roboscript.actions.timing import PlayTone

__all__ = ["Parallel", "Repeat"]

ActionFactory = Callable[[], Action]


def _factory(item: Action | ActionFactory) -> ActionFactory:
    """An action given as an instance is a template: every run gets a fresh copy."""
    if isinstance(item, Action):
        return lambda: copy.deepcopy(item)
    return item


def _written(item: object) -> str:
    """An action, or a maker of one, as a fix names it: ``Drive(...)``, ``Square`` (a mission)."""
    if isinstance(item, Action):
        return item.written_call()
    if isinstance(item, type):
        return item.__name__
    return getattr(item, "__name__", None) or repr(item)


def _needs(items: Sequence[Action | ActionFactory]) -> frozenset[str]:
    needed: set[str] = set()
    for item in items:
        if isinstance(item, Action):
            needed |= type(item).requires | getattr(item, "child_requires", frozenset())
    return frozenset(needed)


class Parallel(Action):
    """Run actions together.

    Example (a Python mission)::

        show_off = state(Parallel([Drive(distance_mm=500), PlayTone(frequency_hz=523,
                                   duration_s=2)]), on_done="next")

    Args:
        factories: The child actions (each copied afresh when the parallel starts), or makers
            of them.
        mode: ``"all"``: done when every child is done, failed as soon as one fails;
            ``"any"``: done as soon as one child is done (the others are stopped), failed
            only if every child failed.

    Outcomes: as above; a child's ``timeout`` counts as a failure.
    """

    name = "parallel"
    summary = "Run actions at the same time."

    @classmethod
    def example(cls, *names: str) -> tuple[str, str]:
        """A whole ``parallel`` of two actions, as YAML and Python write it."""
        drive, tone = Drive.written("distance"), PlayTone.written()
        return f"`parallel: {{all: [{drive[0]}, {tone[0]}]}}`", f"Parallel([{drive[1]}, {tone[1]}])"

    @classmethod
    def under_specified(cls, missing: Sequence[str]) -> UnderSpecifiedError:
        """``Parallel()``: it needs its actions."""
        return cls.needs("parallel needs the actions to run together, in a list")

    @classmethod
    def given_too_many(cls, given: Sequence[Any]) -> UnderSpecifiedError:
        """``Parallel(a, b, c)``: the actions without their list's brackets."""
        return cls.unlisted(given)

    @classmethod
    def unlisted(cls, given: Sequence[Any]) -> UnderSpecifiedError:
        """The error for actions given one by one (``Parallel(a, b, c)``), with the fix
        written with them: ``Parallel([Drive(distance_mm=500), Rotate(angle_deg=90)])``."""
        actions = [_written(item) for item in given if not isinstance(item, str)]
        modes = [f', mode="{item}"' for item in given if isinstance(item, str)][:1]
        yaml = cls.example()[0]
        return UnderSpecifiedError(
            "parallel takes a list of actions, in [ ]",
            yaml=yaml,
            python=f"Parallel([{', '.join(actions)}]{''.join(modes)})",
        )

    def __init__(self, factories: Sequence[Action | ActionFactory], mode: str = "all") -> None:
        if isinstance(factories, str) or not isinstance(factories, Iterable):
            # Parallel(Drive(...), PlayTone(...)): the actions without the list's [ ]
            raise type(self).unlisted([factories] if mode == "all" else [factories, mode])
        if mode not in ("all", "any"):
            yaml, python = type(self).example()
            raise UnderSpecifiedError(
                "parallel runs 'all' or 'any'",
                yaml=yaml.replace("{all:", "{any:"),
                python=python.removesuffix(")") + ', mode="any")',
            )
        if not factories:
            raise type(self).needs("parallel needs at least one action")
        self.child_requires = _needs(factories)
        """Capabilities the children need (the class itself needs none)."""
        self.actions = tuple(factories)
        """The children as given (a Python mission's compiler reads them)."""
        self.factories = [_factory(item) for item in factories]
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

    Example (a Python mission)::

        square = state(Repeat(Rotate(angle_deg=90), times=4), on_done="home")

    Args:
        factory: The action to repeat (copied afresh for each run), or a maker of it.
        times: How many times: a whole number from 1 to :attr:`most_times` (an hour of ticks).

    Outcomes: ``done`` after the last run; the first run that does not end ``done`` ends the
    repeat with its outcome.
    """

    name = "repeat"
    summary = "Run an action several times."

    @classmethod
    def example(cls, *names: str) -> tuple[str, str]:
        """A whole ``repeat``, as YAML and Python write it."""
        turn = Rotate.written()
        return f"`repeat: {{times: 4, do: {turn[0]}}}`", f"Repeat({turn[1]}, times=4)"

    @classmethod
    def under_specified(cls, missing: Sequence[str]) -> UnderSpecifiedError:
        """``Repeat()``: it needs an action (``factory``) and how many ``times`` to run it."""
        if "factory" not in missing:
            return cls.needs("repeat needs 'times', how many times to run the action")
        if "times" not in missing:
            return cls.needs("repeat needs the action to repeat")
        return cls.needs("repeat needs an action and how many times to run it")

    @classmethod
    def given_too_many(cls, given: Sequence[Any]) -> UnderSpecifiedError:
        """``Repeat(a, b, 4)``: several actions, where a repeat runs one."""
        return cls.several()

    @classmethod
    def several(cls) -> UnderSpecifiedError:
        """The error for several actions to repeat: a repeat runs one, which may be a whole
        mission of its own (its states one after another)."""
        return UnderSpecifiedError(
            "repeat runs one action: to repeat several one after another, make them the"
            " states of a mission of their own, and repeat that",
            yaml="`repeat: {times: 4, do: {mission: steps.yaml}}`",
            python="Repeat(Steps, times=4), Steps being a Mission class with those states",
        )

    most_times = 180_000
    """Most runs a ``repeat`` may ask for: each run takes at least one 50 Hz tick, and a
    mission runs at most an hour (``roboscript.mission.limits.MAX_TIME_S``), so a repeat of
    more could never finish."""

    @classmethod
    def times_problem(cls, times: object, action: str = "") -> UnderSpecifiedError | None:
        """The error for ``times`` that is not a whole number of runs from 1 to
        :attr:`most_times`, in one sentence with the fix, or ``None`` if it is one.

        Args:
            times: The ``times`` as written (an int from Python; YAML's value as read).
            action: The repeated action as a Python mission writes it, for the example.
        """
        action = action or Rotate.written()[1]
        yaml, python = cls.example()[0], f"Repeat({action}, times=4)"
        if isinstance(times, int) and not isinstance(times, bool):
            if times > cls.most_times:
                shown = f"{times:,}" if times.bit_length() <= 64 else "so many"
                return UnderSpecifiedError(
                    f"repeat times: {shown} runs cannot finish within a mission's longest"
                    f" run (an hour, which holds at most {cls.most_times:,} runs)",
                    yaml=f"`times: {cls.most_times}` or fewer",
                    python=f"Repeat({action}, times={cls.most_times}) or fewer",
                )
            if times == 0:
                return UnderSpecifiedError(
                    "repeat times: 0 would not run the action at all (at least 1)",
                    yaml=yaml,
                    python=python,
                )
            if times < 0:
                return UnderSpecifiedError(
                    f"repeat times: {times} is not a number of runs (at least 1)",
                    yaml=yaml,
                    python=python,
                )
            return None
        written = times.strip() if isinstance(times, str) else ""
        try:  # YAML reads 1e9 as text
            number = float(written) if written and not written.isdigit() else None
        except ValueError:
            number = None
        if number is not None and number.is_integer() and number > cls.most_times:
            return cls.times_problem(int(number), action)
        if number is not None and number.is_integer() and number >= 1:
            return UnderSpecifiedError(
                f"repeat times is a whole number written out in digits, and {written} is not",
                yaml=f"`times: {int(number)}`",
                python=f"Repeat({action}, times={int(number)})",
            )
        if isinstance(times, float):
            whole = times.is_integer() and 1 <= times <= cls.most_times
            return UnderSpecifiedError(
                f"repeat times is a whole number of runs, and {times!r} is not one"
                + (" (a whole number has no decimal point)" if whole else ""),
                yaml=f"`times: {int(times)}`" if whole else yaml,
                python=f"Repeat({action}, times={int(times)})" if whole else python,
            )
        if written.isdigit() and 1 <= int(written) <= cls.most_times:  # times: "4"
            return UnderSpecifiedError(
                "repeat's times is a whole number, written without quotes",
                yaml=f"`times: {int(written)}`",
                python=f"Repeat({action}, times={int(written)})",
            )
        flag = isinstance(times, bool)
        return UnderSpecifiedError(
            "repeat needs 'times', a whole number of at least 1"
            + (f", and {str(times).lower()} is not a number" if flag else ""),
            yaml=yaml,
            python=python,
            python_message="repeat needs 'times', a whole number of at least 1"
            + (f", and {times} is not a number" if flag else ""),
        )

    def __init__(self, factory: Action | ActionFactory, times: int) -> None:
        if isinstance(factory, int) and isinstance(times, Action):  # Repeat(4, Rotate(...))
            raise UnderSpecifiedError(
                "repeat takes the action first, then how many times",
                yaml=f"`repeat: {{times: {factory}, do: ...}}`",
                python=f"Repeat({_written(times)}, times={factory})",
            )
        if isinstance(times, Action) or isinstance(factory, list | tuple):
            raise type(self).several()  # Repeat(Rotate(...), Drive(...)), Repeat([...], ...)
        problem = type(self).times_problem(times, _written(factory))
        if problem is not None:
            raise problem
        self.child_requires = _needs([factory])
        """Capabilities the repeated action needs."""
        self.action = factory
        """The repeated action as given (a Python mission's compiler reads it)."""
        self.factory = _factory(factory)
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
            # Already stopped: leaving the state must not stop it a second time.
            self._child = None
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
