"""What a stepped-sine step reports: steady only where the stop rule ended it (a step run
to the cap is not), and the scatter of its amplitude over the last windows."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from pdamper.coupling.frf import (
    DEFAULT_STEADY,
    SCATTER_WINDOWS,
    HarmonicLoad,
    _steady_stop,
    _window_amplitudes,
    frequency_response,
)
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

F = 5.0
PER_CYCLE = 64


def _run(amplitudes_per_cycle):
    """A container motion of whole cycles at F, cycle c with amplitude a_c (a sine, the
    load's phase 0 at t = 0)."""
    a = np.repeat(np.asarray(amplitudes_per_cycle, float), PER_CYCLE)
    t = np.arange(a.size + 1) / (PER_CYCLE * F)
    a = np.append(a, a[-1])
    return SimpleNamespace(time=t, container_position=a * np.sin(2 * math.pi * F * t))


def test_the_stop_rule_says_whether_it_ended_the_step():
    stop = _steady_stop(1 / F, F, DEFAULT_STEADY)
    assert not stop.fired
    n = DEFAULT_STEADY.min_cycles + 2
    assert not stop(_run(np.linspace(1e-3, 2e-3, n)))  # still growing
    assert not stop.fired
    assert stop(_run([1e-3] * n))  # steady: it ends the step
    assert stop.fired


def test_window_amplitudes_of_known_windows():
    # windows of 3 cycles with amplitudes 1..5 mm, the latest last
    amps = np.repeat([1e-3, 2e-3, 3e-3, 4e-3, 5e-3], 3)
    r = _run(amps)
    got = _window_amplitudes(r.time, r.container_position, F, 0.0, amps.size, 3)
    assert len(got) == SCATTER_WINDOWS == 5
    assert got == pytest.approx([5e-3, 4e-3, 3e-3, 2e-3, 1e-3], rel=1e-3)


def _response(max_cycles):
    return frequency_response(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE,
                              HarmonicLoad("force", 2.0), [5.0, 5.5], sweep="up",
                              max_cycles=max_cycles, with_harmonic_balance=False)


def test_a_steady_step_has_no_scatter():
    c = _response(2000).sweeps["up"]
    assert c.steady.all()
    assert np.all(c.amplitude_std / c.amplitude < 1e-3)
    assert c.amplitude_mean == pytest.approx(c.amplitude, rel=1e-3)


def test_a_step_cut_short_reports_its_scatter():
    res = _response(5)
    c = res.sweeps["up"]
    assert not c.steady.any() and (c.cycles == 5).all()
    assert np.all(c.amplitude_std > 0.01 * c.amplitude)  # the transient's beat
    p = res.as_dict()["points"][0]["up"]
    assert p["steady"] is False
    assert p["amplitude_std"] == pytest.approx(float(c.amplitude_std[0]))
    ds = res.to_dataset()
    assert "sweep_amplitude_std" in ds and ds["sweep_amplitude_std"].attrs["units"] == "m"
