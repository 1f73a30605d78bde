"""``python -m experiments.paper``: see ``experiments.paper.cli``."""

from experiments.paper.cli import main

main()
