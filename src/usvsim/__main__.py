"""`python -m usvsim ...` is the `usvsim` command (as `python -m usvsim.cli`)."""

from usvsim.cli.app import main

main()
