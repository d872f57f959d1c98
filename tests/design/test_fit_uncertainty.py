"""A fitted curve's parameter covariance as uncertain inputs: principal axes, truncation."""

import math

import numpy as np
import pytest
from scipy.stats import truncnorm

from pdamper.contact.fit import fit_restitution
from pdamper.contact.restitution import ExponentialRestitution, LinearRestitution
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.design.uncertainty import (
    FitAxis,
    ParameterFit,
    design_matrices,
    fit_groups,
    propagate,
)
from pdamper.errors import InputError


def _unbounded(p):  # every parameter vector is valid: no truncation beyond 4 sd
    return tuple(p)


def _exp_curve(p):
    return ExponentialRestitution(*p)


def test_principal_axes_of_a_two_by_two_covariance_in_closed_form():
    a, b, c = 4e-4, 1.2e-4, 1e-4
    fit = ParameterFit("x", ("p", "q"), ("", ""), np.array([0.5, 0.3]),
                       np.array([[a, b], [b, c]]), _unbounded)
    sd, directions = fit.axes()
    root = math.sqrt(((a - c) / 2) ** 2 + b**2)
    lam = np.array([(a + c) / 2 + root, (a + c) / 2 - root])
    assert sd == pytest.approx(np.sqrt(lam), rel=1e-12)
    theta = 0.5 * math.atan2(2 * b, a - c)  # the major axis' angle
    v1 = np.array([math.cos(theta), math.sin(theta)])
    v2 = np.array([-math.sin(theta), math.cos(theta)])
    v2 = v2 * np.sign(v2[np.argmax(np.abs(v2))])  # the sign convention: largest > 0
    assert directions[:, 0] == pytest.approx(sd[0] * v1, rel=1e-10)
    assert directions[:, 1] == pytest.approx(sd[1] * v2, rel=1e-10)
    # V diag(sd) (V diag(sd))^T is the covariance again; z = e_1 moves by the first axis
    assert directions @ directions.T == pytest.approx(fit.covariance, rel=1e-12)
    assert fit.parameters_at([1.0, 0.0]) == pytest.approx(fit.values + sd[0] * v1)
    names = [u.field for u in fit.inputs()]
    assert names == ["x[pc1]", "x[pc2]"]
    assert all(u.low == -4.0 and u.high == 4.0 for u in fit.inputs())


def test_sampled_parameters_recover_the_fits_mean_and_covariance():
    cov = np.array([[4e-4, -1.5e-4, 2e-4],
                    [-1.5e-4, 2.5e-4, -0.5e-4],
                    [2e-4, -0.5e-4, 9e-4]])
    values = np.array([0.8, 0.4, 0.3])
    fit = ParameterFit("restitution.particle_wall", ("e0", "e_inf", "v_c"),
                       ("", "", "m/s"), values, cov, _exp_curve)
    inputs = fit.inputs()
    assert all(u.low == -4.0 and u.high == 4.0 for u in inputs)  # far from invalid CORs
    n = 4096
    a, b = design_matrices(inputs, n, seed=7)
    p = np.array([fit.parameters_at(z) for z in np.concatenate([a, b], axis=1).T])
    # the expected moments of the 4-sd truncated normal along each axis (closed form)
    var4 = truncnorm(-4, 4).var()
    assert 0.998 < var4 < 1.0
    expected = cov * var4
    sd = np.sqrt(np.diag(expected))
    # sampling error of a mean: sd / sqrt(2 n); of a covariance: ~ sd_i sd_j sqrt(2 / 2 n)
    assert np.all(np.abs(p.mean(axis=0) - values) < 3 * sd / math.sqrt(2 * n))
    err = np.cov(p.T) - expected
    assert np.all(np.abs(err) < 4 * np.outer(sd, sd) * math.sqrt(2 / (2 * n)))


def test_truncation_keeps_every_sample_a_valid_cor():
    # e0 = 0.97 +- 0.02: the normal reaches above 1 beyond 1.5 sd; the box stops there
    cov = np.diag([0.02, 0.01, 0.05]) ** 2
    fit = ParameterFit("restitution.particle_wall", ("e0", "e_inf", "v_c"),
                       ("", "", "m/s"), np.array([0.97, 0.5, 0.3]), cov, _exp_curve)
    inputs = fit.inputs()
    e0_axis = next(u for u in inputs if abs(fit.axes()[1][0, u.axis]) > 0)
    assert e0_axis.high == pytest.approx(1.5, abs=1e-6)
    a, b = design_matrices(inputs, 1024, seed=1)
    for z in np.concatenate([a, b], axis=1).T:  # never raises: every curve is a COR
        curve = fit.sample(z)
        assert 0 < curve.e0 <= 1 and 0 < curve.e_inf <= 1 and curve.v_c > 0


