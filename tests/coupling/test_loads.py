"""Load histories on the structure (pdamper.coupling.loads): harmonic records against the
closed-form forced response and transmissibility of the 1-DOF, against harmonic balance
with the analytical damper, the one-mode model against the 1-DOF, the energy balance."""

import dataclasses
import math

import numpy as np
import pytest

from pdamper.coupling.loads import LoadHistory, run_load, simulate_load
from pdamper.coupling.pseudo_force import pseudo_force_coefficients
from pdamper.errors import InputError
from pdamper.io.loads import read_load
from pdamper.io.modes import read_modes
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure import SingleDOFStructure
from pdamper.structure.modal import ModalStructure

#: The paper's 1-DOF with 5 % damping, so that the start-up transient is gone (e^-17)
#: within the 10 s records below.
ZETA = 0.05
STRUCTURE = SingleDOFStructure(
    mass=PAPER_STRUCTURE.mass, stiffness=PAPER_STRUCTURE.stiffness,
    damping=2 * ZETA * math.sqrt(PAPER_STRUCTURE.stiffness * PAPER_STRUCTURE.mass))
NO_PARTICLES = AnalyticalDamper(dataclasses.replace(PAPER_DAMPER, count=0))


def _write(tmp_path, name, header, t, v):
    p = tmp_path / name
    rows = "".join(f"{float(a)!r}, {float(b)!r}\n" for a, b in zip(t, v, strict=True))
    p.write_text(f"# written by the test\n{header}\n{rows}")
    return p


def _harmonic_csv(tmp_path, amplitude, f, duration, per_period=200):
    """``amplitude sin(2 pi f t)`` [N] written in ms and N."""
    t = np.linspace(0.0, duration, int(duration * f * per_period) + 1)
    return _write(tmp_path, "force.csv", "time [ms], force [N]", t * 1e3,
                  amplitude * np.sin(2 * math.pi * f * t))


def _steady(res, periods, f):
    """Half the peak-to-peak of the last ``periods`` of the output [m]."""
    x = res.displacement[res.time >= res.time[-1] - periods / f]
    return 0.5 * (x.max() - x.min())


@pytest.mark.parametrize("f", [3.0, 5.56, 8.0])
def test_harmonic_force_without_particles_is_the_closed_form(tmp_path, f):
    """A CSV of 2 N sin(2 pi f t): the steady amplitude and RMS are those of
    ``F / |K - W^2 M + i W D|`` to 2e-4 (sampling of the peak, 200 samples a period)."""
    h = read_load(_harmonic_csv(tmp_path, 2.0, f, 10.0))
    res = simulate_load(NO_PARTICLES, STRUCTURE, h)
    w = 2 * math.pi * f
    s = STRUCTURE
    x = 2.0 / abs(s.stiffness - w * w * s.mass + 1j * w * s.damping)
    assert _steady(res, 4, f) == pytest.approx(x, rel=2e-4)
    peak, rms = res.window(res.time[-1] - 4 / f)
    assert rms == pytest.approx(x / math.sqrt(2), rel=2e-4)
    assert res.dissipated_energy == 0.0 and not res.cycles[-1].damping


def _harmonic_balance(model, structure, force, f):
    """The steady amplitudes X of ``X |K - W^2 (M + m_eff(f, X)) + i W (D + d(f, X))| = F``
    (the damper's describing function at the forcing frequency): every root on a fine
    log grid, refined by Brent's method."""
    from scipy.optimize import brentq

    w = 2 * math.pi * f

    def g(x):
        me, d, _ = pseudo_force_coefficients(model, f, x)
        return x * abs(structure.stiffness - w * w * (structure.mass + me)
                       + 1j * w * (structure.damping + d)) - force

    xs = np.geomspace(1e-4, 0.1, 300)
    gs = np.array([g(x) for x in xs])
    return [brentq(g, xs[i], xs[i + 1], xtol=1e-12)
            for i in np.flatnonzero(np.sign(gs[1:]) != np.sign(gs[:-1]))]


