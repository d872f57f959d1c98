"""Fitting COR models to measured points (Level I): the stated parameter uncertainty is
honest, i.e. synthetic data's true parameters fall within it as often as it claims."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.contact.fit import FIT_MODELS, fit_restitution
from pdamper.contact.restitution import ExponentialRestitution, LinearRestitution
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.errors import InputError

TRUE = {
    "exponential": ExponentialRestitution(0.97, 0.47, 0.25),
    "linear": LinearRestitution(0.9, 0.06, 1.8),
    "thornton": ThorntonRestitution(0.02),
}
V = np.linspace(0.05, 1.8, 15)
SIGMA = 0.01
REPLICAS = 200


@pytest.mark.parametrize("model", list(FIT_MODELS))
def test_fit_recovers_parameters_within_stated_uncertainty(model):
    """200 synthetic data sets (15 points, Gaussian noise of sigma = 0.01, given as std):
    each parameter lies within one stated standard error of the truth in 68 % of the fits
    (binomial 3-sigma band: 58-78 %), within three in more than 97 %."""
    truth = TRUE[model]
    rng = np.random.default_rng(2024)
    inside1 = np.zeros(len(truth.PARAMETERS))
    inside3 = np.zeros(len(truth.PARAMETERS))
    for _ in range(REPLICAS):
        e = truth(V) + rng.normal(0.0, SIGMA, V.size)
        fit = fit_restitution(V, e, std=np.full(V.size, SIGMA), model=model)
        z = np.abs(fit.values - np.array(truth.parameters)) / fit.uncertainty
        inside1 += z < 1.0
        inside3 += z < 3.0
    assert np.all((inside1 / REPLICAS > 0.58) & (inside1 / REPLICAS < 0.78)), inside1 / REPLICAS
    assert np.all(inside3 / REPLICAS > 0.97), inside3 / REPLICAS


def test_exact_data_is_recovered_and_the_band_contains_it():
    truth = TRUE["exponential"]
    fit = fit_restitution(V, truth(V), model="exponential")
    assert fit.values == pytest.approx(truth.parameters, rel=1e-6)
    assert not fit.absolute_sigma
    rng = np.random.default_rng(1)
    noisy = fit_restitution(V, truth(V) + rng.normal(0, SIGMA, V.size), model="exponential")
    lo, hi = noisy.band(V, k=3.0)
    assert np.all((lo <= truth(V)) & (truth(V) <= hi))
    # without std, the residual scatter sets the scale: about the noise
    assert noisy.chi2_reduced == pytest.approx(SIGMA**2, rel=0.8)
    d = noisy.as_dict()
    assert set(d["parameters"]) == {"e0", "e_inf", "v_c"} and d["points"] == V.size


def test_fitted_curve_is_a_cor_curve_for_the_dem():
    fit = fit_restitution(V, TRUE["linear"](V), model="linear")
    assert isinstance(fit.curve, LinearRestitution) and fit.curve.v_hold == pytest.approx(1.8)
    v, e = fit.curve.tabulate()
    assert np.all((e > 0) & (e <= 1))


@pytest.mark.parametrize(("kw", "match"), [
    ({"model": "spline"}, "must be one of"),
    ({"velocity": V[:3], "restitution": V[:3] * 0 + 0.5}, "at least 4 points"),
    ({"std": np.zeros(V.size)}, "std"),
])
def test_bad_fits(kw, match):
    args = {"velocity": V, "restitution": TRUE["exponential"](V), "model": "exponential", **kw}
    with pytest.raises(InputError, match=match):
        fit_restitution(**args)
