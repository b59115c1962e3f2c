"""``python -m roboscript`` and the ``roboscript`` command: signals first, then the command line.

The command line imports a good deal before it can act (a third of a second on a slow
machine). Ctrl-C, SIGTERM and SIGHUP are given their handlers before any of it
(:mod:`roboscript.interrupts` needs only the standard library), so a signal while the program
starts ends it with the same one line and exit status as a signal later on.
"""

from __future__ import annotations

import sys
from typing import NoReturn

from roboscript.interrupts import exit_status_for, reason_for
from roboscript.interrupts import install as install_interrupts

__all__ = ["main"]


def main() -> NoReturn:
    """Run the ``roboscript`` command line and exit with its status."""
    install_interrupts()
    try:
        # imported here, after the handlers: a signal while it loads is one like any other
        from roboscript.cli import main as command_line
    except KeyboardInterrupt as exc:
        print(f"error: {reason_for(exc)}", file=sys.stderr)
        sys.exit(exit_status_for(exc))
    command_line()


if __name__ == "__main__":
    main()