@pytest.mark.parametrize("f", [4.0, 5.0, 6.5])
def test_analytic_damper_reaches_the_harmonic_balance_amplitude(tmp_path, f):
    """The paper's damper and structure at 2 N: the steady amplitude of the time simulation
    (record from a CSV) is the harmonic-balance solution of the same model (one solution at
    these frequencies) within 0.5 %, and equals the run of the same force given in memory."""
    model = AnalyticalDamper(PAPER_DAMPER)
    roots = _harmonic_balance(model, PAPER_STRUCTURE, 2.0, f)
    assert len(roots) == 1
    res = simulate_load(model, PAPER_STRUCTURE, read_load(_harmonic_csv(tmp_path, 2.0, f, 40.0)))
    assert _steady(res, 3, f) == pytest.approx(roots[0], rel=5e-3)
    assert res.cycles[-1].frequency == pytest.approx(f, rel=1e-3)
    direct = simulate_load(model, PAPER_STRUCTURE, LoadHistory.harmonic(2.0, f, 40.0))
    assert _steady(direct, 3, f) == pytest.approx(_steady(res, 3, f), rel=1e-3)


@pytest.mark.parametrize("f", [4.0, 6.5])
def test_a_harmonic_load_history_reproduces_the_frf_point(tmp_path, f):
    """The record of 2 N sin(2 pi f t) run as a load history lands on the steady amplitude
    `pdamper frf` reports at f for the same damper and structure (its stable harmonic-balance
    solution and its stepped sine), within 0.5 %."""
    from pdamper.coupling.frf import HarmonicLoad, frequency_response

    model = AnalyticalDamper(PAPER_DAMPER)
    res = simulate_load(model, PAPER_STRUCTURE, read_load(_harmonic_csv(tmp_path, 2.0, f, 40.0)))
    frf = frequency_response(model, PAPER_STRUCTURE, HarmonicLoad("force", 2.0), [f],
                             sweep="up")
    hb = frf.harmonic_balance
    stable = hb.amplitude[0][hb.branch[0] == "stable"]
    assert stable.size == 1
    assert _steady(res, 3, f) == pytest.approx(float(stable[0]), rel=5e-3)
    assert _steady(res, 3, f) == pytest.approx(float(frf.sweeps["up"].amplitude[0]), rel=5e-3)


@pytest.mark.parametrize("f", [3.0, 5.56, 9.0])
def test_base_acceleration_without_particles_is_the_transmissibility(tmp_path, f):
    """0.3 g sin(2 pi f t) at the base: the absolute acceleration amplitude is
    ``A sqrt(1 + (2 zeta r)^2) / |1 - r^2 + 2 i zeta r|`` and the motion relative to the
    base ``A / |w_n^2 - W^2 + 2 i zeta w_n W|``, both to 2e-4."""
    a0 = 0.3 * 9.80665
    t = np.linspace(0.0, 10.0, int(10.0 * f * 200) + 1)
    p = _write(tmp_path, "acc.csv", "time [s], acceleration [g0]", t,
               0.3 * np.sin(2 * math.pi * f * t))
    res = simulate_load(NO_PARTICLES, STRUCTURE, read_load(p, "base_acceleration"))
    r = f / STRUCTURE.natural_frequency
    wn, w = 2 * math.pi * STRUCTURE.natural_frequency, 2 * math.pi * f
    sel = res.time >= res.time[-1] - 4 / f
    acc = 0.5 * (res.acceleration[sel].max() - res.acceleration[sel].min())
    assert acc == pytest.approx(a0 * math.hypot(1, 2 * ZETA * r)
                                / abs(1 - r * r + 2j * ZETA * r), rel=2e-4)
    assert _steady(res, 4, f) == pytest.approx(a0 / abs(wn**2 - w**2 + 2j * ZETA * wn * w),
                                               rel=2e-4)


def _shock_force():
    """A 40 ms half-sine of 40 N (about 20 mm of swing), then 3 s of rest, in 1 ms
    samples."""
    t = np.arange(0.0, 3.04, 1e-3)
    return LoadHistory(t, np.where(t < 0.04, 40.0 * np.sin(math.pi * t / 0.04), 0.0))


