"""Quasi-Monte Carlo propagation of input uncertainty, against closed forms."""

import math

import numpy as np
import pytest

from pdamper.design.uncertainty import UncertainInput, check_points, propagate
from pdamper.errors import InputError

A, B, S1, S2 = 2.0, 3.0, 0.1, 0.2


def _quadratic(p):
    # y = a x1 + b x2^2 with x1 ~ N(0, s1), x2 ~ N(0, s2), independent:
    # E y = b s2^2, Var y = a^2 s1^2 + 2 b^2 s2^4, S_1 = a^2 s1^2 / Var, S_2 = 2 b^2 s2^4 / Var
    # (no interaction: first order = total)
    return {"y": A * p["x1"] + B * p["x2"] ** 2, "x1": p["x1"]}


def _closed_form():
    var = A**2 * S1**2 + 2 * B**2 * S2**4
    return B * S2**2, math.sqrt(var), A**2 * S1**2 / var, 2 * B**2 * S2**4 / var


@pytest.mark.parametrize("seed", [0, 7])
def test_mean_spread_and_indices_recovered_within_sampling_error(seed):
    inputs = [UncertainInput("x1", 0.0, S1), UncertainInput("x2", 0.0, S2)]
    n = 1024
    r = propagate(_quadratic, inputs, n, seed)
    mean, std, s1, s2 = _closed_form()
    y = r.answers["y"]
    m = 2 * n  # points of A and B
    # Monte Carlo standard errors (QMC does better): 3 of them
    assert abs(y.mean - mean) < 3 * std / math.sqrt(m)
    kurt = (A**4 * 3 * S1**4 + 6 * A**2 * S1**2 * 2 * B**2 * S2**4 + B**4 * 60 * S2**8) \
        / std**4  # E[(y - Ey)^4] / Var^2 of the two independent terms
    assert abs(y.std - std) < 3 * std * math.sqrt((kurt - 1) / (4 * m))
    for name, exact in (("x1", s1), ("x2", s2)):
        lo, hi = y.total_order_interval[name]
        assert lo - 0.02 <= exact <= hi + 0.02, (name, exact, lo, hi)
        lo, hi = y.first_order_interval[name]
        assert lo - 0.02 <= exact <= hi + 0.02, (name, exact, lo, hi)
        assert y.total_order[name] == pytest.approx(exact, abs=0.05)
    assert y.ranking == ["x1", "x2"] and y.driver == "x1"
    # an answer of x1 alone: x2's indices are 0, x1 drives it
    assert r.answers["x1"].total_order["x2"] == pytest.approx(0.0, abs=1e-12)
    assert r.answers["x1"].driver == "x1"
    assert r.runs == n * 4 + 1 and r.seed == seed


def test_ranking_follows_the_variances():
    # swap the inputs' weight: x2 must now drive (S_2 = 0.97)
    inputs = [UncertainInput("x1", 0.0, 0.01), UncertainInput("x2", 0.0, 0.5)]
    r = propagate(_quadratic, inputs, 256, 1)
    assert r.answers["y"].driver == "x2"


def test_percentiles_of_a_linear_answer():
    r = propagate(lambda p: {"y": p["x"]}, [UncertainInput("x", 10.0, 2.0)], 2048, 3)
    y = r.answers["y"]
    # normal quantiles: 5 % at -1.645 sd, 50 % at the mean
    assert y.percentiles[5.0] == pytest.approx(10.0 - 1.6449 * 2.0, abs=0.1)
    assert y.percentiles[50.0] == pytest.approx(10.0, abs=0.05)


def test_truncation_keeps_samples_in_range():
    u = UncertainInput("particles.friction", 0.02, 0.03, low=0.0)
    r = propagate(lambda p: {"mu": p["particles.friction"]}, [u], 512, 0)
    assert r.samples.min() >= 0.0
    assert r.answers["mu"].mean == pytest.approx(float(u.distribution().mean()), rel=0.02)


def test_reproducible_with_the_seed():
    inputs = [UncertainInput("x1", 0.0, S1), UncertainInput("x2", 0.0, S2)]
    a = propagate(_quadratic, inputs, 64, 5).as_dict()
    b = propagate(_quadratic, inputs, 64, 5).as_dict()
    c = propagate(_quadratic, inputs, 64, 6).as_dict()
    a.pop("seconds"), b.pop("seconds"), c.pop("seconds")
    assert a == b and a != c


@pytest.mark.parametrize("n", [0, 3, 10, 2**17, 8.0, True])
def test_points_must_be_a_power_of_two(n):
    with pytest.raises(InputError) as exc:
        check_points(n)
    assert exc.value.field == "uncertainty"


@pytest.mark.parametrize("sd", [0.0, -0.1, math.nan, math.inf])
def test_bad_standard_deviation(sd):
    with pytest.raises(InputError) as exc:
        UncertainInput("particles.friction", 0.1, sd, low=0.0)
    assert exc.value.field == "particles.friction"


def test_non_finite_answers_are_an_error():
    with pytest.raises(InputError):
        propagate(lambda p: {"y": np.inf}, [UncertainInput("x", 0.0, 1.0)], 8)


def test_array_answers_get_a_band():
    t = np.linspace(0.0, 1.0, 5)
    r = propagate(lambda p: {"y": p["k"], "curve": np.exp(-p["k"] * t)},
                  [UncertainInput("k", 1.0, 0.1)], 512, 2)
    b = r.bands["curve"]
    assert set(r.answers) == {"y"}
    assert np.allclose(b["nominal"], np.exp(-t))
    # exp(-k t) is monotone in k: its percentiles are those of k mapped through it (up to
    # the interpolation between neighbouring samples)
    k = r.answers["y"].percentiles
    assert np.allclose(b["p5"], np.exp(-k[95.0] * t), rtol=1e-3)
    assert np.allclose(b["p95"], np.exp(-k[5.0] * t), rtol=1e-3)
