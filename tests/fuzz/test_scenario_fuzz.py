"""Fuzzing the scenario reader: every generated TOML document (and every
corrupted one) is either a scenario or one InputError naming a field, at once; a scenario
then answers every run's resource check the same way, and ``pdamper analytic --scenario``
answers as the command line must."""

from __future__ import annotations

import random

from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import SCENARIOS, grid, quantity, toml_document

from answers import ERROR_LINE, check_answer, time_bound
from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.runs.resources import check_resources
from pdamper.units import parse_quantity, parse_range

BOUND = 30.0
RUNS = [("excitation", "analytic"), ("excitation", "dem"), ("map", "analytic"), ("map", "dem"),
        ("simulation", None), ("simulation", "dem"), ("optimization", None),
        ("case_study", None), ("case_study_dem", None)]


def refused(exc: InputError) -> None:
    line = f"error: {exc}"
    assert "\n" not in line, line
    assert ERROR_LINE.match(line), line


@given(st.one_of(quantity("Hz"), quantity("m"), st.text()), st.sampled_from(["Hz", "m", "s", ""]))
def test_quantities(text, unit):
    try:
        value = parse_quantity(text, unit, "x.y")
    except InputError as exc:
        assert exc.field == "x.y"
        refused(exc)
    else:
        assert isinstance(value, float) and abs(value) < float("inf")


@given(grid("Hz"))
def test_ranges(text):
    try:
        a, b, n = parse_range(text, "Hz", "map.frequency")
    except InputError as exc:
        assert exc.field == "map.frequency"
        refused(exc)
    else:
        assert (n == 1 and a == b) or (n >= 2 and a < b)


def _document(doc: dict, corrupt: int | None) -> str:
    text = toml_document(doc)
    if corrupt is not None and text:
        i = corrupt % len(text)
        text = text[:i] + random.Random(corrupt).choice("[]=\"'{}#\n\\x") + text[i + 1:]
    return text


@settings(max_examples=2 * settings.default.max_examples)  # of the profile: 80 in CI
@given(SCENARIOS, st.one_of(st.none(), st.none(), st.integers(0, 10**6)))
def test_scenario_files(cli, tmp_path_factory, doc, corrupt):
    path = tmp_path_factory.mktemp("fuzz") / "s.toml"
    path.write_text(_document(doc, corrupt), encoding="utf-8")
    with time_bound(BOUND):
        try:
            sc = load_scenario(path)
        except InputError as exc:
            refused(exc)
            sc = None
        if sc is not None:
            for run, model in RUNS:
                try:
                    check_resources(sc, run, model)
                except InputError as exc:
                    refused(exc)
        code, out, err = cli("analytic", "--scenario", path, "--json")
    check_answer(code, out, err, ok=(sc is not None) or None)