def test_one_mode_model_equal_to_the_1dof_gives_the_same_response(tmp_path):
    """modes.csv with the 1-DOF's one mode (phi = 1 / sqrt(M)) gives the 1-DOF's response
    to a force and to a base acceleration (to 1e-9: M = 1 / phi^2 rounds); a two-mode model
    whose second mode does not move at the damper runs the N-mode path and agrees too."""
    s = PAPER_STRUCTURE
    p = tmp_path / "modes.csv"
    p.write_text("frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
                 f"{s.natural_frequency!r}, {s.damping_ratio!r}, {1 / math.sqrt(s.mass)!r}\n")
    model = AnalyticalDamper(PAPER_DAMPER)
    one = read_modes(p)
    two = ModalStructure([s.natural_frequency, 40.0], [s.damping_ratio, 0.02],
                         [1 / math.sqrt(s.mass), 0.0])
    base = LoadHistory(*(lambda t: (t, 2.0 * np.sin(2 * math.pi * 5.0 * t)))(
        np.linspace(0, 4, 4001)), kind="base_acceleration")
    for load, structures in ((_shock_force(), (one, two)), (base, (one,))):
        ref = simulate_load(model, s, load)
        for st in structures:
            res = simulate_load(model, st, load)
            assert len(res.cycles) == len(ref.cycles) > 5
            np.testing.assert_allclose(res.displacement, ref.displacement, rtol=1e-9,
                                       atol=1e-9 * ref.peak)
            np.testing.assert_allclose(res.acceleration, ref.acceleration, rtol=1e-9,
                                       atol=1e-9 * ref.peak_acceleration)
            assert res.dissipated_energy == pytest.approx(ref.dissipated_energy, rel=1e-9)


@pytest.mark.parametrize("load", ["harmonic", "shock"])
def test_energy_balance(load):
    """Dissipated by the damper = input work - the structure's energy change - its own
    damping, within 1e-3 of the input work (trapezoidal quadrature of the sampled
    response; measured about 2e-5), with the damper taking a real share of it."""
    model = AnalyticalDamper(PAPER_DAMPER)
    h = LoadHistory.harmonic(2.0, 5.5, 10.0) if load == "harmonic" else _shock_force()
    res = simulate_load(model, PAPER_STRUCTURE, h, tail=1.0)
    assert res.dissipated_energy > 0.1 * res.input_work > 0
    assert abs(res.energy_balance_error) < 1e-3


def test_record_finer_than_the_sample_rate_is_followed():
    """A record at 10 kHz with the output at 2 kHz: the steps are refined to the record's
    interval and the steady amplitude is still the closed form."""
    f = 5.0
    h = LoadHistory.harmonic(2.0, f, 10.0, samples_per_period=2000)
    res = simulate_load(NO_PARTICLES, STRUCTURE, h, sample_rate=2000.0)
    assert res.inputs["integration_step"] == pytest.approx(1e-4)
    assert np.diff(res.time)[0] == pytest.approx(5e-4)
    w = 2 * math.pi * f
    x = 2.0 / abs(STRUCTURE.stiffness - w * w * STRUCTURE.mass + 1j * w * STRUCTURE.damping)
    assert _steady(res, 4, f) == pytest.approx(x, rel=2e-4)


def test_tail_is_free_vibration():
    """After the record the load is zero: the tail decays."""
    res = simulate_load(NO_PARTICLES, STRUCTURE, LoadHistory.harmonic(2.0, 5.0, 2.0), tail=3.0)
    assert res.time[-1] == pytest.approx(5.0)
    assert np.all(res.load[res.time > 2.0 + 1e-9] == 0.0)
    late = np.abs(res.displacement[res.time > 4.5]).max()
    assert late < 0.05 * np.abs(res.displacement[res.time < 2.0]).max()


def test_effective_fields_follow_the_analytical_model_they_were_mapped_from():
    """Model 2 from a 19 x 40 analytical map (clamped outside it) under the same loads as
    model 3: the steady amplitude of a 2 N harmonic force within 0.1 %, and under the shock
    the peak (before the first update) equal, the RMS within 3 % and the dissipated energy
    within 10 % (measured 1.5 % and 6.4 %: the map's bilinear interpolation of eta)."""
    from pdamper.analysis.fields import effective_field
    from pdamper.models import EffectiveFieldDamper

    m3 = AnalyticalDamper(PAPER_DAMPER)
    ds = effective_field(m3, np.linspace(2, 20, 19), np.geomspace(1e-4, 0.2, 40))
    m2 = EffectiveFieldDamper(PAPER_DAMPER, field=ds, extrapolation="clamp")
    h = LoadHistory.harmonic(2.0, 5.0, 40.0)
    a, b = simulate_load(m3, PAPER_STRUCTURE, h), simulate_load(m2, PAPER_STRUCTURE, h)
    assert b.model == "fields" and len(b.cycles) == len(a.cycles)
    assert _steady(b, 3, 5.0) == pytest.approx(_steady(a, 3, 5.0), rel=1e-3)
    a, b = (simulate_load(m, PAPER_STRUCTURE, _shock_force()) for m in (m3, m2))
    assert b.peak == pytest.approx(a.peak, rel=1e-9)
    assert b.rms == pytest.approx(a.rms, rel=0.03)
    assert b.dissipated_energy == pytest.approx(a.dissipated_energy, rel=0.1)


