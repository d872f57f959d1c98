"""Hypothesis profiles of the fuzz suite.

``ci`` (default): a bounded, derandomised number of examples, so that CI is reproducible
and fast. ``long``: a randomised run with many examples, on demand::

    HYPOTHESIS_PROFILE=long python3 -m pytest tests/fuzz

What a long run finds goes into the corpus (``tests/hostile_corpus.py``).
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

#: The ``cli`` fixture is shared by the examples of a test on purpose: it reads and clears
#: the captured output after every invocation.
_SUPPRESS = [HealthCheck.too_slow, HealthCheck.function_scoped_fixture]
settings.register_profile("ci", max_examples=40, derandomize=True, deadline=None,
                          database=None, print_blob=True, suppress_health_check=_SUPPRESS)
settings.register_profile("long", max_examples=2000, deadline=None, print_blob=True,
                          suppress_health_check=_SUPPRESS)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
