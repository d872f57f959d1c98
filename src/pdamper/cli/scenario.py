"""``pdamper example-scenario``: print a commented scenario file."""

from __future__ import annotations

import sys


def example_scenario() -> None:
    """Print a commented scenario TOML with every key and its default."""
    from pdamper.io.scenario import EXAMPLE_SCENARIO

    sys.stdout.write(EXAMPLE_SCENARIO)
