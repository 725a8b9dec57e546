"""``python -m taxelkit`` runs the command line."""

from taxelkit.cli import main

main()
