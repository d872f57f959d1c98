"""The forced response's faster paths give the answers of the plain ones: Brent's method in
lockstep finds scipy's roots bit for bit, the tables made together are the tables made one
frequency at a time, and harmonic balance calls the model a few dozen times, not once per
root-finding step."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pdamper.coupling import frf as F
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE


def test_lockstep_brent_is_brentq_bit_for_bit():
    funcs = [lambda x: x**3 - 2.0, lambda x: math.cos(x) - x, lambda x: math.exp(x) - 5.0,
             lambda x: (x - 0.3) * 1e6 + math.sin(40 * x), lambda x: math.tanh(x - 1e-3)]
    brackets = [(0.0, 3.0), (0.0, 1.0), (0.0, 4.0), (0.0, 1.0), (-1.0, 2.0)]
    calls = []

    def fn(which, xs):
        calls.append(len(xs))
        return [funcs[j](x) for j, x in zip(which, xs, strict=True)]

    got = F._brent_lockstep(fn, brackets, xtol=1e-14, rtol=1e-12, maxiter=200)
    want = [brentq(f, a, b, xtol=1e-14, rtol=1e-12, maxiter=200)
            for f, (a, b) in zip(funcs, brackets, strict=True)]
    assert got == want  # exactly: the same steps
    assert max(calls) == len(funcs)  # all brackets evaluated together


def test_lockstep_brent_refuses_what_brentq_refuses():
    with pytest.raises(ValueError, match="different signs"):
        F._brent_lockstep(lambda w, xs: [x * x + 1.0 for x in xs], [(0.0, 1.0)],
                          xtol=1e-14, rtol=1e-12, maxiter=200)
    with pytest.raises(ValueError, match="NaN"):
        F._brent_lockstep(lambda w, xs: [math.nan if 0 < x < 1 else x - 0.5 for x in xs],
                          [(0.0, 1.0)], xtol=1e-14, rtol=1e-12, maxiter=200)


def test_tables_together_equal_one_by_one():
    model = AnalyticalDamper(PAPER_DAMPER)
    load = F.HarmonicLoad("force", 2.0)
    freqs = [4.0, 5.3, 7.9]
    bounds = [F.stroke_bounds(PAPER_STRUCTURE, load, model, f) for f in freqs]
    together = F.describing_functions(model, freqs, bounds, 300)
    for f, (lo, hi), t in zip(freqs, bounds, together, strict=True):
        one = F.describing_function(model, f, lo, hi, 300)
        for name in ("stroke", "effective_mass", "damping", "loss_factor", "mode"):
            assert np.array_equal(getattr(t, name), getattr(one, name)), name


class _Counting(AnalyticalDamper):
    calls = 0

    def response(self, *a, **k):
        type(self).calls += 1
        return super().response(*a, **k)


def test_harmonic_balance_calls_the_model_in_rounds_not_per_step():
    model = _Counting(PAPER_DAMPER)
    freqs = np.linspace(4.5, 6.5, 21)
    hb = F.harmonic_balance(model, PAPER_STRUCTURE, F.HarmonicLoad("force", 2.0), freqs)
    roots = int(np.count_nonzero(hb.branch != ""))
    assert roots >= 21
    # one call per Brent round (tens), not one per function evaluation (about 10 per root)
    assert _Counting.calls < 80 < 8 * roots


def test_stepped_sine_holds_each_cycles_state_free_part(monkeypatch):
    """A step's cycles that return to an (m_eff, d) already seen reuse its propagators:
    far fewer eigen-decompositions than cycles, and the same curve bit for bit as when
    every cycle computes its own."""
    model = AnalyticalDamper(PAPER_DAMPER)
    load = F.HarmonicLoad("force", 2.0)
    freqs = np.linspace(4.8, 5.8, 9)
    calls = []
    real = F._propagators
    monkeypatch.setattr(F, "_propagators", lambda *a: calls.append(1) or real(*a))
    held = F.stepped_sine_pseudo_force(model, PAPER_STRUCTURE, load, freqs, "up", tables={})
    assert len(calls) < int(held.cycles.sum()) / 3
    plain_cycle = F._matrix_cycle
    monkeypatch.setattr(F, "_matrix_cycle", lambda *a: plain_cycle(*a[:7], None))
    plain = F.stepped_sine_pseudo_force(model, PAPER_STRUCTURE, load, freqs, "up", tables={})
    for name in ("amplitude", "phase", "stroke", "loss_factor", "amplitude_std"):
        assert np.array_equal(getattr(held, name), getattr(plain, name), equal_nan=True), name
    for name in ("cycles", "mode", "steady"):
        assert np.array_equal(getattr(held, name), getattr(plain, name)), name
