"""``pdamper example-scenario``: print a commented scenario file."""

from __future__ import annotations


def example_scenario() -> None:
    """Print a commented scenario TOML with every key and its default."""
    from pdamper.files import write_stdout
    from pdamper.io.scenario import EXAMPLE_SCENARIO

    write_stdout(EXAMPLE_SCENARIO)
