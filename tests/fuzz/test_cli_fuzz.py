"""Fuzzing the command line: for every generated invocation of ``analytic``,
``map``, ``simulate`` and ``optimize``, either exit 0 with finite JSON, or exit 2 with
exactly one line on stderr naming a field, within a time bound; never a traceback.

Generated values keep valid runs quick (small grids, short durations) and add the absurd
and malformed ones; the DEM's inputs are fuzzed through the scenario
(``test_scenario_fuzz.py``), since a valid DEM run takes seconds.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import INTEGERS, bounded_number, grid, quantity

from answers import check_answer, time_bound

#: Seconds one invocation may take.
BOUND = 30.0


def options(**choices) -> st.SearchStrategy[list[str]]:
    """Some of the options, each with a generated value."""
    return st.fixed_dictionaries({}, optional=choices).map(
        lambda d: [a for k, v in d.items() for a in (f"--{k}", str(v))])


def answered(cli, args):
    with time_bound(BOUND):
        code, out, err = cli(*args)
    check_answer(code, out, err)
    return code


@given(options(frequency=quantity("Hz"), amplitude=quantity("m"), particles=INTEGERS))
def test_analytic(cli, args):
    answered(cli, ["analytic", *args, "--json"])


@given(options(frequency=grid("Hz"), amplitude=grid("m"), particles=INTEGERS,
               model=st.sampled_from(["analytic", "quantum", ""])))
def test_map(cli, args):
    answered(cli, ["map", *args, "--json"])


@given(options(duration=quantity("s", bounded_number(3.0), quick=True),
               **{"initial-displacement": quantity("m")}, particles=INTEGERS))
def test_simulate(cli, args):
    answered(cli, ["simulate", "--model", "analytic", *args, "--json"])


@settings(max_examples=max(5, settings.default.max_examples // 3))  # ~0.3 s each
@given(options(at=quantity("s", bounded_number(2.0), quick=True),
               step=st.one_of(st.integers(16, 400), st.integers(-3, 0),
                              st.sampled_from([10**20, "x"]))))
def test_optimize(cli, args):
    answered(cli, ["optimize", "--model", "analytic", *args, "--json"])
