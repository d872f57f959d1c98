"""``python -m pdamper``: the command line."""

from pdamper.cli import entry

entry()
