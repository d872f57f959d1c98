"""The near-harmonic flag of describing-function runs (pdamper.coupling.harmonicity): a
1-DOF decay and a harmonic load are near-harmonic, the machine frame's two-mode shock is
not, and the output says so, naming the plastic fidelity."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.coupling import Simulation, run_load
from pdamper.coupling.harmonicity import (
    NEAR_HARMONIC_DEVIATION,
    harmonicity,
    of_result,
    window_deviation,
)
from pdamper.coupling.loads import LoadHistory
from pdamper.coupling.results import CycleUpdate
from pdamper.models import AnalyticalDamper, PlasticBedDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

FRAME = Path(__file__).resolve().parents[2] / "examples" / "machine-frame"


def _update(t, x, f, d=1.0):
    return CycleUpdate(t, x, f, None, 0.0, d, 0.5)


def test_deviation_of_a_sine_and_of_a_sine_with_its_octave():
    t = np.linspace(0.0, 1.0, 4001)
    x = -0.01 * np.cos(2 * math.pi * 5.0 * t)
    ups = [_update(k * 0.2, 0.01, 5.0) for k in range(4)]
    h = harmonicity(t, x, ups)
    assert h.deviation == pytest.approx(0.0, abs=1e-6) and h.near_harmonic
    # a second component of a third of the amplitude an octave up: 1/3 RMS deviation
    y = x + 0.01 / 3 * np.sin(2 * math.pi * 10.0 * t)
    h2 = harmonicity(t, y, ups)
    assert h2.deviation == pytest.approx(1 / 3, rel=1e-3) and not h2.near_harmonic
    # the update at the wrong amplitude counts as far off as the motion it missed
    assert window_deviation(t, x, 0.0, 0.02, 5.0) == pytest.approx(
        math.sqrt(0.5 * 0.01**2 + 0.01**2) / (0.02 / math.sqrt(2)), rel=1e-3)
    # a period beyond the run: nothing to measure
    assert harmonicity(t, x, [_update(0.9, 0.01, 5.0)]) is None


def test_one_mode_decay_and_harmonic_load_are_near_harmonic():
    r = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -0.058).run(1.0)
    h = of_result(r)
    assert h is not None and h.near_harmonic and h.deviation < 0.2
    load = run_load(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE,
                    LoadHistory.harmonic(2.0, 5.0, 4.0))
    h = of_result(load)
    assert h is not None and h.near_harmonic and h.deviation < 0.1


def test_two_mode_shock_is_not_near_harmonic_and_the_output_names_plastic(cli):
    code, out, err = cli("simulate", "--scenario", FRAME / "scenario.toml", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["near_harmonic"] is False
    assert d["harmonicity"]["deviation"] > 4 * NEAR_HARMONIC_DEVIATION
    assert d["harmonicity"]["threshold"] == NEAR_HARMONIC_DEVIATION
    code, text, _ = cli("simulate", "--scenario", FRAME / "scenario.toml")
    warn = [ln for ln in text.splitlines() if "not near-harmonic" in ln]
    assert len(warn) == 1 and "--model plastic" in warn[0]
    # the plastic fidelity has no loss factor to judge: null, with the reason
    code, out, _ = cli("simulate", "--scenario", FRAME / "scenario.toml", "--model",
                       "plastic", "--json")
    d = json.loads(out)
    assert d["near_harmonic"] is None and "follows the motion" in d["not_applicable"][
        "near_harmonic"]


def test_release_json_carries_the_flag(cli):
    code, out, err = cli("simulate", "--duration", "1s", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["near_harmonic"] is True and d["harmonicity"]["windows"] >= 3
    code, text, _ = cli("simulate", "--duration", "1s")
    assert "not near-harmonic" not in text


def test_the_plastic_run_has_no_updates_to_judge():
    r = Simulation(PAPER_STRUCTURE, PlasticBedDamper(PAPER_DAMPER), -0.058).run(0.5)
    assert r.cycles == () and of_result(r) is None
