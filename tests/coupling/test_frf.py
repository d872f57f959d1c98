"""Forced response: linear FRF, harmonic balance and the stepped sine (pdamper.coupling.frf)."""

import math

import numpy as np
import pytest

from pdamper.coupling.frf import (
    DEFAULT_STEADY,
    HarmonicLoad,
    frequency_response,
    judge_amplitudes,
    linear_frf,
    receptance,
)
from pdamper.errors import InputError
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure import SingleDOFStructure
from pdamper.structure.modal import ModalStructure

F = np.linspace(3.0, 9.0, 121)


def closed_form_1dof(s, force, f):
    """x = F / (K - M W^2 + i W D), written out here (not the module's receptance)."""
    w = 2 * math.pi * np.asarray(f)
    return force / (s.stiffness - s.mass * w**2 + 1j * w * s.damping)


def three_modes():
    return ModalStructure(np.array([5.5, 31.0, 88.0]), np.array([0.005, 0.01, 0.02]),
                          np.array([0.8, -0.5, 0.3]), output_shape=np.array([0.4, 0.6, -0.2]))


def test_no_particles_equals_closed_form_1dof():
    m = AnalyticalDamper(PAPER_DAMPER.with_count(0))
    r = frequency_response(m, PAPER_STRUCTURE, HarmonicLoad("force", 2.0), F, sweep="none")
    ref = closed_form_1dof(PAPER_STRUCTURE, 2.0, F)
    hb = r.harmonic_balance
    assert hb.amplitude.shape == (F.size, 1) and np.all(hb.branch[:, 0] == "stable")
    np.testing.assert_allclose(hb.amplitude[:, 0], np.abs(ref), rtol=1e-6)
    np.testing.assert_allclose(hb.phase[:, 0], np.angle(ref), rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(hb.stroke[:, 0], np.abs(ref), rtol=1e-6)
    np.testing.assert_allclose(r.linear, ref, rtol=1e-6)


def test_no_particles_equals_closed_form_n_modes():
    s = three_modes()
    m = AnalyticalDamper(PAPER_DAMPER.with_count(0))
    f = np.linspace(2.0, 100.0, 99)
    r = frequency_response(m, s, HarmonicLoad("force", 3.0), f, sweep="none")
    w = 2 * math.pi * f[:, None]
    wi = 2 * math.pi * s.frequencies
    ref = 3.0 * np.sum(s.output_shape * s.damper_shape
                       / (wi**2 - w**2 + 2j * s.damping_ratios * wi * w), axis=1)
    np.testing.assert_allclose(r.harmonic_balance.amplitude[:, 0], np.abs(ref), rtol=1e-6)
    np.testing.assert_allclose(r.harmonic_balance.phase[:, 0], np.angle(ref), rtol=1e-6,
                               atol=1e-9)


def test_no_particles_stepped_sine_reaches_the_closed_form():
    s = three_modes()
    m = AnalyticalDamper(PAPER_DAMPER.with_count(0))
    f = np.array([4.0, 5.0, 5.5, 6.0, 7.0, 30.0, 31.0, 32.0])
    r = frequency_response(m, s, HarmonicLoad("force", 3.0), f, sweep="up")
    up = r.sweeps["up"]
    assert up.steady.all()
    # steady to the criterion's 0.1 % per window: the transient left is of that order
    # (far above a resonance the slow first mode's transient leaks into the per-cycle
    # amplitude: not judged here)
    np.testing.assert_allclose(up.amplitude, np.abs(r.linear), rtol=5e-3)


def test_base_motion_1dof_is_the_transmissibility():
    s = PAPER_STRUCTURE
    m = AnalyticalDamper(PAPER_DAMPER.with_count(0))
    f = np.linspace(3, 9, 13)
    r = frequency_response(m, s, HarmonicLoad("base", 1e-3), f, sweep="none")
    w = 2 * math.pi * f
    t = (s.stiffness + 1j * w * s.damping) / (s.stiffness - s.mass * w**2 + 1j * w * s.damping)
    np.testing.assert_allclose(r.harmonic_balance.amplitude[:, 0], 1e-3 * np.abs(t), rtol=1e-6)
    # an acceleration amplitude is A / W^2 of displacement at each frequency
    ra = frequency_response(m, s, HarmonicLoad("base", 2.943, acceleration=True), f,
                            sweep="none")
    np.testing.assert_allclose(ra.harmonic_balance.amplitude[:, 0],
                               2.943 / w**2 * np.abs(t), rtol=1e-6)


def test_base_motion_on_n_modes_is_refused():
    m = AnalyticalDamper(PAPER_DAMPER)
    with pytest.raises(InputError) as e:
        frequency_response(m, three_modes(), HarmonicLoad("base", 1e-3), [5.0])
    assert e.value.field == "base"


def test_one_mode_equal_to_the_1dof_gives_identical_frf():
    m = AnalyticalDamper(PAPER_DAMPER)
    f = np.linspace(4.5, 6.5, 21)
    one = ModalStructure.from_single_dof(PAPER_STRUCTURE)
    a = frequency_response(m, PAPER_STRUCTURE, HarmonicLoad("force", 2.0), f)
    b = frequency_response(m, one, HarmonicLoad("force", 2.0), f)
    np.testing.assert_array_equal(a.harmonic_balance.amplitude, b.harmonic_balance.amplitude)
    for d in ("up", "down"):
        np.testing.assert_array_equal(a.sweeps[d].amplitude, b.sweeps[d].amplitude)


@pytest.fixture(scope="module")
def paper_2n():
    """The analytic model on the paper's damper and structure at 2 N, 121 points 3-9 Hz."""
    return frequency_response(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE,
                              HarmonicLoad("force", 2.0), F)


def test_harmonic_balance_and_stepped_sine_agree_within_2_percent_of_peak(paper_2n):
    r = paper_2n
    hb = r.harmonic_balance
    peak = r.peak()  # of the sweeps (an isolated upper branch near 33 mm is not reached)
    assert 0.010 < peak < 0.030  # well above the stroke where the bed lifts
    for d in ("up", "down"):
        c = r.sweeps[d]
        # steady almost everywhere; a point on a mode boundary may chatter (reported)
        assert np.count_nonzero(c.steady) >= 0.95 * F.size, d
        for i in range(F.size):
            stable = hb.amplitude[i][hb.branch[i] == "stable"]
            gap = np.min(np.abs(stable - c.amplitude[i]))
            assert gap <= 0.02 * peak, (d, F[i], c.amplitude[i], stable)


def test_stepped_sine_follows_the_branch_its_direction_predicts():
    # 128 spheres at 1 N: a jump near 5.1 Hz, hysteresis between the sweeps
    f = np.linspace(4.9, 5.4, 26)
    r = frequency_response(AnalyticalDamper(PAPER_DAMPER.with_count(128)), PAPER_STRUCTURE,
                           HarmonicLoad("force", 1.0), f)
    hb = r.harmonic_balance
    up, down = r.sweeps["up"], r.sweeps["down"]
    multi = [i for i in range(f.size) if np.count_nonzero(hb.branch[i] == "stable") >= 2]
    assert multi, "the case must have several stable solutions somewhere"
    for i in multi:
        stable = np.sort(hb.amplitude[i][hb.branch[i] == "stable"])
        low, high = stable[0], stable[-1]
        # up: still on the high branch it came from (amplitudes falling past resonance);
        # down: on the low branch it came from
        assert up.amplitude[i] == pytest.approx(high, rel=0.01), f[i]
        assert down.amplitude[i] == pytest.approx(low, rel=0.01), f[i]
        assert up.steady[i] and down.steady[i]
    # after the jump both sweeps are on the one solution left
    after = multi[-1] + 1
    assert up.amplitude[after] == pytest.approx(down.amplitude[after], rel=0.01)
    assert up.amplitude[after] < 0.7 * up.amplitude[multi[-1]]


def test_result_exports(paper_2n, tmp_path):
    ds = paper_2n.to_dataset()
    assert ds["hb_amplitude"].attrs["units"] == "m"
    assert ds["sweep_phase"].attrs["units"] == "rad"
    assert list(ds["sweep"].values) == ["up", "down"]
    path = tmp_path / "frf.nc"
    ds.to_netcdf(path)
    d = paper_2n.as_dict()
    assert len(d["points"]) == F.size and {"up", "down", "harmonic_balance"} <= set(d["points"][0])
    assert paper_2n.peak() == pytest.approx(max(paper_2n.sweeps["up"].amplitude.max(),
                                                paper_2n.sweeps["down"].amplitude.max()))
    assert paper_2n.peak((3.0, 4.0)) < paper_2n.peak()
    assert paper_2n.rms((3.0, 4.0)) < paper_2n.peak((3.0, 4.0))


def test_receptance_static_and_modal():
    s = three_modes()
    h0 = receptance(s, 1e-9)
    assert h0.real == pytest.approx(float(np.sum(s.damper_shape**2 / s.angular_frequencies**2)))
    one = SingleDOFStructure(2.0, 0.0, 800.0)
    assert abs(linear_frf(one, HarmonicLoad("force", 1.0), [1.0])[0]) == pytest.approx(
        1.0 / abs(800.0 - 2.0 * (2 * math.pi) ** 2))


def test_amplitude_judge_uses_the_map_criterion():
    assert not judge_amplitudes([1.0] * 5, DEFAULT_STEADY).stationary  # too few cycles
    assert judge_amplitudes([1.0] * 20, DEFAULT_STEADY).stationary
    drifting = list(np.linspace(1.0, 1.05, 20))
    assert not judge_amplitudes(drifting, DEFAULT_STEADY).stationary


@pytest.mark.parametrize("kwargs, field", [
    ({"frequency": [-1.0]}, "frequency"),
    ({"frequency": [float("nan")]}, "frequency"),
    ({"frequency": []}, "frequency"),
    ({"sweep": "sideways"}, "sweep"),
])
def test_bad_inputs_name_the_field(kwargs, field):
    args = {"frequency": [5.0], **kwargs}
    f = args.pop("frequency")
    with pytest.raises(InputError) as e:
        frequency_response(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE,
                           HarmonicLoad("force", 1.0), f, **args)
    assert e.value.field == field


@pytest.mark.parametrize("kind, amp, field", [("force", -1.0, "force"), ("force", 0.0, "force"),
                                              ("base", float("inf"), "base"),
                                              ("torque", 1.0, "load")])
def test_bad_loads_name_the_field(kind, amp, field):
    with pytest.raises(InputError) as e:
        HarmonicLoad(kind, amp)
    assert e.value.field == field


def test_n_modes_harmonic_balance_and_stepped_sine_agree():
    """The damper on a 3-mode structure, observed at another point: both solutions agree."""
    s = three_modes()
    f = np.linspace(4.5, 7.0, 26)
    r = frequency_response(AnalyticalDamper(PAPER_DAMPER), s, HarmonicLoad("force", 2.0), f)
    hb = r.harmonic_balance
    peak = r.peak()
    assert peak < 0.5 * np.abs(r.linear).max()  # the damper works on this structure too
    for d in ("up", "down"):
        c = r.sweeps[d]
        assert np.count_nonzero(c.steady) >= 0.9 * f.size
        for i in np.flatnonzero(c.steady):
            stable = hb.amplitude[i][hb.branch[i] == "stable"]
            assert np.min(np.abs(stable - c.amplitude[i])) <= 0.02 * peak, (d, f[i])
            # the output point is not the damper point here
            assert c.amplitude[i] != pytest.approx(c.stroke[i], rel=1e-3)


def test_dem_stepped_sine_runs_and_continues():
    """The DEM stepped sine (model 1) with a small bed: two steps, the second continuing
    from the first's state; amplitudes near the analytic model's (a small bed damps
    little: both near the linear response)."""
    from pdamper.models import DEMDamper

    f = np.array([4.0, 4.5])
    d = PAPER_DAMPER.with_count(4)
    r = frequency_response(DEMDamper(d), PAPER_STRUCTURE, HarmonicLoad("force", 0.5), f,
                           sweep="up", max_cycles=40)
    c = r.sweeps["up"]
    assert r.harmonic_balance is None  # the DEM has no describing function of its own
    assert np.all(np.isfinite(c.amplitude)) and np.all(c.cycles <= 40)
    lin = np.abs(r.linear)
    np.testing.assert_allclose(c.amplitude, lin, rtol=0.1)
    np.testing.assert_allclose(c.phase, np.angle(r.linear), atol=0.05)
    assert np.all(c.diagnostics["steps"] > 0)
    # accelerations below g: the DEM classifier sees a resting bed
    assert np.all(c.mode == 0)
    assert np.all(c.effective_mass > 0.5 * d.bed_mass)


def test_dem_stepped_sine_under_base_motion_is_the_transmissibility():
    """Base motion on the DEM's structure: amplitude and phase against the base
    displacement, as the closed form without particles for a bed that stays at rest."""
    from pdamper.models import DEMDamper

    s = SingleDOFStructure(1.514, 20.0, 1848.0)  # damped: the base's phase is not the force's
    r = frequency_response(DEMDamper(PAPER_DAMPER.with_count(4)), s,
                           HarmonicLoad("base", 3e-4), [4.0], sweep="up", max_cycles=40)
    c = r.sweeps["up"]
    np.testing.assert_allclose(c.amplitude, np.abs(r.linear), rtol=0.1)
    np.testing.assert_allclose(c.phase, np.angle(r.linear), atol=0.05)
    force_phase = np.angle(r.linear[0] / complex(s.stiffness, 2 * math.pi * 4.0 * s.damping))
    assert abs(force_phase - np.angle(r.linear[0])) > 0.2