def test_linear_fit_truncated_where_its_end_leaves_zero_one():
    v = np.linspace(0.1, 2.0, 8)
    e = LinearRestitution(0.9, 0.2, 2.0)(v) + np.array(
        [0.01, -0.02, 0.015, 0.0, -0.01, 0.02, -0.015, 0.005])
    fit = fit_restitution(v, e, np.full(v.size, 0.05), model="linear")
    pf = ParameterFit("restitution.particle_wall", fit.parameters, fit.curve.UNITS,
                      fit.values, fit.covariance, fit.curve_at)
    a, b = design_matrices(pf.inputs(), 512, seed=2)
    ends = [c.e0 - c.slope * c.v_hold for c in
            (pf.sample(z) for z in np.concatenate([a, b], axis=1).T)]
    assert 0 < min(ends) and max(ends) <= 1


def test_fit_on_the_edge_of_valid_cors_sampled_on_its_valid_side():
    # e0 fitted at exactly 1: its axis is truncated to [-4, 0] (a half normal), never above
    fit = ParameterFit("restitution.particle_wall", ("e0", "e_inf", "v_c"), ("", "", "m/s"),
                       np.array([1.0, 0.5, 0.3]), np.diag([1e-4, 1e-4, 1e-4]), _exp_curve)
    (e0_axis,) = [u for u in fit.inputs() if abs(fit.axes()[1][0, u.axis]) > 0]
    assert (e0_axis.low, e0_axis.high) == (-4.0, pytest.approx(0.0, abs=1e-9))


def test_fit_without_uncertainty_is_refused():
    fit = ParameterFit("restitution.particle_wall", ("e0", "e_inf", "v_c"), ("", "", "m/s"),
                       np.array([0.9, 0.5, 0.3]), np.zeros((3, 3)), _exp_curve)
    with pytest.raises(InputError) as exc:
        fit.inputs()
    assert exc.value.field == "restitution.particle_wall" and "no uncertainty" in exc.value.message


def test_group_of_a_fit_in_the_answers():
    # y depends on the first parameter only; the fit's axes share it (a correlated pair)
    cov = np.array([[1.0, 0.6], [0.6, 1.0]]) * 1e-2
    fit = ParameterFit("g", ("p", "q"), ("", ""), np.array([1.0, 2.0]), cov, _unbounded)
    inputs = fit.inputs()
    assert isinstance(inputs[0], FitAxis) and list(fit_groups(inputs)) == ["g"]
    r = propagate(lambda z: {"y": float(fit.parameters_at([z["g[pc1]"], z["g[pc2]"]])[0])},
                  inputs, 1024, seed=3)
    y = r.answers["y"]
    assert y.std == pytest.approx(0.1 * math.sqrt(truncnorm(-4, 4).var()), rel=0.02)
    g = y.groups["g"]
    assert g["inputs"] == ["g[pc1]", "g[pc2]"]
    # y is linear in the axes: the indices add up to the whole variance
    assert g["first_order_sum"] == pytest.approx(1.0, abs=0.05)
    assert g["total_order_sum"] == pytest.approx(1.0, abs=0.05)
    # equal weights 0.1 sqrt(1.6 / 2), 0.1 sqrt(0.4 / 2): the major axis drives y (0.8)
    assert y.driver == "g[pc1]" and y.total_order["g[pc1]"] == pytest.approx(0.8, abs=0.05)


def test_thornton_fit_sampled_around_its_yield_velocity():
    v = np.linspace(0.5, 3.0, 8)
    e = ThorntonRestitution(0.5)(v) + np.array([0.01, -0.01, 0.02, 0, -0.02, 0.01, 0, -0.01])
    fit = fit_restitution(v, e, model="thornton")
    pf = ParameterFit("restitution.particle_wall", fit.parameters, fit.curve.UNITS,
                      fit.values, fit.covariance, fit.curve_at)
    (axis,) = pf.inputs()
    a, b = design_matrices([axis], 2048, seed=4)
    vy = np.array([pf.sample([z]).yield_velocity for z in np.concatenate([a, b], axis=1)[0]])
    sd = float(fit.uncertainty[0]) * truncnorm(axis.low, axis.high).std()
    assert abs(vy.mean() - fit.values[0]) < 3 * sd / math.sqrt(vy.size)
    assert vy.std(ddof=1) == pytest.approx(sd, rel=0.05) and vy.min() > 0
