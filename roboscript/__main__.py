"""``python -m roboscript``: the command line."""

from roboscript.cli import main

main()