def test_beam_participation_factors_sum_to_the_moving_mass():
    """With every mode of the FE beam, sum Gamma_i^2 = r^T M r (the mass that moves with a
    rigid translation of the clamp: beam and tip mass less the clamp node's share)."""
    from pdamper.parameters.vertical_dampers_paper import paper_beam
    from pdamper.structure.beam import cantilever_matrices

    beam, tip = paper_beam()
    k, m = cantilever_matrices(beam, tip)
    s = ModalStructure.from_beam(beam, tip, k.shape[0])
    r = np.zeros(k.shape[0])
    r[0::2] = 1.0
    assert np.sum(s.participation**2) == pytest.approx(r @ m @ r, rel=1e-9)
    moving = beam.length * beam.width * beam.height * beam.density + tip.mass
    assert r @ m @ r == pytest.approx(moving, rel=0.01)


@pytest.mark.parametrize("f", [4.0, 30.0])
def test_base_acceleration_of_the_beam_is_the_modal_superposition(f):
    """The paper's beam with three modes, its clamp shaken at 2 m/s^2 without particles:
    the steady tip motion relative to the clamp is
    ``|sum_i phi_i Gamma_i A / (w_i^2 - W^2 + 2 i zeta_i w_i W)|`` to 5e-4."""
    from pdamper.parameters.vertical_dampers_paper import paper_beam

    beam, tip = paper_beam()
    s = ModalStructure.from_beam(beam, tip, 3, damping_ratio=0.05)
    dur = 10.0
    t = np.linspace(0.0, dur, int(dur * f * 200) + 1)
    load = LoadHistory(t, 2.0 * np.sin(2 * math.pi * f * t), "base_acceleration")
    res = simulate_load(NO_PARTICLES, s, load, sample_rate=max(2000.0, 400 * f))
    w, wi = 2 * math.pi * f, s.angular_frequencies
    x = abs(np.sum(s.output_shape * s.participation * 2.0
                   / (wi**2 - w**2 + 2j * s.damping_ratios * wi * w)))
    assert _steady(res, 4, f) == pytest.approx(x, rel=5e-4)


def test_models_without_a_load_form_and_base_motion_of_n_modes_are_errors():
    from pdamper.models import DEMDamper

    h = LoadHistory.harmonic(1.0, 5.0, 1.0)

    class NoLoadForm(AnalyticalDamper):
        coupling = "other"

    with pytest.raises(InputError) as e:
        run_load(NoLoadForm(PAPER_DAMPER), PAPER_STRUCTURE, h)
    assert e.value.field == "simulation.model"
    two = ModalStructure([5.0, 40.0], [0.01, 0.01], [0.8, 0.5])
    base = LoadHistory(h.time, h.values, "base_acceleration")
    with pytest.raises(InputError) as e:  # the DEM on N modes: no participation factors
        run_load(DEMDamper(PAPER_DAMPER), two, base)
    assert e.value.field == "base_acceleration"
    with pytest.raises(InputError) as e:
        simulate_load(NO_PARTICLES, two, base)
    assert e.value.field == "base_acceleration"
    assert simulate_load(NO_PARTICLES, two, h).peak > 0  # a force runs on N modes


@pytest.mark.parametrize("kwargs, field", [
    ({"time": [0.0], "values": [1.0]}, "load"),
    ({"time": [0.0, 0.0], "values": [1.0, 2.0]}, "load"),
    ({"time": [0.0, 1.0], "values": [1.0, math.nan]}, "load"),
    ({"time": [0.0, 1.0], "values": [1.0, 2.0], "kind": "base_acceleration",
      "source": ""}, None),
])
def test_load_history_checks(kwargs, field):
    if field is None:
        assert LoadHistory(**kwargs).kind == "base_acceleration"
        return
    with pytest.raises(InputError) as e:
        LoadHistory(**kwargs)
    assert e.value.field == field
